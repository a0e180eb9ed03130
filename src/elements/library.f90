!> Element library: the entry point that, for an element type, provides the shape data, plus
!! the element-level frequency bound used for the critical time step.
!!
!! All element families (Q4, Q8, Q9 and Bezier-extracted NURBS spans) share the isoparametric
!! solid kernels of ictus_elements_solid2d (stiffness, mass, stress); they differ only in their
!! shape data. Lagrange shape data come from here; NURBS spans get theirs from
!! ictus_elements_iga, span by span.
module ictus_elements_library
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, elem_shape_t
  use ictus_elements_lagrange, only: lagrange_shape_data
  implicit none
  private
  public :: element_shape_data, element_default_ngauss, element_omega_max

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

  !> Full Gauss rule (points per direction) of a Lagrange element type: 2 for Q4, 3 for Q8 and
  !! Q9; 0 for any other type.
  pure integer function element_default_ngauss(etype)
    integer, intent(in) :: etype
    select case (etype)
    case (ETYPE_Q4)
      element_default_ngauss = 2
    case (ETYPE_Q8, ETYPE_Q9)
      element_default_ngauss = 3
    case default
      element_default_ngauss = 0
    end select
  end function element_default_ngauss

  !> Shape data of a finite-element type for an ngauss x ngauss Gauss rule.
  !! etype: ETYPE_Q4/Q8/Q9; ngauss: points per direction; shp: filled (nen, ngp, n, dn, w).
  !! For ETYPE_IGA (shape data depend on the span) or an unknown type, shp is left empty
  !! (nen = ngp = 0, nothing allocated).
  subroutine element_shape_data(etype, ngauss, shp)
    integer, intent(in) :: etype, ngauss
    type(elem_shape_t), intent(out) :: shp
    select case (etype)
    case (ETYPE_Q4, ETYPE_Q8, ETYPE_Q9)
      call lagrange_shape_data(etype, ngauss, shp)
    end select
  end subroutine element_shape_data

  !> Largest natural frequency of one free element, omega^2 = lambda_max(K_e, M_e), with the
  !! 2-dof-per-node mass M_e = me (x) I_2. By the element bound (physics.md §4.2) the global
  !! omega_max is at most the maximum over the elements, so 2/max_e(omega) is a safe Δt.
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
end module ictus_elements_library
