!> The element library: the one dispatcher by element type, and the element routine with its
!! tasks.
!!
!! `element_kind(etype)` describes a type (names, nodes, faces, Gauss rule, kernel, shape
!! functions); everything else in ictus asks it instead of testing type codes. The table is
!! filled once from each family's `<type>_kind()`: adding an element type is one file with its
!! shape functions and `<type>_kind()`, one code in ictus_elements_types and one line in
!! `fill_table` (doc/architecture.md, "Adding an element type").
!!
!! `element_routine(task, ...)` runs one task on one element (mass, internal force, stiffness,
!! stress, Jacobian check) through the type's kernel. Q4, Q8, Q9 and Bezier-extracted NURBS
!! spans share the isoparametric solid kernel (ictus_elements_solid2d) and differ only in their
!! shape data; the hexahedra C3D8, C3D20 and C3D27 share the 3D one (ictus_elements_solid3d).
!! The time loop's internal force calls `element_force` with the geometry that
!! `element_geometry` stored once.
module ictus_elements_library
  use ictus_core_kinds, only: dp
  use ictus_core_strings, only: upper
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA, ETYPE_C3D8, &
      ETYPE_C3D20, ETYPE_C3D27, ETYPE_IGA3, ETYPE_BUILTIN, elem_shape_t, element_kind_t, &
      TASK_MASS, TASK_FORCE, TASK_STIFFNESS, TASK_STRESS, TASK_JACOBIAN, TASK_ROTATION, KERNEL_SOLID2D, &
      KERNEL_SOLID3D
  use ictus_elements_quadrature, only: gauss_rule_2d, gauss_rule_3d
  use ictus_elements_lagrange, only: q4_kind, q8_kind, q9_kind
  use ictus_elements_hexahedra, only: c3d8_kind, c3d20_kind, c3d27_kind
  use ictus_elements_iga, only: iga_kind, iga3_kind
  use ictus_elements_solid2d, only: solid2d_stiffness, solid2d_mass, solid2d_stress, &
      solid2d_min_detj, solid2d_geometry, solid2d_force, solid2d_rotation
  use ictus_elements_solid3d, only: solid3d_stiffness, solid3d_mass, solid3d_stress, &
      solid3d_min_detj, solid3d_geometry, solid3d_force, solid3d_rotation
  use ictus_materials_law, only: law_t
  use ictus_materials_material, only: material_t
  implicit none
  private
  public :: element_kind, element_register, element_type_count, etype_name, etype_nen, &
      etype_ndm, element_type_of, element_default_ngauss, element_type_named, &
      element_abaqus_names, element_shape_data, element_shape_rule, element_routine, &
      element_out_t, element_geometry, element_force, element_types_named

  !> Everything is computed per unit thickness in 2D (doc/results.md): with a uniform
  !! thickness t, stiffness, mass and forces all scale with t, and the motion does not depend
  !! on it.
  real(dp), parameter :: unit_thickness = 1.0_dp

  !> The table of element types, filled at first use; `ntypes` in use.
  type(element_kind_t), allocatable :: table(:)
  integer :: ntypes = 0

  !> Results of one call of the element routine.
  type :: element_out_t
    !> TASK_STIFFNESS: stiffness (ndm nen, ndm nen), dof order x1, y1[, z1], ...; TASK_MASS:
    !! scalar consistent mass (nen, nen).
    real(dp), allocatable :: s(:,:)
    !> TASK_FORCE: internal force (ndm, nen).
    real(dp), allocatable :: p(:,:)
    !> TASK_STRESS: Cauchy stress and strain per quadrature point (6, ngp), (xx, yy, zz, xy,
    !! yz, zx; tensor shears; the logarithmic strain with NLGEOM).
    real(dp), allocatable :: sig(:,:), eps(:,:)
    !> TASK_MASS: element mass; TASK_FORCE: strain energy; TASK_JACOBIAN: smallest det J;
    !! TASK_ROTATION: the largest infinitesimal rotation (rad).
    real(dp) :: scalar = 0.0_dp
    !> 0, or the first quadrature point with det J <= 0 (TASK_JACOBIAN: the point of the
    !! smallest det J).
    integer :: ierr = 0
  end type element_out_t


