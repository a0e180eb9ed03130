!> MASS SOLVER=KRONECKER (ictus_solver_mass_kronecker) against a dense LAPACK solve of the
!! assembled consistent mass on its free dofs, model by model from decks written here:
!!
!! * Q8, Q9 and Q4 grids with graded spacing and nodes numbered against the lattice, NURBS
!!   rectangles of degree 2 (graded knots) and 3 (the generic band path), two separate Q8
!!   blocks, grids longer than one block of columns of the solve with the nodes of each
!!   lattice column one range of the model's nodes or not; with fixed lines in either direction and isolated fixed
!!   points (one, and three on one edge). Each must be taken by the Kronecker solver and
!!   agree with the dense solve to 1e-11, and its fused step (mass_step: the solve with the
!!   updates of v and u folded in) must give the bits of the solve and the updates;
!! * what must be refused, with its reason, and then (MASS SOLVER=AUTO) solved by the
!!   Cholesky factor instead, still agreeing with the dense solve: a Q8 grid whose midside
!!   nodes are off the midpoints (the lattice is found; the set-up check refuses it), two
!!   densities, a grid turned by 30 degrees, a NURBS patch with a non-unit weight, more
!!   isolated fixed points than the solver takes; and MASS SOLVER=KRONECKER on such a mesh
!!   returns an error instead of a fallback.
program test_kronecker_mass
  use ictus_core_kinds, only: dp
  use ictus_core_errors, only: error_count
  use ictus_core_strings, only: str
  use ictus_solver_model, only: model_t, MASS_SOLVER_KRONECKER, MASS_SOLVER_CHOLESKY, &
      MASS_SOLVER_AUTO
  use ictus_solver_domain, only: domain_t, domain_init
  use ictus_solver_assemble, only: operators_t, assemble_operators
  use ictus_solver_sparse, only: bsr_t, bsr_upper_t, bsr_upper_init, bsr_upper_matvec, &
      bsr_matvec_ordered, bsr_matvec
  use ictus_solver_mass_operator, only: mass_op_t, mass_op_init, mass_solve, mass_step, &
      mass_steps_fused
  use ictus_solver_tensor_layout, only: tensor_layout_t, tensor_layout
  use ictus_io_deck_types, only: deck_t
  use ictus_io_deck_reader, only: read_deck
  use ictus_app_build_model, only: build_model
  use ictus_test_check, only: checker_t
  implicit none
  type(checker_t) :: t
  real(dp), parameter :: pi = acos(-1.0_dp)
  call t%start("app/kronecker_mass")
  ! grids: type, elements, graded?, boundary, expected solver
  call check_fe(t, 'q8 graded, roller bottom', 'Q8', 5, 4, grade=.true., bc='roller', &
      expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q8 uniform, clamped left, 3 points', 'Q8', 6, 3, grade=.false., &
      bc='left+points', expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q9 graded, roller bottom', 'Q9', 4, 3, grade=.true., bc='roller', &
      expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q4 graded, clamped left', 'Q4', 7, 5, grade=.true., bc='left', &
      expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q8, two blocks', 'Q8', 3, 2, grade=.true., bc='roller', &
      expect=MASS_SOLVER_KRONECKER, blocks=2)
  ! longer than one block of columns of the solve (col_block = 32 lattice columns), nodes
  ! in the order of the lattice columns (the solve reads and writes them as ranges) or across
  call check_fe(t, 'q8 tall', 'Q8', 4, 34, grade=.true., bc='roller', &
      expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q8 tall, nodes across the lattice', 'Q8', 4, 34, grade=.true., &
      bc='roller', expect=MASS_SOLVER_KRONECKER, across=.true.)
  call check_fe(t, 'q8 tall, clamped left, 3 points', 'Q8', 3, 20, grade=.false., &
      bc='left+points', expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q9 tall', 'Q9', 3, 20, grade=.true., bc='roller', &
      expect=MASS_SOLVER_KRONECKER)
  call check_fe(t, 'q4 tall, nodes across the lattice', 'Q4', 5, 40, grade=.true., &
      bc='left', expect=MASS_SOLVER_KRONECKER, across=.true.)
  call check_iga(t, 'nurbs p = 2, graded knots', 2, weight=1.0_dp, expect=MASS_SOLVER_KRONECKER)
  call check_iga(t, 'nurbs p = 3', 3, weight=1.0_dp, expect=MASS_SOLVER_KRONECKER)
  ! refused, then solved by the factor
  call check_fe(t, 'q8, midside nodes off the midpoints', 'Q8', 4, 3, grade=.true., &
      bc='roller', expect=MASS_SOLVER_CHOLESKY, offmid=.true., reason='not the tensor-product')
  call check_fe(t, 'q8, two densities', 'Q8', 4, 3, grade=.false., bc='roller', &
      expect=MASS_SOLVER_CHOLESKY, density2=.true., reason='not the tensor-product')
  call check_fe(t, 'q8, turned by 30 degrees', 'Q8', 4, 3, grade=.false., bc='roller', &
      expect=MASS_SOLVER_CHOLESKY, turn=30.0_dp, reason='do not lie on a grid')
  call check_fe(t, 'q4, ten fixed points', 'Q4', 11, 2, grade=.false., bc='points10', &
      expect=MASS_SOLVER_CHOLESKY, reason='not on whole lattice lines')
  call check_iga(t, 'nurbs p = 2, a non-unit weight', 2, weight=0.8_dp, &
      expect=MASS_SOLVER_CHOLESKY, reason='not the tensor-product')
  call check_fe(t, 'q8 off the midpoints, KRONECKER asked', 'Q8', 4, 3, grade=.true., &
      bc='roller', expect=MASS_SOLVER_KRONECKER, offmid=.true., asked='KRONECKER', &
      reason='not the tensor-product')
  call t%finish()
