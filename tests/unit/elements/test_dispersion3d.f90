!> The highest frequency of free meshes of cubes in 3D against the 1D result
!! (doc/elements3d.md §6a).
!!
!! 1D: a lumped linear bar has omega_max = 2 c/h (the mode of wavelength 2h).
!! 3D, C3D8 lumped (row-sum = HRZ = m/8 per node): on one element the dilatational mode
!! u_A = (xi_A, eta_A, zeta_A) is the highest, omega^2 = 4 E/((1 - 2 nu) rho h^2), i.e.
!! omega h/c_d = 2 sqrt((1 + nu)/(1 - nu)), c_d^2 = E (1 - nu)/((1 + nu)(1 - 2 nu) rho).
!! On a block of n^3 cubes the field u = ((-1)^i, (-1)^j, (-1)^k) at node (i, j, k) is, on
!! each element, (s_x xi_A, s_y eta_A, s_z zeta_A) with signs s = +-1 that depend on the
!! element. At nu = 0 (lambda = 0) the strain energy of such a field does not depend on the
!! signs, so each element's Rayleigh quotient is omega_e^2, and u^T K u = omega_e^2 u^T M u;
!! no mesh mode exceeds the largest element mode: omega_max h/c = 2 for every n, the 1D value.
!! For nu > 0 the signs matter (lambda couples the directions) and the mesh value falls below
!! the element's: measured here at n = 2, 3 (nu = 0.3: 2.156, 2.159 against 2.726 for one
!! element), checked against the element bound; the quadratic hexahedra (HRZ) likewise.
program test_dispersion3d
  use ictus_core_kinds, only: dp
  use ictus_elements_types, only: ETYPE_C3D8, ETYPE_C3D20, ETYPE_C3D27, elem_shape_t, &
      TASK_MASS, TASK_STIFFNESS
  use ictus_elements_library, only: element_shape_data, element_routine, element_out_t, &
      etype_nen
  use ictus_elements_hexahedra, only: hexahedra_node_xi
  use ictus_materials_law, only: kinematics_t, ANALYSIS_3D
  use ictus_materials_material, only: material_t, material_make_law
  use ictus_test_check, only: checker_t
  use ictus_test_elements, only: element_omega_max
  implicit none
  real(dp), parameter :: e_mod = 1000.0_dp, rho = 1.0_dp, h = 0.5_dp
  type(checker_t) :: t
  integer :: n, k
  real(dp) :: nu, w, we, cd
  call t%start("elements/dispersion3d")
  do k = 1, 2
    nu = merge(0.0_dp, 0.3_dp, k == 1)
    cd = sqrt(e_mod*(1.0_dp - nu)/((1.0_dp + nu)*(1.0_dp - 2.0_dp*nu)*rho))
    do n = 1, 3
      w = mesh_omega(ETYPE_C3D8, 2, n, nu, we)
      call t%close(we*h/cd, 2.0_dp*sqrt((1.0_dp + nu)/(1.0_dp - nu)), 1.0e-10_dp, &
          'C3D8 lumped, one cube: omega_max h/c_d = 2 sqrt((1 + nu)/(1 - nu))')
      if (nu == 0.0_dp) then
        call t%close(w*h/cd, 2.0_dp, 1.0e-10_dp, &
            'C3D8 lumped, n^3 cubes, nu = 0: omega_max h/c = 2, the 1D value')
      else
        print '(a, f4.2, a, i1, a, f8.5, a, f8.5)', '  C3D8 lumped, nu = ', nu, ', n = ', n, &
            ': omega_max h/c_d = ', w*h/cd, ', element ', we*h/cd
        call t%true(w <= we*(1.0_dp + 1.0e-12_dp), 'C3D8 lumped: mesh omega_max <= element')
      end if
    end do
    do n = 1, 2
      w = mesh_omega(ETYPE_C3D20, 3, n, nu, we)
      print '(a, f4.2, a, i1, a, f8.5, a, f8.5)', '  C3D20 HRZ, nu = ', nu, ', n = ', n, &
          ': omega_max h/c_d = ', w*h/cd, ', element ', we*h/cd
      call t%true(w <= we*(1.0_dp + 1.0e-12_dp), 'C3D20 HRZ: mesh omega_max <= element')
      w = mesh_omega(ETYPE_C3D27, 3, n, nu, we)
      print '(a, f4.2, a, i1, a, f8.5, a, f8.5)', '  C3D27 HRZ, nu = ', nu, ', n = ', n, &
          ': omega_max h/c_d = ', w*h/cd, ', element ', we*h/cd
      call t%true(w <= we*(1.0_dp + 1.0e-12_dp), 'C3D27 HRZ: mesh omega_max <= element')
    end do
  end do
  call t%finish()

