!> Element type codes and the shape-function data that every element routine consumes.
module ictus_elements_types
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA, etype_name, etype_nen, elem_shape_t

  !> Lagrange/serendipity quadrilaterals from *ELEMENT, and NURBS (Bezier-extracted) spans.
  integer, parameter :: ETYPE_Q4 = 1, ETYPE_Q8 = 2, ETYPE_Q9 = 3, ETYPE_IGA = 4

  !> Shape functions of one element (or one element type) at its quadrature points.
  !! Derivatives are with respect to the parent coordinates (xi, eta) in [-1, 1]^2, so the
  !! same element routine serves Lagrange elements and Bezier-extracted NURBS spans.
  type :: elem_shape_t
    !> Number of element nodes / control points.
    integer :: nen = 0
    !> Number of quadrature points.
    integer :: ngp = 0
    !> Shape function values, (nen, ngp).
    real(dp), allocatable :: n(:,:)
    !> Derivatives d N / d(xi, eta), (2, nen, ngp).
    real(dp), allocatable :: dn(:,:,:)
    !> Quadrature weights in the parent domain, (ngp).
    real(dp), allocatable :: w(:)
  end type elem_shape_t

contains

  !> Deck name of an element type.
  pure function etype_name(etype) result(name)
    integer, intent(in) :: etype
    character(len=:), allocatable :: name
    select case (etype)
    case (ETYPE_Q4)
      name = 'Q4'
    case (ETYPE_Q8)
      name = 'Q8'
    case (ETYPE_Q9)
      name = 'Q9'
    case (ETYPE_IGA)
      name = 'IGA'
    case default
      name = '?'
    end select
  end function etype_name

  !> Nodes per element of a finite-element type (0 for IGA: it depends on the degrees).
  pure integer function etype_nen(etype)
    integer, intent(in) :: etype
    select case (etype)
    case (ETYPE_Q4)
      etype_nen = 4
    case (ETYPE_Q8)
      etype_nen = 8
    case (ETYPE_Q9)
      etype_nen = 9
    case default
      etype_nen = 0
    end select
  end function etype_nen
end module ictus_elements_types
