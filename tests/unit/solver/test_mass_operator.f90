!> The consistent-mass solves (Jacobi PCG, and the Cholesky factor) with fixed dofs against a
!! dense LAPACK solve, and the lumped solve.
program test_mass_operator
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, csr_t, graph_from_elements, csr_init, &
      csr_add_element
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_solve, mass_apply, &
      MASS_SOLVER_CHOLESKY
  use ictus_solver_mass_cholesky, only: cholesky_solver_t
  use ictus_solver_domain, only: domain_t
  use ictus_test_solver, only: domain_init_serial
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  !> Nodes of the chain of the consistent-mass tests.
  integer, parameter :: nch = 20
  call t%start("solver/mass_operator")
  call test_consistent(t)
  call test_cholesky(t)
  call test_lumped(t)
  call t%finish()
contains

  !> A 1D chain of nn = nch linear "elements" with the consistent mass (h/6)[2 1; 1 2]
  !! (sparse m and dense md), its one-rank domain and a load f(2, nn).
  subroutine build_chain(m, md, dom, f)
    integer, parameter :: nn = nch
    type(csr_t), intent(out) :: m
    real(dp), intent(out) :: md(nn, nn), f(2, nn)
    type(domain_t), intent(out) :: dom
    integer :: conn(2, nn - 1), nen(nn - 1), e
    real(dp) :: me(2, 2)
    type(graph_t) :: g
    do e = 1, nn - 1
      conn(:, e) = [e, e + 1]
    end do
    nen = 2
    call graph_from_elements(nn, nn, nn - 1, 2, nen, conn, [(e, e = 1, nn)], g)
    call csr_init(m, g)
    md = 0.0_dp
    do e = 1, nn - 1
      ! element sizes vary, to make the matrix less regular
      me = (1.0_dp + 0.1_dp*e)/6.0_dp*reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
      call csr_add_element(m, 2, conn(:, e), me)
      md(e:e + 1, e:e + 1) = md(e:e + 1, e:e + 1) + me
    end do
    call domain_init_serial(dom, nn)
    do e = 1, nn
      f(:, e) = [sin(real(e, dp)), cos(real(3*e, dp))]
    end do
  end subroutine build_chain

  subroutine test_consistent(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nn = nch
    type(csr_t) :: m
    type(mass_op_t) :: op
    type(domain_t) :: dom
    real(dp) :: md(nn, nn), f(2, nn), a(2, nn), rhs(nn - 1, 2), mdf(nn - 1, nn - 1), mv(2, nn)
    logical :: fixed(2, nn)
    integer :: ipiv(nn - 1), info, i, ierr, iters_tight
    call build_chain(m, md, dom, f)
    fixed = .false.
    fixed(1, 1) = .true.
    fixed(2, nn) = .true.
    call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed)
    a = 0.0_dp
    call mass_solve(op, dom, f, a, ierr)
    call t%equal_int(ierr, 0, "PCG converged")
    iters_tight = op%last_iter
    ! dense reference: component 1 without node 1, component 2 without node nn
    mdf = md(2:nn, 2:nn)
    rhs(:, 1) = f(1, 2:nn)
    call dgesv(nn - 1, 1, mdf, nn - 1, ipiv, rhs(:, 1), nn - 1, info)
    call t%close_abs(maxval(abs(a(1, 2:nn) - rhs(:, 1))), 0.0_dp, 1e-10_dp, &
        "component 1 = dense solve on the free dofs")
    call t%close_abs(abs(a(1, 1)), 0.0_dp, 0.0_dp, "fixed dof has zero acceleration")
    mdf = md(1:nn - 1, 1:nn - 1)
    rhs(:, 2) = f(2, 1:nn - 1)
    call dgesv(nn - 1, 1, mdf, nn - 1, ipiv, rhs(:, 2), nn - 1, info)
    call t%close_abs(maxval(abs(a(2, 1:nn - 1) - rhs(:, 2))), 0.0_dp, 1e-10_dp, &
        "component 2 = dense solve on the free dofs")
    ! warm start from the solution: no iteration needed
    call mass_solve(op, dom, f, a, ierr)
    call t%equal_int(op%last_iter, 0, "warm start from the solution needs no iteration")
    call mass_apply(op, a, mv)
    call t%close_abs(maxval(abs(mv(1, 2:nn) - f(1, 2:nn))), 0.0_dp, 1e-10_dp, "M a = f")
    ! a looser tolerance (MASS TOL=): fewer iterations, and the residual on the free dofs
    ! still below rtol |f| (2-norms over the free dofs)
    call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, 1.0e-4_dp)
    a = 0.0_dp
    call mass_solve(op, dom, f, a, ierr)
    call t%equal_int(ierr, 0, "PCG converged to 1e-4")
    call t%true(op%last_iter < iters_tight, "a looser tolerance takes fewer iterations")
    call mass_apply(op, a, mv)
    mv = (f - mv)*op%free
    call t%true(norm2(mv) <= 1.0e-4_dp*norm2(f*op%free), "residual <= 1e-4 |f|")
    call t%true(norm2(mv) > 1.0e-12_dp*norm2(f*op%free), &
        "residual above 1e-12 |f| (the solve stopped early)")
  end subroutine test_consistent

  !> MASS_SOLVER_CHOLESKY on the same chain: (a) x fixed at node 1, y at node nn (the two
  !! nodes form the dense tail of the factor); (b) both fixed at node 1 and node 7 (no tail).
  !! Each component must equal the dense solve on its free dofs to round-off.
  subroutine test_cholesky(t)
    type(checker_t), intent(inout) :: t
    character(len=*), parameter :: label(2) = ['tail   ', 'no tail']
    integer, parameter :: nn = nch
    real(dp) :: md(nn, nn), f(2, nn), a(2, nn), x(nn), mdf(nn, nn), err
    logical :: fixed(2, nn), free(nn)
    integer :: ipiv(nn), info, i, c, k, nf, ierr, idx(nn)
    type(csr_t) :: m
    type(domain_t) :: dom
    type(mass_op_t) :: op
    call build_chain(m, md, dom, f)
    do k = 1, 2
      fixed = .false.
      if (k == 1) then
        fixed(1, 1) = .true.
        fixed(2, nn) = .true.
      else
        fixed(:, 1) = .true.
        fixed(:, 7) = .true.
      end if
      call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, &
          solver=MASS_SOLVER_CHOLESKY, ierr=ierr)
      call t%equal_int(ierr, 0, trim(label(k))//": factorised")
      select type (s => op%impl)
      type is (cholesky_solver_t)
        call t%equal_int(s%chol%ntail, merge(2, 0, k == 1), trim(label(k))//": tail size")
      class default
        call t%true(.false., trim(label(k))//": the Cholesky solver is taken")
      end select
      a = 0.0_dp
      call mass_solve(op, dom, f, a, ierr)
      do c = 1, 2
        free = .not. fixed(c, :)
        nf = count(free)
        idx(1:nf) = pack([(i, i = 1, nn)], free)
        mdf(1:nf, 1:nf) = md(idx(1:nf), idx(1:nf))
        x(1:nf) = f(c, idx(1:nf))
        call dgesv(nf, 1, mdf, nn, ipiv, x, nn, info)
        err = maxval(abs(a(c, idx(1:nf)) - x(1:nf)))/maxval(abs(x(1:nf)))
        call t%close_abs(err, 0.0_dp, 1.0e-13_dp, trim(label(k))//": component "// &
            char(48 + c)//" = dense solve on its free dofs")
        call t%true(all(a(c, :) == 0.0_dp .or. free), trim(label(k))//": component "// &
            char(48 + c)//" is 0 on its fixed dofs")
      end do
    end do
  end subroutine test_cholesky

  subroutine test_lumped(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: nn = 5
    type(csr_t) :: m
    type(mass_op_t) :: op
    type(domain_t) :: dom
    real(dp) :: f(2, nn), a(2, nn), md(nn)
    logical :: fixed(2, nn)
    integer :: ierr
    md = [1.0_dp, 2.0_dp, 4.0_dp, 0.0_dp, 8.0_dp]
    fixed = .false.
    fixed(2, 3) = .true.
    call domain_init_serial(dom, nn)
    call mass_op_init(op, dom, .false., m, md, fixed)
    f = 1.0_dp
    a = 0.0_dp
    call mass_solve(op, dom, f, a, ierr)
    call t%close(a(1, 2), 0.5_dp, 0.0_dp, "lumped: f/m")
    call t%close(a(2, 3), 0.0_dp, 0.0_dp, "lumped: fixed dof")
    call t%close(a(1, 4), 0.0_dp, 0.0_dp, "lumped: massless node (no element) stays")
  end subroutine test_lumped
end program test_mass_operator
