!> Readers of the NURBS patch cards (doc/user-guide.md §4, doc/iga.md): *PATCH opens a patch, the
!! *KNOTS and *CONTROL POINTS that follow it fill it in, and *ELEVATE / *REFINE record a
!! refinement of a named patch. A 2D analysis has bivariate patches (two values per
!! direction parameter, control points "x, y, w"), a 3D one trivariate patches (three values,
!! "x, y, z, w"; doc/iga.md §11).
!!
!! The knot vectors and control points are checked here, card by card (length, order,
!! openness, multiplicities, weights); that every patch got both, and that *ELEVATE / *REFINE
!! name a known patch, is checked over the whole deck by `check_deck` (ictus_io_deck_checks).
!! `app/build_model` applies the refinements in deck order.
module ictus_io_deck_patch
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: str, str_list
  use ictus_io_deck_lexer, only: line_where
  use ictus_io_deck_types, only: deck_t, patch_in_t, patch_op_in_t, OP_ELEVATE, OP_REFINE
  use ictus_io_deck_card, only: card_t, reader_t, max_generated, card_error, check_params, &
      get_name, get_ints, get_choice, no_data, stream_reals, get_param
  use ictus_io_deck_grow, only: grow_patches, grow_patch_ops
  implicit none
  private
  public :: read_patch, read_knots, read_control_points, read_patch_op

