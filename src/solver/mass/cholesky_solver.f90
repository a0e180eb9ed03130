!> MASS SOLVER=CHOLESKY of the mass operator (ictus_solver_mass_solver): M is factorised once
!! (doc/theory.md §5), sparse Cholesky in METIS nested-dissection order (ictus_solver_cholesky).
!! Every rank holds the factor of the whole M and solves the whole system after an allgather
!! of f (ictus_solver_mass_gathered), so the solution is the same bits on any number of
!! ranks; the memory of the factor does not shrink with more ranks.
module ictus_solver_mass_cholesky
  use ictus_core_kinds, only: dp, i8
  use ictus_core_memory, only: available_memory
  use ictus_core_logger, only: log_info
  use ictus_core_strings, only: str
  use ictus_core_timer, only: wall_time
  use ictus_parallel_env, only: allreduce_max, env_node_size
  use ictus_parallel_partition, only: nested_dissection
  use ictus_solver_cholesky, only: chol_t, chol_analyse, chol_factor, chol_solve, tail_order
  use ictus_solver_sparse, only: csr_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t, consistent_solver_t, &
      consistent_setup
  use ictus_solver_mass_gathered, only: gathered_mass_t, gathered_t, gather_mass, &
      gathered_setup, gathered_loads
  implicit none
  private
  public :: cholesky_init, cholesky_solver_t

  !> Largest dense tail of the Cholesky factor (dofs kept in one component only); beyond it
  !! each component gets a factor of its own.
  integer, parameter :: max_tail = 4000

  !> The factor(s) of the whole M and the factor of each component (fac, one entry per
  !! component: 2 in 2D, 3 in 3D), the pivot of every gathered node (gpiv) and of every owned
  !! node (opiv), the solve's work (max_rows, components) and the gathered loads and solution
  !! (g).
  type, extends(consistent_solver_t) :: cholesky_solver_t
    type(chol_t) :: chol
    integer, allocatable :: fac(:)
    integer, allocatable :: gpiv(:), opiv(:)
    real(dp), allocatable :: xl(:,:)
    type(gathered_t) :: g
  contains
    procedure :: solve => cholesky_solve
    procedure :: report => cholesky_report
  end type cholesky_solver_t

