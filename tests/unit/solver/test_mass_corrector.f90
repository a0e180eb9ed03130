!> MASS_SOLVER_CORRECTOR (k row-sum-preconditioned passes) on the mass of a uniform biquadratic
!! B-spline mesh, against facts derived independently of the code (doc/theory.md §5):
!!
!! * the interior stencil of the 1D mass is h/120 [1, 26, 66, 26, 1], so a Fourier mode
!!   cos(theta i) has the symbol s = (66 + 52 cos theta + 2 cos 2 theta)/120 and k passes
!!   return (1 - (1 - s)^(k+1)) times the exact acceleration away from the boundary;
!! * a uniform acceleration is returned exactly (the row sums are the preconditioner);
!! * momentum: the sum of M a equals the sum of f for any f (no fixed dofs);
!! * the approximate inverse is symmetric and lies between D^-1 and M^-1 (Loewner order),
!!   growing with k;
!! * with fixed dofs, the passes act on the free block (dense reference);
!! * a mass with a negative entry is refused.
program test_mass_corrector
  use ictus_core_kinds, only: dp
  use ictus_solver_sparse, only: graph_t, csr_t, graph_from_elements, csr_init, &
      csr_add_element
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_solve, mass_apply, &
      MASS_SOLVER_CORRECTOR
  use ictus_solver_domain, only: domain_t
  use ictus_test_solver, only: domain_init_serial
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  !> Control points in x and y.
  integer, parameter :: nx = 40, ny = 12, nn = nx*ny
  type(csr_t) :: m
  real(dp) :: md(nn, nn)
  type(domain_t) :: dom
  call t%start("solver/mass_corrector")
  call build_mesh(m, md, dom)
  call test_stencil(t)
  call test_dispersion(t)
  call test_uniform_and_momentum(t)
  call test_symmetry_and_order(t)
  call test_fixed(t)
  call test_negative(t)
  call t%finish()
