!> Finite strain through the element routine (doc/theory.md §2), every element type and law:
!! - objectivity: the total-Lagrangian internal force of u = (R(theta) - I) X vanishes, to
!!   1e-12 of |K_e| |X|, for theta up to 2 pi (St. Venant-Kirchhoff, neo-Hookean, J2);
!! - homogeneous deformation: u = (F - I) X on a distorted element (curved Q8/Q9 sides, a
!!   rational quarter-annulus NURBS element) gives at every quadrature point the closed-form
!!   Cauchy stress: sigma = F S F^T / J with S = lambda tr(E) I + 2 mu E (SVK), and
!!   sigma = (2 C10/J) dev(bbar) + (2/D1)(J - 1) I (neo-Hookean), written out here; J2 on its
!!   elastic branch and after yield against its point routine (closed forms of J2 are in
!!   test_laws; here the element must reproduce F exactly at every point).
!! Both hold with the mean dilatation (F-bar) too: a rotation keeps J = 1 and a homogeneous F
!! its own mean. With it, the force must still be the variation of the element's energy
!! (doc/theory.md §2.1): f_a against central differences of the energy in u_a, for SVK, the
!! neo-Hookean and linear elasticity in small strain (B-bar), on a non-homogeneous field.
program test_finite_strain
  use ictus_core_kinds, only: dp, pi
  use ictus_elements_types, only: ETYPE_Q4, ETYPE_Q8, ETYPE_Q9, ETYPE_IGA, elem_shape_t, &
      TASK_FORCE, TASK_STIFFNESS, TASK_STRESS
  use ictus_elements_library, only: element_shape_data, element_routine, element_out_t, &
      etype_name
  use ictus_elements_iga, only: iga_shape_data
  use ictus_geometry_patch, only: patch_t, patch_build_elements
  use ictus_materials_law, only: kinematics_t, ANALYSIS_PLANE_STRAIN
  use ictus_materials_material, only: material_t, material_make_law
  use ictus_test_check, only: checker_t
  use ictus_test_elements, only: svk_cauchy
  implicit none
  type(checker_t) :: t
  type(material_t) :: mats(3), lin
  character(len=12), parameter :: names(3) = [character(len=12) :: 'SVK', 'neo-Hookean', 'J2']
  type(kinematics_t), parameter :: finite = kinematics_t(ANALYSIS_PLANE_STRAIN, .true.)
  real(dp), parameter :: e_mod = 1000.0_dp, nu = 0.3_dp, c10 = 25.0_dp, d1 = 0.02_dp
  integer :: k, et, im
  logical :: mean_on = .false.
  call t%start("elements/finite_strain")
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], finite, mats(1)%law)
  call material_make_law('NEO HOOKE', [c10, d1], finite, mats(2)%law)
  call material_make_law('J2', [e_mod, nu, 5.0_dp, 0.0_dp, 105.0_dp, 1.0_dp], finite, mats(3)%law)
  call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(), lin%law)
  mats%density = 1.0_dp
  lin%density = 1.0_dp
  do im = 1, 2
    mean_on = im == 2
    do et = ETYPE_Q4, ETYPE_IGA
      do k = 1, 3
        call case_element(t, et, k)
      end do
    end do
  end do
  do et = ETYPE_Q4, ETYPE_IGA
    call case_variation(t, et, mats(1), 'SVK')
    call case_variation(t, et, mats(2), 'neo-Hookean')
    call case_variation(t, et, lin, 'small-strain elastic (B-bar)')
  end do
  call t%finish()

