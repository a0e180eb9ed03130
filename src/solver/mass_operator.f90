!> The mass operator of the time loop: a = M^-1 f on the free dofs, and v -> M v.
!!
!! Lumped mass: a division by the nodal mass. Consistent mass, four solvers:
!!
!! * MASS_SOLVER_AUTO (the default of the deck) resolves at set-up to KRONECKER when the model
!!   is made of tensor-product lattices whose mass that solver proves it solves exactly, and
!!   to CHOLESKY otherwise (the log says which, and why).
!! * MASS_SOLVER_KRONECKER: exact solves by 1D banded factors along the lattice directions of
!!   NURBS patches and rectangular Q4/Q8/Q9 grids (ictus_solver_tensor_mass). Like the
!!   Cholesky factor it runs on every rank on the gathered f, so the bits do not depend on
!!   the number of ranks; its memory is a few vectors.
!! * MASS_SOLVER_CHOLESKY: M is factorised once (doc/theory.md §5),
!!   sparse Cholesky in METIS nested-dissection order (ictus_solver_cholesky). Every rank
!!   holds the factor of the whole M and solves the whole system after an allgather of f, so
!!   the solution is the same bits on any number of ranks; the memory of the factor does not
!!   shrink with more ranks.
!! * MASS_SOLVER_CG: a Jacobi-preconditioned conjugate gradient, warm-started from the
!!   caller's previous solution, to the relative residual `rtol`. It runs on this rank's rows;
!!   the search direction's ghost values come by halo exchange and the dot products are
!!   reproducible global sums, so the iterates are the same bits on any number of ranks.
!! * MASS_SOLVER_CORRECTOR: a fixed number k of passes x <- x + D^-1 (f - M x) from
!!   x = D^-1 f, with D the row sums of M (predictor/multi-corrector, doc/theory.md §5.1). This is
!!   not a converged solve but a fixed approximate inverse M_k^-1 = sum_{j=0..k}
!!   (I - D^-1 M)^j D^-1: symmetric, between D^-1 and M^-1 in the Loewner order when M has no
!!   negative entries (then the eigenvalues of D^-1 M lie in (0, 1]), so it is positive
!!   definite, conserves momentum exactly and keeps the stable step between the row-sum and
!!   the consistent one; smooth modes see the error (1 - s)^(k+1) of the mass symbol s
!!   (doc/theory.md §5). Each pass is one product with M after a halo exchange; no global sum.
!!
!! All work arrays are allocated once in `mass_op_init`; a solve allocates nothing.
module ictus_solver_mass_operator
  use ictus_core_kinds, only: dp, i8
  use ictus_parallel_repro, only: repro_dot, repro_sigma, repro_totals, levels
  use ictus_parallel_env, only: allreduce_max, allgather_int, allgatherv_int, allgatherv_real, &
      env_size, env_node_size
  use ictus_parallel_halo, only: halo_exchange
  use ictus_parallel_partition, only: nested_dissection
  use ictus_solver_cholesky, only: chol_t, chol_analyse, chol_factor, chol_solve, tail_order
  use ictus_core_memory, only: alloc_stream, available_memory
  use ictus_core_errors, only: fatal
  use ictus_core_logger, only: log_info
  use ictus_core_strings, only: str
  use ictus_core_timer, only: wall_time
  use ictus_solver_sparse, only: csr_t, csr_matvec, csr_diagonal, csr_row_sums, csr_copy
  use ictus_solver_domain, only: domain_t
  use ictus_solver_model, only: MASS_SOLVER_CG, MASS_SOLVER_CHOLESKY, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO
  use ictus_solver_tensor_mass, only: tensor_layout_t, tensor_mass_t, tensor_mass_setup, &
      tensor_mass_solve, tensor_mass_step, tensor_mass_renumber, tensor_mass_describe
  implicit none
  private
  public :: mass_op_t, mass_op_init, mass_solve, mass_apply, mass_set_added, mass_step, &
      mass_steps_fused, &
      mass_min_entry, MASS_SOLVER_CG, MASS_SOLVER_CHOLESKY, MASS_SOLVER_CORRECTOR, &
      MASS_SOLVER_KRONECKER, MASS_SOLVER_AUTO

  !> Largest dense tail of the Cholesky factor (dofs kept in one component only); beyond it
  !! each component gets a factor of its own.
  integer, parameter :: max_tail = 4000

  type :: mass_op_t
    !> Owned nodes (rows), local nodes (owned + ghost), global nodes.
    integer :: nn = 0
    integer :: nlocal = 0
    integer :: nglobal = 0
    logical :: consistent = .false.
    !> Consistent mass (scalar, acting on both components).
    type(csr_t) :: m
    !> Lumped masses (owned nodes).
    real(dp), allocatable :: m_diag(:)
    !> 1/m on free dofs, 0 on fixed dofs and massless nodes (2, nn); also the preconditioner
    !! (for a consistent mass m is its diagonal, or with the corrector its row sum).
    real(dp), allocatable :: inv_diag(:,:)
    !> 1 on free dofs, 0 on fixed ones (2, nlocal).
    real(dp), allocatable :: free(:,:)
    !> Relative residual tolerance and iteration limit of the conjugate gradient.
    real(dp) :: rtol = 1.0e-12_dp
    !> Largest absolute row sum of M and largest 1/m (global): bounds of the CG's terms.
    real(dp) :: m_inf = 0.0_dp
    real(dp) :: inv_max = 0.0_dp
    integer :: max_iter = 500
    !> Statistics: iterations of the last solve, and summed over all solves.
    integer :: last_iter = 0
    integer :: total_iter = 0
    integer :: n_solves = 0
    !> Work vectors: residual r (2, nn) and M p in q (2, nn), CG only; direction p (2, nlocal:
    !! ghosts by halo), also the corrector's iterate.
    real(dp), allocatable :: r(:,:), p(:,:), q(:,:)
    !> Consistent-mass solver (MASS_SOLVER_*; AUTO is resolved by mass_op_init), and why
    !! the set-up refused a solver (AUTO: why it is not KRONECKER).
    integer :: solver = MASS_SOLVER_CG
    character(len=:), allocatable :: setup_msg
    !> Kronecker solver, and the offset of this rank's owned nodes in the gathered vectors.
    type(tensor_mass_t) :: tm
    integer :: offset = 0
    !> Cholesky: the factor(s) of the whole M, the factor of each component, the rank sizes
    !! of the allgather (2 x owned nodes) and their offsets, the pivot of every gathered node
    !! and of every owned node, the send buffer (2 nn), the gathered f (2 nglobal), the
    !! solution in pivot order (2, nglobal) and the solve's work (max_rows, 2).
    type(chol_t) :: chol
    integer :: fac(2) = 1
    !> Corrector: passes k, the second and third iterates (2, nlocal) next to p, the half
    !! bandwidth of M, and whether two passes share one sweep (no ghosts: one rank).
    integer :: passes = 2
    real(dp), allocatable :: xs(:,:), xt(:,:)
    integer :: bw = 0
    logical :: paired = .false.
    integer, allocatable :: counts(:), displs(:), gpiv(:), opiv(:)
    real(dp), allocatable :: fsend(:), fall(:), x(:,:), xl(:,:)
  end type mass_op_t

