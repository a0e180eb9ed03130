!> Power iteration for omega_max against the exact eigenvalues of a lumped spring chain:
!! fixed-free chain of n equal springs k and masses m has
!! omega_j = 2 sqrt(k/m) sin((2j-1) pi/(4n+2)).
program test_timestep
  use ictus_core_kinds, only: dp, pi
  use ictus_solver_sparse, only: graph_t, bsr_t, csr_t, graph_from_elements, bsr_init, &
      bsr_add_element
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init
  use ictus_solver_timestep, only: omega_max_power
  use ictus_solver_domain, only: domain_t
  use ictus_test_solver, only: domain_init_serial
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  call t%start("solver/timestep")
  call test_chain(t)
  call t%finish()
contains

  subroutine test_chain(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: n = 30, nn = n + 1
    integer :: conn(2, n), nen(n), e, i, iters
    real(dp) :: ke(4, 4), omega, exact, stiff, mass
    type(graph_t) :: g
    type(bsr_t) :: k
    type(csr_t) :: m
    type(mass_op_t) :: op
    type(domain_t) :: dom
    logical :: fixed(2, nn)
    stiff = 400.0_dp
    mass = 1.0_dp
    do e = 1, n
      conn(:, e) = [e, e + 1]
    end do
    nen = 2
    call graph_from_elements(nn, nn, n, 2, nen, conn, [(i, i = 1, nn)], g)
    call bsr_init(k, g)
    ! axial spring in x only; y is fixed everywhere
    ke = 0.0_dp
    ke(1, 1) = stiff
    ke(3, 3) = stiff
    ke(1, 3) = -stiff
    ke(3, 1) = -stiff
    do e = 1, n
      call bsr_add_element(k, 2, conn(:, e), ke)
    end do
    fixed = .false.
    fixed(2, :) = .true.
    fixed(1, 1) = .true.
    call domain_init_serial(dom, nn)
    call mass_op_init(op, dom, .false., m, [(mass, i = 1, nn)], fixed)
    call omega_max_power(k, op, dom, omega, iters, 1.0e-10_dp, 20000)
    ! fixed-free chain with unit masses: the end mass also 1 (not 1/2)
    exact = 2.0_dp*sqrt(stiff/mass)*sin(real(2*n - 1, dp)*pi/real(4*n + 2, dp))
    call t%close(omega, exact, 1.0e-4_dp, "omega_max of a fixed-free spring chain")
    call t%true(omega <= exact*(1.0_dp + 1.0e-12_dp), "Rayleigh quotient from below")
  end subroutine test_chain
end program test_timestep
