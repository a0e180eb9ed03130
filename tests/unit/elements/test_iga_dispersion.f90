!> Exact 1D discrete dispersion of p = 2 B-splines (doc/reference.md §6.1) and the 1D omega_max
!! table of doc/reference.md §6.2, from element matrices integrated here: the B-splines of a
!! uniform knot vector by Bezier extraction (ictus_geometry_bezier), Gauss-Legendre rules
!! (ictus_elements_quadrature), and eigenvalues by LAPACK dsygv.
!!
!! Periodic strip of nsp spans of size h (closed basis: function j lives on spans j..j+2 mod
!! nsp), E = rho = 1 (c = 1). With x = k h, C = cos x, Omega = omega h / c:
!!   consistent: Omega^2 = 20 (1 - C)(2 + C)/(16 + 13 C + C^2)
!!   row-sum:    Omega^2 = 2 (1 - C)(2 + C)/3
!! at k = 2 pi j/(nsp h), j = 0..nsp-1: the sorted eigenvalues must match to 1e-10.
program test_iga_dispersion
  use ictus_core_sort, only: sort
  use ictus_core_kinds, only: dp, pi
  use ictus_geometry_bezier, only: bezier_extraction_1d, bernstein
  use ictus_elements_quadrature, only: gauss_legendre
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: h = 0.5_dp

  call t%start("elements/iga_dispersion")
  call case_stencils(t)
  call case_periodic(t, 24)
  call case_periodic(t, 7)
  call case_open(t)
  call t%finish()

