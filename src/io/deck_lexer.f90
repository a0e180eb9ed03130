!> Lexical layer of the deck reader: files -> logical lines -> keyword lines and value tokens.
!!
!! `load_deck` reads the main deck and every `*INCLUDE`d file (recursively, detecting cycles)
!! into one flat list of logical lines. Comment lines (`**`), trailing `** comments` and blank
!! lines are dropped; every remaining line keeps its file and line number. The reader then
!! splits keyword lines with `parse_keyword` and data lines with `split_values`, and converts
!! tokens with `parse_real` / `parse_int`, which accept only well-formed numbers (no `nan`,
!! `inf`, `1.0.0`, and nothing whose magnitude overflows).
!! Nothing here uses a fixed-length line buffer: files are read whole in stream mode.
module ictus_io_deck_lexer
  use ictus_core_kinds, only: dp, i8
  use ictus_core_errors, only: input_error
  use ictus_core_strings, only: upper, str
  use ictus_core_ticker, only: ticker_t, ticker_start
  implicit none
  private
  public :: token_t, deck_line_t, deck_source_t, param_t, keyword_t, load_deck, line_where, &
      parse_keyword, split_values, split_fields, parse_real, parse_int, is_number, shown, collapse_blanks

  !> A variable-length string (one value token, or one file path).
  type :: token_t
    character(len=:), allocatable :: s
  end type token_t

  !> One logical line of the deck: comment stripped, left-adjusted, non-empty.
  type :: deck_line_t
    character(len=:), allocatable :: text
    !> Index into `deck_source_t%files`.
    integer :: file = 0
    !> Line number in that file (1-based).
    integer :: line = 0
    !> True for a line starting with `*` (a keyword line).
    logical :: is_keyword = .false.
  end type deck_line_t

  !> All logical lines of a deck, includes expanded in place.
  type :: deck_source_t
    integer :: n_lines = 0
    type(deck_line_t), allocatable :: lines(:)
    integer :: n_files = 0
    !> Paths of the files read, as opened.
    type(token_t), allocatable :: files(:)
    !> False when the main file could not be read.
    logical :: ok = .false.
    !> Number of physical lines in the main file (for messages about the whole deck).
    integer :: main_last_line = 0
  end type deck_source_t

  !> One parameter of a keyword line: `NAME=value` or a bare flag word.
  type :: param_t
    !> Upper case, blanks collapsed ("MASS PENALTY").
    character(len=:), allocatable :: name
    !> As written, trimmed; '' for a flag. Numeric continuation tokens are appended with ','.
    character(len=:), allocatable :: value
    logical :: is_flag = .false.
  end type param_t

  !> A parsed keyword line.
  type :: keyword_t
    !> Card name without the `*`: upper case, blanks collapsed ("CONTACT PAIR").
    character(len=:), allocatable :: name
    integer :: n_params = 0
    type(param_t), allocatable :: params(:)
  end type keyword_t

  !> Deepest *INCLUDE nesting accepted.
  integer, parameter :: max_include_depth = 32