contains

  !> omega_max of a free block of n^3 cubes of side h (type et, Gauss rule ng, HRZ lumped
  !! mass), and we that of one element.
  function mesh_omega(et, ng, n, nu, we) result(w)
    integer, intent(in) :: et, ng, n
    real(dp), intent(in) :: nu
    real(dp), intent(out) :: we
    real(dp) :: w
    type(material_t) :: mat
    type(elem_shape_t) :: shp
    type(element_out_t) :: kout, mout
    real(dp), allocatable :: kg(:,:), mg(:,:), ml(:)
    real(dp) :: xl(3, 27), xa(3)
    integer :: nen, np, nnode, ex, ey, ez, a, b, ix(27), dofs(81), info
    call material_make_law('LINEAR ELASTIC', [e_mod, nu], kinematics_t(ANALYSIS_3D, .false.), &
        mat%law)
    mat%density = rho
    nen = etype_nen(et)
    call element_shape_data(et, ng, shp)
    np = 2*n + 1
    nnode = np**3
    allocate(kg(3*nnode, 3*nnode), mg(nnode, nnode), ml(nen), source=0.0_dp)
    do ez = 0, n - 1
      do ey = 0, n - 1
        do ex = 0, n - 1
          do a = 1, nen
            call hexahedra_node_xi(a, xa)
            ix(a) = (2*ex + 1 + nint(xa(1))) + np*(2*ey + 1 + nint(xa(2))) + &
                np*np*(2*ez + 1 + nint(xa(3))) + 1
            xl(:, a) = h*([ex, ey, ez] + 0.5_dp*(xa + 1.0_dp))
            dofs(3*a - 2:3*a) = 3*(ix(a) - 1) + [1, 2, 3]
          end do
          call element_routine(TASK_STIFFNESS, et, shp, xl(:, 1:nen), mat, kout)
          call element_routine(TASK_MASS, et, shp, xl(:, 1:nen), mat, mout)
          ! HRZ: the diagonal of the consistent mass scaled to the element mass
          ml = [(mout%s(a, a), a = 1, nen)]
          ml = ml*mout%scalar/sum(ml)
          do b = 1, 3*nen
            do a = 1, 3*nen
              kg(dofs(a), dofs(b)) = kg(dofs(a), dofs(b)) + kout%s(a, b)
            end do
          end do
          do a = 1, nen
            mg(ix(a), ix(a)) = mg(ix(a), ix(a)) + ml(a)
          end do
          if (ex + ey + ez == 0) call element_omega_max(nen, kout%s, diag(ml), .true., we, &
              info, ndm=3)
        end do
      end do
    end do
    ! drop the nodes no element uses (the mid nodes of C3D8 blocks)
    call compact(kg, mg, nnode)
    call element_omega_max(size(mg, 1), kg, mg, .true., w, info, ndm=3)
  end function mesh_omega

  pure function diag(v) result(d)
    real(dp), intent(in) :: v(:)
    real(dp) :: d(size(v), size(v))
    integer :: i
    d = 0.0_dp
    do i = 1, size(v)
      d(i, i) = v(i)
    end do
  end function diag

  !> Keeps the nodes with a positive mass (rows and columns of kg with them).
  subroutine compact(kg, mg, nnode)
    real(dp), allocatable, intent(inout) :: kg(:,:), mg(:,:)
    integer, intent(in) :: nnode
    integer, allocatable :: keep(:), dk(:)
    integer :: i
    keep = pack([(i, i = 1, nnode)], [(mg(i, i) > 0.0_dp, i = 1, nnode)])
    dk = [(3*(keep((i + 2)/3) - 1) + mod(i - 1, 3) + 1, i = 1, 3*size(keep))]
    kg = kg(dk, dk)
    mg = mg(keep, keep)
  end subroutine compact
end program test_dispersion3d