contains

  !> The dispatcher: one line per element type.
  subroutine fill_table()
    if (ntypes > 0) return
    allocate(table(ETYPE_BUILTIN + 4))
    table(ETYPE_Q4) = q4_kind()
    table(ETYPE_Q8) = q8_kind()
    table(ETYPE_Q9) = q9_kind()
    table(ETYPE_IGA) = iga_kind()
    table(ETYPE_C3D8) = c3d8_kind()
    table(ETYPE_C3D20) = c3d20_kind()
    table(ETYPE_C3D27) = c3d27_kind()
    table(ETYPE_IGA3) = iga3_kind()
    ntypes = ETYPE_BUILTIN
  end subroutine fill_table

  !> Adds an element type at run time (a type defined outside src/elements, e.g. by a test)
  !! and returns its code.
  function element_register(k) result(etype)
    type(element_kind_t), intent(in) :: k
    integer :: etype
    type(element_kind_t), allocatable :: grown(:)
    call fill_table()
    if (ntypes == size(table)) then
      allocate(grown(2*size(table)))
      grown(1:ntypes) = table(1:ntypes)
      call move_alloc(grown, table)
    end if
    ntypes = ntypes + 1
    table(ntypes) = k
    etype = ntypes
  end function element_register

  !> Number of element types (codes 1 .. element_type_count()).
  integer function element_type_count()
    call fill_table()
    element_type_count = ntypes
  end function element_type_count

  !> Description of element type etype (an empty one, name '?', for an unknown code).
  function element_kind(etype) result(k)
    integer, intent(in) :: etype
    type(element_kind_t) :: k
    call fill_table()
    if (etype >= 1 .and. etype <= ntypes) k = table(etype)
  end function element_kind

  !> Deck name of an element type ('?' for an unknown code).
  function etype_name(etype) result(name)
    integer, intent(in) :: etype
    character(len=:), allocatable :: name
    call fill_table()
    name = '?'
    if (etype >= 1 .and. etype <= ntypes) name = trim(table(etype)%name)
  end function etype_name

  !> Nodes per element of a finite-element type (0 for NURBS: it depends on the degrees).
  integer function etype_nen(etype)
    integer, intent(in) :: etype
    call fill_table()
    etype_nen = 0
    if (etype >= 1 .and. etype <= ntypes) etype_nen = table(etype)%nen
  end function etype_nen

  !> Spatial dimension of an element type (2 or 3; 0 for an unknown code).
  integer function etype_ndm(etype)
    integer, intent(in) :: etype
    call fill_table()
    etype_ndm = 0
    if (etype >= 1 .and. etype <= ntypes) etype_ndm = table(etype)%ndm
  end function etype_ndm

  !> Code of the finite-element type with deck name `name` (any case); 0 when none (NURBS
  !! spans are not named on *ELEMENT).
  integer function element_type_of(name)
    character(len=*), intent(in) :: name
    integer :: t
    call fill_table()
    element_type_of = 0
    do t = 1, ntypes
      if (table(t)%nen > 0 .and. trim(table(t)%name) == upper(trim(name))) then
        element_type_of = t
        return
      end if
    end do
  end function element_type_of

  !> The finite-element type with deck name `name` (any case), its own name or one of its
  !! Abaqus names (`alias` of its description): its code (0 when none), the analysis the name
  !! implies (0: none) and its Gauss points per direction (0: the type's full rule).
  subroutine element_type_named(name, etype, analysis, gauss)
    character(len=*), intent(in) :: name
    integer, intent(out) :: etype, analysis, gauss
    integer :: t, a
    etype = element_type_of(name)
    analysis = 0
    gauss = 0
    if (etype > 0) return
    do t = 1, ntypes
      if (table(t)%nen == 0) cycle
      do a = 1, table(t)%naliases
        if (trim(table(t)%alias(a)) == upper(trim(name))) then
          etype = t
          analysis = table(t)%alias_analysis(a)
          gauss = table(t)%alias_gauss(a)
          return
        end if
      end do
    end do
  end subroutine element_type_named

  !> The Abaqus names of the finite-element types, for messages: "CPE4, CPS4 (Q4), ...";
  !! ndm (optional): only the types of that dimension.
  function element_abaqus_names(ndm) result(list)
    integer, intent(in), optional :: ndm
    character(len=:), allocatable :: list
    integer :: t, a
    call fill_table()
    list = ''
    do t = 1, ntypes
      if (table(t)%nen == 0 .or. table(t)%naliases == 0) cycle
      if (present(ndm)) then
        if (table(t)%ndm /= ndm) cycle
      end if
      if (len(list) > 0) list = list//', '
      do a = 1, table(t)%naliases
        if (a > 1) list = list//', '
        list = list//trim(table(t)%alias(a))
      end do
      list = list//' ('//trim(table(t)%name)//')'
    end do
  end function element_abaqus_names

  !> The deck names of the finite-element types, comma separated (for messages); ndm
  !! (optional): only the types of that dimension.
  function element_types_named(ndm) result(list)
    integer, intent(in), optional :: ndm
    character(len=:), allocatable :: list
    integer :: t
    call fill_table()
    list = ''
    do t = 1, ntypes
      if (table(t)%nen == 0) cycle
      if (present(ndm)) then
        if (table(t)%ndm /= ndm) cycle
      end if
      if (len(list) > 0) list = list//', '
      list = list//trim(table(t)%name)
    end do
  end function element_types_named

  !> Full Gauss rule (points per direction) of a finite-element type; 0 for NURBS (p + 1 from
  !! the degrees) or an unknown type.
  integer function element_default_ngauss(etype)
    integer, intent(in) :: etype
    call fill_table()
    element_default_ngauss = 0
    if (etype >= 1 .and. etype <= ntypes) element_default_ngauss = table(etype)%ngauss
  end function element_default_ngauss

  !> Shape data of a finite-element type for its quadrature rule of `ngauss`: the type's own
  !! rule where it has one, else the ngauss^ndm Gauss rule (xi running fastest, then eta).
  !! etype; ngauss; shp: filled (nen, ngp, n, dn, w). For NURBS (shape data depend on the span) or an unknown type,
  !! shp is left empty (nen = ngp = 0, nothing allocated).
  subroutine element_shape_data(etype, ngauss, shp)
    integer, intent(in) :: etype, ngauss
    type(elem_shape_t), intent(out) :: shp
    real(dp), allocatable :: xq(:,:), wq(:)
    type(element_kind_t) :: k
    k = element_kind(etype)
    if (k%nen == 0) return
    if (associated(k%rule)) then
      call k%rule(ngauss, xq, wq)
    else if (k%ndm == 3) then
      allocate(xq(3, ngauss**3), wq(ngauss**3))
      call gauss_rule_3d(ngauss, ngauss, ngauss, xq, wq)
    else
      allocate(xq(2, ngauss*ngauss), wq(ngauss*ngauss))
      call gauss_rule_2d(ngauss, ngauss, xq, wq)
    end if
    call element_shape_rule(etype, xq, wq, shp)
  end subroutine element_shape_data

  !> Shape data of a finite-element type at any quadrature rule: points xq(ndm, ngp) in the
  !! parent domain and weights wq(ngp). shp is left empty for NURBS or an unknown type.
  subroutine element_shape_rule(etype, xq, wq, shp)
    integer, intent(in) :: etype
    real(dp), intent(in) :: xq(:,:), wq(:)
    type(elem_shape_t), intent(out) :: shp
    type(element_kind_t) :: k
    integer :: g
    k = element_kind(etype)
    if (k%nen == 0 .or. .not. associated(k%shape)) return
    shp%nen = k%nen
    shp%ngp = size(wq)
    allocate(shp%n(k%nen, shp%ngp), shp%dn(k%ndm, k%nen, shp%ngp), shp%w(shp%ngp))
    shp%w = wq
    do g = 1, shp%ngp
      call k%shape(xq(:, g), shp%n(:, g), shp%dn(:, :, g))
    end do
  end subroutine element_shape_rule

  !> The element routine: runs `task` (TASK_*; TASK_STIFFNESS with the law's reference
  !! tangent) on one element of type etype with shape data
  !! shp, node coordinates xl(ndm, nen) and material mat (whose law knows its kinematics: 2D
  !! idealisation or 3D, small or finite strain). The type's kernel decides ndm: 2 for
  !! KERNEL_SOLID2D (per unit thickness), 3 for KERNEL_SOLID3D.
  !! TASK_FORCE and TASK_STRESS also take the displacements ul(ndm, nen) and the history
  !! hist_old(nhist, ngp); TASK_FORCE returns hist_new. `mean` (optional): the element shares
  !! its mean dilatation (B-bar / F-bar, doc/theory.md §2.1). Results go to `out` (element_out_t),
  !! whose arrays are allocated to fit.
  subroutine element_routine(task, etype, shp, xl, mat, out, ul, hist_old, hist_new, mean)
    integer, intent(in) :: task, etype
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(:,:)
    type(material_t), intent(in) :: mat
    type(element_out_t), intent(inout) :: out
    real(dp), intent(in), optional :: ul(:,:), hist_old(:,:)
    real(dp), intent(out), optional :: hist_new(:,:)
    logical, intent(in), optional :: mean
    real(dp), allocatable :: dnx(:,:,:), dvol(:), h0(:,:), h1(:,:)
    real(dp) :: d(3, 3), d6(6, 6)
    integer :: nen, nh, ndm
    logical :: k3
    nen = shp%nen
    out%ierr = 0
    nh = mat%law%nhist
    k3 = element_kind_kernel(etype) == KERNEL_SOLID3D
    ndm = merge(3, 2, k3)
    if (present(hist_old)) then
      h0 = hist_old
    else
      allocate(h0(nh, shp%ngp), source=0.0_dp)
    end if
    select case (task)
    case (TASK_MASS)
      call fit(out%s, nen, nen)
      if (k3) then
        call solid3d_mass(nen, shp, xl, mat%density, out%s, out%scalar, out%ierr)
      else
        call solid2d_mass(nen, shp, xl, mat%density, unit_thickness, out%s, out%scalar, out%ierr)
      end if
    case (TASK_STIFFNESS)
      call fit(out%s, ndm*nen, ndm*nen)
      if (k3) then
        call mat%law%tangent_3d(d6)
        call solid3d_stiffness(nen, shp, xl, d6, out%s, out%ierr)
      else
        call mat%law%tangent_2d(d)
        call solid2d_stiffness(nen, shp, xl, d, unit_thickness, out%s, out%ierr)
      end if
    case (TASK_FORCE)
      call fit(out%p, ndm, nen)
      allocate(dnx(ndm, nen, shp%ngp), dvol(shp%ngp), h1(nh, shp%ngp))
      call element_geometry(etype, shp, xl, dnx, dvol, out%ierr)
      if (out%ierr /= 0) return
      call element_force(etype, nen, shp%ngp, dnx, dvol, ul, mat%law, h0, h1, out%p, &
          out%scalar, out%ierr, mean)
      if (present(hist_new)) hist_new = h1
    case (TASK_STRESS)
      call fit(out%sig, 6, shp%ngp)
      call fit(out%eps, 6, shp%ngp)
      if (k3) then
        call solid3d_stress(nen, shp, xl, ul, mat%law, h0, out%sig, out%ierr, out%eps, mean)
      else
        call solid2d_stress(nen, shp, xl, ul, mat%law, h0, out%sig, out%ierr, out%eps, mean)
      end if
    case (TASK_JACOBIAN)
      if (k3) then
        call solid3d_min_detj(nen, shp, xl, out%scalar, out%ierr)
      else
        call solid2d_min_detj(nen, shp, xl, out%scalar, out%ierr)
      end if
    case (TASK_ROTATION)
      if (k3) then
        call solid3d_rotation(nen, shp, xl, ul, out%scalar, out%ierr)
      else
        call solid2d_rotation(nen, shp, xl, ul, out%scalar, out%ierr)
      end if
    end select
  end subroutine element_routine

  !> Allocates a(n1, n2) unless it has that shape already.
  subroutine fit(a, n1, n2)
    real(dp), allocatable, intent(inout) :: a(:,:)
    integer, intent(in) :: n1, n2
    if (allocated(a)) then
      if (size(a, 1) == n1 .and. size(a, 2) == n2) return
      deallocate(a)
    end if
    allocate(a(n1, n2))
  end subroutine fit

  !> Geometry of an element for its internal force, computed once: Cartesian derivatives
  !! dnx(ndm, nen, ngp) and volume weights dvol(ngp); ierr: 0 or the first point with
  !! det J <= 0.
  subroutine element_geometry(etype, shp, xl, dnx, dvol, ierr)
    integer, intent(in) :: etype
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(:,:)
    real(dp), intent(out) :: dnx(:,:,:), dvol(:)
    integer, intent(out) :: ierr
    select case (element_kind_kernel(etype))
    case (KERNEL_SOLID2D)
      call solid2d_geometry(shp%nen, shp, xl, unit_thickness, dnx, dvol, ierr)
    case (KERNEL_SOLID3D)
      call solid3d_geometry(shp%nen, shp, xl, dnx, dvol, ierr)
    case default
      ierr = -1
    end select
  end subroutine element_geometry

  !> Internal force f(ndm, nen) and stored energy of one element from its stored geometry
  !! (element_geometry), its displacements ul(ndm, nen) and its law;
  !! hist_old/hist_new (nhist, ngp); ierr: 0, or the first point with det F <= 0. Called for
  !! every element in every step of the element-loop force.
  subroutine element_force(etype, nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, &
      energy, ierr, mean)
    integer, intent(in) :: etype, nen, ngp
    integer, intent(out) :: ierr
    real(dp), intent(in) :: dnx(:,:,:), dvol(:), ul(:,:), hist_old(:,:)
    class(law_t), intent(in) :: law
    real(dp), intent(out) :: hist_new(:,:), f(:,:), energy
    logical, intent(in), optional :: mean
    select case (element_kind_kernel(etype))
    case (KERNEL_SOLID2D)
      call solid2d_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, ierr, &
          mean)
    case (KERNEL_SOLID3D)
      call solid3d_force(nen, ngp, dnx, dvol, ul, law, hist_old, hist_new, f, energy, ierr, &
          mean)
    case default
      ierr = -1
    end select
  end subroutine element_force

  !> Kernel of an element type (0 for an unknown code), without copying its description.
  integer function element_kind_kernel(etype)
    integer, intent(in) :: etype
    call fill_table()
    element_kind_kernel = 0
    if (etype >= 1 .and. etype <= ntypes) element_kind_kernel = table(etype)%kernel
  end function element_kind_kernel

end module ictus_elements_library
