!> Element type codes, the description of an element type, the tasks of the element routine,
!! and the shape-function data that every element kernel consumes.
module ictus_elements_types
  use ictus_core_kinds, only: dp
  implicit none
  private
  public :: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA, ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27, &
      ETYPE_IGA3, ETYPE_BUILTIN, etype_is_nurbs, elem_shape_t, element_kind_t, shape_at_i, &
      rule_i, add_alias, TASK_MASS, TASK_FORCE, TASK_STIFFNESS, TASK_STRESS, TASK_JACOBIAN, &
      TASK_ROTATION, KERNEL_SOLID2D, KERNEL_SOLID3D

  !> Lagrange/serendipity quadrilaterals from *ELEMENT, NURBS (Bezier-extracted) spans, and
  !! the hexahedra C3D8 (trilinear), C3D20 (serendipity) and C3D27 (triquadratic).
  !! Codes index the dispatcher's table (ictus_elements_library); a type registered at run
  !! time (`element_register`) takes the next code after ETYPE_BUILTIN.
  integer, parameter :: ETYPE_Q4 = 1, ETYPE_Q8 = 2, ETYPE_Q9 = 3, ETYPE_IGA = 4
  integer, parameter :: ETYPE_C3D8 = 5, ETYPE_C3D20 = 6, ETYPE_C3D27 = 7
  !> The Bezier-extracted span of a trivariate NURBS patch (3D; ETYPE_IGA is the bivariate one).
  integer, parameter :: ETYPE_IGA3 = 8
  integer, parameter :: ETYPE_BUILTIN = 8

  !> Tasks of the element routine (`element_routine`): the scalar consistent mass, the internal
  !! force of the material law, the small-strain stiffness of a linear law, the stress at the
  !! quadrature points, the smallest Jacobian determinant, and the largest infinitesimal
  !! rotation of the displacement gradient (the small-strain guard).
  integer, parameter :: TASK_MASS = 1, TASK_FORCE = 2, TASK_STIFFNESS = 3, TASK_STRESS = 4, &
      TASK_JACOBIAN = 5, TASK_ROTATION = 6

  !> Element kernels: the isoparametric 2D solid (ictus_elements_solid2d) and the
  !! isoparametric 3D solid (ictus_elements_solid3d).
  integer, parameter :: KERNEL_SOLID2D = 1, KERNEL_SOLID3D = 2

  !> Shape functions of one element (or one element type) at its quadrature points.
  !! Derivatives are with respect to the parent coordinates in [-1, 1]^ndm, so the same
  !! element kernel serves Lagrange elements and Bezier-extracted NURBS spans.
  type :: elem_shape_t
    !> Number of element nodes / control points.
    integer :: nen = 0
    !> Number of quadrature points.
    integer :: ngp = 0
    !> Shape function values, (nen, ngp).
    real(dp), allocatable :: n(:,:)
    !> Derivatives d N / d(xi, eta[, zeta]), (ndm, nen, ngp).
    real(dp), allocatable :: dn(:,:,:)
    !> Quadrature weights in the parent domain, (ngp).
    real(dp), allocatable :: w(:)
  end type elem_shape_t

  abstract interface
    !> Shape functions n(nen) and parent derivatives dn(ndm, nen) at the parent point xi(ndm).
    pure subroutine shape_at_i(xi, n, dn)
      import :: dp
      real(dp), intent(in) :: xi(:)
      real(dp), intent(out) :: n(:), dn(:,:)
    end subroutine shape_at_i
    !> Quadrature rule of an element type for `n` (points per direction of a tensor rule, or
    !! the type's own measure of its order): points xq(ndm, ngp) in the parent domain and
    !! weights wq(ngp), allocated here.
    pure subroutine rule_i(n, xq, wq)
      import :: dp
      integer, intent(in) :: n
      real(dp), allocatable, intent(out) :: xq(:,:), wq(:)
    end subroutine rule_i
  end interface

  !> What the rest of the program knows of an element type: names, sizes, faces, the kernel
  !! and the shape functions. Filled by the type's own `<type>_kind()` (one file per family).
  type :: element_kind_t
    !> Deck name (TYPE= on *ELEMENT) and the name of its XDMF topology.
    character(len=16) :: name = '?'
    character(len=16) :: xdmf = ''
    !> Other deck names of the type (the Abaqus names, deck format 2): for each, the analysis
    !! it implies (ANALYSIS_PLANE_STRAIN, _STRESS or _3D of ictus_materials_law; 0: none) and
    !! its Gauss points per direction (0: the type's full rule).
    integer :: naliases = 0
    character(len=16) :: alias(6) = ''
    integer :: alias_analysis(6) = 0
    integer :: alias_gauss(6) = 0
    !> Spatial dimension (2 for the quadrilaterals and NURBS spans, 3 for the hexahedra),
    !! nodes (0: set by the NURBS degrees), corner nodes.
    integer :: ndm = 2
    integer :: nen = 0
    integer :: ncorner = 0
    !> Full Gauss rule: points per direction (0: from the degrees, p + 1).
    integer :: ngauss = 0
    !> Faces: how many, nodes per face and their local node numbers (nfn, nface). In 2D a face
    !! is an edge, its nodes in order along it. In 3D a face is a quadrilateral, its nodes in
    !! the order of Q4/Q8/Q9 (corners, then the midside of corners 1-2, 2-3, 3-4, 4-1, then
    !! the centre), the corners running so that the right-hand rule gives the outward normal.
    integer :: nface = 0
    integer :: nfn = 0
    integer, allocatable :: face(:,:)
    !> Node order of the XDMF topology, where it differs from ours: XDMF node k is local node
    !! xdmf_order(k) (not allocated: the same order).
    integer, allocatable :: xdmf_order(:)
    !> Polynomial order along an edge (1 linear, 2 quadratic) and whether the element has the
    !! centre node of a full tensor-product Lagrange element.
    integer :: order = 0
    logical :: centre = .false.
    !> Element kernel (KERNEL_*).
    integer :: kernel = KERNEL_SOLID2D
    !> Shape functions at a parent point (null for NURBS, whose shape depends on the span).
    procedure(shape_at_i), pointer, nopass :: shape => null()
    !> Quadrature rule; null: the tensor Gauss rule of ndm directions on [-1, 1]^ndm.
    procedure(rule_i), pointer, nopass :: rule => null()
  end type element_kind_t

contains

  !> Adds an Abaqus deck name to k: the analysis it implies and its Gauss rule (0: the full one).
  subroutine add_alias(k, name, analysis, gauss)
    type(element_kind_t), intent(inout) :: k
    character(len=*), intent(in) :: name
    integer, intent(in) :: analysis, gauss
    k%naliases = k%naliases + 1
    k%alias(k%naliases) = name
    k%alias_analysis(k%naliases) = analysis
    k%alias_gauss(k%naliases) = gauss
  end subroutine add_alias
  !> Whether an element type is a NURBS span (bivariate ETYPE_IGA or trivariate ETYPE_IGA3),
  !! whose nodes and shape data come from its patch.
  pure logical function etype_is_nurbs(etype)
    integer, intent(in) :: etype
    etype_is_nurbs = etype == ETYPE_IGA .or. etype == ETYPE_IGA3
  end function etype_is_nurbs
end module ictus_elements_types