contains

  !> Reads the deck `path` and all files it includes into `src`. Problems (missing file,
  !! include cycle, bad *INCLUDE card) are reported with `input_error`. `tk`: the ticker of
  !! the reading phase, ticked with the position in each file (a ticker of its own if absent).
  subroutine load_deck(path, src, tk)
    character(len=*), intent(in) :: path
    type(deck_source_t), intent(out) :: src
    type(ticker_t), intent(inout), optional :: tk
    type(token_t) :: stack(max_include_depth)
    type(ticker_t) :: own
    integer :: nlines
    allocate(src%lines(1024), src%files(0))
    if (present(tk)) then
      call load_file(path, '', src, stack, 0, src%ok, nlines, tk)
    else
      call ticker_start(own, 'deck reading')
      call load_file(path, '', src, stack, 0, src%ok, nlines, own)
    end if
    src%main_last_line = nlines
  end subroutine load_deck

  !> "file:line" of logical line `i`.
  function line_where(src, i) result(w)
    type(deck_source_t), intent(in) :: src
    integer, intent(in) :: i
    character(len=:), allocatable :: w
    w = src%files(src%lines(i)%file)%s//':'//str(src%lines(i)%line)
  end function line_where

  !> Reads one file (recursively its includes). `from` is the "file:line" of the *INCLUDE card
  !! ('' for the main deck); `depth` the number of files on `stack`.
  recursive subroutine load_file(path, from, src, stack, depth, ok, nlines, tk)
    character(len=*), intent(in) :: path, from
    type(deck_source_t), intent(inout) :: src
    type(token_t), intent(inout) :: stack(:)
    integer, intent(in) :: depth
    logical, intent(out) :: ok
    integer, intent(out) :: nlines
    type(ticker_t), intent(inout) :: tk
    character(len=:), allocatable :: buf, where
    integer :: ifile, pos, next, lineno
    logical :: in_include

    nlines = 0
    call read_whole_file(path, buf, ok)
    if (.not. ok) then
      if (len(from) == 0) then
        call input_error(path, 'cannot open the deck file "'//shown(path, 300)//'"')
      else
        call input_error(from, '*INCLUDE: cannot open file "'//shown(path, 300)//'"')
      end if
      return
    end if
    call push_file(src, path)
    ifile = src%n_files
    stack(depth + 1)%s = normalize_path(path)

    in_include = .false.
    pos = 1
    lineno = 0
    tk%name = 'deck reading, '//path
    do while (pos <= len(buf))
      call tk%tick(pos, len(buf))
      next = index(buf(pos:), achar(10))
      if (next == 0) then
        next = len(buf) + 1
      else
        next = pos + next - 1
      end if
      lineno = lineno + 1
      where = path//':'//str(lineno)
      call add_line(buf(pos:next - 1), ifile, lineno, where, src, stack, depth + 1, tk, &
          in_include)
      pos = next + 1
    end do
    nlines = lineno
  end subroutine load_file

  !> Cleans one physical line and appends it to `src` (or expands it when it is *INCLUDE).
  !! `in_include` is true while the lines after an *INCLUDE card are read (they must be
  !! keyword lines).
  recursive subroutine add_line(raw, ifile, lineno, where, src, stack, depth, tk, in_include)
    character(len=*), intent(in) :: raw, where
    integer, intent(in) :: ifile, lineno, depth
    type(deck_source_t), intent(inout) :: src
    type(token_t), intent(inout) :: stack(:)
    type(ticker_t), intent(inout) :: tk
    logical, intent(inout) :: in_include
    character(len=:), allocatable :: text
    type(keyword_t) :: kw
    logical :: ok
    integer :: k

    text = clean_line(raw)
    if (len(text) == 0) return
    if (text(1:1) /= '*') then
      if (in_include) then
        call input_error(where, '*INCLUDE: takes no data lines, found "'//shown(text)//'"')
        in_include = .false.
        return
      end if
      call push_line(src, deck_line_t(text, ifile, lineno, .false.))
      return
    end if
    in_include = .false.
    k = index(text, ',')
    if (k == 0) k = len(text) + 1
    if (upper(collapse_blanks(text(2:k - 1))) == 'INCLUDE') then
      call parse_keyword(text, where, kw, ok)
      in_include = .true.
      if (ok) call include_file(kw, where, src%files(ifile)%s, src, stack, depth, tk)
      tk%name = 'deck reading, '//src%files(ifile)%s
      return
    end if
    call push_line(src, deck_line_t(text, ifile, lineno, .true.))
  end subroutine add_line

  !> Expands an *INCLUDE card (`where` is its location in file `parent`, `depth` the number
  !! of files open so far).
  recursive subroutine include_file(kw, where, parent, src, stack, depth, tk)
    type(keyword_t), intent(in) :: kw
    character(len=*), intent(in) :: where, parent
    type(deck_source_t), intent(inout) :: src
    type(token_t), intent(inout) :: stack(:)
    integer, intent(in) :: depth
    type(ticker_t), intent(inout) :: tk
    character(len=:), allocatable :: name, path, chain
    integer :: k, nlines
    logical :: ok

    name = ''
    do k = 1, kw%n_params
      if (kw%params(k)%name == 'INPUT' .and. .not. kw%params(k)%is_flag) then
        name = kw%params(k)%value
      else
        call input_error(where, '*INCLUDE: unknown parameter '//shown(kw%params(k)%name)// &
            ' (expected INPUT=path)')
      end if
    end do
    if (len(name) == 0) then
      call input_error(where, '*INCLUDE: missing parameter INPUT=path')
      return
    end if
    if (name(1:1) == '/') then
      path = name
    else
      path = dir_of(parent)//name
    end if
    do k = 1, depth
      if (stack(k)%s == normalize_path(path)) then
        chain = ''
        do nlines = k, depth
          chain = chain//stack(nlines)%s//' -> '
        end do
        call input_error(where, '*INCLUDE: include cycle: '//shown(chain//path, 400))
        return
      end if
    end do
    if (depth >= size(stack)) then
      call input_error(where, '*INCLUDE: includes nested deeper than '// &
          str(size(stack))//' files')
      return
    end if
    call load_file(path, where, src, stack, depth, ok, nlines, tk)
  end subroutine include_file


  !> Reads a whole file into `buf` (stream access: any content, any line length).
  subroutine read_whole_file(path, buf, ok)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: buf
    logical, intent(out) :: ok
    integer :: u, ios
    integer(i8) :: n
    logical :: exists

    ok = .false.
    buf = ''
    if (len_trim(path) == 0) return
    inquire(file=path, exist=exists)
    if (.not. exists) return
    open(newunit=u, file=path, status='old', action='read', access='stream', &
        form='unformatted', iostat=ios)
    if (ios /= 0) return
    inquire(unit=u, size=n)
    if (n < 0 .or. n > int(huge(1), i8)) then
      close(u)
      return
    end if
    deallocate(buf)
    allocate(character(len=int(n)) :: buf)
    if (n > 0) then
      read(u, iostat=ios) buf
      if (ios /= 0) then
        close(u)
        return
      end if
    end if
    close(u)
    ok = .true.
  end subroutine read_whole_file

  !> Appends one logical line, growing the list geometrically.
  subroutine push_line(src, line)
    type(deck_source_t), intent(inout) :: src
    type(deck_line_t), intent(in) :: line
    type(deck_line_t), allocatable :: tmp(:)
    integer :: i
    if (src%n_lines == size(src%lines)) then
      allocate(tmp(2*size(src%lines)))
      do i = 1, src%n_lines
        call move_alloc(src%lines(i)%text, tmp(i)%text)
        tmp(i)%file = src%lines(i)%file
        tmp(i)%line = src%lines(i)%line
        tmp(i)%is_keyword = src%lines(i)%is_keyword
      end do
      call move_alloc(tmp, src%lines)
    end if
    src%n_lines = src%n_lines + 1
    src%lines(src%n_lines) = line
  end subroutine push_line

  !> Appends a file path to `src%files`.
  subroutine push_file(src, path)
    type(deck_source_t), intent(inout) :: src
    character(len=*), intent(in) :: path
    type(token_t), allocatable :: tmp(:)
    integer :: i
    allocate(tmp(src%n_files + 1))
    do i = 1, src%n_files
      call move_alloc(src%files(i)%s, tmp(i)%s)
    end do
    tmp(src%n_files + 1)%s = path
    call move_alloc(tmp, src%files)
    src%n_files = src%n_files + 1
  end subroutine push_file

  !> A physical line without its comment, CR, tabs, and leading/trailing blanks.
  pure function clean_line(raw) result(text)
    character(len=*), intent(in) :: raw
    character(len=:), allocatable :: text
    integer :: i, k
    text = raw
    do i = 1, len(text)
      if (text(i:i) == achar(9) .or. text(i:i) == achar(13)) text(i:i) = ' '
    end do
    k = index(text, '**')
    if (k > 0) text = text(1:k - 1)
    text = trim(adjustl(text))
  end function clean_line

  !> Splits a keyword line `*NAME, P=v, FLAG, P=v1,v2` into `kw`. A bare numeric token after
  !! `P=v` continues that value (`DEGREE=2,2`); a bare word is a flag. Reports malformed lines
  !! at `where` and returns ok = .false. for them.
  subroutine parse_keyword(text, where, kw, ok)
    character(len=*), intent(in) :: text, where
    type(keyword_t), intent(out) :: kw
    logical, intent(out) :: ok
    character(len=:), allocatable :: field
    integer :: pos, next, eq, nf, np

    ok = .true.
    allocate(kw%params(0))
    pos = 2
    nf = 0
    do
      next = index(text(pos:), ',')
      if (next == 0) then
        field = trim(adjustl(text(pos:)))
      else
        field = trim(adjustl(text(pos:pos + next - 2)))
      end if
      nf = nf + 1
      if (nf == 1) then
        kw%name = upper(collapse_blanks(field))
        if (len(kw%name) == 0) then
          call input_error(where, 'keyword line without a card name (expected *NAME, ...)')
          ok = .false.
          return
        end if
      else if (len(field) > 0) then
        eq = index(field, '=')
        if (eq > 0) then
          if (len_trim(field(1:eq - 1)) == 0) then
            call input_error(where, '*'//kw%name//': parameter value "'//shown(field)// &
                '" without a parameter name before "="')
            ok = .false.
          else
            call push_param(kw, upper(collapse_blanks(field(1:eq - 1))), &
                trim(adjustl(field(eq + 1:))), .false.)
          end if
        else if (is_number(field)) then
          np = kw%n_params
          if (np > 0) then
            if (kw%params(np)%is_flag) np = 0
          end if
          if (np > 0) then
            kw%params(np)%value = kw%params(np)%value//','//field
          else
            call input_error(where, '*'//kw%name//': value "'//shown(field)// &
                '" without a parameter name before it (expected PARAM=value)')
            ok = .false.
          end if
        else
          call push_param(kw, upper(collapse_blanks(field)), '', .true.)
        end if
      end if
      if (next == 0) exit
      pos = pos + next
    end do
  end subroutine parse_keyword

  !> Appends a parameter to `kw`.
  subroutine push_param(kw, name, value, is_flag)
    type(keyword_t), intent(inout) :: kw
    character(len=*), intent(in) :: name, value
    logical, intent(in) :: is_flag
    type(param_t), allocatable :: tmp(:)
    integer :: i
    allocate(tmp(kw%n_params + 1))
    do i = 1, kw%n_params
      call move_alloc(kw%params(i)%name, tmp(i)%name)
      call move_alloc(kw%params(i)%value, tmp(i)%value)
      tmp(i)%is_flag = kw%params(i)%is_flag
    end do
    tmp(kw%n_params + 1)%name = name
    tmp(kw%n_params + 1)%value = value
    tmp(kw%n_params + 1)%is_flag = is_flag
    call move_alloc(tmp, kw%params)
    kw%n_params = kw%n_params + 1
  end subroutine push_param

  !> Splits a data line (or a parameter value) into tokens separated by commas and/or blanks.
  subroutine split_values(text, toks, n)
    character(len=*), intent(in) :: text
    type(token_t), allocatable, intent(out) :: toks(:)
    integer, intent(out) :: n
    integer :: i, start, cap
    type(token_t), allocatable :: tmp(:)

    cap = 8
    allocate(toks(cap))
    n = 0
    start = 0
    do i = 1, len(text) + 1
      if (i <= len(text)) then
        if (text(i:i) /= ',' .and. text(i:i) /= ' ') then
          if (start == 0) start = i
          cycle
        end if
      end if
      if (start > 0) then
        if (n == cap) then
          cap = 2*cap
          allocate(tmp(cap))
          tmp(1:n) = toks(1:n)
          call move_alloc(tmp, toks)
        end if
        n = n + 1
        toks(n)%s = text(start:i - 1)
        start = 0
      end if
    end do
  end subroutine split_values

  !> Splits a data line into fields for cards whose fields have defaults (deck format 2): like
  !! `split_values`, but an empty field between commas (or before the first comma) is kept as
  !! an empty token, meaning "the default". An empty field after the last comma is dropped
  !! (a trailing comma ends the line).
  subroutine split_fields(text, toks, n)
    character(len=*), intent(in) :: text
    type(token_t), allocatable, intent(out) :: toks(:)
    integer, intent(out) :: n
    type(token_t), allocatable :: part(:), tmp(:)
    integer :: pos, next, m, k
    character(len=:), allocatable :: field

    allocate(toks(8))
    n = 0
    pos = 1
    do
      next = index(text(pos:), ',')
      if (next == 0) then
        field = text(pos:)
      else
        field = text(pos:pos + next - 2)
      end if
      call split_values(field, part, m)
      if (m == 0 .and. next /= 0) then
        m = 1
        part(1)%s = ''
      end if
      if (n + m > size(toks)) then
        allocate(tmp(2*(n + m)))
        tmp(1:n) = toks(1:n)
        call move_alloc(tmp, toks)
      end if
      do k = 1, m
        toks(n + k)%s = part(k)%s
      end do
      n = n + m
      if (next == 0) exit
      pos = pos + next
    end do
  end subroutine split_fields

  !> True when `s` is a well-formed number (integer or real).
  pure logical function is_number(s)
    character(len=*), intent(in) :: s
    integer :: mag
    logical :: zero
    call real_syntax(s, is_number, mag, zero)
  end function is_number

  !> Converts `s` to a real. ok = .false. for anything but a plain decimal number
  !! ([sign] digits [. digits] [E|D [sign] digits]) of magnitude in [1e-307, 1e308), or zero.
  subroutine parse_real(s, x, ok)
    character(len=*), intent(in) :: s
    real(dp), intent(out) :: x
    logical, intent(out) :: ok
    integer :: mag, ios
    logical :: zero
    x = 0.0_dp
    call real_syntax(s, ok, mag, zero)
    if (.not. ok) return
    if (zero) return
    if (abs(mag) > 307) then
      ok = .false.
      return
    end if
    read(s, *, iostat=ios) x
    ok = ios == 0
    if (.not. ok) x = 0.0_dp
  end subroutine parse_real

  !> Converts `s` to a default integer; ok = .false. unless `s` is [sign] digits in range.
  pure subroutine parse_int(s, i, ok)
    character(len=*), intent(in) :: s
    integer, intent(out) :: i
    logical, intent(out) :: ok
    integer :: k, k0
    integer(i8) :: v
    i = 0
    ok = .false.
    if (len(s) == 0) return
    k0 = 1
    if (s(1:1) == '+' .or. s(1:1) == '-') k0 = 2
    if (k0 > len(s)) return
    v = 0
    do k = k0, len(s)
      if (s(k:k) < '0' .or. s(k:k) > '9') return
      v = 10*v + (iachar(s(k:k)) - iachar('0'))
      if (v > int(huge(1), i8)) return
    end do
    if (k0 == 2 .and. s(1:1) == '-') v = -v
    i = int(v)
    ok = .true.
  end subroutine parse_int

  !> Syntax check of a decimal number. `mag` is its decimal order of magnitude (position of
  !! the leading significant digit plus the exponent), `zero` true when all digits are 0.
  pure subroutine real_syntax(s, ok, mag, zero)
    character(len=*), intent(in) :: s
    logical, intent(out) :: ok
    integer, intent(out) :: mag
    logical, intent(out) :: zero
    integer :: k, n, nint_digits, nfrac, first_nz, expo, esign, nexp
    logical :: in_frac

    ok = .false.
    mag = 0
    zero = .true.
    n = len(s)
    k = 1
    if (n == 0) return
    if (s(1:1) == '+' .or. s(1:1) == '-') k = 2
    nint_digits = 0
    nfrac = 0
    first_nz = 0
    in_frac = .false.
    do while (k <= n)
      if (s(k:k) >= '0' .and. s(k:k) <= '9') then
        if (in_frac) then
          nfrac = nfrac + 1
          if (first_nz == 0 .and. s(k:k) /= '0') first_nz = -nfrac
        else
          nint_digits = nint_digits + 1
          if (first_nz == 0 .and. s(k:k) /= '0') first_nz = nint_digits
        end if
      else if (s(k:k) == '.' .and. .not. in_frac) then
        in_frac = .true.
      else
        exit
      end if
      k = k + 1
    end do
    if (nint_digits + nfrac == 0) return
    expo = 0
    if (k <= n) then
      if (index('eEdD', s(k:k)) == 0) return
      k = k + 1
      esign = 1
      if (k <= n) then
        if (s(k:k) == '+' .or. s(k:k) == '-') then
          if (s(k:k) == '-') esign = -1
          k = k + 1
        end if
      end if
      nexp = 0
      do while (k <= n)
        if (s(k:k) < '0' .or. s(k:k) > '9') return
        nexp = nexp + 1
        if (expo < 100000) expo = 10*expo + (iachar(s(k:k)) - iachar('0'))
        k = k + 1
      end do
      if (nexp == 0) return
      expo = esign*expo
    end if
    ok = .true.
    if (first_nz == 0) return
    zero = .false.
    if (first_nz > 0) then
      mag = nint_digits - first_nz + expo
    else
      mag = first_nz + expo
    end if
  end subroutine real_syntax

  !> `s` made safe for a message: control and non-ASCII bytes as '?', cut to `max_len`
  !! characters (default 40) with "..." appended.
  pure function shown(s, max_len) result(r)
    character(len=*), intent(in) :: s
    integer, intent(in), optional :: max_len
    character(len=:), allocatable :: r
    integer :: i, m, c
    m = 40
    if (present(max_len)) m = max_len
    r = s(1:min(len(s), m))
    do i = 1, len(r)
      c = iachar(r(i:i))
      if (c < 32 .or. c > 126) r(i:i) = '?'
    end do
    if (len(s) > m) r = r//'...'
  end function shown

  !> `s` trimmed, with every run of blanks inside it replaced by one blank.
  pure function collapse_blanks(s) result(r)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: r
    integer :: i
    logical :: prev_blank
    r = ''
    prev_blank = .false.
    do i = 1, len_trim(s)
      if (s(i:i) == ' ') then
        if (.not. prev_blank .and. len(r) > 0) r = r//' '
        prev_blank = .true.
      else
        r = r//s(i:i)
        prev_blank = .false.
      end if
    end do
  end function collapse_blanks

  !> Directory part of a path, with its trailing '/' ('' when there is none).
  pure function dir_of(path) result(d)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: d
    d = path(1:index(path, '/', back=.true.))
  end function dir_of

  !> A path with "//", "./" and "dir/../" removed (for include-cycle detection).
  pure function normalize_path(path) result(r)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: r
    type(token_t) :: parts(256)
    integer :: n, pos, next
    character(len=:), allocatable :: part
    n = 0
    pos = 1
    do while (pos <= len(path))
      next = index(path(pos:), '/')
      if (next == 0) then
        next = len(path) + 1
      else
        next = pos + next - 1
      end if
      part = path(pos:next - 1)
      pos = next + 1
      if (len(part) == 0 .or. part == '.') cycle
      if (part == '..' .and. n > 0) then
        if (parts(n)%s /= '..') then
          n = n - 1
          cycle
        end if
      end if
      if (n < size(parts)) then
        n = n + 1
        parts(n)%s = part
      end if
    end do
    r = ''
    if (len(path) > 0) then
      if (path(1:1) == '/') r = '/'
    end if
    do pos = 1, n
      if (pos > 1) r = r//'/'
      r = r//parts(pos)%s
    end do
  end function normalize_path

end module ictus_io_deck_lexer
