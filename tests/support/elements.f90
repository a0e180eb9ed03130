!> Element routines that only the tests use.
module ictus_test_elements
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: element_omega_max

  interface
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: dp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
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
  !! 2-dof-per-node mass M_e = me (x) I_2. By the element bound (doc/theory.md §4) the global
  !! omega_max is at most the maximum over the elements, so 2/max_e(omega) is a safe dt.
  !! nen: nodes; ke(2*nen, 2*nen): stiffness (dof order x1, y1, ...); me(nen, nen): scalar
  !! consistent mass, or, when lumped = .true., only its diagonal is used (the lumped masses);
  !! omega: the frequency, or -1 when the mass is not positive definite (a non-positive lumped
  !! mass, or dsygv failing); info (optional): 0, or the LAPACK info / -(index of the first
  !! non-positive lumped mass).
  subroutine element_omega_max(nen, ke, me, lumped, omega, info)
    integer, intent(in) :: nen
    real(dp), intent(in) :: ke(2*nen, 2*nen), me(nen, nen)
    logical, intent(in) :: lumped
    real(dp), intent(out) :: omega
    integer, intent(out), optional :: info
    real(dp) :: a(2*nen, 2*nen), b(2*nen, 2*nen), lam(2*nen), s(2*nen)
    real(dp) :: work(16*nen)
    integer :: i, j, n, ierr
    n = 2*nen
    omega = -1.0_dp
    ierr = 0
    if (lumped) then
      do i = 1, nen
        if (.not. me(i, i) > 0.0_dp) then
          ierr = -i
          exit
        end if
        s(2*i - 1:2*i) = 1.0_dp/sqrt(me(i, i))
      end do
      if (ierr == 0) then
        do j = 1, n
          a(:, j) = s*ke(:, j)*s(j)
        end do
        call dsyev('N', 'U', n, a, n, lam, work, size(work), ierr)
      end if
    else
      b = 0.0_dp
      do j = 1, nen
        do i = 1, nen
          b(2*i - 1, 2*j - 1) = me(i, j)
          b(2*i, 2*j) = me(i, j)
        end do
      end do
      a = ke
      call dsygv(1, 'N', 'U', n, a, n, b, n, lam, work, size(work), ierr)
    end if
    if (ierr == 0) omega = sqrt(max(lam(n), 0.0_dp))
    if (present(info)) info = ierr
  end subroutine element_omega_max
end module ictus_test_elements
