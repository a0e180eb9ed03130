!> The card being read and the helpers every card reader shares (doc/user-guide.md §3).
!!
!! `read_deck` (ictus_io_deck_reader) hands each card to one routine `read_<card>` as a
!! `card_t` (its keyword line and the range of its data lines), together with the `reader_t`
!! (the loaded source and what the reader remembers from one card to the next). The helpers
!! here check and convert what a card reader needs, and report every problem with
!! `input_error` in the same words for every card:
!! * keyword-line helpers: allowed parameters and flags, names, choices, numbers, and
!!   `card_error`, which marks the card bad so that its data is skipped;
!! * data-line helpers: no data, one line, a fixed number of values per line, a stream of
!!   numbers over any number of lines, and single fields as integers, reals, names or node
!!   targets.
module ictus_io_deck_card
  use ictus_core_kinds, only: dp, str_len
  use ictus_core_ticker, only: ticker_t
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: upper, str
  use ictus_io_deck_lexer, only: token_t, deck_source_t, keyword_t, line_where, split_values, &
      parse_real, parse_int, is_number, shown, collapse_blanks
  use ictus_io_deck_types, only: where_len
  implicit none
  private
  public :: card_t, reader_t, max_generated
  public :: card_error, check_params, get_param, has_param, has_flag, get_name, get_choice, &
      get_ints, get_reals, get_positive
  public :: no_data, has_data, one_line, line_reals, stream_reals, count_ok, tok_int, &
      tok_real, tok_name, tok_target, plural, target_dof_value, dof_names, LINE_OK, LINE_STOP, &
      LINE_SKIP

  !> One card being read: its keyword line and the range of its data lines.
  type :: card_t
    type(keyword_t) :: kw
    !> "*NAME" for messages.
    character(len=:), allocatable :: label
    character(len=where_len) :: where = ''
    !> Data lines are src%lines(first:last) (empty when last < first).
    integer :: first = 1
    integer :: last = 0
    !> Set once a problem on the keyword line was reported: the data is then skipped.
    logical :: bad = .false.
  end type card_t

  !> What the reader remembers from one card to the next.
  type :: reader_t
    type(deck_source_t) :: src
    !> Material that *ELASTIC/*DENSITY belong to: 0 none, -1 a broken *MATERIAL (ignore).
    integer :: material = 0
    !> Patch that *KNOTS/*CONTROL POINTS belong to: 0 none, -1 a broken *PATCH (ignore).
    integer :: patch = 0
    !> *SURFACE INTERACTION that *FRICTION belongs to: 0 none, -1 a broken one (ignore).
    integer :: interaction = 0
    logical :: in_step = .false.
    !> Inside a second (rejected) *STEP: its cards are skipped.
    logical :: skip_step = .false.
    logical :: has_dynamic = .false.
    logical :: has_history = .false.
    logical :: has_field = .false.
    logical :: has_restart = .false.
    logical :: has_analysis = .false.
    !> Allocated length of the node arrays (>= deck%n_nodes).
    integer :: node_cap = 0
    !> SKIP_* bits: kinds of definitions that had errors (see check_deck).
    integer :: broken = 0
    !> Progress lines of a long read, ticked with the line being read (long data cards
    !! tick every line too).
    type(ticker_t) :: tk
  end type reader_t

  !> Most values a *NSET GENERATE or *CONTROL POINTS card may produce (guards memory).
  integer, parameter :: max_generated = 10000000

  !> What `target_dof_value` found.
  integer, parameter :: LINE_OK = 0, LINE_STOP = 1, LINE_SKIP = 2

contains

  ! ------------------------------------------------------------------------------------------
  ! Keyword-line helpers: parameters
  ! ------------------------------------------------------------------------------------------

  !> Reports a problem with the card at its keyword line and marks the card bad.
  subroutine card_error(c, msg)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: msg
    call input_error(c%where, c%label//': '//msg)
    c%bad = .true.
  end subroutine card_error

  !> Checks the parameters of `c` against `allowed` (NAME=value parameters) and `flags` (bare
  !! words), both as '|'-separated lists: unknown, valueless and repeated parameters.
  subroutine check_params(c, allowed, flags)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: allowed, flags
    integer :: k, j
    do k = 1, c%kw%n_params
      associate (p => c%kw%params(k))
        if (p%is_flag .and. in_list(p%name, flags)) then
          continue
        else if (p%is_flag .and. in_list(p%name, allowed)) then
          call card_error(c, 'parameter '//p%name//' needs a value ('//p%name//'=...)')
        else if (.not. p%is_flag .and. in_list(p%name, flags)) then
          call card_error(c, p%name//' takes no value (write it as a bare word)')
        else if (.not. in_list(p%name, allowed)) then
          call card_error(c, 'unknown parameter '//shown(p%name)//expected_params(allowed, &
              flags))
        else if (len(p%value) == 0) then
          call card_error(c, 'parameter '//p%name//'= has no value')
        end if
        do j = 1, k - 1
          if (c%kw%params(j)%name == p%name) then
            call card_error(c, 'parameter '//p%name//' given twice')
            exit
          end if
        end do
      end associate
    end do
  end subroutine check_params

  !> " (expected A=, B=, FLAG)" or " (this card takes no parameters)".
  pure function expected_params(allowed, flags) result(r)
    character(len=*), intent(in) :: allowed, flags
    character(len=:), allocatable :: r
    integer :: k
    r = ''
    if (len(allowed) > 0) r = allowed//'='
    do k = len(r), 1, -1
      if (r(k:k) == '|') r = r(1:k - 1)//'=, '//r(k + 1:)
    end do
    if (len(flags) > 0) then
      if (len(r) > 0) r = r//', '
      r = r//flags
    end if
    do k = len(r), 1, -1
      if (r(k:k) == '|') r = r(1:k - 1)//', '//r(k + 1:)
    end do
    if (len(r) == 0) then
      r = ' (this card takes no parameters)'
    else
      r = ' (expected '//r//')'
    end if
  end function expected_params

  !> True when `name` is one of the '|'-separated `list`.
  pure logical function in_list(name, list)
    character(len=*), intent(in) :: name, list
    in_list = len(name) > 0 .and. index('|'//list//'|', '|'//name//'|') > 0
  end function in_list

  !> The value of parameter `name` (first occurrence) in `value`; false when absent or a flag.
  logical function get_param(c, name, value) result(found)
    type(card_t), intent(in) :: c
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: value
    integer :: k
    found = .false.
    value = ''
    do k = 1, c%kw%n_params
      if (c%kw%params(k)%name == name .and. .not. c%kw%params(k)%is_flag) then
        value = c%kw%params(k)%value
        found = len(value) > 0
        return
      end if
    end do
  end function get_param

  !> True when parameter `name=` is present.
  logical function has_param(c, name)
    type(card_t), intent(in) :: c
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: v
    has_param = get_param(c, name, v)
  end function has_param

  !> True when the bare word `flag` is present.
  logical function has_flag(c, flag)
    type(card_t), intent(in) :: c
    character(len=*), intent(in) :: flag
    integer :: k
    has_flag = .false.
    do k = 1, c%kw%n_params
      if (c%kw%params(k)%is_flag .and. c%kw%params(k)%name == flag) has_flag = .true.
    end do
  end function has_flag

  !> Reports a missing required parameter.
  subroutine missing(c, name, what)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: name, what
    call card_error(c, 'missing required parameter '//name//'='//what)
  end subroutine missing

  !> A name parameter (NAME=, MATERIAL=, ELSET=, ...) in upper case; '' when absent or bad.
  subroutine get_name(c, key, required, name)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key
    logical, intent(in) :: required
    character(len=*), intent(out) :: name
    character(len=:), allocatable :: v
    name = ''
    if (.not. get_param(c, key, v)) then
      if (required) call missing(c, key, 'name')
      return
    end if
    if (.not. valid_name(v)) then
      call card_error(c, 'bad name '//key//'='//shown(v)//name_rule())
      return
    end if
    name = upper(v)
  end subroutine get_name

  !> One of the '|'-separated `choices` for parameter `key`: its position, 0 when absent.
  subroutine get_choice(c, key, choices, k, required)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key, choices
    integer, intent(out) :: k
    logical, intent(in), optional :: required
    character(len=:), allocatable :: v, u, list
    integer :: pos, next
    k = 0
    if (.not. get_param(c, key, v)) then
      if (present(required)) then
        if (required) call missing(c, key, choices)
      end if
      return
    end if
    u = upper(collapse_blanks(v))
    pos = 1
    do
      k = k + 1
      next = index(choices(pos:), '|')
      if (next == 0) then
        if (u == choices(pos:)) return
        exit
      end if
      if (u == choices(pos:pos + next - 2)) return
      pos = pos + next
    end do
    k = 0
    list = choices
    do pos = len(list), 1, -1
      if (list(pos:pos) == '|') list = list(1:pos - 1)//', '//list(pos + 1:)
    end do
    call card_error(c, 'bad value '//key//'='//shown(v)//' (expected one of '//list//')')
  end subroutine get_choice

  !> The text `v` of parameter `key` and its m comma-separated values; false when absent
  !! (then reported as missing if `required`).
  logical function param_values(c, key, what, v, toks, m, required) result(found)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key, what
    character(len=:), allocatable, intent(out) :: v
    type(token_t), allocatable, intent(out) :: toks(:)
    integer, intent(out) :: m
    logical, intent(in), optional :: required
    m = 0
    found = get_param(c, key, v)
    if (.not. found) then
      if (present(required)) then
        if (required) call missing(c, key, what)
      end if
      return
    end if
    call split_values(v, toks, m)
  end function param_values

  !> `n` integers of parameter `key` (e.g. DEGREE=2,2); false when absent or bad (reported).
  logical function get_ints(c, key, n, what, vals, required) result(ok)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key, what
    integer, intent(in) :: n
    integer, intent(inout) :: vals(n)
    logical, intent(in), optional :: required
    character(len=:), allocatable :: v
    type(token_t), allocatable :: toks(:)
    integer :: m, k
    ok = .false.
    if (.not. param_values(c, key, what, v, toks, m, required)) return
    if (m == n) then
      ok = .true.
      do k = 1, n
        if (ok) call parse_int(toks(k)%s, vals(k), ok)
      end do
    end if
    if (.not. ok) call card_error(c, 'bad value '//key//'='//shown(v)//' (expected '// &
        str(n)//' integer'//plural(n)//': '//what//')')
  end function get_ints

  !> `n` reals of parameter `key` (e.g. POINT=x,y); false when absent or bad (reported).
  logical function get_reals(c, key, n, what, vals, required) result(ok)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key, what
    integer, intent(in) :: n
    real(dp), intent(inout) :: vals(n)
    logical, intent(in), optional :: required
    character(len=:), allocatable :: v
    type(token_t), allocatable :: toks(:)
    integer :: m, k
    ok = .false.
    if (.not. param_values(c, key, what, v, toks, m, required)) return
    if (m == n) then
      ok = .true.
      do k = 1, n
        if (ok) call parse_real(toks(k)%s, vals(k), ok)
      end do
    end if
    if (.not. ok) call card_error(c, 'bad value '//key//'='//shown(v)//' (expected '// &
        str(n)//' number'//plural(n)//': '//what//')')
  end function get_reals

  !> A required parameter `key` that must be a number > 0 (PENALTY=).
  subroutine get_positive(c, key, x)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: key
    real(dp), intent(inout) :: x
    real(dp) :: v(1)
    if (get_reals(c, key, 1, 'a number > 0', v, required=.true.)) then
      if (v(1) > 0.0_dp) then
        x = v(1)
      else
        call card_error(c, key//'='//str(v(1))//' must be > 0')
      end if
    end if
  end subroutine get_positive

  !> True for a valid name: a letter or '_', then letters, digits, '_', '-' or '.', at most
  !! str_len characters.
  pure logical function valid_name(s)
    character(len=*), intent(in) :: s
    integer :: k
    character :: ch
    valid_name = .false.
    if (len(s) == 0 .or. len(s) > str_len) return
    do k = 1, len(s)
      ch = s(k:k)
      if ((ch >= 'A' .and. ch <= 'Z') .or. (ch >= 'a' .and. ch <= 'z') .or. ch == '_') cycle
      if (k > 1 .and. ((ch >= '0' .and. ch <= '9') .or. ch == '-' .or. ch == '.')) cycle
      return
    end do
    valid_name = .true.
  end function valid_name

  !> The naming rule, for messages.
  pure function name_rule() result(r)
    character(len=:), allocatable :: r
    r = ' (expected a name: a letter or _, then letters, digits, _, - or ., at most '// &
        str(str_len)//' characters)'
  end function name_rule

  ! ------------------------------------------------------------------------------------------
  ! Data-line helpers
  ! ------------------------------------------------------------------------------------------

  !> Reports data lines on a card that takes none.
  subroutine no_data(c, rd)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(in) :: rd
    if (c%last < c%first) return
    call input_error(line_where(rd%src, c%first), c%label//': takes no data lines, found "'// &
        shown(rd%src%lines(c%first)%text)//'"')
  end subroutine no_data

  !> True when the card has data lines; reports "expect, found no data line" otherwise.
  logical function has_data(c, expect) result(ok)
    type(card_t), intent(inout) :: c
    character(len=*), intent(in) :: expect
    ok = c%last >= c%first
    if (.not. ok) call input_error(c%where, expect//', found no data line')
  end function has_data

  !> The single data line of a card (index `i`); reports a missing or extra line.
  logical function one_line(c, rd, expect, i) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(in) :: rd
    character(len=*), intent(in) :: expect
    integer, intent(out) :: i
    i = c%first
    ok = has_data(c, expect)
    if (ok .and. c%last > c%first) then
      call input_error(line_where(rd%src, c%first + 1), expect//' on one data line, '// &
          'found another line "'//shown(rd%src%lines(c%first + 1)%text)//'"')
      ok = .false.
    end if
  end function one_line

  !> Exactly `n` numbers from data line `i`.
  logical function line_reals(rd, i, n, expect, v) result(ok)
    type(reader_t), intent(in) :: rd
    integer, intent(in) :: i, n
    character(len=*), intent(in) :: expect
    real(dp), intent(out) :: v(n)
    type(token_t), allocatable :: toks(:)
    integer :: m, k
    v = 0.0_dp
    call split_values(rd%src%lines(i)%text, toks, m)
    ok = count_ok(m, n, n, expect, line_where(rd%src, i))
    do k = 1, n
      if (ok) ok = tok_real(toks, k, expect, line_where(rd%src, i), v(k))
    end do
  end function line_reals

  !> All data of a card as one stream of numbers `v`, with the data-line index of each.
  logical function stream_reals(c, rd, expect, v, tline) result(ok)
    type(card_t), intent(inout) :: c
    type(reader_t), intent(in) :: rd
    character(len=*), intent(in) :: expect
    real(dp), allocatable, intent(out) :: v(:)
    integer, allocatable, intent(out) :: tline(:)
    type(token_t), allocatable :: toks(:)
    integer :: i, n, k, m, cap
    real(dp), allocatable :: tv(:)
    integer, allocatable :: tl(:)

    ok = has_data(c, expect)
    cap = 16
    allocate(v(cap), tline(cap))
    m = 0
    do i = c%first, c%last
      if (.not. ok) exit
      call split_values(rd%src%lines(i)%text, toks, n)
      if (m + n > cap) then
        cap = max(2*cap, m + n)
        allocate(tv(cap), tl(cap))
        tv(1:m) = v(1:m)
        tl(1:m) = tline(1:m)
        call move_alloc(tv, v)
        call move_alloc(tl, tline)
      end if
      do k = 1, n
        if (ok) ok = tok_real(toks, k, expect, line_where(rd%src, i), v(m + k))
        tline(m + k) = i
      end do
      m = m + n
      if (m > 3*max_generated) then
        call input_error(line_where(rd%src, i), expect//', found more than '// &
            str(3*max_generated)//' numbers')
        ok = .false.
      end if
    end do
    v = v(1:m)
    tline = tline(1:m)
  end function stream_reals

  !> Checks nmin <= n <= nmax; reports "expect, found n values" otherwise.
  logical function count_ok(n, nmin, nmax, expect, where) result(ok)
    integer, intent(in) :: n, nmin, nmax
    character(len=*), intent(in) :: expect, where
    ok = n >= nmin .and. n <= nmax
    if (.not. ok) call input_error(where, expect//', found '//str(n)//' value'//plural(n))
  end function count_ok

  !> Token `k` as an integer; reports 'expect, found "tok" in field k' otherwise.
  logical function tok_int(toks, k, expect, where, i) result(ok)
    type(token_t), intent(in) :: toks(:)
    integer, intent(in) :: k
    character(len=*), intent(in) :: expect, where
    integer, intent(out) :: i
    call parse_int(toks(k)%s, i, ok)
    if (.not. ok) call input_error(where, expect//', found "'//shown(toks(k)%s)// &
        '" in field '//str(k)//' (expected an integer)')
  end function tok_int

  !> Token `k` as a real; reports 'expect, found "tok" in field k' otherwise.
  logical function tok_real(toks, k, expect, where, x) result(ok)
    type(token_t), intent(in) :: toks(:)
    integer, intent(in) :: k
    character(len=*), intent(in) :: expect, where
    real(dp), intent(out) :: x
    call parse_real(toks(k)%s, x, ok)
    if (ok) return
    if (is_number(toks(k)%s)) then
      call input_error(where, expect//', found "'//shown(toks(k)%s)//'" in field '// &
          str(k)//' (out of range: expected a magnitude between 1e-307 and 1e308)')
    else
      call input_error(where, expect//', found "'//shown(toks(k)%s)//'" in field '// &
          str(k)//' (expected a number)')
    end if
  end function tok_real

  !> Token `k` as a name (upper case); reports a bad name.
  logical function tok_name(toks, k, expect, where, name) result(ok)
    type(token_t), intent(in) :: toks(:)
    integer, intent(in) :: k
    character(len=*), intent(in) :: expect, where
    character(len=*), intent(out) :: name
    ok = valid_name(toks(k)%s)
    name = ''
    if (ok) then
      name = upper(toks(k)%s)
    else
      call input_error(where, expect//', found "'//shown(toks(k)%s)//'" in field '// &
          str(k)//name_rule())
    end if
  end function tok_name

  !> A data line "node set or node id, dof, value" of `card` (*CLOAD, *INITIAL CONDITIONS):
  !! LINE_OK; LINE_STOP after an error in its form (the card's other lines are not read);
  !! LINE_SKIP after a dof outside 1..ndm (the next line is read).
  integer function target_dof_value(text, card, expect, where, target, dof, value, ndm) &
      result(status)
    character(len=*), intent(in) :: text, card, expect, where
    integer, intent(in) :: ndm
    character(len=*), intent(out) :: target
    integer, intent(out) :: dof
    real(dp), intent(out) :: value
    type(token_t), allocatable :: toks(:)
    integer :: n
    status = LINE_STOP
    dof = 0
    value = 0.0_dp
    call split_values(text, toks, n)
    if (.not. count_ok(n, 3, 3, expect, where)) return
    if (.not. tok_target(toks, 1, expect, where, target)) return
    if (.not. tok_int(toks, 2, expect, where, dof)) return
    if (.not. tok_real(toks, 3, expect, where, value)) return
    status = LINE_OK
    if (dof >= 1 .and. dof <= ndm) return
    call input_error(where, card//': dof '//str(dof)//' outside 1..'//str(ndm)//' ('// &
        dof_names(ndm)//')')
    status = LINE_SKIP
  end function target_dof_value

  !> What the dofs of a model of dimension ndm are, for messages: "1 = x, 2 = y" (2D; dof 3
  !! would need *ANALYSIS, TYPE=3D) or "1 = x, 2 = y, 3 = z".
  function dof_names(ndm) result(t)
    integer, intent(in) :: ndm
    character(len=:), allocatable :: t
    t = '1 = x, 2 = y'
    if (ndm == 3) t = t//', 3 = z'
    if (ndm == 2) t = t//'; dof 3 (z) is in a 3D analysis, *ANALYSIS, TYPE=3D'
  end function dof_names

  !> Token `k` as a node set name or a node id (stored as its canonical digits).
  logical function tok_target(toks, k, expect, where, target) result(ok)
    type(token_t), intent(in) :: toks(:)
    integer, intent(in) :: k
    character(len=*), intent(in) :: expect, where
    character(len=*), intent(out) :: target
    integer :: id
    call parse_int(toks(k)%s, id, ok)
    if (ok) then
      target = str(id)
      if (id <= 0) then
        call input_error(where, expect//', found node id '//str(id)//' in field '//str(k)// &
            ' (ids are > 0)')
        ok = .false.
      end if
    else
      ok = tok_name(toks, k, expect, where, target)
    end if
  end function tok_target

  !> 's' unless n == 1.
  pure function plural(n) result(r)
    integer, intent(in) :: n
    character(len=:), allocatable :: r
    r = trim(merge('s', ' ', n /= 1))
  end function plural

end module ictus_io_deck_card