contains

  !> Sets up the operator for the rows of `dom`. `m` is used only when `consistent`;
  !! `fixed(2, nlocal)` marks Dirichlet dofs, whose accelerations are zero; `rtol` is the
  !! relative residual at which the conjugate gradient stops (default 1e-12); `solver` is a
  !! MASS_SOLVER_* (default CG); `passes` the corrector's k (default 2). `ierr` (when
  !! present) is 0, or 1 when the Cholesky factor cannot be made (see `cholesky_init`) or the
  !! corrector meets a negative entry of M; without it such a failure is fatal. `layout`
  !! (the model's lattices, ictus_solver_tensor_mass) is needed by MASS_SOLVER_KRONECKER and
  !! AUTO; without it they are refused (AUTO: the Cholesky factor).
  subroutine mass_op_init(op, dom, consistent, m, m_diag, fixed, rtol, solver, ierr, passes, &
      layout)
    type(mass_op_t), intent(out) :: op
    type(domain_t), intent(in) :: dom
    logical, intent(in) :: consistent
    type(csr_t), intent(in) :: m
    real(dp), intent(in) :: m_diag(:)
    logical, intent(in) :: fixed(:,:)
    real(dp), intent(in), optional :: rtol
    integer, intent(in), optional :: solver
    integer, intent(out), optional :: ierr
    integer, intent(in), optional :: passes
    type(tensor_layout_t), intent(in), optional :: layout
    real(dp), allocatable :: d(:), val(:)
    integer, allocatable :: cnt(:), gid(:), row_ptr(:), col(:)
    logical, allocatable :: keep(:,:)
    integer :: i, c, nn, err, e
    character(len=:), allocatable :: msg
    nn = dom%nowned
    op%nn = nn
    op%nlocal = dom%nlocal
    op%nglobal = dom%nn_global
    op%consistent = consistent
    if (present(rtol)) op%rtol = rtol
    if (present(solver)) op%solver = solver
    if (present(passes)) op%passes = passes
    if (present(ierr)) ierr = 0
    op%m_diag = m_diag(1:nn)
    call alloc_stream(op%inv_diag, 2, nn, 0.0_dp)
    call alloc_stream(op%free, 2, dom%nlocal, 0.0_dp)
    allocate(d(nn))
    if (consistent) then
      call csr_copy(op%m, m)
      if (op%solver == MASS_SOLVER_CORRECTOR) then
        call csr_row_sums(m, d)
        call alloc_stream(op%xs, 2, dom%nlocal, 0.0_dp)
        op%paired = dom%nlocal == nn
        if (op%paired .and. op%passes > 2) call alloc_stream(op%xt, 2, dom%nlocal, 0.0_dp)
        do i = 1, nn
          c = m%g%row_ptr(i)
          if (m%g%row_ptr(i + 1) > c) op%bw = max(op%bw, maxval(abs(m%g%col(c: &
              m%g%row_ptr(i + 1) - 1) - i)))
        end do
      else
        call csr_diagonal(m, d)
      end if
      ! residual and product of the conjugate gradient; p is also the corrector's iterate
      if (op%solver == MASS_SOLVER_CG) then
        call alloc_stream(op%r, 2, nn, 0.0_dp)
        call alloc_stream(op%q, 2, nn, 0.0_dp)
      end if
      call alloc_stream(op%p, 2, dom%nlocal, 0.0_dp)
    else
      d = m_diag(1:nn)
    end if
    do i = 1, dom%nlocal
      do c = 1, 2
        op%free(c, i) = merge(0.0_dp, 1.0_dp, fixed(c, i))
      end do
    end do
    do i = 1, nn
      do c = 1, 2
        if (fixed(c, i) .or. .not. d(i) > 0.0_dp) then
          op%free(c, i) = 0.0_dp
          op%inv_diag(c, i) = 0.0_dp
        else
          op%inv_diag(c, i) = 1.0_dp/d(i)
        end if
      end do
    end do
    if (consistent) then
      do i = 1, nn
        op%m_inf = max(op%m_inf, sum(abs(op%m%val(op%m%g%row_ptr(i):op%m%g%row_ptr(i + 1) - 1))))
      end do
      op%inv_max = maxval(op%inv_diag)
      call allreduce_max(op%m_inf)
      call allreduce_max(op%inv_max)
      err = 0
      if (op%solver == MASS_SOLVER_CORRECTOR) then
        if (mass_min_entry(m, nn) < 0.0_dp) then
          err = 1
          msg = 'MASS SOLVER=CORRECTOR needs a mass matrix without negative entries'
        end if
      else if (op%solver /= MASS_SOLVER_CG) then
        call gather_mass(op, dom, d, fixed, cnt, gid, row_ptr, col, val, keep)
        if (op%solver == MASS_SOLVER_KRONECKER .or. op%solver == MASS_SOLVER_AUTO) then
          if (present(layout)) then
            call kronecker_init(op, dom, layout, cnt, gid, row_ptr, col, val, keep, err, msg)
          else
            err = 1
            msg = 'no lattice layout of the model was given'
          end if
          if (err /= 0 .and. op%solver == MASS_SOLVER_AUTO) then
            call log_info('consistent mass: not solved along lattice directions ('//msg// &
                '); Cholesky factor instead')
            op%setup_msg = msg
            op%solver = MASS_SOLVER_CHOLESKY
            err = 0
          else if (err /= 0) then
            msg = 'MASS SOLVER=KRONECKER: '//msg
          end if
        end if
        if (op%solver == MASS_SOLVER_CHOLESKY) call cholesky_init(op, dom, cnt, gid, &
            row_ptr, col, val, keep, err, msg)
      end if
      if (op%solver /= MASS_SOLVER_CG) then
        ! one decision for all ranks (a rank alone must not stop)
        e = merge(1, 0, err /= 0)
        call allreduce_max(e)
        if (e /= 0) then
          if (err == 0) msg = 'the set-up of the mass solve failed on another rank'
          op%setup_msg = msg
          if (.not. present(ierr)) call fatal('consistent mass', msg, 1)
          ierr = 1
          call log_info('consistent mass: '//msg)
        end if
      end if
    end if
  end subroutine mass_op_init

  !> The whole consistent mass on every rank, in the order of the global node numbers: the
  !! owned rows of every rank are gathered (row_ptr(ng + 1), col (global ids, sorted), val),
  !! with keep(ng, 2) the dofs to solve (free, and the node has mass: the CG's rule), cnt the
  !! owned nodes of every rank and gid the global id of every gathered node.
  subroutine gather_mass(op, dom, d, fixed, cnt, gid, row_ptr, col, val, keep)
    type(mass_op_t), intent(in) :: op
    type(domain_t), intent(in) :: dom
    real(dp), intent(in) :: d(:)
    logical, intent(in) :: fixed(:,:)
    integer, allocatable, intent(out) :: cnt(:), gid(:), row_ptr(:), col(:)
    real(dp), allocatable, intent(out) :: val(:)
    logical, allocatable, intent(out) :: keep(:,:)
    integer, allocatable :: ncnt(:), len_all(:), col_all(:), keep_all(:), keep_loc(:)
    real(dp), allocatable :: val_all(:)
    integer :: nn, ng, np, i, k, p, q, c, g, nnz
    nn = op%nn
    ng = op%nglobal
    np = env_size()
    allocate(cnt(np), ncnt(np), gid(ng), len_all(ng))
    ! rows: global ids and lengths, then columns (global ids), values and kept dofs
    call allgather_int(nn, cnt)
    call allgatherv_int(dom%halo%gid(1:nn), cnt, gid)
    call allgatherv_int(op%m%g%row_ptr(2:nn + 1) - op%m%g%row_ptr(1:nn), cnt, len_all)
    nnz = op%m%g%row_ptr(nn + 1) - 1
    call allgather_int(nnz, ncnt)
    allocate(col_all(sum(ncnt)), val_all(sum(ncnt)))
    call allgatherv_int(dom%halo%gid(op%m%g%col(1:nnz)), ncnt, col_all)
    call allgatherv_real(op%m%val(1:nnz), ncnt, val_all)
    allocate(keep_loc(2*nn), keep_all(2*ng))
    do i = 1, nn
      do c = 1, 2
        keep_loc(2*(i - 1) + c) = merge(1, 0, .not. fixed(c, i) .and. d(i) > 0.0_dp)
      end do
    end do
    call allgatherv_int(keep_loc, 2*cnt, keep_all)
    ! the global matrix in the order of the global node numbers
    allocate(row_ptr(ng + 1), col(size(col_all)), val(size(col_all)), keep(ng, 2))
    row_ptr(1) = 1
    do q = 1, ng
      row_ptr(gid(q) + 1) = len_all(q)
    end do
    do g = 1, ng
      row_ptr(g + 1) = row_ptr(g) + row_ptr(g + 1)
    end do
    k = 1
    do q = 1, ng
      g = gid(q)
      p = row_ptr(g)
      col(p:p + len_all(q) - 1) = col_all(k:k + len_all(q) - 1)
      val(p:p + len_all(q) - 1) = val_all(k:k + len_all(q) - 1)
      keep(g, 1) = keep_all(2*q - 1) == 1
      keep(g, 2) = keep_all(2*q) == 1
      k = k + len_all(q)
    end do
  end subroutine gather_mass

  !> The Kronecker solver of the gathered mass (ictus_solver_tensor_mass) on every rank.
  !! err = 1 with `msg` when the mass is not what the lattices promise.
  subroutine kronecker_init(op, dom, layout, cnt, gid, row_ptr, col, val, keep, err, msg)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(in) :: dom
    type(tensor_layout_t), intent(in) :: layout
    integer, intent(in) :: cnt(:), gid(:), row_ptr(:), col(:)
    real(dp), intent(in) :: val(:)
    logical, intent(in) :: keep(:,:)
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    integer, allocatable :: pos(:)
    integer :: q, ng, np
    real(dp) :: t0
    t0 = wall_time()
    ng = op%nglobal
    np = env_size()
    call tensor_mass_setup(op%tm, layout, ng, row_ptr, col, val, keep, err, msg)
    if (err /= 0) return
    if (np > 1) then
      ! read and write the gathered vectors: node g is at position pos(g)
      allocate(pos(ng))
      do q = 1, ng
        pos(gid(q)) = q
      end do
      call tensor_mass_renumber(op%tm, pos)
      call gather_setup(op, dom, cnt)
    end if
    op%solver = MASS_SOLVER_KRONECKER
    call log_info('consistent mass: solved along lattice directions (MASS SOLVER=KRONECKER) '// &
        'on '//tensor_mass_describe(op%tm)//', set-up and check '//str(wall_time() - t0, 3)// &
        ' s')
  end subroutine kronecker_init

  !> The Cholesky factor of the whole consistent mass (gathered by `gather_mass`) on every
  !! rank, ordered by METIS nested dissection and factorised. The components share one
  !! factor when their kept dofs are the same, else get one each. err = 1 with `msg` when
  !! METIS fails, M is not positive definite or memory runs out.
  subroutine cholesky_init(op, dom, cnt, gid, row_ptr, col, val, keep, err, msg)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: cnt(:), gid(:), row_ptr(:), col(:)
    real(dp), intent(in) :: val(:)
    logical, intent(in) :: keep(:,:)
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    integer, allocatable :: order(:), rp_aug(:), col_aug(:)
    integer :: nn, ng, np, i, q, c, ntail
    integer(i8) :: stored, need, avail
    real(dp) :: t0, mem(2)
    err = 0
    nn = op%nn
    ng = op%nglobal
    np = env_size()
    t0 = wall_time()
    ! dofs kept in one component only (e.g. a roller edge) are eliminated last, as one dense
    ! tail: the factor is shared up to there (ictus_solver_cholesky, chol_t%ntail)
    ntail = count(keep(:, 1) .neqv. keep(:, 2))
    op%fac = [1, 1]
    if (ntail > max_tail) op%fac = [1, 2]
    if (ntail > max_tail .or. ntail == 0) then
      allocate(order(ng))
      call nested_dissection(ng, row_ptr, col, order, err)
      if (err == 0) call chol_analyse(op%chol, ng, row_ptr, col, order, op%fac(2), err)
    else
      call tail_order(ng, row_ptr, col, keep(:, 1) .neqv. keep(:, 2), order, rp_aug, col_aug, &
          err)
      if (err == 0) call chol_analyse(op%chol, ng, rp_aug, col_aug, order, 1, err, ntail)
    end if
    if (err /= 0) then
      msg = 'the mass matrix could not be ordered for its Cholesky factor (METIS failed or '// &
          'the factor has too many rows to index)'
      return
    end if
    ! memory: the factor, the update stack and the largest update matrix, on every rank of
    ! the node; refused before allocating when it does not fit (the same decision on all ranks)
    need = 8*(op%chol%val_ptr(op%chol%nsup + 1)*op%fac(2) + op%chol%stack_size + &
        op%chol%w_size + int(op%chol%ntail, i8)**2)
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
      call chol_factor(op%chol, row_ptr, col, val, keep(:, 1) .or. keep(:, 2), 1, err, keep)
    else
      do c = 1, op%fac(2)
        call chol_factor(op%chol, row_ptr, col, val, keep(:, c), c, err)
        if (err /= 0) exit
      end do
    end if
    if (err == -1) then
      msg = 'not enough memory for the Cholesky factor of the mass matrix ('// &
          str(real(op%chol%nnz, dp)*8.0e-9_dp*op%fac(2), 3)//' GB per rank); use '// &
          '*DYNAMIC, EXPLICIT, MASS SOLVER=CG'
      err = 1
      return
    else if (err > 0) then
      msg = 'the mass matrix is not positive definite at node '//str(err)
      err = 1
      return
    end if
    ! pivots of the gathered nodes and of the owned nodes; work arrays of the solve
    allocate(op%gpiv(ng), op%opiv(nn))
    do q = 1, ng
      op%gpiv(q) = op%chol%inv(gid(q))
    end do
    do i = 1, nn
      op%opiv(i) = op%chol%inv(dom%halo%gid(i))
    end do
    call gather_setup(op, dom, cnt)
    allocate(op%xl(op%chol%max_rows, 2))
    stored = size(op%chol%val, kind=i8)
    if (allocated(op%chol%tail2)) stored = stored + size(op%chol%tail2, kind=i8)
    call log_info('consistent mass: Cholesky factor of '//str(ng)//' rows in '// &
        str(op%chol%nsup)//' supernodes, '//str(op%chol%nnz)//' non-zeros, '// &
        str(op%chol%ntail)//' rows in the dense tail, '//str(op%fac(2))//' factor(s), '// &
        str(real(stored, dp)*8.0e-6_dp, 4)//' MB stored on every rank, '// &
        str(op%chol%flops*op%fac(2), 3)//' flops, '//str(wall_time() - t0, 3)//' s')
  end subroutine cholesky_init

  !> The buffers of the solves on gathered loads (Cholesky, Kronecker): the sizes of every
  !! rank's part (2 x its owned nodes cnt) and their offsets, this rank's offset in nodes, the
  !! send buffer, the gathered f and the solution x (2, nglobal).
  subroutine gather_setup(op, dom, cnt)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: cnt(:)
    integer :: q
    op%counts = 2*cnt
    op%displs = [0, (sum(op%counts(1:q)), q = 1, size(cnt) - 1)]
    op%offset = op%displs(dom%rank + 1)/2
    call alloc_stream(op%x, 2, op%nglobal, 0.0_dp)
    allocate(op%fsend(2*op%nn), op%fall(2*op%nglobal))
  end subroutine gather_setup

  !> op%fall <- f on the free dofs of every rank's owned nodes, in rank order (allocates
  !! nothing).
  subroutine gather_loads(op, f)
    type(mass_op_t), intent(inout) :: op
    real(dp), intent(in) :: f(:,:)
    integer :: i
    do i = 1, op%nn
      op%fsend(2*i - 1) = f(1, i)*op%free(1, i)
      op%fsend(2*i) = f(2, i)*op%free(2, i)
    end do
    call allgatherv_real(op%fsend, op%counts, op%fall, op%displs)
  end subroutine gather_loads

  !> The smallest entry of the owned rows (1..nn) of a scalar CSR matrix, over all ranks.
  function mass_min_entry(m, nn) result(vmin)
    type(csr_t), intent(in) :: m
    integer, intent(in) :: nn
    real(dp) :: vmin, t(1)
    t(1) = 0.0_dp
    if (nn > 0) t(1) = -minval(m%val(1:m%g%row_ptr(nn + 1) - 1))
    call allreduce_max(t)
    vmin = -t(1)
  end function mass_min_entry

  !> Lumped mass only: owned node i gets the added mass dm >= 0 in the solve a = M^-1 f
  !! (bipenalty, doc/contact.md §6a): inv_diag = 1/(m_i + dm) on its free dofs; dm = 0 restores
  !! 1/m_i. Massless nodes and fixed dofs keep 0; m_diag (the kinetic energy and mass_apply)
  !! is not changed. Does nothing for a consistent mass.
  !! @param op operator; @param i owned node (1..nn); @param dm added mass
  pure subroutine mass_set_added(op, i, dm)
    type(mass_op_t), intent(inout) :: op
    integer, intent(in) :: i
    real(dp), intent(in) :: dm
    if (op%consistent) return
    if (op%m_diag(i) > 0.0_dp) op%inv_diag(:, i) = op%free(:, i)/(op%m_diag(i) + dm)
  end subroutine mass_set_added

  !> mv = M v on the owned rows (v must hold current ghost values for a consistent mass).
  subroutine mass_apply(op, v, mv)
    type(mass_op_t), intent(in) :: op
    real(dp), intent(in) :: v(:,:)
    real(dp), intent(inout) :: mv(:,:)
    integer :: i
    if (op%consistent) then
      call csr_matvec(op%nn, op%m%g%row_ptr, op%m%g%col, op%m%val, v, mv)
    else
      do i = 1, op%nn
        mv(:, i) = op%m_diag(i)*v(:, i)
      end do
    end if
  end subroutine mass_apply

  !> Solves M a = f on the free owned dofs (a = 0 on fixed ones); f and a are (2, >= nn).
  !! For a consistent mass, `a` holds the start value on entry (e.g. the previous step's
  !! acceleration). `ierr` = 1 when the conjugate gradient did not converge.
  !!
  !! The conjugate gradient makes three passes over memory per iteration (`cg_product`,
  !! `cg_update`, `cg_direction`); the dot products are folded into them as reproducible
  !! sums (ictus_parallel_repro) whose level boundaries come from a priori bounds of the
  !! terms, so no pass is spent on a maximum: |p_i q_i| <= pmax^2 m_inf with m_inf the largest
  !! absolute row sum of M; |r_i| <= rmax + |alpha| m_inf pmax for the updated residual. The
  !! maxima pmax, rmax are global (one allreduce per iteration), so every rank uses the same
  !! boundaries and the iterates are the same bits on any number of ranks.
  subroutine mass_solve(op, dom, f, a, ierr)
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    real(dp) :: rz, alpha, beta, fnorm2, rnorm2, pq, rbound, mx(2), tot(2)
    real(dp) :: part(2, levels, 2)
    integer :: it, nn, nterms, q, i
    ierr = 0
    nn = op%nn
    if (.not. op%consistent) then
      a(:, 1:nn) = f(:, 1:nn)*op%inv_diag
      return
    end if
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    if (op%solver == MASS_SOLVER_KRONECKER) then
      ! one rank: the owned nodes are the global ones, in order; several: as the Cholesky
      ! path, on the gathered f, and take the owned rows
      if (.not. allocated(op%fall)) then
        call tensor_mass_solve(op%tm, f, a)
        return
      end if
      call gather_loads(op, f)
      call tensor_mass_solve(op%tm, op%fall, op%x)
      a(:, 1:nn) = op%x(:, op%offset + 1:op%offset + nn)
      return
    end if
    if (op%solver == MASS_SOLVER_CHOLESKY) then
      ! f on the free dofs of every rank's nodes to every rank, solve, take the owned rows
      call gather_loads(op, f)
      do q = 1, op%nglobal
        op%x(1, op%gpiv(q)) = op%fall(2*q - 1)
        op%x(2, op%gpiv(q)) = op%fall(2*q)
      end do
      call chol_solve(op%chol, op%fac, op%x, op%xl)
      do i = 1, nn
        a(:, i) = op%x(:, op%opiv(i))
      end do
      return
    end if
    if (op%solver == MASS_SOLVER_CORRECTOR) then
      ! x = D^-1 f, then k passes x <- x + D^-1 (f - M x), the last one into a. Several
      ! ranks: one pass per sweep, the iterates alternate between p and xs, whose ghosts come
      ! by halo exchange before each product. One rank: two passes per sweep over M
      ! (`corrector_pair`), the same operations row by row, so the same bits.
      op%p(:, 1:nn) = f(:, 1:nn)*op%inv_diag
      it = op%passes
      do while (it > 0)
        if (op%paired .and. it >= 2) then
          if (it == 2) then
            call corrector_pair(nn, op%bw, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, f, &
                op%inv_diag, op%xs, a)
          else
            call corrector_pair(nn, op%bw, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, f, &
                op%inv_diag, op%xs, op%xt)
            call swap_iterates(op, third=.true.)
          end if
          it = it - 2
        else
          call halo_exchange(dom%halo, op%p)
          if (it == 1) then
            call corrector_pass(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, f, &
                op%inv_diag, a)
          else
            call corrector_pass(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, f, &
                op%inv_diag, op%xs)
            call swap_iterates(op)
          end if
          it = it - 1
        end if
      end do
      op%last_iter = op%passes
      op%total_iter = op%total_iter + op%passes
      return
    end if
    nterms = 2*op%nglobal
    ! residual of the start value
    op%p(:, 1:nn) = a(:, 1:nn)*op%free(:, 1:nn)
    call halo_exchange(dom%halo, op%p)
    call csr_matvec(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q)
    a(:, 1:nn) = op%p(:, 1:nn)
    op%r = (f(:, 1:nn) - op%q)*op%free(:, 1:nn)
    op%q = f(:, 1:nn)*op%free(:, 1:nn)
    fnorm2 = repro_dot(nn, op%q, op%q, op%nglobal)
    if (fnorm2 == 0.0_dp) then
      a(:, 1:nn) = 0.0_dp
      return
    end if
    rnorm2 = repro_dot(nn, op%r, op%r, op%nglobal)
    if (rnorm2 <= op%rtol**2*fnorm2) return
    ! first direction p = r/m (beta = 0) and r.p
    call cg_direction(nn, op%r, op%inv_diag, 0.0_dp, op%p, mx(1))
    rz = repro_dot(nn, op%r, op%p, op%nglobal)
    mx(2) = maxval(abs(op%r))
    call allreduce_max(mx)
    do it = 1, op%max_iter
      call halo_exchange(dom%halo, op%p)
      call cg_product(nn, op%m%g%row_ptr, op%m%g%col, op%m%val, op%p, op%q, &
          mx(1)**2*op%m_inf, nterms, part(:, :, 1))
      tot(1:1) = repro_totals(part(:, :, 1:1))
      pq = tot(1)
      alpha = rz/pq
      rbound = mx(2) + abs(alpha)*op%m_inf*mx(1)
      call cg_update(nn, alpha, op%p, op%q, op%inv_diag, a, op%r, rbound**2, &
          rbound**2*op%inv_max, nterms, part, mx(2))
      tot = repro_totals(part)
      rnorm2 = tot(1)
      op%last_iter = it
      if (rnorm2 <= op%rtol**2*fnorm2) exit
      beta = tot(2)/rz
      rz = tot(2)
      call cg_direction(nn, op%r, op%inv_diag, beta, op%p, mx(1))
      call allreduce_max(mx)
    end do
    op%total_iter = op%total_iter + op%last_iter
    if (rnorm2 > op%rtol**2*fnorm2) ierr = 1
  end subroutine mass_solve

  !> Whether `mass_step` can fold the velocity and displacement updates of a step into the
  !! solve: a consistent mass solved along the lattice directions on one rank (on several
  !! the solve runs on the gathered loads, and the step takes mass_solve and its updates).
  pure logical function mass_steps_fused(op)
    type(mass_op_t), intent(in) :: op
    mass_steps_fused = op%consistent .and. op%solver == MASS_SOLVER_KRONECKER .and. &
        .not. allocated(op%fall)
  end function mass_steps_fused

  !> The undamped step's updates with the solve folded in (needs mass_steps_fused): with
  !! kf = K u on the owned nodes, v <- v - dt M^-1 kf and u_next <- u + dt v, the same bits
  !! as mass_solve of -kf followed by v = v + dt a and u_next = u + dt v, without the passes
  !! over the acceleration (which is not stored).
  subroutine mass_step(op, kf, dt, u, v, u_next)
    type(mass_op_t), intent(inout) :: op
    real(dp), intent(in) :: kf(:,:), dt, u(:,:)
    real(dp), intent(inout) :: v(:,:), u_next(:,:)
    op%n_solves = op%n_solves + 1
    op%last_iter = 0
    call tensor_mass_step(op%tm, kf, dt, u, v, u_next)
  end subroutine mass_step

  !> One corrector pass on the n owned rows: y = x + d (f - M x), x with current ghosts and
  !! d = 1/row sum on free dofs (0 on fixed ones, where x and y stay 0).
  subroutine corrector_pass(n, row_ptr, col, val, x, f, d, y)
    integer, intent(in) :: n
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), x(2, *), f(2, *), d(2, *)
    real(dp), intent(inout) :: y(2, *)
    integer :: i
    do i = 1, n
      call corrector_row(i, row_ptr, col, val, x, f, d, y)
    end do
  end subroutine corrector_pass

  !> Two corrector passes in one sweep over the rows of M (all columns are rows: no ghosts):
  !! y = x + d (f - M x) at row i, then z = y + d (f - M y) at row i - w, w the half
  !! bandwidth of M, whose rows i - 2w .. i of y are complete then; the rows of M between
  !! the two stages stay in the cache, so M comes from memory once for two passes.
  subroutine corrector_pair(n, w, row_ptr, col, val, x, f, d, y, z)
    integer, intent(in) :: n, w
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), x(2, *), f(2, *), d(2, *)
    real(dp), intent(inout) :: y(2, *), z(2, *)
    integer :: i, j
    do i = 1, n + w
      if (i <= n) call corrector_row(i, row_ptr, col, val, x, f, d, y)
      j = i - w
      if (j >= 1) call corrector_row(j, row_ptr, col, val, y, f, d, z)
    end do
  end subroutine corrector_pair

  !> Row i of a corrector pass: y_i = x_i + d_i (f_i - (M x)_i).
  pure subroutine corrector_row(i, row_ptr, col, val, x, f, d, y)
    integer, intent(in) :: i
    integer, intent(in) :: row_ptr(*), col(*)
    real(dp), intent(in) :: val(*), x(2, *), f(2, *), d(2, *)
    real(dp), intent(inout) :: y(2, *)
    integer :: k, j
    real(dp) :: s1, s2
    s1 = 0.0_dp
    s2 = 0.0_dp
    do k = row_ptr(i), row_ptr(i + 1) - 1
      j = col(k)
      s1 = s1 + val(k)*x(1, j)
      s2 = s2 + val(k)*x(2, j)
    end do
    y(1, i) = x(1, i) + d(1, i)*(f(1, i) - s1)
    y(2, i) = x(2, i) + d(2, i)*(f(2, i) - s2)
  end subroutine corrector_row

  !> The corrector's new iterate xs (or with `third`, xt) becomes p, and p takes its place
  !! (no copy, no allocation).
  subroutine swap_iterates(op, third)
    type(mass_op_t), intent(inout) :: op
    logical, intent(in), optional :: third
    real(dp), allocatable :: t(:,:)
    call move_alloc(op%p, t)
    if (present(third)) then
      call move_alloc(op%xt, op%p)
      call move_alloc(t, op%xt)
    else
      call move_alloc(op%xs, op%p)
      call move_alloc(t, op%xs)
    end if
  end subroutine swap_iterates

  !> q = M p on the n owned rows (p with current ghosts) and this rank's level sums of p.q
  !! (lanes = the two components) for terms bounded by `bound`. The rows go in chunks whose
  !! q is still in the L1 cache when its terms are summed.
  subroutine cg_product(n, row_ptr, col, val, p, q, bound, nterms, part)
    integer, intent(in) :: n, nterms
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), p(2, *), bound
    real(dp), intent(inout) :: q(2, *)
    real(dp), intent(out) :: part(2, levels)
    integer, parameter :: chunk = 1024
    real(dp) :: sigma(levels), t, w
    integer :: i0, i, c, l
    call repro_sigma(bound, nterms, sigma)
    part = 0.0_dp
    do i0 = 1, n, chunk
      call csr_matvec(min(chunk, n - i0 + 1), row_ptr(i0), col, val, p, q(1, i0))
      do i = i0, min(i0 + chunk - 1, n)
        do c = 1, 2
          t = p(c, i)*q(c, i)
          do l = 1, levels
            w = (t + sigma(l)) - sigma(l)
            part(c, l) = part(c, l) + w
            t = t - w
          end do
        end do
      end do
    end do
  end subroutine cg_product

  !> a += alpha p; r -= alpha q on the free dofs (inv_diag > 0); level sums of r.r and
  !! r.(r/m) (bounded by brr and brz); rmax = max |r| on this rank.
  subroutine cg_update(n, alpha, p, q, inv_diag, a, r, brr, brz, nterms, part, rmax)
    integer, intent(in) :: n, nterms
    real(dp), intent(in) :: alpha, p(2, *), q(2, *), inv_diag(2, *), brr, brz
    real(dp), intent(inout) :: a(2, *), r(2, *)
    real(dp), intent(out) :: part(2, levels, 2), rmax
    real(dp) :: s_rr(levels), s_rz(levels), rc, t, w
    integer :: i, c, l
    call repro_sigma(brr, nterms, s_rr)
    call repro_sigma(brz, nterms, s_rz)
    part = 0.0_dp
    rmax = 0.0_dp
    do i = 1, n
      do c = 1, 2
        a(c, i) = a(c, i) + alpha*p(c, i)
        rc = r(c, i)
        if (inv_diag(c, i) > 0.0_dp) rc = rc - alpha*q(c, i)
        r(c, i) = rc
        rmax = max(rmax, abs(rc))
        t = rc*rc
        do l = 1, levels
          w = (t + s_rr(l)) - s_rr(l)
          part(c, l, 1) = part(c, l, 1) + w
          t = t - w
        end do
        t = rc*(rc*inv_diag(c, i))
        do l = 1, levels
          w = (t + s_rz(l)) - s_rz(l)
          part(c, l, 2) = part(c, l, 2) + w
          t = t - w
        end do
      end do
    end do
  end subroutine cg_update

  !> p = r/m + beta p on the owned dofs; pmax = max |p| on this rank.
  subroutine cg_direction(n, r, inv_diag, beta, p, pmax)
    integer, intent(in) :: n
    real(dp), intent(in) :: r(2, *), inv_diag(2, *), beta
    real(dp), intent(inout) :: p(2, *)
    real(dp), intent(out) :: pmax
    integer :: i, c
    pmax = 0.0_dp
    do i = 1, n
      do c = 1, 2
        p(c, i) = r(c, i)*inv_diag(c, i) + beta*p(c, i)
        pmax = max(pmax, abs(p(c, i)))
      end do
    end do
  end subroutine cg_direction
end module ictus_solver_mass_operator
