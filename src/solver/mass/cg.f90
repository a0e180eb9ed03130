!> MASS SOLVER=CG of the mass operator (ictus_solver_mass_solver): a Jacobi-preconditioned
!! conjugate gradient, warm-started from the caller's previous solution, to the relative
!! residual `rtol`. It runs on this rank's rows; the search direction's ghost values come by
!! halo exchange and the dot products are reproducible global sums, so the iterates are the
!! same bits on any number of ranks.
!!
!! The conjugate gradient makes three passes over memory per iteration (`cg_product`,
!! `cg_update`, `cg_direction`); the dot products are folded into them as reproducible
!! sums (ictus_parallel_repro) whose level boundaries come from a priori bounds of the
!! terms, so no pass is spent on a maximum: |p_i q_i| <= pmax^2 m_inf with m_inf the largest
!! absolute row sum of M; |r_i| <= rmax + |alpha| m_inf pmax for the updated residual. The
!! maxima pmax, rmax are global (one allreduce per iteration), so every rank uses the same
!! boundaries and the iterates are the same bits on any number of ranks.
module ictus_solver_mass_cg
  use ictus_core_kinds, only: dp
  use ictus_core_memory, only: alloc_stream
  use ictus_core_strings, only: str
  use ictus_parallel_repro, only: repro_dot, repro_sigma, repro_totals, levels
  use ictus_parallel_env, only: allreduce_max
  use ictus_parallel_halo, only: halo_exchange
  use ictus_solver_sparse, only: csr_t, csr_matvec
  use ictus_solver_domain, only: domain_t
  use ictus_solver_mass_solver, only: mass_core_t, mass_solver_t, consistent_solver_t, &
      consistent_setup
  implicit none
  private
  public :: cg_init

  type, extends(consistent_solver_t) :: cg_solver_t
    !> Relative residual tolerance and iteration limit.
    real(dp) :: rtol = 1.0e-12_dp
    integer :: max_iter = 500
    !> Largest absolute row sum of M and largest 1/m (global): bounds of the terms.
    real(dp) :: m_inf = 0.0_dp
    real(dp) :: inv_max = 0.0_dp
    !> Residual r and M p in q (ndm, nn), direction p (ndm, nlocal: ghosts by halo).
    real(dp), allocatable :: r(:,:), p(:,:), q(:,:)
  contains
    procedure :: solve => cg_solve
    procedure :: report => cg_report
  end type cg_solver_t

