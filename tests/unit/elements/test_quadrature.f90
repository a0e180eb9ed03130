!> Gauss-Legendre rules: exactness for degree 2n-1, failure at degree 2n, weights, 2D and 3D
!! ordering and exactness.
program test_quadrature
  use ictus_core_kinds, only: dp
  use ictus_elements_quadrature, only: gauss_legendre, gauss_rule_2d, gauss_rule_3d
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("elements/quadrature")
  call case_1d(t)
  call case_2d(t)
  call case_3d(t)
  call t%finish()

contains

  !> Exact moment of x^k on [-1, 1].
  pure real(dp) function moment(k)
    integer, intent(in) :: k
    if (mod(k, 2) == 1) then
      moment = 0.0_dp
    else
      moment = 2.0_dp/real(k + 1, dp)
    end if
  end function moment

  subroutine case_1d(t)
    type(checker_t), intent(inout) :: t
    real(dp), allocatable :: xi(:), w(:)
    integer :: n, k
    character(len=40) :: lab
    do n = 1, 10
      allocate(xi(n), w(n))
      call gauss_legendre(n, xi, w)
      write(lab, '(a,i0)') 'weights sum n=', n
      call t%close(sum(w), 2.0_dp, 1.0e-14_dp, trim(lab))
      write(lab, '(a,i0)') 'ascending, inside, w>0 n=', n
      call t%true(all(xi(2:n) > xi(1:n-1)) .and. all(abs(xi) < 1.0_dp) .and. all(w > 0.0_dp), &
          trim(lab))
      do k = 0, 2*n - 1
        write(lab, '(a,i0,a,i0)') 'exact n=', n, ' degree ', k
        call t%close_abs(sum(w*xi**k), moment(k), 1.0e-14_dp, trim(lab))
      end do
      ! degree 2n is NOT integrated exactly: the error is the squared L2 norm of the
      ! monic Legendre norm (2.9e-6 for n = 10), so the rule must miss the exact moment
      write(lab, '(a,i0)') 'inexact degree 2n, n=', n
      call t%true(abs(sum(w*xi**(2*n)) - moment(2*n)) > 1.0e-7_dp, trim(lab))
      deallocate(xi, w)
    end do
    ! known closed forms
    allocate(xi(2), w(2))
    call gauss_legendre(2, xi, w)
    call t%close(xi(2), 1.0_dp/sqrt(3.0_dp), 1.0e-15_dp, '2-pt point')
    deallocate(xi, w)
    allocate(xi(3), w(3))
    call gauss_legendre(3, xi, w)
    call t%close(xi(3), sqrt(0.6_dp), 1.0e-15_dp, '3-pt point')
    call t%close(w(2), 8.0_dp/9.0_dp, 1.0e-15_dp, '3-pt centre weight')
    call t%close(w(1), 5.0_dp/9.0_dp, 1.0e-15_dp, '3-pt end weight')
  end subroutine case_1d

  subroutine case_2d(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: xi(2, 6), w(6)
    integer :: a, b
    character(len=40) :: lab
    call gauss_rule_2d(2, 3, xi, w)
    call t%close(sum(w), 4.0_dp, 1.0e-14_dp, '2d weights sum')
    ! direction 1 fastest: points 1, 2 share eta, differ in xi
    call t%true(xi(2, 1) == xi(2, 2) .and. xi(1, 1) < xi(1, 2) .and. xi(1, 3) == xi(1, 1), &
        '2d ordering')
    do b = 0, 5
      do a = 0, 3
        write(lab, '(a,i0,a,i0)') '2d exact x^', a, ' y^', b
        call t%close_abs(sum(w*xi(1, :)**a*xi(2, :)**b), moment(a)*moment(b), 1.0e-14_dp, &
            trim(lab))
      end do
    end do
  end subroutine case_2d

  !> The 2x3x4 rule: weights sum to 8, xi fastest then eta, exact for x^a y^b z^c with
  !! a <= 3, b <= 5, c <= 7, and not for z^8.
  subroutine case_3d(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: xi(3, 24), w(24)
    integer :: a, b, c
    character(len=40) :: lab
    call gauss_rule_3d(2, 3, 4, xi, w)
    call t%close(sum(w), 8.0_dp, 1.0e-14_dp, '3d weights sum')
    call t%true(xi(2, 1) == xi(2, 2) .and. xi(3, 1) == xi(3, 6) .and. xi(1, 1) < xi(1, 2) .and. &
        xi(2, 1) < xi(2, 3) .and. xi(3, 6) < xi(3, 7), '3d ordering')
    do c = 0, 7
      do b = 0, 5
        do a = 0, 3
          write(lab, '(a,i0,a,i0,a,i0)') '3d exact x^', a, ' y^', b, ' z^', c
          call t%close_abs(sum(w*xi(1, :)**a*xi(2, :)**b*xi(3, :)**c), &
              moment(a)*moment(b)*moment(c), 1.0e-14_dp, trim(lab))
        end do
      end do
    end do
    call t%true(abs(sum(w*xi(3, :)**8) - 4.0_dp*moment(8)) > 1.0e-7_dp, '3d inexact z^8')
  end subroutine case_3d
end program test_quadrature
