!> MASS SOLVER=CORRECTOR of the mass operator (ictus_solver_mass_solver): a fixed number k of
!! passes x <- x + D^-1 (f - M x) from x = D^-1 f, with D the row sums of M
!! (predictor/multi-corrector, doc/theory.md §5.1). This is not a converged solve but a fixed
!! approximate inverse M_k^-1 = sum_{j=0..k} (I - D^-1 M)^j D^-1: symmetric, between D^-1 and
!! M^-1 in the Loewner order when M has no negative entries (then the eigenvalues of D^-1 M
!! lie in (0, 1]), so it is positive definite, conserves momentum exactly and keeps the
!! stable step between the row-sum and the consistent one; smooth modes see the error
!! (1 - s)^(k+1) of the mass symbol s (doc/theory.md §5). Each pass is one product with M
!! after a halo exchange; no global sum.
module ictus_solver_mass_corrector
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_core_strings, only: str
  use ictus_parallel_env, only: allreduce_max
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: csr_t
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t, consistent_solver_t, &
      consistent_setup
  implicit none
  private
  public :: corrector_init, mass_min_entry

  type, extends(consistent_solver_t) :: corrector_solver_t
    !> Passes k, the half bandwidth of M, and whether two passes share one sweep (no ghosts:
    !! one rank).
    integer :: passes = 2
    integer :: bw = 0
    logical :: paired = .false.
    !> The iterates (2, nlocal: ghosts by halo): p, the next one xs, and xt, the third of a
    !! paired sweep.
    real(dp), allocatable :: p(:,:), xs(:,:), xt(:,:)
  contains
    procedure :: solve => corrector_solve
    procedure :: report => corrector_report
  end type corrector_solver_t

contains

  !> The corrector of the consistent mass m (this rank's rows) with the dofs
  !! `fixed(2, nlocal)`, `passes` passes (default 2). err = 1 with `msg` when M has a
  !! negative entry on any rank.
  subroutine corrector_init(s, c, m, fixed, passes, err, msg)
    class(mass_solver_t), allocatable, intent(out) :: s
    type(mass_core_t), intent(inout) :: c
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    integer, intent(in), optional :: passes
    integer, intent(out) :: err
    character(len=:), allocatable, intent(out) :: msg
    type(corrector_solver_t), allocatable :: t
    integer :: i, k
    allocate(t)
    if (present(passes)) t%passes = passes
    call consistent_setup(t, c, m, fixed, row_sums=.true.)
    call alloc_stream(t%xs, 2, c%nlocal, 0.0_dp)
    t%paired = c%nlocal == c%nn
    if (t%paired .and. t%passes > 2) call alloc_stream(t%xt, 2, c%nlocal, 0.0_dp)
    do i = 1, c%nn
      k = m%g%row_ptr(i)
      if (m%g%row_ptr(i + 1) > k) t%bw = max(t%bw, maxval(abs(m%g%col(k: &
          m%g%row_ptr(i + 1) - 1) - i)))
    end do
    call alloc_stream(t%p, 2, c%nlocal, 0.0_dp)
    err = 0
    if (mass_min_entry(m, c%nn) < 0.0_dp) then
      err = 1
      msg = 'MASS SOLVER=CORRECTOR needs a mass matrix without negative entries'
    end if
    call move_alloc(t, s)
  end subroutine corrector_init

  !> x = D^-1 f, then k passes x <- x + D^-1 (f - M x), the last one into a. Several ranks:
  !! one pass per sweep, the iterates alternate between p and xs, whose ghosts come by halo
  !! exchange before each product. One rank: two passes per sweep over M (`corrector_pair`),
  !! the same operations row by row, so the same bits.
  subroutine corrector_solve(self, c, dom, f, a, ierr)
    class(corrector_solver_t), intent(inout) :: self
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    integer :: it, nn
    ierr = 0
    nn = c%nn
    self%p(:, 1:nn) = f(:, 1:nn)*c%inv_diag
    it = self%passes
    do while (it > 0)
      if (self%paired .and. it >= 2) then
        if (it == 2) then
          call corrector_pair(nn, self%bw, self%m%g%row_ptr, self%m%g%col, self%m%val, &
              self%p, f, c%inv_diag, self%xs, a)
        else
          call corrector_pair(nn, self%bw, self%m%g%row_ptr, self%m%g%col, self%m%val, &
              self%p, f, c%inv_diag, self%xs, self%xt)
          call swap_iterates(self, third=.true.)
        end if
        it = it - 2
      else
        call halo_exchange(dom%halo, self%p)
        if (it == 1) then
          call corrector_pass(nn, self%m%g%row_ptr, self%m%g%col, self%m%val, self%p, f, &
              c%inv_diag, a)
        else
          call corrector_pass(nn, self%m%g%row_ptr, self%m%g%col, self%m%val, self%p, f, &
              c%inv_diag, self%xs)
          call swap_iterates(self)
        end if
        it = it - 1
      end if
    end do
    c%last_iter = self%passes
    c%total_iter = c%total_iter + self%passes
  end subroutine corrector_solve

  function corrector_report(self, c) result(line)
    class(corrector_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    character(len=:), allocatable :: line
    line = 'consistent mass: '//str(c%n_solves)//' approximate solves of '// &
        str(self%passes)//' corrector passes'
  end function corrector_report

  !> The new iterate xs (or with `third`, xt) becomes p, and p takes its place (no copy, no
  !! allocation).
  subroutine swap_iterates(s, third)
    type(corrector_solver_t), intent(inout) :: s
    logical, intent(in), optional :: third
    real(dp), allocatable :: t(:,:)
    call move_alloc(s%p, t)
    if (present(third)) then
      call move_alloc(s%xt, s%p)
      call move_alloc(t, s%xt)
    else
      call move_alloc(s%xs, s%p)
      call move_alloc(t, s%xs)
    end if
  end subroutine swap_iterates

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
end module ictus_solver_mass_corrector