contains

  !> Node coordinates and shape data of a distorted element of type et.
  subroutine element_of(et, xl, shp)
    integer, intent(in) :: et
    real(dp), allocatable, intent(out) :: xl(:,:)
    type(elem_shape_t), intent(out) :: shp
    real(dp), parameter :: c(2, 9) = reshape([0.0_dp, 0.0_dp, 1.2_dp, 0.1_dp, 1.3_dp, 1.1_dp, &
        -0.1_dp, 0.9_dp, 0.62_dp, 0.02_dp, 1.3_dp, 0.55_dp, 0.6_dp, 1.05_dp, -0.02_dp, &
        0.45_dp, 0.6_dp, 0.52_dp], [2, 9])
    type(patch_t) :: q
    real(dp) :: cp(3, 9), kn(6), r, w
    integer :: i, j
    if (et /= ETYPE_IGA) then
      call element_shape_data(et, 3, shp)
      xl = c(:, 1:shp%nen)
      return
    end if
    ! a quarter annulus 1 <= r <= 2, direction 1 radial, direction 2 the exact arc
    kn = [0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
    do j = 1, 3
      do i = 1, 3
        r = 1.0_dp + 0.5_dp*real(i - 1, dp)
        w = merge(sqrt(0.5_dp), 1.0_dp, j == 2)
        cp(:, i + 3*(j - 1)) = [r*merge(1.0_dp, 0.0_dp, j < 3), r*merge(1.0_dp, 0.0_dp, j > 1), w]
      end do
    end do
    call q%init('ARC', [2, 2], [3, 3], kn, kn, cp)
    call patch_build_elements(q)
    call iga_shape_data(q%p, q%c1(:, :, 1), q%c2(:, :, 1), q%cp(3, q%ien(:, 1)), [3, 3], shp)
    xl = q%cp(1:2, q%ien(:, 1))
  end subroutine element_of

  subroutine case_element(t, et, k)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, k
    type(elem_shape_t) :: shp
    type(element_out_t) :: out, kout
    real(dp), allocatable :: xl(:,:), ul(:,:), h0(:,:), h1(:,:)
    real(dp) :: r(2, 2), worst, scale
    integer :: a, j
    character(len=:), allocatable :: tag
    tag = trim(etype_name(et))//', '//trim(names(k))
    if (mean_on) tag = tag//', mean dilatation'
    call element_of(et, xl, shp)
    allocate(ul(2, shp%nen), h0(mats(k)%law%nhist, shp%ngp), h1(mats(k)%law%nhist, shp%ngp))
    h0 = 0.0_dp
    call element_routine(TASK_STIFFNESS, et, shp, xl, lin, kout)
    scale = maxval(abs(kout%s))*maxval(abs(xl))
    worst = 0.0_dp
    do j = 1, 8
      r = rotation(2.0_dp*pi*real(j, dp)/8.0_dp + 0.05_dp)
      do a = 1, shp%nen
        ul(:, a) = matmul(r, xl(:, a)) - xl(:, a)
      end do
      call element_routine(TASK_FORCE, et, shp, xl, mats(k), out, ul, h0, h1, mean_on)
      worst = max(worst, maxval(abs(out%p)))
    end do
    call t%close_abs(worst, 0.0_dp, 1.0e-12_dp*scale, tag//': f_int of a rigid rotation = 0')
    if (k /= 3) then
      call case_homogeneous(t, et, k, shp, xl, reshape([1.3_dp, -0.1_dp, 0.4_dp, 0.8_dp], &
          [2, 2]), tag//': homogeneous F, closed-form stress at every point')
    else
      ! J2 on its elastic branch, then after yield
      call case_homogeneous(t, et, k, shp, xl, reshape([1.004_dp, -0.001_dp, 0.002_dp, &
          0.997_dp], [2, 2]), tag//': homogeneous F, closed-form stress at every point')
      call case_homogeneous(t, et, k, shp, xl, reshape([1.05_dp, 0.01_dp, 0.0_dp, 1.0_dp], &
          [2, 2]), tag//' after yield: homogeneous F, the stress of the point routine at '// &
          'every point')
    end if
  end subroutine case_element

  !> u = (F - I) X on the element: the stress at every point against closed_form(F).
  subroutine case_homogeneous(t, et, k, shp, xl, f, label)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et, k
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(:,:), f(2, 2)
    character(len=*), intent(in) :: label
    type(element_out_t) :: out
    real(dp) :: ul(2, shp%nen), h0(mats(k)%law%nhist, shp%ngp), sig_want(6), err
    integer :: a, g
    h0 = 0.0_dp
    do a = 1, shp%nen
      ul(:, a) = matmul(f, xl(:, a)) - xl(:, a)
    end do
    call element_routine(TASK_STRESS, et, shp, xl, mats(k), out, ul, h0, mean=mean_on)
    call closed_form(k, f, sig_want)
    err = 0.0_dp
    do g = 1, shp%ngp
      err = max(err, maxval(abs(out%sig(:, g) - sig_want)))
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-10_dp*maxval(abs(sig_want)), label)
  end subroutine case_homogeneous

  !> With the mean dilatation, f_a = dE/du_a: the force of a non-homogeneous field against
  !! central differences of the element's energy (step 1e-6, error O(1e-12) relative).
  subroutine case_variation(t, et, mat, name)
    type(checker_t), intent(inout) :: t
    integer, intent(in) :: et
    type(material_t), intent(in) :: mat
    character(len=*), intent(in) :: name
    type(elem_shape_t) :: shp
    type(element_out_t) :: out
    real(dp), allocatable :: xl(:,:), ul(:,:), up(:,:), h0(:,:), h1(:,:)
    real(dp) :: ep, em, err, h
    integer :: a, i
    call element_of(et, xl, shp)
    allocate(ul(2, shp%nen), h0(0, shp%ngp), h1(0, shp%ngp))
    do a = 1, shp%nen
      ul(:, a) = 0.08_dp*[sin(3.0_dp*xl(1, a) + xl(2, a)), cos(2.0_dp*xl(2, a) - xl(1, a))]
    end do
    call element_routine(TASK_FORCE, et, shp, xl, mat, out, ul, h0, h1, .true.)
    h = 1.0e-6_dp
    err = 0.0_dp
    do a = 1, shp%nen
      do i = 1, 2
        up = ul
        up(i, a) = ul(i, a) + h
        ep = energy_of(et, shp, xl, mat, up)
        up(i, a) = ul(i, a) - h
        em = energy_of(et, shp, xl, mat, up)
        err = max(err, abs(out%p(i, a) - (ep - em)/(2.0_dp*h)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-6_dp*maxval(abs(out%p)), trim(etype_name(et))//', '// &
        name//', mean dilatation: f_a = dE/du_a (central differences)')
  end subroutine case_variation

  !> The energy of the mean-dilatation element at displacements u.
  real(dp) function energy_of(et, shp, xl, mat, u)
    integer, intent(in) :: et
    type(elem_shape_t), intent(in) :: shp
    real(dp), intent(in) :: xl(:,:), u(:,:)
    type(material_t), intent(in) :: mat
    type(element_out_t) :: o
    real(dp) :: h0(0, shp%ngp), h1(0, shp%ngp)
    call element_routine(TASK_FORCE, et, shp, xl, mat, o, u, h0, h1, .true.)
    energy_of = o%scalar
  end function energy_of

  !> The Cauchy stress of law k at the plane-strain F (2 x 2 in-plane part, F_33 = 1).
  subroutine closed_form(k, f2, sig)
    integer, intent(in) :: k
    real(dp), intent(in) :: f2(2, 2)
    real(dp), intent(out) :: sig(6)
    real(dp) :: f(3, 3), s(3, 3), b(3, 3), detf, lam, mu, tr, w, g(3, 3), h(8), h1(8)
    integer :: i
    f = 0.0_dp
    f(1:2, 1:2) = f2
    f(3, 3) = 1.0_dp
    detf = f2(1, 1)*f2(2, 2) - f2(1, 2)*f2(2, 1)
    select case (k)
    case (1)
      mu = e_mod/(2.0_dp*(1.0_dp + nu))
      lam = e_mod*nu/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu))
      s = svk_cauchy(lam, mu, f, detf)
    case (2)
      b = matmul(f, transpose(f))*detf**(-2.0_dp/3.0_dp)
      tr = (b(1, 1) + b(2, 2) + b(3, 3))/3.0_dp
      s = (2.0_dp*c10/detf)*b
      do i = 1, 3
        s(i, i) = s(i, i) - (2.0_dp*c10/detf)*tr + (2.0_dp/d1)*(detf - 1.0_dp)
      end do
    case default
      g = f
      do i = 1, 3
        g(i, i) = g(i, i) - 1.0_dp
      end do
      h = 0.0_dp
      call mats(3)%law%stress(g, h, h1, sig, w)
      return
    end select
    sig = [s(1, 1), s(2, 2), s(3, 3), s(1, 2), s(2, 3), s(3, 1)]
  end subroutine closed_form

  pure function rotation(th) result(r)
    real(dp), intent(in) :: th
    real(dp) :: r(2, 2)
    r = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
  end function rotation
end program test_finite_strain
