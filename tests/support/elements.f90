!> Element routines that only the tests use.
module ictus_test_elements
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: shape_at_i
  use ictus_test_check, only: checker_t
  implicit none
  private
  public :: element_omega_max, check_shape_functions, solve_dense, cross3, svk_cauchy

  interface
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: dp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
    subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: dp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv
    subroutine dsygv(itype, jobz, uplo, n, a, lda, b, ldb, w, work, lwork, info)
      import :: dp
      integer, intent(in) :: itype, n, lda, ldb, lwork
      character, intent(in) :: jobz, uplo
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsygv
  end interface

contains

  !> Largest natural frequency of one free element, omega^2 = lambda_max(K_e, M_e), with the
  !! ndm-dof-per-node mass M_e = me (x) I_ndm. By the element bound (doc/theory.md §4) the
  !! global omega_max is at most the maximum over the elements, so 2/max_e(omega) is a safe dt.
  !! nen: nodes; ke(ndm*nen, ndm*nen): stiffness (dof order x1, y1[, z1], ...); me(nen, nen):
  !! scalar consistent mass, or, when lumped = .true., only its diagonal is used (the lumped
  !! masses); omega: the frequency, or -1 when the mass is not positive definite (a
  !! non-positive lumped mass, or dsygv failing); info (optional): 0, or the LAPACK info /
  !! -(index of the first non-positive lumped mass); ndm (optional): 2 (default) or 3.
  subroutine element_omega_max(nen, ke, me, lumped, omega, info, ndm)
    integer, intent(in) :: nen
    real(dp), intent(in) :: ke(:,:), me(nen, nen)
    logical, intent(in) :: lumped
    real(dp), intent(out) :: omega
    integer, intent(out), optional :: info
    integer, intent(in), optional :: ndm
    real(dp), allocatable :: a(:,:), b(:,:), lam(:), s(:), work(:)
    integer :: i, j, n, ierr, nd
    nd = 2
    if (present(ndm)) nd = ndm
    n = nd*nen
    allocate(a(n, n), b(n, n), lam(n), s(n), work(8*n))
    omega = -1.0_dp
    ierr = 0
    if (lumped) then
      do i = 1, nen
        if (.not. me(i, i) > 0.0_dp) then
          ierr = -i
          exit
        end if
        s(nd*(i - 1) + 1:nd*i) = 1.0_dp/sqrt(me(i, i))
      end do
      if (ierr == 0) then
        do j = 1, n
          a(:, j) = s*ke(:, j)*s(j)
        end do
        call dsyev('N', 'U', n, a, n, lam, work, size(work), ierr)
      end if
    else
      b = 0.0_dp
      do j = 1, n
        do i = 1, n
          if (mod(i - j, nd) == 0) b(i, j) = me((i - 1)/nd + 1, (j - 1)/nd + 1)
        end do
      end do
      a = ke
      call dsygv(1, 'N', 'U', n, a, n, b, n, lam, work, size(work), ierr)
    end if
    if (ierr == 0) omega = sqrt(max(lam(n), 0.0_dp))
    if (present(info)) info = ierr
  end subroutine element_omega_max

  !> Checks of a family's shape functions at the parent points pts(ndm, np): partition of
  !! unity (1e-15), each derivative summing to zero (1e-14), the derivatives against central
  !! differences (step 1e-5: truncation ~1e-10 for these polynomials; 1e-9), and the Kronecker
  !! delta at the nodes of parent coordinates xnode(ndm, nen) (1e-15).
  subroutine check_shape_functions(t, label, shape, xnode, pts)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    procedure(shape_at_i) :: shape
    real(dp), intent(in) :: xnode(:,:), pts(:,:)
    real(dp), parameter :: h = 1.0e-5_dp
    real(dp) :: n(size(xnode, 2)), dn(size(xnode, 1), size(xnode, 2)), np(size(xnode, 2))
    real(dp) :: nm(size(xnode, 2)), dd(size(xnode, 1), size(xnode, 2)), x(size(xnode, 1))
    integer :: p, a, b, i
    do p = 1, size(pts, 2)
      call shape(pts(:, p), n, dn)
      call t%close(sum(n), 1.0_dp, 1.0e-15_dp, label//' sum N = 1')
      do i = 1, size(xnode, 1)
        call t%close_abs(sum(dn(i, :)), 0.0_dp, 1.0e-14_dp, label//' sum dN = 0')
        x = pts(:, p)
        x(i) = x(i) + h
        call shape(x, np, dd)
        x(i) = x(i) - 2.0_dp*h
        call shape(x, nm, dd)
        do a = 1, size(xnode, 2)
          call t%close_abs(dn(i, a), (np(a) - nm(a))/(2.0_dp*h), 1.0e-9_dp, &
              label//' dN vs central difference')
        end do
      end do
    end do
    do b = 1, size(xnode, 2)
      call shape(xnode(:, b), n, dn)
      do a = 1, size(xnode, 2)
        call t%close_abs(n(a), merge(1.0_dp, 0.0_dp, a == b), 1.0e-15_dp, &
            label//' N_A(x_B) = delta_AB')
      end do
    end do
  end subroutine check_shape_functions

  !> Solves a x = b in place (LAPACK dgesv): a(n, n) is overwritten by its LU factors, b(n)
  !! by x; info: 0, or dgesv's info.
  subroutine solve_dense(n, a, b, info)
    integer, intent(in) :: n
    real(dp), intent(inout) :: a(n, n), b(n)
    integer, intent(out) :: info
    integer :: ipiv(n)
    call dgesv(n, 1, a, n, ipiv, b, n, info)
  end subroutine solve_dense

  !> The cross product a x b.
  pure function cross3(a, b) result(c)
    real(dp), intent(in) :: a(3), b(3)
    real(dp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross3

  !> The St. Venant-Kirchhoff Cauchy stress of a deformation gradient f(3, 3), written out:
  !! sigma = F S F^T / J with S = lambda tr(E) I + 2 mu E, E = (F^T F - I)/2, J = det F
  !! (given as detf).
  pure function svk_cauchy(lam, mu, f, detf) result(sig)
    real(dp), intent(in) :: lam, mu, f(3, 3), detf
    real(dp) :: sig(3, 3)
    real(dp) :: e(3, 3), s(3, 3), tr
    integer :: i
    e = 0.5_dp*matmul(transpose(f), f)
    do i = 1, 3
      e(i, i) = e(i, i) - 0.5_dp
    end do
    tr = e(1, 1) + e(2, 2) + e(3, 3)
    s = 2.0_dp*mu*e
    do i = 1, 3
      s(i, i) = s(i, i) + lam*tr
    end do
    sig = matmul(matmul(f, s), transpose(f))/detf
  end function svk_cauchy
end module ictus_test_elements