contains

  !> The conjugate gradient of the consistent mass m (this rank's rows) with the dofs
  !! `fixed(ndm, nlocal)`, to the relative residual `rtol` (default 1e-12).
  subroutine cg_init(s, c, m, fixed, rtol)
    class(mass_solver_t), allocatable, intent(out) :: s
    type(mass_core_t), intent(inout) :: c
    type(csr_t), intent(in) :: m
    logical, intent(in) :: fixed(:,:)
    real(dp), intent(in), optional :: rtol
    type(cg_solver_t), allocatable :: t
    integer :: i
    allocate(t)
    if (present(rtol)) t%rtol = rtol
    call consistent_setup(t, c, m, fixed)
    call alloc_stream(t%r, size(fixed, 1), c%nn, 0.0_dp)
    call alloc_stream(t%q, size(fixed, 1), c%nn, 0.0_dp)
    call alloc_stream(t%p, size(fixed, 1), c%nlocal, 0.0_dp)
    do i = 1, c%nn
      t%m_inf = max(t%m_inf, sum(abs(t%m%val(t%m%g%row_ptr(i):t%m%g%row_ptr(i + 1) - 1))))
    end do
    t%inv_max = maxval(c%inv_diag)
    call allreduce_max(t%m_inf)
    call allreduce_max(t%inv_max)
    call move_alloc(t, s)
  end subroutine cg_init

  subroutine cg_solve(self, c, dom, f, a, ierr)
    class(cg_solver_t), intent(inout) :: self
    type(mass_core_t), intent(inout) :: c
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: f(:,:)
    real(dp), intent(inout) :: a(:,:)
    integer, intent(out) :: ierr
    real(dp) :: rz, alpha, beta, fnorm2, rnorm2, pq, rbound, mx(2), tot(2)
    real(dp) :: part(size(a, 1), levels, 2)
    integer :: it, nn, nterms, nc
    ierr = 0
    nn = c%nn
    nc = size(a, 1)
    nterms = nc*c%nglobal
    ! residual of the start value
    self%p(:, 1:nn) = a(:, 1:nn)*c%free(:, 1:nn)
    call halo_exchange(dom%halo, self%p)
    call csr_matvec(nn, self%m%g%row_ptr, self%m%g%col, self%m%val, self%p, self%q, nc)
    a(:, 1:nn) = self%p(:, 1:nn)
    self%r = (f(:, 1:nn) - self%q)*c%free(:, 1:nn)
    self%q = f(:, 1:nn)*c%free(:, 1:nn)
    fnorm2 = repro_dot(nn, self%q, self%q, c%nglobal)
    if (fnorm2 == 0.0_dp) then
      a(:, 1:nn) = 0.0_dp
      return
    end if
    rnorm2 = repro_dot(nn, self%r, self%r, c%nglobal)
    if (rnorm2 <= self%rtol**2*fnorm2) return
    ! first direction p = r/m (beta = 0) and r.p
    call cg_direction(nc, nn, self%r, c%inv_diag, 0.0_dp, self%p, mx(1))
    rz = repro_dot(nn, self%r, self%p, c%nglobal)
    mx(2) = maxval(abs(self%r))
    call allreduce_max(mx)
    do it = 1, self%max_iter
      call halo_exchange(dom%halo, self%p)
      call cg_product(nc, nn, self%m%g%row_ptr, self%m%g%col, self%m%val, self%p, self%q, &
          mx(1)**2*self%m_inf, nterms, part(:, :, 1))
      tot(1:1) = repro_totals(part(:, :, 1:1))
      pq = tot(1)
      alpha = rz/pq
      rbound = mx(2) + abs(alpha)*self%m_inf*mx(1)
      call cg_update(nc, nn, alpha, self%p, self%q, c%inv_diag, a, self%r, rbound**2, &
          rbound**2*self%inv_max, nterms, part, mx(2))
      tot = repro_totals(part)
      rnorm2 = tot(1)
      c%last_iter = it
      if (rnorm2 <= self%rtol**2*fnorm2) exit
      beta = tot(2)/rz
      rz = tot(2)
      call cg_direction(nc, nn, self%r, c%inv_diag, beta, self%p, mx(1))
      call allreduce_max(mx)
    end do
    c%total_iter = c%total_iter + c%last_iter
    if (rnorm2 > self%rtol**2*fnorm2) ierr = 1
  end subroutine cg_solve

  function cg_report(self, c) result(line)
    class(cg_solver_t), intent(in) :: self
    type(mass_core_t), intent(in) :: c
    character(len=:), allocatable :: line
    line = 'consistent mass: '//str(c%n_solves)//' solves, mean '// &
        str(real(c%total_iter, dp)/max(1, c%n_solves), 3)// &
        ' CG iterations per solve (relative residual '//str(self%rtol)//')'
  end function cg_report

  !> q = M p on the n owned rows (p with current ghosts) and this rank's level sums of p.q
  !! (lanes = the two components) for terms bounded by `bound`. The rows go in chunks whose
  !! q is still in the L1 cache when its terms are summed.
  subroutine cg_product(nc, n, row_ptr, col, val, p, q, bound, nterms, part)
    integer, intent(in) :: nc, n, nterms
    integer, intent(in) :: row_ptr(n + 1), col(*)
    real(dp), intent(in) :: val(*), p(nc, *), bound
    real(dp), intent(inout) :: q(nc, *)
    real(dp), intent(out) :: part(nc, levels)
    integer, parameter :: chunk = 1024
    real(dp) :: sigma(levels), t, w
    integer :: i0, i, c, l
    call repro_sigma(bound, nterms, sigma)
    part = 0.0_dp
    do i0 = 1, n, chunk
      call csr_matvec(min(chunk, n - i0 + 1), row_ptr(i0), col, val, p, q(1, i0), nc)
      do i = i0, min(i0 + chunk - 1, n)
        do c = 1, nc
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
  subroutine cg_update(nc, n, alpha, p, q, inv_diag, a, r, brr, brz, nterms, part, rmax)
    integer, intent(in) :: nc, n, nterms
    real(dp), intent(in) :: alpha, p(nc, *), q(nc, *), inv_diag(nc, *), brr, brz
    real(dp), intent(inout) :: a(nc, *), r(nc, *)
    real(dp), intent(out) :: part(nc, levels, 2), rmax
    real(dp) :: s_rr(levels), s_rz(levels), rc, t, w
    integer :: i, c, l
    call repro_sigma(brr, nterms, s_rr)
    call repro_sigma(brz, nterms, s_rz)
    part = 0.0_dp
    rmax = 0.0_dp
    do i = 1, n
      do c = 1, nc
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
  subroutine cg_direction(nc, n, r, inv_diag, beta, p, pmax)
    integer, intent(in) :: nc, n
    real(dp), intent(in) :: r(nc, *), inv_diag(nc, *), beta
    real(dp), intent(inout) :: p(nc, *)
    real(dp), intent(out) :: pmax
    integer :: i, c
    pmax = 0.0_dp
    do i = 1, n
      do c = 1, nc
        p(c, i) = r(c, i)*inv_diag(c, i) + beta*p(c, i)
        pmax = max(pmax, abs(p(c, i)))
      end do
    end do
  end subroutine cg_direction
end module ictus_solver_mass_cg
