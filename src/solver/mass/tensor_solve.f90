!> The solve of MASS SOLVER=KRONECKER (ictus_solver_tensor_types) block by block, into x or
!! folded into the step; each block by the sweeps of its kind: tensor_kernels.inc (direct
!! blocks, loads and stores of lattice columns) and tensor_q8.inc (serendipity blocks). The
!! two files are included here rather than modules of their own so that the compiler sees the
!! whole solve in one unit, inlining and specialising across the sweeps. Allocates nothing.
module ictus_solver_tensor_solve
  use ictus_core_kinds, only: dp
  use ictus_solver_tensor_types, only: band_t, cond_t, comp_t, tblock_t, tensor_mass_t, &
      TENSOR_DIRECT, TENSOR_SERENDIPITY, col_block
  implicit none
  private
  public :: tensor_mass_solve, tensor_mass_step, base_solve, nodal_value

contains

  !> x = M^-1 f on the solved dofs of every block (0 on fixed dofs and outside the blocks);
  !! f and x are (2, ng) in the node numbering of the blocks (a flat gathered vector of
  !! pairs will do). Allocates nothing.
  !!
  !! Both components go through each pass together. Passes over the lattice: Kronecker
  !! blocks 3 (load with the forward elimination along direction 2, the direction-1 solves
  !! of col_block columns at a time inside it; back substitution; store with the point
  !! correction), Q8 blocks 6 (load in the hierarchical basis; forward; back with the
  !! B x B values picked out; forward from g - E mu; back; store with the change to nodal
  !! values and the point correction).
  subroutine tensor_mass_solve(tm, f, x)
    type(tensor_mass_t), intent(inout) :: tm
    real(dp), intent(in) :: f(2, *)
    real(dp), intent(inout) :: x(2, *)
    integer :: ib, k
    do k = 1, size(tm%outside)
      x(:, tm%outside(k)) = 0.0_dp
    end do
    do ib = 1, tm%nblocks
      call solve_block(tm%b(ib), f, x=x)
    end do
  end subroutine tensor_mass_solve

  !> The velocity and displacement updates of a step with the solve folded in: with
  !! kf = K u (2, *), v <- v - dt M^-1 kf and u_next <- u + dt v on every node, the same
  !! bits as a = tensor_mass_solve(-kf), v = v + dt a, u_next = u + dt v (the solve is
  !! linear and rounding is symmetric in the sign). Saves the passes over a. Allocates
  !! nothing.
  subroutine tensor_mass_step(tm, kf, dt, u, v, u_next)
    type(tensor_mass_t), intent(inout) :: tm
    real(dp), intent(in) :: kf(2, *), dt, u(2, *)
    real(dp), intent(inout) :: v(2, *), u_next(2, *)
    integer :: ib, k, l
    do k = 1, size(tm%outside)
      l = tm%outside(k)
      u_next(:, l) = u(:, l) + dt*v(:, l)
    end do
    do ib = 1, tm%nblocks
      call solve_block(tm%b(ib), kf, dt=dt, u=u, v=v, u_next=u_next)
    end do
  end subroutine tensor_mass_step

  !> The solve of one block for the loads f, stored into x or (with dt) folded into the
  !! step (`emit_column`); a Q8 block stores each column as its last pass finishes it.
  subroutine solve_block(b, f, x, dt, u, v, u_next)
    type(tblock_t), intent(inout) :: b
    real(dp), intent(in) :: f(2, *)
    real(dp), intent(inout), optional :: x(2, *)
    real(dp), intent(in), optional :: dt, u(2, *)
    real(dp), intent(inout), optional :: v(2, *), u_next(2, *)
    if (b%kind == TENSOR_DIRECT) then
      call base_solve(b, 1, 2, f)
      call store(b, x, dt, u, v, u_next)
    else
      call q8_front(b, 1, 2, f)
      call q8_backward_store(b, x, dt, u, v, u_next)
    end if
  end subroutine solve_block

  !> b%z(:, :, c1:c2) <- the solve of those components without the point correction, for
  !! the nodal loads f (both components: c1 = 1, c2 = 2) or for a unit load at lattice point
  !! `unit`: the Kronecker inverse, or for Q8 the capacitance solve in the hierarchical basis
  !! (module header), which leaves hierarchical coefficients in z (`store` and `nodal_value`
  !! change them to nodal values).
  subroutine base_solve(b, c1, c2, f, unit)
    type(tblock_t), intent(inout) :: b
    integer, intent(in) :: c1, c2
    real(dp), intent(in), optional :: f(2, *)
    integer, intent(in), optional :: unit(2)
    if (b%kind == TENSOR_DIRECT) then
      call forward(b, c1, c2, f, unit)
      call backward(b, c1, c2)
      return
    end if
    call q8_front(b, c1, c2, f, unit)
    call q8_backward(b, c1, c2)
  end subroutine base_solve

  include 'tensor_kernels.inc'

  include 'tensor_q8.inc'
end module ictus_solver_tensor_solve