contains

  !> The Cholesky solver of the consistent mass m (this rank's rows) with the dofs
  !! `fixed(nd, nlocal)` (nd = 2 or 3 components); gm is the gathered mass, made here unless another solver's set-up
  !! made it. err = 1 with `msg` when the factor cannot be made (`cholesky_setup`).
  subroutine cholesky_init(s, c, dom, m, fixed, gm, err, msg)
    class(mass_solver_t), allocatable, intent(out) :: s
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(in) :: dom
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    type(gathered_mass_t), intent(inout) :: gm
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    type(cholesky_solver_t), allocatable :: t
    allocate(t)
    call consistent_setup(t, c, m, fixed)
    call gather_mass(gm, c, dom, m, fixed)
    call cholesky_setup(t, c, dom, gm, err, msg)
    call move_alloc(t, s)
  end subroutine cholesky_init

  !> The Cholesky factor of the whole consistent mass gm on every rank, ordered by METIS
  !! nested dissection and factorised. The components share one factor when their kept
  !! dofs are the same, else get one per set of kept dofs (`factor_of_component`); in 2D
  !! two sets that differ on at most max_tail nodes share the factor up to a dense tail.
  !! err = 1 with `msg` when METIS fails, M is not positive definite or memory runs out.
  subroutine cholesky_setup(s, c, dom, gm, err, msg)
    type(cholesky_solver_t), intent(inout) :: s
    type(mass_core_t), intent(in) :: c
    type(domain_t), intent(in) :: dom
    type(gathered_mass_t), intent(in) :: gm
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    integer, allocatable :: order(:), rp_aug(:), col_aug(:)
    integer :: nn, ng, i, q, c2, ntail, nd, nfac, f
    integer(i8) :: stored, need, avail
    real(dp) :: t0, mem(2)
    associate (row_ptr => gm%row_ptr, col => gm%col, val => gm%val, keep => gm%keep)
      err = 0
      nn = c%nn
      ng = c%nglobal
      t0 = wall_time()
      ! dofs kept in one component only (e.g. a roller edge) are eliminated last, as one dense
      ! tail: the factor is shared up to there (ictus_solver_cholesky, chol_t%ntail)
      nd = size(keep, 2)
      ntail = 0
      if (nd == 2) ntail = count(keep(:, 1) .neqv. keep(:, 2))
      s%fac = factor_of_component(keep)
      if (ntail > 0 .and. ntail <= max_tail) s%fac = 1
      nfac = maxval(s%fac)
      if (ntail > max_tail .or. ntail == 0) then
        allocate(order(ng))
        call nested_dissection(ng, row_ptr, col, order, err)
        if (err == 0) call chol_analyse(s%chol, ng, row_ptr, col, order, nfac, err)
      else
        call tail_order(ng, row_ptr, col, keep(:, 1) .neqv. keep(:, 2), order, rp_aug, col_aug, &
            err)
        if (err == 0) call chol_analyse(s%chol, ng, rp_aug, col_aug, order, 1, err, ntail)
      end if
      if (err /= 0) then
        msg = 'the mass matrix could not be ordered for its Cholesky factor (METIS failed or '// &
            'the factor has too many rows to index)'
        return
      end if
      ! memory: the factor, the update stack and the largest update matrix, on every rank of
      ! the node; refused before allocating when it does not fit (the same decision on all ranks)
      need = 8*(s%chol%val_ptr(s%chol%nsup + 1)*nfac + s%chol%stack_size + &
          s%chol%w_size + int(s%chol%ntail, i8)**2)
      mem(1) = real(need, dp)*env_node_size()
      mem(2) = -huge(1.0_dp)
      avail = available_memory()
      if (avail >= 0) mem(2) = -real(avail, dp)
      call allreduce_max(mem)
      if (mem(2) > -huge(1.0_dp) .and. mem(1) > -mem(2)) then
        err = 1
        msg = 'the Cholesky factor of the mass matrix needs '//str(real(need, dp)/1.0e6_dp, 4)// &
            ' MB on each of the '//str(env_node_size())//' rank(s) of a node, but '// &
            str(-mem(2)/1.0e6_dp, 4)//' MB are available (ICTUS_MEMORY_LIMIT_MB, /proc/meminfo)'// &
            '; use *DYNAMIC, EXPLICIT, MASS SOLVER=CG (no factor), or fewer ranks per node'
        return
      end if
      if (ntail > 0 .and. ntail <= max_tail) then
        call chol_factor(s%chol, row_ptr, col, val, keep(:, 1) .or. keep(:, 2), 1, err, keep)
      else
        do f = 1, nfac
          c2 = findloc(s%fac, f, 1)
          call chol_factor(s%chol, row_ptr, col, val, keep(:, c2), f, err)
          if (err /= 0) exit
        end do
      end if
      if (err == -1) then
        msg = 'not enough memory for the Cholesky factor of the mass matrix ('// &
            str(real(s%chol%nnz, dp)*8.0e-9_dp*nfac, 3)//' GB per rank); use '// &
            '*DYNAMIC, EXPLICIT, MASS SOLVER=CG'
        err = 1
        return
      else if (err > 0) then
        msg = 'the mass matrix is not positive definite at node '//str(err)
        err = 1
        return
      end if
      ! pivots of the gathered nodes and of the owned nodes; work arrays of the solve
      allocate(s%gpiv(ng), s%opiv(nn))
      do q = 1, ng
        s%gpiv(q) = s%chol%inv(gm%gid(q))
      end do
      do i = 1, nn
        s%opiv(i) = s%chol%inv(dom%halo%gid(i))
      end do
      call gathered_setup(s%g, c, dom, gm%cnt)
      allocate(s%xl(s%chol%max_rows, nd))
      stored = size(s%chol%val, kind=i8)
      if (allocated(s%chol%tail2)) stored = stored + size(s%chol%tail2, kind=i8)
      call log_info('consistent mass: Cholesky factor of '//str(ng)//' rows in '// &
          str(s%chol%nsup)//' supernodes, '//str(s%chol%nnz)//' non-zeros, '// &
          str(s%chol%ntail)//' rows in the dense tail, '//str(nfac)//' factor(s) for '// &
          str(nd)//' components, '//str(real(stored, dp)*8.0e-6_dp, 4)//' MB stored on '// &
          'every rank, '//str(s%chol%flops*nfac, 3)//' flops, '//str(wall_time() - t0, 3)//' s')
    end associate
  end subroutine cholesky_setup

  !> f on the free dofs of every rank's nodes to every rank, solve, take the owned rows.
  subroutine cholesky_solve(self, c, dom, f, a, ierr)
    class(cholesky_solver_t), intent(inout) :: self
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    integer :: q, i, nd
    ierr = 0
    call gathered_loads(self%g, c, f)
    nd = size(self%fac)
    do q = 1, c%nglobal
      self%g%x(:, self%gpiv(q)) = self%g%fall(nd*(q - 1) + 1:nd*q)
    end do
    call chol_solve(self%chol, self%fac, self%g%x, self%xl)
    do i = 1, c%nn
      a(:, i) = self%g%x(:, self%opiv(i))
    end do
  end subroutine cholesky_solve

  !> The factor of each component (columns of keep: the kept dofs of the gathered nodes):
  !! components with the same kept dofs share one, numbered 1, 2, ... in component order.
  pure function factor_of_component(keep) result(fac)
    logical, intent(in) :: keep(:,:)
    integer :: fac(size(keep, 2))
    integer :: c, b
    do c = 1, size(keep, 2)
      fac(c) = maxval([0, fac(1:c - 1)]) + 1
      do b = 1, c - 1
        if (all(keep(:, b) .eqv. keep(:, c))) then
          fac(c) = fac(b)
          exit
        end if
      end do
    end do
  end function factor_of_component

  function cholesky_report(self, c) result(line)
    class(cholesky_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    character(len=:), allocatable :: line
    line = 'consistent mass: '//str(c%n_solves)//' solves with the Cholesky factor'
  end function cholesky_report
end module ictus_solver_mass_cholesky