contains

  !> Uniform knot vector with nsp spans of size h, open (p+1 repeated end knots) or not.
  pure function uniform_knots(nsp, open) result(kn)
    integer, intent(in) :: nsp
    logical, intent(in) :: open
    real(dp), allocatable :: kn(:)
    integer :: i
    if (open) then
      kn = [0.0_dp, 0.0_dp, [(h*i, i = 0, nsp)], h*nsp, h*nsp]
    else
      kn = [(h*i, i = -2, nsp + 2)]
    end if
  end function uniform_knots

  !> Element stiffness ke(a, b) = int N_a' N_b' dx and mass me(a, b) = int N_a N_b dx of span
  !! e (extraction operator ce(3, 3)), span length h, 3 Gauss points (exact for degree 5).
  subroutine element_matrices(ce, ke, me)
    real(dp), intent(in) :: ce(3, 3)
    real(dp), intent(out) :: ke(3, 3), me(3, 3)
    real(dp) :: xg(3), wg(3), b(3), db(3), n(3), dn(3)
    integer :: g, a
    call gauss_legendre(3, xg, wg)
    ke = 0.0_dp
    me = 0.0_dp
    do g = 1, 3
      call bernstein(2, 0.5_dp*(xg(g) + 1.0_dp), b, db)
      n = matmul(ce, b)
      dn = matmul(ce, db)/h          ! d/dx = (1/h) d/dt
      do a = 1, 3
        ke(:, a) = ke(:, a) + dn*dn(a)*wg(g)*0.5_dp*h
        me(:, a) = me(:, a) + n*n(a)*wg(g)*0.5_dp*h
      end do
    end do
  end subroutine element_matrices

  !> Element matrices of an interior span of a uniform knot vector (all three B-splines
  !! are the uniform ones there).
  subroutine interior_element(ke, me)
    real(dp), intent(out) :: ke(3, 3), me(3, 3)
    real(dp), allocatable :: c(:,:,:)
    integer :: nel
    call bezier_extraction_1d(8, 2, uniform_knots(6, .true.), nel, c)
    call element_matrices(c(:, :, 3), ke, me)
  end subroutine interior_element

  !> The assembled interior stencils K = (1/6h)[-1, -2, 6, -2, -1], M = (h/120)[1, 26, 66,
  !! 26, 1] (doc/reference.md §6.1): row sums of the element contributions to one function.
  subroutine case_stencils(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: ke(3, 3), me(3, 3), ks(-2:2), ms(-2:2)
    integer :: a, b
    call interior_element(ke, me)
    ! function j is local function a of span j - a + 1 (a = 1..3); its partner is local b
    ks = 0.0_dp
    ms = 0.0_dp
    do a = 1, 3
      do b = 1, 3
        ks(b - a) = ks(b - a) + ke(a, b)
        ms(b - a) = ms(b - a) + me(a, b)
      end do
    end do
    call t%true(maxval(abs(ks - [-1.0_dp, -2.0_dp, 6.0_dp, -2.0_dp, -1.0_dp]/(6.0_dp*h))) &
        < 1.0e-14_dp/h, "stiffness stencil (1/6h)[-1, -2, 6, -2, -1]")
    call t%true(maxval(abs(ms - [1.0_dp, 26.0_dp, 66.0_dp, 26.0_dp, 1.0_dp]*h/120.0_dp)) &
        < 1.0e-15_dp*h, "mass stencil (h/120)[1, 26, 66, 26, 1]")
    call t%close(sum(ms), h, 1.0e-14_dp, "row sum of the mass stencil = h")
  end subroutine case_stencils

  !> Generalised eigenvalues of (kg, mg), ascending: omega^2. n: size.
  subroutine eigenvalues(n, kg, mg, lam, info)
    integer, intent(in) :: n
    real(dp), intent(in) :: kg(n, n), mg(n, n)
    real(dp), intent(out) :: lam(n)
    integer, intent(out) :: info
    real(dp) :: a(n, n), b(n, n), work(8*n)
    a = kg
    b = mg
    call dsygv(1, 'N', 'U', n, a, n, b, n, lam, work, size(work), info)
  end subroutine eigenvalues

  !> Periodic strip of nsp spans: consistent and row-sum eigenvalues against the formulas.
  subroutine case_periodic(t, nsp)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: nsp
    real(dp) :: ke(3, 3), me(3, 3), kg(nsp, nsp), mg(nsp, nsp), ml(nsp, nsp)
    real(dp) :: lam(nsp), w2c(nsp), w2r(nsp), cx
    integer :: e, a, b, ia, ib, j, info
    character(len=32) :: tag
    write(tag, '(a,i0,a)') ' (periodic, ', nsp, ' spans)'
    call interior_element(ke, me)
    kg = 0.0_dp
    mg = 0.0_dp
    do e = 1, nsp
      do a = 1, 3
        ia = mod(e + a - 2, nsp) + 1
        do b = 1, 3
          ib = mod(e + b - 2, nsp) + 1
          kg(ia, ib) = kg(ia, ib) + ke(a, b)
          mg(ia, ib) = mg(ia, ib) + me(a, b)
        end do
      end do
    end do
    ml = 0.0_dp
    do a = 1, nsp
      ml(a, a) = sum(mg(a, :))
    end do
    do j = 0, nsp - 1
      cx = cos(2.0_dp*pi*real(j, dp)/real(nsp, dp))
      w2c(j + 1) = 20.0_dp*(1.0_dp - cx)*(2.0_dp + cx)/(16.0_dp + 13.0_dp*cx + cx**2)/h**2
      w2r(j + 1) = 2.0_dp*(1.0_dp - cx)*(2.0_dp + cx)/3.0_dp/h**2
    end do
    call sort(w2c)
    call sort(w2r)
    call eigenvalues(nsp, kg, mg, lam, info)
    call t%equal_int(info, 0, "dsygv, consistent"//trim(tag))
    call t%true(maxval(abs(lam - w2c)) < 1.0e-10_dp*maxval(w2c), &
        "consistent: omega^2 = 20(1-C)(2+C)/(16+13C+C^2)/h^2 at all k"//trim(tag))
    call eigenvalues(nsp, kg, ml, lam, info)
    call t%equal_int(info, 0, "dsygv, row-sum"//trim(tag))
    call t%true(maxval(abs(lam - w2r)) < 1.0e-10_dp*maxval(w2r), &
        "row-sum: omega^2 = 2(1-C)(2+C)/3/h^2 at all k"//trim(tag))
    call t%true(maxval(w2c)*h**2 <= 10.0_dp*(1.0_dp + 1.0e-14_dp), &
        "consistent omega_max h/c <= sqrt(10)"//trim(tag))
    call t%true(maxval(w2r)*h**2 <= 1.5_dp*(1.0_dp + 1.0e-14_dp), &
        "row-sum omega_max h/c <= sqrt(1.5)"//trim(tag))
  end subroutine case_periodic

  !> Open knot vector, 40 spans: omega_max h/c with free and fixed ends (doc/reference.md §6.2:
  !! free 4.645 / 2.320, fixed 3.162 / 1.437, consistent / row-sum; given to 4 digits, so
  !! checked to half a unit of the last digit).
  subroutine case_open(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nsp = 40, n = nsp + 2
    real(dp), allocatable :: c(:,:,:)
    real(dp) :: ke(3, 3), me(3, 3), kg(n, n), mg(n, n), ml(n, n), lam(n)
    real(dp) :: kf(n-2, n-2), mf(n-2, n-2), lf(n-2, n-2)
    integer :: e, nel, info, a, i0
    call bezier_extraction_1d(n, 2, uniform_knots(nsp, .true.), nel, c)
    kg = 0.0_dp
    mg = 0.0_dp
    do e = 1, nel
      call element_matrices(c(:, :, e), ke, me)
      i0 = e - 1
      kg(i0 + 1:i0 + 3, i0 + 1:i0 + 3) = kg(i0 + 1:i0 + 3, i0 + 1:i0 + 3) + ke
      mg(i0 + 1:i0 + 3, i0 + 1:i0 + 3) = mg(i0 + 1:i0 + 3, i0 + 1:i0 + 3) + me
    end do
    ml = 0.0_dp
    do a = 1, n
      ml(a, a) = sum(mg(a, :))
    end do
    call t%close(ml(1, 1), h/3.0_dp, 1.0e-14_dp, "open knots: end row-sum mass h/3 (doc/iga.md §5)")
    call t%close(ml(2, 2), 2.0_dp*h/3.0_dp, 1.0e-14_dp, "open knots: next row-sum mass 2h/3")
    call eigenvalues(n, kg, mg, lam, info)
    call t%close_abs(sqrt(lam(n))*h, 4.645_dp, 5.0e-4_dp, "open, free ends, consistent: 4.645")
    call eigenvalues(n, kg, ml, lam, info)
    call t%close_abs(sqrt(lam(n))*h, 2.320_dp, 5.0e-4_dp, "open, free ends, row-sum: 2.320")
    ! fixed ends: the end control points (which interpolate the end values) removed
    kf = kg(2:n-1, 2:n-1)
    mf = mg(2:n-1, 2:n-1)
    lf = ml(2:n-1, 2:n-1)
    call eigenvalues(n - 2, kf, mf, lam(1:n-2), info)
    call t%close_abs(sqrt(lam(n-2))*h, 3.162_dp, 5.0e-4_dp, "open, fixed ends, consistent: "// &
        "3.162 (no outlier)")
    call eigenvalues(n - 2, kf, lf, lam(1:n-2), info)
    call t%close_abs(sqrt(lam(n-2))*h, 1.437_dp, 5.0e-4_dp, "open, fixed ends, row-sum: 1.437")
  end subroutine case_open
end program test_iga_dispersion