contains

  !> Lattice coordinate of line k = 0..2n (vertices at even k, midpoints between them):
  !! graded vertices x_v = (v/n)^1.4 (or uniform), scaled to length len.
  pure real(dp) function line_coord(k, n, len, grade, offmid) result(x)
    integer, intent(in) :: k, n
    real(dp), intent(in) :: len
    logical, intent(in) :: grade, offmid
    real(dp) :: a, b, w
    a = vertex(k/2, n, len, grade)
    if (mod(k, 2) == 0) then
      x = a
    else
      b = vertex(k/2 + 1, n, len, grade)
      w = 0.5_dp
      if (offmid) w = 0.4_dp
      x = a + w*(b - a)
    end if
  end function line_coord

  pure real(dp) function vertex(v, n, len, grade)
    integer, intent(in) :: v, n
    real(dp), intent(in) :: len
    logical, intent(in) :: grade
    vertex = len*real(v, dp)/n
    if (grade) vertex = len*(real(v, dp)/n)**1.4_dp
  end function vertex

  !> A grid of nx x ny elements of type et (Q4, Q8, Q9) on [0, 2] x [0, 1] (with `blocks`
  !! = 2 a second grid beside it), nodes numbered backwards and listed along the x lines (the
  !! lattice columns of the solve), or with `across` listed along the y lines (a lattice
  !! column's nodes are not one range of the model's nodes); boundary conditions `bc`:
  !! 'roller' (bottom y, lower left x), 'left' (left edge), 'left+points' (left edge and x at
  !! three top nodes), 'points10' (x at ten top nodes, y on the left edge).
  subroutine check_fe(t, label, et, nx, ny, grade, bc, expect, blocks, offmid, density2, turn, &
      reason, asked, across)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label, et, bc
    integer, intent(in) :: nx, ny, expect
    logical, intent(in) :: grade
    integer, intent(in), optional :: blocks
    logical, intent(in), optional :: offmid, density2
    real(dp), intent(in), optional :: turn
    character(len=*), intent(in), optional :: reason, asked
    logical, intent(in), optional :: across
    character(len=*), parameter :: path = 'test_kronecker_mass.inp'
    integer :: u, s, n1, n2, nb, blk, i, j, k, nn, a, b, ne, np, idx
    integer, allocatable :: id(:,:,:)
    real(dp) :: x, y, c, sn, x0
    logical :: off, two
    character(len=16) :: solver
    s = 2
    if (et == 'Q4') s = 1
    nb = 1
    if (present(blocks)) nb = blocks
    off = .false.
    if (present(offmid)) off = offmid
    two = .false.
    if (present(density2)) two = density2
    c = 1.0_dp
    sn = 0.0_dp
    if (present(turn)) then
      c = cos(turn*pi/180.0_dp)
      sn = sin(turn*pi/180.0_dp)
    end if
    solver = 'AUTO'
    if (present(asked)) solver = asked
    n1 = s*nx + 1
    n2 = s*ny + 1
    allocate(id(0:n1 - 1, 0:n2 - 1, nb), source=0)
    nn = 0
    do blk = 1, nb
      do j = 0, n2 - 1
        do i = 0, n1 - 1
          if (et == 'Q8' .and. mod(i, 2) == 1 .and. mod(j, 2) == 1) cycle
          nn = nn + 1
          id(i, j, blk) = nn
        end do
      end do
    end do
    where (id > 0) id = nn + 1 - id
    open(newunit=u, file=path, status='replace', action='write')
    call write_materials(u)
    write(u, '(a)') '*NODE'
    do blk = 1, nb
      x0 = 3.0_dp*(blk - 1)
      do k = 0, n1*n2 - 1
        if (present(across)) then
          i = k/n2
          j = mod(k, n2)
        else
          i = mod(k, n1)
          j = k/n1
        end if
        if (id(i, j, blk) == 0) cycle
        x = x0 + line_coord(i*(3 - s), nx, 2.0_dp, grade, off .and. s == 2)
        y = line_coord(j*(3 - s), ny, 1.0_dp, grade, off .and. s == 2)
        write(u, '(i0,2(", ",es24.16))') id(i, j, blk), c*x - sn*y, sn*x + c*y
      end do
    end do
    ne = 0
    do blk = 1, nb
      do b = 0, ny - 1
        do a = 0, nx - 1
          ne = ne + 1
          if (ne == 1 .or. (two .and. a == nx/2 .and. b == 0)) then
            if (two .and. a == nx/2 .and. b == 0) then
              write(u, '(a)') '*ELEMENT, TYPE='//et//', ELSET=BODY2, MATERIAL=MAT2'
            else
              write(u, '(a)') '*ELEMENT, TYPE='//et//', ELSET=BODY, MATERIAL=MAT'
            end if
          else if (two .and. a == nx/2 + 1 .and. b == 0) then
            write(u, '(a)') '*ELEMENT, TYPE='//et//', ELSET=BODY3, MATERIAL=MAT'
          end if
          i = s*a
          j = s*b
          select case (et)
          case ('Q4')
            write(u, '(i0,4(", ",i0))') ne, id(i, j, blk), id(i + 1, j, blk), &
                id(i + 1, j + 1, blk), id(i, j + 1, blk)
          case ('Q8')
            write(u, '(i0,8(", ",i0))') ne, id(i, j, blk), id(i + 2, j, blk), &
                id(i + 2, j + 2, blk), id(i, j + 2, blk), id(i + 1, j, blk), &
                id(i + 2, j + 1, blk), id(i + 1, j + 2, blk), id(i, j + 1, blk)
          case default
            write(u, '(i0,9(", ",i0))') ne, id(i, j, blk), id(i + 2, j, blk), &
                id(i + 2, j + 2, blk), id(i, j + 2, blk), id(i + 1, j, blk), &
                id(i + 2, j + 1, blk), id(i + 1, j + 2, blk), id(i, j + 1, blk), &
                id(i + 1, j + 1, blk)
          end select
        end do
      end do
    end do
    write(u, '(a)') '*NSET, NSET=BOTTOM'
    do blk = 1, nb
      do i = 0, n1 - 1
        if (id(i, 0, blk) > 0) write(u, '(i0)') id(i, 0, blk)
      end do
    end do
    write(u, '(a)') '*NSET, NSET=LEFT'
    do blk = 1, nb
      do j = 0, n2 - 1
        if (id(0, j, blk) > 0) write(u, '(i0)') id(0, j, blk)
      end do
    end do
    write(u, '(a)') '*BOUNDARY'
    select case (bc)
    case ('roller')
      write(u, '(a)') 'BOTTOM, 2, 2'
      do blk = 1, nb
        write(u, '(i0,a)') id(0, 0, blk), ', 1, 1'
      end do
    case ('left')
      write(u, '(a)') 'LEFT, 1, 2'
    case ('left+points', 'points10')
      if (bc == 'left+points') then
        write(u, '(a)') 'LEFT, 1, 2'
        np = 3
      else
        write(u, '(a)') 'LEFT, 2, 2'
        np = 10
      end if
      k = 0
      do idx = 1, n1 - 1
        if (id(idx, n2 - 1, 1) == 0) cycle
        k = k + 1
        if (k > np) exit
        write(u, '(i0,a)') id(idx, n2 - 1, 1), ', 1, 1'
      end do
    end select
    write(u, '(a)') '*MASS, TYPE=CONSISTENT'
    call write_step(u, solver)
    close(u)
    call run_case(t, label, path, expect, reason)
  end subroutine check_fe

  !> A NURBS rectangle [0, 2] x [0, 1] of degree p: coarse knots with one interior knot
  !! (at 0.3 for p = 2: graded), control points at the Greville abscissae (an exact linear
  !! map), the middle weight `weight`, refined to 6 x 5 spans; bottom fixed in y and control
  !! point 1 in x.
  subroutine check_iga(t, label, p, weight, expect, reason)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    integer, intent(in) :: p, expect
    real(dp), intent(in) :: weight
    character(len=*), intent(in), optional :: reason
    character(len=*), parameter :: path = 'test_kronecker_mass.inp'
    real(dp) :: knots(2*p + 3), grev(p + 2), w
    integer :: u, i, j, n
    n = p + 2
    knots(1:p + 1) = 0.0_dp
    knots(p + 2) = 0.3_dp
    if (p == 3) knots(p + 2) = 0.5_dp
    knots(p + 3:2*p + 3) = 1.0_dp
    do i = 1, n
      grev(i) = sum(knots(i + 1:i + p))/p
    end do
    open(newunit=u, file=path, status='replace', action='write')
    call write_materials(u)
    write(u, '(a,i0,a,i0,a,i0,a,i0)') '*PATCH, NAME=P, MATERIAL=MAT, DEGREE=', p, ',', p, &
        ', SIZE=', n, ',', n
    write(u, '(a)') '*KNOTS, DIRECTION=1'
    write(u, '(*(g0.16,:," "))') knots
    write(u, '(a)') '*KNOTS, DIRECTION=2'
    write(u, '(*(g0.16,:," "))') knots
    write(u, '(a)') '*CONTROL POINTS'
    do j = 1, n
      do i = 1, n
        w = 1.0_dp
        if (i == 2 .and. j == 2) w = weight
        write(u, '(es24.16,2(", ",es24.16))') 2.0_dp*grev(i), grev(j), w
      end do
    end do
    write(u, '(a)') '*REFINE, PATCH=P, SUBDIVIDE=3,2'
    write(u, '(a)') '*NSET, NSET=FIX, PATCH=P, SIDE=ETA0'
    write(u, '(a)') '*BOUNDARY'
    write(u, '(a)') 'FIX, 2, 2'
    write(u, '(a)') '1, 1, 1'
    write(u, '(a)') '*MASS, TYPE=CONSISTENT'
    call write_step(u, 'AUTO')
    close(u)
    call run_case(t, label, path, expect, reason)
  end subroutine check_iga

  subroutine write_materials(u)
    integer, intent(in) :: u
    write(u, '(a)') '*HEADING'
    write(u, '(a)') 'test_kronecker_mass'
    write(u, '(a)') '*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1'
    write(u, '(a)') '*MATERIAL, NAME=MAT'
    write(u, '(a)') '*ELASTIC'
    write(u, '(a)') '1000, 0.3'
    write(u, '(a)') '*DENSITY'
    write(u, '(a)') '2.5'
    write(u, '(a)') '*MATERIAL, NAME=MAT2'
    write(u, '(a)') '*ELASTIC'
    write(u, '(a)') '1000, 0.3'
    write(u, '(a)') '*DENSITY'
    write(u, '(a)') '3.5'
  end subroutine write_materials

  subroutine write_step(u, solver)
    integer, intent(in) :: u
    character(len=*), intent(in) :: solver
    write(u, '(a)') '*STEP'
    write(u, '(a)') '*DYNAMIC, EXPLICIT, MASS SOLVER='//trim(solver)
    write(u, '(a)') '1e-4, 1e-3'
    write(u, '(a)') '*END STEP'
  end subroutine write_step

  !> Reads the deck, assembles M, sets up the mass operator as a run does and solves for a
  !! load field; checks the solver taken (and the reason of a refusal) and, unless the
  !! Kronecker solver was asked for and refused, the solution against a dense solve.
  subroutine run_case(t, label, path, expect, reason)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label, path
    integer, intent(in) :: expect
    character(len=*), intent(in), optional :: reason
    type(deck_t) :: deck
    type(model_t) :: model
    type(domain_t) :: dom
    type(operators_t) :: ops
    type(mass_op_t) :: op
    type(tensor_layout_t) :: lay
    integer, allocatable :: bad(:), dofs(:), ipiv(:)
    real(dp), allocatable :: f(:,:), a(:,:), md(:,:), rhs(:), sol(:,:)
    integer :: nbad, ierr, i, c, q, nd, info, k, nn
    real(dp) :: err, scale
    call read_deck(path, deck)
    call t%true(error_count() == 0, label//': deck read')
    if (error_count() > 0) return
    call build_model(deck, model)
    call domain_init(dom, model, ierr)
    call assemble_operators(model, dom, ops, bad, nbad)
    call check_upper(t, label, ops%k)
    call tensor_layout(model, lay)
    call mass_op_init(op, dom, ops%consistent, ops%m, ops%m_diag, model%fixed, &
        solver=model%mass_solver, ierr=ierr, layout=lay)
    if (model%mass_solver == MASS_SOLVER_KRONECKER .and. expect == MASS_SOLVER_KRONECKER &
        .and. present(reason)) then
      call t%true(ierr == 1, label//': MASS SOLVER=KRONECKER asked and refused')
      call t%true(index(op%setup_msg, reason) > 0, label//': reason "'//reason//'" in "'// &
          op%setup_msg//'"')
      return
    end if
    call t%true(ierr == 0, label//': set-up')
    call t%equal_int(op%solver, expect, label//': solver taken (4 = KRONECKER, 2 = CHOLESKY)')
    if (present(reason)) call t%true(index(op%setup_msg, reason) > 0, label//': reason "'// &
        reason//'" in "'//op%setup_msg//'"')
    call t%true(model%mass_solver == MASS_SOLVER_AUTO, label//': AUTO is the default asked')
    ! a load on every dof, the solve, and the dense solve of the free dofs of each component
    nn = model%nn
    allocate(f(2, nn), a(2, nn), sol(2, nn))
    do i = 1, nn
      f(:, i) = [sin(1.3_dp*i) + 0.2_dp, cos(0.7_dp*i*i)]
    end do
    a = 0.0_dp
    call mass_solve(op, dom, f, a, ierr)
    call t%true(ierr == 0, label//': solve')
    allocate(md(nn, nn), source=0.0_dp)
    do i = 1, nn
      do q = ops%m%g%row_ptr(i), ops%m%g%row_ptr(i + 1) - 1
        md(i, ops%m%g%col(q)) = ops%m%val(q)
      end do
    end do
    sol = 0.0_dp
    do c = 1, 2
      dofs = pack([(i, i = 1, nn)], .not. model%fixed(c, :))
      nd = size(dofs)
      rhs = f(c, dofs)
      allocate(ipiv(nd))
      block
        real(dp) :: mf(nd, nd)
        mf = md(dofs, dofs)
        call dgesv(nd, 1, mf, nd, ipiv, rhs, nd, info)
      end block
      call t%true(info == 0, label//': dense solve')
      do k = 1, nd
        sol(c, dofs(k)) = rhs(k)
      end do
      deallocate(ipiv)
    end do
    scale = maxval(abs(sol))
    err = maxval(abs(a - sol))/scale
    call t%true(err <= 1.0e-11_dp, label//': M^-1 f against the dense solve, rel. error '// &
        str(err, 3))
    call t%true(all(a(1, :) == 0.0_dp .or. .not. model%fixed(1, :)) .and. &
        all(a(2, :) == 0.0_dp .or. .not. model%fixed(2, :)), label//': 0 on the fixed dofs')
    if (op%solver == MASS_SOLVER_KRONECKER) call check_fused(t, label, op, dom, f)
  end subroutine run_case

  !> The assembled K is symmetric bit for bit (each element matrix's upper triangle
  !! mirrored), so on one rank its upper blocks qualify for the consistent step's product and
  !! give the bits of the full rows in column order, and that product is K x to round-off.
  subroutine check_upper(t, label, k)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    type(bsr_t), intent(in) :: k
    type(bsr_upper_t) :: up
    real(dp), allocatable :: x(:,:), y1(:,:), y2(:,:), y3(:,:)
    integer :: i, n
    n = k%g%n
    call bsr_upper_init(k, up)
    call t%equal_int(up%n, n, label//': K symmetric bit for bit, upper storage taken')
    if (up%n /= n) return
    allocate(x(2, n), y1(2, n), y2(2, n), y3(2, n))
    do i = 1, n
      x(:, i) = [sin(0.61_dp*i) + 0.1_dp, cos(1.7_dp*i)]
    end do
    call bsr_matvec_ordered(n, k%g%row_ptr, k%g%col, k%val, x, y1)
    y2 = huge(1.0_dp)
    call bsr_upper_matvec(up, x, y2)
    call bsr_matvec(n, k%g%row_ptr, k%g%col, k%val, x, y3)
    call t%true(all(y1 == y2), label//': K x from the upper blocks = full rows, bit for bit')
    call t%true(maxval(abs(y1 - y3)) <= 1.0e-13_dp*maxval(abs(y3)), label// &
        ': K x in column order = the two-chain product to round-off')
  end subroutine check_upper

  !> The step's updates folded into the solve (mass_step, taken by one rank) against the
  !! solve of -kf and the updates it replaces: v + dt a and u + dt v, the same bits.
  subroutine check_fused(t, label, op, dom, kf)
    type(checker_t), intent(inout) :: t
    character(len=*), intent(in) :: label
    type(mass_op_t), intent(inout) :: op
    type(domain_t), intent(inout) :: dom
    real(dp), intent(in) :: kf(:,:)
    real(dp), allocatable :: u(:,:), v(:,:), a(:,:), v1(:,:), un1(:,:), v2(:,:), un2(:,:)
    real(dp), parameter :: dt = 0.0137_dp
    integer :: i, ierr
    allocate(u, v, a, v1, un1, v2, un2, mold=kf)
    do i = 1, size(kf, 2)
      u(:, i) = [cos(0.31_dp*i), sin(2.1_dp*i)]
      v(:, i) = [sin(0.17_dp*i*i), cos(1.9_dp*i) - 0.3_dp]
    end do
    call t%true(mass_steps_fused(op), label//': one rank folds the updates into the solve')
    call mass_solve(op, dom, -kf, a, ierr)
    v1 = v + dt*a
    un1 = u + dt*v1
    v2 = v
    un2 = 0.0_dp
    call mass_step(op, kf, dt, u, v2, un2)
    call t%true(all(v1 == v2) .and. all(un1 == un2), label//': the fused step gives the '// &
        'bits of the solve and the updates')
  end subroutine check_fused
end program test_kronecker_mass
