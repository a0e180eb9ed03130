!> The amplitudes and the pressure kernel of the loads (doc/theory.md §4a) against closed forms:
!! TABULAR and SMOOTH STEP values at and between the points, constant outside them, the smooth
!! step's zero slope at its points; the consistent nodal forces of a uniform pressure on a
!! 3-node edge (p L (1, 4, 1)/6, pushing into the body) and on a 2-node edge, reference and
!! current (follower) geometry, and only on owned rows.
program test_loads
  use ictus_core_kinds, only: dp
  use ictus_solver_amplitude, only: amplitude_t, amp_value, amp_factor, AMP_TABULAR, &
      AMP_SMOOTH_STEP
  use ictus_contact_surface, only: contact_surface_t, surface_init, SEG_LAGRANGE
  use ictus_solver_pressure, only: pressure_rt_t, pressure_setup, pressure_add
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/loads")
  call test_amplitudes(t)
  call test_pressure(t)
  call t%finish()
contains

  subroutine test_amplitudes(t)
    type(checker_t), intent(inout) :: t
    type(amplitude_t) :: a(2)
    real(dp) :: xi, h
    a(1)%kind = AMP_TABULAR
    a(1)%t = [1.0_dp, 3.0_dp, 4.0_dp]
    a(1)%a = [2.0_dp, -2.0_dp, 5.0_dp]
    a(2) = a(1)
    a(2)%kind = AMP_SMOOTH_STEP
    call t%close(amp_value(a(1), 0.0_dp), 2.0_dp, 0.0_dp, 'tabular: a_1 before the first point')
    call t%close(amp_value(a(1), 9.0_dp), 5.0_dp, 0.0_dp, 'tabular: a_m after the last point')
    call t%close(amp_value(a(1), 3.0_dp), -2.0_dp, 0.0_dp, 'tabular: the value at a point')
    call t%close(amp_value(a(1), 1.5_dp), 1.0_dp, 1.0e-15_dp, 'tabular: linear between points')
    call t%close(amp_value(a(1), 3.5_dp), 1.5_dp, 1.0e-15_dp, 'tabular: second interval')
    xi = 0.25_dp
    call t%close(amp_value(a(2), 1.5_dp), 2.0_dp - 4.0_dp*xi**3*(10.0_dp - 15.0_dp*xi + &
        6.0_dp*xi**2), 1.0e-15_dp, 'smooth step: xi^3 (10 - 15 xi + 6 xi^2) at xi = 1/4')
    call t%close(amp_value(a(2), 2.0_dp), 0.0_dp, 1.0e-15_dp, 'smooth step: the middle value')
    h = 1.0e-4_dp
    call t%true(abs(amp_value(a(2), 3.0_dp + h) - amp_value(a(2), 3.0_dp)) < 1.0e-9_dp, &
        'smooth step: zero slope after a point (O(h^3))')
    call t%true(abs(amp_value(a(2), 3.0_dp - h) - amp_value(a(2), 3.0_dp)) < 1.0e-9_dp, &
        'smooth step: zero slope before a point (O(h^3))')
    call t%close(amp_factor(a, 0, 7.0_dp), 1.0_dp, 0.0_dp, 'no amplitude: factor 1')
    call t%close(amp_factor(a, 2, 9.0_dp), 5.0_dp, 0.0_dp, 'amplitude 2 after its last point')
  end subroutine test_amplitudes

  subroutine test_pressure(t)
    type(checker_t), intent(inout) :: t
    type(contact_surface_t) :: s
    type(pressure_rt_t) :: pr
    real(dp) :: x0(2, 5), u(2, 5), f(2, 5)
    integer :: g2l(5)
    ! a 3-node edge (nodes 1, 2, 3) along +x, body on its left (y > 0), and a 2-node edge
    ! (nodes 3, 4) from (2, 0) up to (2, 1): body on its left (x < 2)
    x0 = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, 2.0_dp, 1.0_dp, &
        9.0_dp, 9.0_dp], [2, 5])
    call surface_init(s, 'S', [SEG_LAGRANGE, SEG_LAGRANGE], [3, 2], &
        reshape([1, 2, 3, 3, 4, 0], [3, 2]), x0)
    g2l = [1, 2, 3, 4, 5]
    call pressure_setup(s, 3.0_dp, 0, g2l, 5, pr)
    call t%equal_int(pr%nseg, 2, 'both segments touch owned nodes')
    u = 0.0_dp
    f = 0.0_dp
    call pressure_add(pr, 1.0_dp, x0, u, .false., 5, f)
    ! edge 1: p L = 6 along +y, split 1 : 4 : 1; edge 2: p L = 3 along -x, split 1 : 1
    call t%close(f(2, 1), 1.0_dp, 1.0e-14_dp, '3-node edge: end node p L/6')
    call t%close(f(2, 2), 4.0_dp, 1.0e-14_dp, '3-node edge: middle node 4 p L/6')
    call t%close(f(2, 3), 1.0_dp, 1.0e-14_dp, '3-node edge: end node p L/6')
    call t%close(f(1, 3), -1.5_dp, 1.0e-14_dp, '2-node edge: p L/2 into the body')
    call t%close(f(1, 4), -1.5_dp, 1.0e-14_dp, '2-node edge: p L/2 into the body')
    call t%close(sum(abs(f(1, 1:2))) + abs(f(2, 4)) + sum(abs(f(:, 5))), 0.0_dp, 1.0e-14_dp, &
        'no force across the edges or on nodes off the surface')
    ! follower: the 2-node edge turned by 90 degrees about node 3 (now from (2, 0) to (1, 0))
    u(:, 4) = [-1.0_dp, -1.0_dp]
    f = 0.0_dp
    call pressure_add(pr, 2.0_dp, x0, u, .true., 5, f)
    call t%close(f(2, 4), -3.0_dp, 1.0e-14_dp, 'follower: the force turns with the edge')
    call t%close(f(1, 4), 0.0_dp, 1.0e-14_dp, 'follower: no force along the old normal')
    ! only owned rows: with nodes 1..2 owned, nothing is added to rows 3..5
    call pressure_setup(s, 3.0_dp, 0, g2l, 2, pr)
    call t%equal_int(pr%nseg, 1, 'one segment touches owned nodes 1, 2')
    f = 0.0_dp
    u = 0.0_dp
    call pressure_add(pr, 1.0_dp, x0, u, .false., 2, f)
    call t%close(f(2, 2), 4.0_dp, 1.0e-14_dp, 'owned row of the touching segment')
    call t%close(sum(abs(f(:, 3:5))), 0.0_dp, 0.0_dp, 'rows of other ranks untouched')
  end subroutine test_pressure
end program test_loads