contains

  !> The 1D mass of one span of uniform quadratic B-splines (h = 1), by 3-point Gauss:
  !! pieces (1 - t)^2/2, (1 + 2t - 2t^2)/2, t^2/2 on t in [0, 1].
  function span_mass() result(me)
    real(dp) :: me(3, 3), b(3), tq, w(3), g(3)
    integer :: q, a
    g = [0.5_dp - sqrt(0.15_dp), 0.5_dp, 0.5_dp + sqrt(0.15_dp)]
    w = [5.0_dp, 8.0_dp, 5.0_dp]/18.0_dp
    me = 0.0_dp
    do q = 1, 3
      tq = g(q)
      b = [0.5_dp*(1.0_dp - tq)**2, 0.5_dp*(1.0_dp + 2.0_dp*tq - 2.0_dp*tq**2), 0.5_dp*tq**2]
      do a = 1, 3
        me(:, a) = me(:, a) + w(q)*b*b(a)
      end do
    end do
  end function span_mass

  !> nx x ny control points (node i + (j - 1) nx), elements of 3 x 3 control points with the
  !! tensor mass me (x) me; sparse m and dense md; a one-rank domain.
  subroutine build_mesh(m, md, dom)
    type(csr_t), intent(out) :: m
    real(dp), intent(out) :: md(nn, nn)
    type(domain_t), intent(out) :: dom
    integer, parameter :: nel = (nx - 2)*(ny - 2)
    integer :: conn(9, nel), nen(nel), e, ex, ey, a, b, i
    real(dp) :: m1(3, 3), me(9, 9)
    type(graph_t) :: g
    m1 = span_mass()
    do b = 1, 3
      do a = 1, 3
        do i = 1, 9
          me(a + 3*(b - 1), i) = m1(a, 1 + mod(i - 1, 3))*m1(b, 1 + (i - 1)/3)
        end do
      end do
    end do
    e = 0
    do ey = 1, ny - 2
      do ex = 1, nx - 2
        e = e + 1
        do b = 1, 3
          do a = 1, 3
            conn(a + 3*(b - 1), e) = ex + a - 1 + (ey + b - 2)*nx
          end do
        end do
      end do
    end do
    nen = 9
    call graph_from_elements(nn, nn, nel, 9, nen, conn, [(i, i = 1, nn)], g)
    call csr_init(m, g)
    md = 0.0_dp
    do e = 1, nel
      call csr_add_element(m, 9, conn(:, e), me)
      md(conn(:, e), conn(:, e)) = md(conn(:, e), conn(:, e)) + me
    end do
    call domain_init_serial(dom, nn)
  end subroutine build_mesh

  integer function node(i, j)
    integer, intent(in) :: i, j
    node = i + (j - 1)*nx
  end function node

  !> The assembled interior row is the known stencil (1, 26, 66, 26, 1)/120 in each direction.
  subroutine test_stencil(t)
    type(checker_t), intent(inout) :: t
    real(dp) :: s(5), err
    integer :: a, b
    s = [1.0_dp, 26.0_dp, 66.0_dp, 26.0_dp, 1.0_dp]/120.0_dp
    err = 0.0_dp
    do b = -2, 2
      do a = -2, 2
        err = max(err, abs(md(node(20, 6), node(20 + a, 6 + b)) - s(a + 3)*s(b + 3)))
      end do
    end do
    call t%close_abs(err, 0.0_dp, 1.0e-15_dp, 'interior row = h^2/120^2 (1,26,66,26,1) x (same)')
  end subroutine test_stencil

  !> f = M phi with phi = cos(theta1 i) (component 1) and cos(theta2 j) (component 2):
  !! k passes give (1 - r^(k+1)) phi at control points more than 2(k+1) + 2 from the edge
  !! across the wave, r = 1 - s(theta).
  subroutine test_dispersion(t)
    type(checker_t), intent(inout) :: t
    real(dp), parameter :: th(2) = [0.9_dp, 0.6_dp]
    type(mass_op_t) :: op
    real(dp) :: phi(2, nn), f(2, nn), a(2, nn), r(2), want, err(2)
    logical :: fixed(2, nn)
    integer :: i, j, k, ierr, c
    do j = 1, ny
      do i = 1, nx
        phi(1, node(i, j)) = cos(th(1)*i)
        phi(2, node(i, j)) = cos(th(2)*j)
      end do
    end do
    f(1, :) = matmul(md, phi(1, :))
    f(2, :) = matmul(md, phi(2, :))
    r = 1.0_dp - (66.0_dp + 52.0_dp*cos(th) + 2.0_dp*cos(2.0_dp*th))/120.0_dp
    fixed = .false.
    do k = 1, 3
      call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, &
          solver=MASS_SOLVER_CORRECTOR, passes=k, ierr=ierr)
      call t%equal_int(ierr, 0, 'corrector set-up, k = '//achar(48 + k))
      a = 0.0_dp
      call mass_solve(op, dom, f, a, ierr)
      err = 0.0_dp
      do j = 1, ny
        do i = 1, nx
          c = node(i, j)
          if (i > 2*(k + 1) + 2 .and. i < nx - 2*(k + 1) - 1) then
            want = (1.0_dp - r(1)**(k + 1))*phi(1, c)
            err(1) = max(err(1), abs(a(1, c) - want))
          end if
          if (j > 2*(k + 1) + 2 .and. j < ny - 2*(k + 1) - 1) then
            want = (1.0_dp - r(2)**(k + 1))*phi(2, c)
            err(2) = max(err(2), abs(a(2, c) - want))
          end if
        end do
      end do
      call t%close_abs(err(1), 0.0_dp, 1.0e-13_dp, 'k = '//achar(48 + k)// &
          ' passes: a = (1 - r^(k+1)) phi in x (theta = 0.9)')
      call t%close_abs(err(2), 0.0_dp, 1.0e-13_dp, 'k = '//achar(48 + k)// &
          ' passes: a = (1 - r^(k+1)) phi in y (theta = 0.6)')
      call t%true(maxval(abs(a(1, :) - phi(1, :))) > 0.5_dp*r(1)**(k + 1), 'k = '// &
          achar(48 + k)//': the error r^(k+1) is there (not a converged solve)')
    end do
  end subroutine test_dispersion

  !> Uniform acceleration returned exactly; momentum sum(M a) = sum(f) for a general f.
  subroutine test_uniform_and_momentum(t)
    type(checker_t), intent(inout) :: t
    type(mass_op_t) :: op
    real(dp) :: f(2, nn), a(2, nn), ma(2, nn)
    logical :: fixed(2, nn)
    integer :: i, ierr
    fixed = .false.
    call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, &
        solver=MASS_SOLVER_CORRECTOR, passes=2)
    f(1, :) = matmul(md, [(3.0_dp, i = 1, nn)])
    f(2, :) = matmul(md, [(-0.5_dp, i = 1, nn)])
    call mass_solve(op, dom, f, a, ierr)
    call t%close_abs(maxval(abs(a(1, :) - 3.0_dp)) + maxval(abs(a(2, :) + 0.5_dp)), 0.0_dp, &
        1.0e-13_dp, 'uniform body force: a = g exactly, boundary rows included')
    do i = 1, nn
      f(:, i) = [sin(1.3_dp*i) + 0.2_dp, cos(0.7_dp*i*i)]
    end do
    call mass_solve(op, dom, f, a, ierr)
    call mass_apply(op, a, ma)
    call t%close_abs(abs(sum(ma(1, :)) - sum(f(1, :))) + abs(sum(ma(2, :)) - sum(f(2, :))), &
        0.0_dp, 1.0e-12_dp, 'momentum: sum(M a) = sum(f)')
  end subroutine test_uniform_and_momentum

  !> x.Mk^-1 y = y.Mk^-1 x; f.D^-1 f <= f.M_1^-1 f <= f.M_2^-1 f <= f.M_3^-1 f <= f.M^-1 f.
  subroutine test_symmetry_and_order(t)
    type(checker_t), intent(inout) :: t
    type(mass_op_t) :: op
    real(dp) :: x(2, nn), y(2, nn), ax(2, nn), ay(2, nn), q(0:4), mf(nn, nn), rhs(nn)
    logical :: fixed(2, nn)
    integer :: i, k, ierr, ipiv(nn), info
    logical :: ordered
    fixed = .false.
    do i = 1, nn
      x(:, i) = [sin(0.37_dp*i), cos(1.1_dp*i)]
      y(:, i) = [cos(2.3_dp*i), sin(0.05_dp*i*i)]
    end do
    do k = 1, 3
      call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, &
          solver=MASS_SOLVER_CORRECTOR, passes=k)
      call mass_solve(op, dom, x, ax, ierr)
      call mass_solve(op, dom, y, ay, ierr)
      if (k == 2) call t%close_abs(sum(y*ax) - sum(x*ay), 0.0_dp, 1.0e-13_dp*sum(abs(y*ax)), &
          'symmetric: y.Mk^-1 x = x.Mk^-1 y')
      q(k) = sum(x(1, :)*ax(1, :))
    end do
    q(0) = 0.0_dp
    do i = 1, nn
      q(0) = q(0) + x(1, i)**2/sum(md(i, :))
    end do
    mf = md
    rhs = x(1, :)
    call dgesv(nn, 1, mf, nn, ipiv, rhs, nn, info)
    q(4) = sum(x(1, :)*rhs)
    ordered = .true.
    do k = 1, 4
      ordered = ordered .and. q(k) >= q(k - 1)
    end do
    call t%true(ordered .and. q(4) > 1.5_dp*q(0), 'Loewner order: D^-1 <= M_1^-1 <= M_2^-1 '// &
        '<= M_3^-1 <= M^-1 on a test vector')
  end subroutine test_symmetry_and_order

  !> Fixed dofs: zero, and the free rows follow sum_j (I - Df^-1 Mff)^j Df^-1 f_f computed
  !! densely on the free block (Df = row sums of M, the preconditioner of the full rows).
  subroutine test_fixed(t)
    type(checker_t), intent(inout) :: t
    integer, parameter :: k = 2
    type(mass_op_t) :: op
    real(dp) :: f(2, nn), a(2, nn), x(nn), d(nn), want(nn), err
    logical :: fixed(2, nn), free(nn)
    integer :: i, j, ierr
    fixed = .false.
    do j = 1, ny
      fixed(1, node(1, j)) = .true.
    end do
    do i = 1, nn
      f(:, i) = [sin(0.9_dp*i), 1.0_dp]
      d(i) = sum(md(i, :))
    end do
    call mass_op_init(op, dom, .true., m, [(1.0_dp, i = 1, nn)], fixed, &
        solver=MASS_SOLVER_CORRECTOR, passes=k)
    call mass_solve(op, dom, f, a, ierr)
    free = .not. fixed(1, :)
    x = merge(f(1, :)/d, 0.0_dp, free)
    do j = 1, k
      want = x + (f(1, :) - matmul(md, x))/d
      x = merge(want, 0.0_dp, free)
    end do
    err = maxval(abs(a(1, :) - x))
    call t%close_abs(err, 0.0_dp, 1.0e-13_dp, 'fixed x on the left edge: free rows = dense passes')
    call t%close_abs(maxval(abs(a(1, :)), mask=.not. free), 0.0_dp, 0.0_dp, &
        'fixed dofs: zero acceleration')
  end subroutine test_fixed

  !> A mass with a negative off-diagonal entry is refused (ierr = 1).
  subroutine test_negative(t)
    type(checker_t), intent(inout) :: t
    type(csr_t) :: mneg
    type(mass_op_t) :: op
    logical :: fixed(2, nn)
    integer :: ierr, i
    fixed = .false.
    mneg = m
    mneg%val(2) = -1.0e-3_dp
    call mass_op_init(op, dom, .true., mneg, [(1.0_dp, i = 1, nn)], fixed, &
        solver=MASS_SOLVER_CORRECTOR, ierr=ierr)
    call t%equal_int(ierr, 1, 'negative entry: set-up refused')
  end subroutine test_negative
end program test_mass_corrector