contains

  !> *PATCH, NAME=, MATERIAL=, DEGREE=p1,p2, SIZE=n1,n2 [, DILATATION=FULL|MEAN]
  !! [, MERGE=YES|NO]: opens a patch for *KNOTS and *CONTROL POINTS. In a 3D analysis the
  !! patch is trivariate: DEGREE=p1,p2,p3, SIZE=n1,n2,n3.
  subroutine read_patch(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(patch_in_t) :: p
    integer :: k, merge, nd

    rd%patch = -1
    nd = d%ndm
    call check_params(c, 'NAME|MATERIAL|DEGREE|SIZE|DILATATION|MERGE', '')
    call get_name(c, 'NAME', .true., p%name)
    call get_choice(c, 'DILATATION', 'FULL|MEAN', p%dilatation)
    call get_choice(c, 'MERGE', 'YES|NO', merge)
    p%merge = merge == 1
    if (p%merge .and. nd == 3) call card_error(c, 'MERGE=YES: not yet in 3D (the control '// &
        'points of trivariate patches are not merged across their faces); one trivariate '// &
        'patch per body, or hexahedra')
    call get_name(c, 'MATERIAL', .true., p%material)
    if (directions_ok(c, 'DEGREE', nd, 'p') .and. get_ints(c, 'DEGREE', nd, &
        directions(nd, 'p'), p%degree(1:nd), required=.true.)) then
      if (any(p%degree(1:nd) < 1)) call card_error(c, 'DEGREE='//str_list(p%degree(1:nd))// &
          ' must be >= 1 in every direction')
    end if
    if (directions_ok(c, 'SIZE', nd, 'n') .and. get_ints(c, 'SIZE', nd, &
        directions(nd, 'n')//' control points per direction', p%size(1:nd), &
        required=.true.)) then
      if (.not. c%bad .and. any(p%size(1:nd) < p%degree(1:nd) + 1)) then
        call card_error(c, 'SIZE='//str_list(p%size(1:nd))// &
            ' must be at least DEGREE+1 in each direction')
      else if (product(int(max(p%size(1:nd), 1), i8)) > max_generated) then
        call card_error(c, 'SIZE='//str_list(p%size(1:nd))// &
            ' is too large (at most '//str(max_generated)//' control points)')
      end if
    end if
    call no_data(c, rd)
    do k = 1, d%n_patches
      if (d%patches(k)%name == p%name .and. len_trim(p%name) > 0) then
        call card_error(c, 'duplicate patch name '//trim(p%name)//' (first defined at '// &
            trim(d%patches(k)%where)//')')
      end if
    end do
    if (c%bad) return
    p%where = c%where
    call grow_patches(d%patches, d%n_patches + 1)
    d%n_patches = d%n_patches + 1
    d%patches(d%n_patches) = p
    rd%patch = d%n_patches
  end subroutine read_patch

  !> "x1,x2" (2D) or "x1,x2,x3" (3D): the values a per-direction parameter expects.
  pure function directions(nd, x) result(what)
    integer, intent(in) :: nd
    character(len=*), intent(in) :: x
    character(len=:), allocatable :: what
    integer :: k
    what = x//'1'
    do k = 2, nd
      what = what//','//x//char(ichar('0') + k)
    end do
  end function directions


  !> False, with the error said, when the per-direction parameter `key` of card c has the
  !! number of values of the other dimension: three (a trivariate patch) in a 2D analysis,
  !! two (a bivariate patch) in a 3D one; x names the values in the message (p: p1,p2).
  !! Other counts are left to get_ints.
  logical function directions_ok(c, key, nd, x) result(ok)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key, x
    integer, intent(in) :: nd
    character(len=:), allocatable :: v
    integer :: m, k
    ok = .true.
    if (.not. get_param(c, key, v)) return
    if (len_trim(v) == 0) return
    m = count([(v(k:k) == ',', k = 1, len(v))]) + 1
    if (nd == 2 .and. m == 3) then
      call card_error(c, key//'='//v//' has three values: a trivariate patch, which needs '// &
          '*ANALYSIS, TYPE=3D; the patches of a 2D analysis are bivariate (expected '// &
          key//'='//directions(2, x)//')')
      ok = .false.
    else if (nd == 3 .and. m == 2) then
      call card_error(c, key//'='//v//' has two values: a bivariate patch; the patches of a '// &
          '3D analysis are trivariate (expected '//key//'='//directions(3, x)//')')
      ok = .false.
    end if
  end function directions_ok

  !> True when a patch sub-card may be read now; reports it otherwise.
  logical function patch_context(c, rd) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    ok = rd%patch > 0
    if (rd%patch == 0) call card_error(c, 'no preceding *PATCH card (expected *PATCH, '// &
        'NAME=..., DEGREE=..., SIZE=... before it)')
  end function patch_context

  !> *KNOTS, DIRECTION=1|2 (and 3 in a 3D analysis): the knot vector (stream of numbers over
  !! any number of lines).
  subroutine read_knots(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    real(dp), allocatable :: u(:)
    integer, allocatable :: tline(:)
    integer :: dir(1), n, p

    call check_params(c, 'DIRECTION', '')
    if (get_ints(c, 'DIRECTION', 1, trim(merge('1, 2 or 3', '1 or 2   ', d%ndm == 3)), dir, &
        required=.true.)) then
      if (dir(1) == 3 .and. d%ndm == 2) then
        call card_error(c, 'bad value DIRECTION=3: the third direction of a trivariate '// &
            'patch (3D); the patches of a 2D analysis are bivariate (expected 1 or 2)')
      else if (dir(1) < 1 .or. dir(1) > d%ndm) then
        call card_error(c, 'bad value DIRECTION='//str(dir(1))//' (expected '// &
            trim(merge('1, 2 or 3', '1 or 2   ', d%ndm == 3))//')')
      end if
    end if
    if (.not. patch_context(c, rd) .or. c%bad) return
    associate (pa => d%patches(rd%patch))
      if (pa%has_knots(dir(1))) then
        call card_error(c, 'second *KNOTS, DIRECTION='//str(dir(1))//' for patch '// &
            trim(pa%name))
        return
      end if
      pa%has_knots(dir(1)) = .true.
      n = pa%size(dir(1))
      p = pa%degree(dir(1))
      if (.not. stream_reals(c, rd, '*KNOTS: expected the knot vector (numbers)', u, tline)) &
          return
      if (.not. knots_ok(c, rd, u, tline, n, p, dir(1))) return
      select case (dir(1))
      case (1)
        pa%knots1 = u
      case (2)
        pa%knots2 = u
      case (3)
        pa%knots3 = u
      end select
    end associate
  end subroutine read_knots

  !> Checks a knot vector: length n+p+1, non-decreasing, open, interior multiplicity <= p.
  logical function knots_ok(c, rd, u, tline, n, p, dir) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(in) :: rd
    real(dp), intent(in) :: u(:)
    integer, intent(in) :: tline(:), n, p, dir
    integer :: k, m, mult
    character(len=:), allocatable :: dd

    ok = .false.
    dd = ', DIRECTION='//str(dir)
    if (size(u) /= n + p + 1) then
      call card_error(c, 'knot vector of length '//str(size(u))//dd//': expected n + p + 1 = '// &
          str(n + p + 1)//' knots (SIZE n='//str(n)//', DEGREE p='//str(p)//')')
      return
    end if
    do k = 2, size(u)
      if (u(k) < u(k - 1)) then
        call input_error(line_where(rd%src, tline(k)), '*KNOTS: decreasing knot vector'//dd// &
            ': knot '//str(k)//' = '//str(u(k))//' < knot '//str(k - 1)//' = '//str(u(k - 1))// &
            ' (expected non-decreasing knots)')
        return
      end if
    end do
    m = size(u)
    if (any(u(1:p + 1) /= u(1)) .or. any(u(m - p:m) /= u(m))) then
      call card_error(c, 'knot vector not open'//dd//': the first and the last p + 1 = '// &
          str(p + 1)//' knots must be equal')
      return
    end if
    if (.not. (u(m) > u(1))) then
      call card_error(c, 'knot vector has zero length'//dd//' (first knot = last knot)')
      return
    end if
    mult = 1
    do k = p + 3, m - p - 1
      if (u(k) == u(k - 1)) then
        mult = mult + 1
      else
        mult = 1
      end if
      if (mult > p) then
        call input_error(line_where(rd%src, tline(k)), '*KNOTS: interior knot '// &
            str(u(k))//dd//' repeated more than p = '//str(p)//' times')
        return
      end if
    end do
    ok = .true.
  end function knots_ok

  !> *CONTROL POINTS: n1*n2 records "x, y, w" (2D) or n1*n2*n3 records "x, y, z, w" (3D),
  !! as a stream, direction-1 index fastest, then 2, then 3; w > 0.
  subroutine read_control_points(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    real(dp), allocatable :: v(:)
    integer, allocatable :: tline(:)
    integer :: ncp, k, nd, nv
    character(len=:), allocatable :: rec, other

    call check_params(c, '', '')
    if (.not. patch_context(c, rd) .or. c%bad) return
    nd = d%ndm
    nv = nd + 1
    rec = trim(merge('"x, y, z, w"', '"x, y, w"   ', nd == 3))
    associate (pa => d%patches(rd%patch))
      if (pa%has_cp) then
        call card_error(c, 'second *CONTROL POINTS for patch '//trim(pa%name))
        return
      end if
      pa%has_cp = .true.
      if (.not. stream_reals(c, rd, '*CONTROL POINTS: expected '//rec//' records (numbers)', &
          v, tline)) return
      ncp = product(pa%size(1:nd))
      if (size(v) /= nv*ncp) then
        other = ''
        if (nd == 2 .and. size(v) == 4*ncp) other = ' (4 values per control point, '// &
            '"x, y, z, w", are a trivariate patch of a 3D analysis)'
        if (nd == 3 .and. size(v) == 3*ncp) other = ' (3 values per control point, '// &
            '"x, y, w", are a bivariate patch of a 2D analysis; in 3D each is "x, y, z, w")'
        call card_error(c, 'patch '//trim(pa%name)//' has SIZE='//str_list(pa%size(1:nd))// &
            ': expected '//str(ncp)//' control points '//rec//' = '// &
            str(nv*ncp)//' numbers, found '//str(size(v))//' numbers'//other)
        return
      end if
      pa%cp = reshape(v, [nv, ncp])
      do k = 1, ncp
        if (.not. (pa%cp(nv, k) > 0.0_dp)) then
          call input_error(line_where(rd%src, tline(nv*k)), '*CONTROL POINTS: weight w of '// &
              'control point '//str(k)//' must be > 0, found '//str(pa%cp(nv, k)))
        end if
      end do
    end associate
  end subroutine read_control_points

  !> *ELEVATE, PATCH=, DEGREE=q1,q2 or *REFINE, PATCH=, SUBDIVIDE=k1,k2 (resolved later);
  !! three values each in a 3D analysis.
  subroutine read_patch_op(c, rd, d)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(inout) :: rd
    type(deck_t), intent(inout) :: d
    type(patch_op_in_t) :: op
    character(len=:), allocatable :: key, x
    integer :: nd

    nd = d%ndm
    if (c%kw%name == 'ELEVATE') then
      op%kind = OP_ELEVATE
      key = 'DEGREE'
      x = 'q'
    else
      op%kind = OP_REFINE
      key = 'SUBDIVIDE'
      x = 'k'
    end if
    call check_params(c, 'PATCH|'//key, '')
    call get_name(c, 'PATCH', .true., op%patch)
    if (directions_ok(c, key, nd, x) .and. get_ints(c, key, nd, directions(nd, x), &
        op%values(1:nd), required=.true.)) then
      if (any(op%values(1:nd) < 1)) call card_error(c, key//'='//str_list(op%values(1:nd))// &
          ' must be >= 1 in every direction')
    end if
    call no_data(c, rd)
    if (c%bad) return
    op%where = c%where
    call grow_patch_ops(d%patch_ops, d%n_patch_ops + 1)
    d%n_patch_ops = d%n_patch_ops + 1
    d%patch_ops(d%n_patch_ops) = op
  end subroutine read_patch_op

end module ictus_io_deck_patch
