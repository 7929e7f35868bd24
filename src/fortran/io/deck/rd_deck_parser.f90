!> Reads the namelist syntax of one deck source into raw group occurrences,
!> converting and checking every value against the schema as it is read, so
!> each error names file, line, group and parameter. `&include` groups are
!> expanded at the point they close (recursively, paths relative to the
!> included deck, cycles rejected).
!>
!> Accepted syntax: `&group ... /` (or `&end`) spanning lines; `name = value`
!> assignments separated by commas, blanks or newlines; `name(k) = v1, v2`
!> assigns from element k on; integers, reals (1, 1.0, 1e-6, 1.0d-3,
!> -2.5E+3), quoted strings ('it''s' or "say ""hi"""), logicals (.true.,
!> .false., T, F), lists with repeat counts (3*0.0); `!` comments.
module rd_deck_parser
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_IO
  use rd_deck_text, only: deck_string_t, append_string, joined, to_lower, int_to_str, is_integer_text, &
                          is_real_text, text_to_real, text_to_integer, text_to_logical, &
                          path_join, path_dir, is_absolute_path
  use rd_file_kind, only: file_kind, regular_file_problem, FILE_REGULAR, FILE_MISSING
  use rd_deck_schema, only: deck_schema_t, group_schema_t, param_schema_t, find_group, &
                            find_param, suggest_name, range_text, PT_REAL, PT_INTEGER, &
                            PT_STRING, PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST
  use rd_deck_lexer, only: token_t, tokenize, TK_GROUP, TK_END, TK_WORD, TK_STRING, TK_EQUALS, &
                           TK_COMMA, TK_LPAREN, TK_RPAREN, TK_UNTERMINATED, TK_EOF
  use rd_deck_store, only: param_value_t, deck_entity_t, source_file_t, append_entity
  implicit none
  private
  public :: parse_context_t, parse_source, read_text_file, expected_text, normalize_path

  !> Maximum include depth: a safety net behind the cycle check.
  integer, parameter :: max_include_depth = 32

  type :: parse_context_t
    type(deck_schema_t) :: schema
    type(source_file_t), allocatable :: sources(:)
    integer :: nsrc = 0
    type(deck_entity_t), allocatable :: entities(:)   !< raw occurrences, in reading order
    integer :: nent = 0
    type(deck_string_t), allocatable :: stack(:)      !< normalized paths being read
  end type parse_context_t

  !> One value item of an assignment, after repeat counts are expanded.
  type :: item_t
    integer :: kind = TK_WORD
    character(len=:), allocatable :: text
  end type item_t

contains

  !> Read a whole text file into one string (lines joined by newlines). `problem` is ''
  !> on success, else what went wrong ("is a directory", "cannot be read").
  subroutine read_text_file(path, text, problem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    character(len=:), allocatable, intent(out) :: problem
    integer :: u, ios, fsize
    text = ''
    ! a directory, FIFO or device is refused before opening: it would read as empty,
    ! endless or block
    problem = regular_file_problem(path)
    if (len(problem) > 0) return
    problem = 'cannot be read'
    open (newunit=u, file=path, access='stream', form='unformatted', status='old', &
          action='read', iostat=ios)
    if (ios /= 0) return
    inquire (unit=u, size=fsize)
    if (fsize < 0) then
      close (u); return
    end if
    deallocate (text)
    allocate (character(len=fsize) :: text)
    if (fsize > 0) read (u, iostat=ios) text
    close (u)
    if (ios == 0) problem = ''
  end subroutine read_text_file

  !> Collapse "./" and "dir/../" so include cycles are detected whatever the spelling.
  function normalize_path(p) result(n)
    character(len=*), intent(in) :: p
    character(len=:), allocatable :: n
    type(deck_string_t) :: parts(256)
    integer :: np, i, start, k
    character(len=:), allocatable :: rest
    character(len=4096) :: cwd
    if (is_absolute_path(p)) then
      rest = p
    else
      call getcwd(cwd)
      rest = trim(cwd) // '/' // p
    end if
    np = 0; start = 1
    do while (start <= len(rest))
      k = index(rest(start:), '/')
      if (k == 0) then
        k = len(rest) + 1
      else
        k = start + k - 1
      end if
      if (k > start) then
        associate (seg => rest(start:k - 1))
          if (seg == '..') then
            if (np > 0) np = np - 1
          else if (seg /= '.' .and. np < size(parts)) then
            np = np + 1; parts(np)%s = seg
          end if
        end associate
      end if
      start = k + 1
    end do
    n = ''
    do i = 1, np
      n = n // '/' // parts(i)%s
    end do
    if (np == 0) n = '/'
  end function normalize_path

  !> What a value of this parameter must look like, for "expected ..." texts.
  function expected_text(p) result(t)
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: t, r
    integer :: i
    select case (p%ptype)
    case (PT_REAL); t = 'a real number'
    case (PT_INTEGER); t = 'an integer'
    case (PT_LOGICAL); t = '.true. or .false.'
    case (PT_STRING)
      if (size(p%allowed) > 0) then
        t = 'one of ' // joined(p%allowed, "'")
        return
      else if (p%is_path) then
        t = 'a quoted file name'
        if (size(p%path_keywords) > 0) then
          r = range_text(p)
          t = t // ' or ' // r(len('a file or ') + 1:)
        end if
        return
      else if (len(p%ref_group) > 0) then
        t = 'the quoted name of a &' // p%ref_group
        do i = 1, size(p%ref_keywords)
          t = t // " or '" // p%ref_keywords(i)%s // "'"
        end do
        return
      else
        t = 'a quoted string'
        return
      end if
    case (PT_REAL_ARRAY)
      if (p%size > 0) then
        t = int_to_str(p%size) // ' real numbers'
      else
        t = 'a list of real numbers'
      end if
    case (PT_STRING_LIST)
      t = 'a list of quoted strings among ' // joined(p%allowed, "'")
      return
    end select
    r = range_text(p)
    if (len(r) > 0) then
      if (r(1:1) == '[' .or. r(1:1) == '(') then
        t = t // ' in ' // r
      else
        t = t // ' ' // r
      end if
    end if
    if (p%unit /= '-') t = t // ' (' // p%unit // ')'
  end function expected_text

  !> Parse one source (a deck file or string already registered as
  !> ctx%sources(isrc)); append its groups, expanding includes, and return the
  !> text with included decks inserted between marker comments.
  recursive subroutine parse_source(ctx, text, isrc, expanded, error)
    type(parse_context_t), intent(inout) :: ctx
    character(len=*), intent(in) :: text
    integer, intent(in) :: isrc
    character(len=:), allocatable, intent(out) :: expanded
    type(error_t), allocatable, intent(out) :: error
    type(token_t), allocatable :: tok(:)
    integer :: ntok, k, gi, include_group
    type(deck_string_t), allocatable :: inserts(:)
    integer, allocatable :: insert_after(:)
    character(len=:), allocatable :: where, cleaned

    call clean_source_text(text, ctx%sources(isrc)%name, cleaned, error)
    if (allocated(error)) return
    call tokenize(cleaned, tok, ntok)
    include_group = find_group(ctx%schema, 'include')
    allocate (inserts(0), insert_after(0))
    k = 1
    do
      select case (tok(k)%kind)
      case (TK_EOF)
        exit
      case (TK_GROUP)
        call parse_group(ctx, tok, k, isrc, gi, error)
        if (allocated(error)) return
        if (gi == include_group) then
          block
            character(len=:), allocatable :: sub
            call include_deck(ctx, sub, error)
            if (allocated(error)) return
            call append_string(inserts, sub)
            insert_after = [insert_after, tok(k - 1)%line]
          end block
        end if
      case default
        where = ctx%sources(isrc)%name // ':' // int_to_str(tok(k)%line) // ': '
        if (tok(k)%kind == TK_END) then
          call make_error(error, RD_ERR_INPUT, where // "'" // shown(tok(k)%text) // &
            "' outside a group; expected it only to close a &group")
        else
          call make_error(error, RD_ERR_INPUT, where // "text outside a group: '" // &
            token_display(tok(k)) // "'; expected only &group ... / blocks, blank lines " // &
            "and ! comments")
        end if
        return
      end select
    end do
    expanded = splice(cleaned, inserts, insert_after)
  end subroutine parse_source

  !> The deck text as the lexer reads it: a UTF-8 byte order mark at the start is
  !> dropped, CR LF and lone CR line ends become LF (files from Windows and classic Mac
  !> OS), and any other control byte (NUL, ESC, form feed, DEL, ...) is an error naming
  !> its line and column: the namelist syntax has no use for them and a silently kept
  !> one would end up in names and results.
  subroutine clean_source_text(text, name, cleaned, error)
    character(len=*), intent(in) :: text, name
    character(len=:), allocatable, intent(out) :: cleaned
    type(error_t), allocatable, intent(out) :: error
    character(len=*), parameter :: bom = achar(239) // achar(187) // achar(191)
    integer :: i, n, line, column, code, first
    allocate (character(len=len(text)) :: cleaned)
    first = 1
    if (len(text) >= 3) then
      if (text(1:3) == bom) first = 4
    end if
    n = 0; line = 1; column = 0
    i = first
    do while (i <= len(text))
      code = iachar(text(i:i))
      column = column + 1
      if (code == 13) then
        n = n + 1; cleaned(n:n) = achar(10)
        line = line + 1; column = 0
        if (i < len(text)) then
          if (text(i + 1:i + 1) == achar(10)) i = i + 1
        end if
      else if (code == 10) then
        n = n + 1; cleaned(n:n) = achar(10)
        line = line + 1; column = 0
      else if ((code < 32 .and. code /= 9) .or. code == 127) then
        call make_error(error, RD_ERR_INPUT, name // ':' // int_to_str(line) // ': control byte 0x' // &
          hex_byte(code) // ' at column ' // int_to_str(column) // '; expected text (printable ' // &
          'characters, tabs and line ends only)')
        return
      else
        n = n + 1; cleaned(n:n) = text(i:i)
      end if
      i = i + 1
    end do
    cleaned = cleaned(1:n)
  end subroutine clean_source_text

  pure function hex_byte(code) result(h)
    integer, intent(in) :: code
    character(len=2) :: h
    character(len=*), parameter :: digits = '0123456789ABCDEF'
    h = digits(code / 16 + 1:code / 16 + 1) // digits(mod(code, 16) + 1:mod(code, 16) + 1)
  end function hex_byte

  function token_display(t) result(s)
    type(token_t), intent(in) :: t
    character(len=:), allocatable :: s
    select case (t%kind)
    case (TK_STRING); s = "'" // t%text // "'"
    case (TK_GROUP); s = '&' // t%text
    case (TK_EOF); s = 'end of file'
    case default; s = t%text
    end select
    s = shown(s)
  end function token_display

  !> A value as quoted in messages: cut to 40 characters (a megabyte-long
  !> value must not become a megabyte-long message).
  pure function shown(t) result(s)
    character(len=*), intent(in) :: t
    character(len=:), allocatable :: s
    if (len(t) > 40) then
      s = t(1:37) // '...'
    else
      s = t
    end if
  end function shown

  !> Insert each included text after its line, between marker comments. Pieces are
  !> joined once per include (not once per line: linear in the deck's size).
  function splice(text, inserts, after) result(out)
    character(len=*), intent(in) :: text
    type(deck_string_t), intent(in) :: inserts(:)
    integer, intent(in) :: after(:)
    character(len=:), allocatable :: out
    integer :: line, i, k, start
    character(len=1), parameter :: nl = achar(10)
    if (size(inserts) == 0) then
      out = text; return
    end if
    out = ''; line = 1; start = 1; k = 1
    ! after(:) is in reading order, i.e. non-decreasing lines
    do i = 1, len(text)
      if (k > size(after)) exit
      if (text(i:i) /= nl) cycle
      do while (k <= size(after))
        if (after(k) /= line) exit
        out = out // text(start:i) // inserts(k)%s
        start = i + 1; k = k + 1
      end do
      line = line + 1
    end do
    if (start <= len(text)) then
      out = out // text(start:)
      if (text(len(text):len(text)) /= nl) out = out // nl
    end if
    do while (k <= size(after))   ! includes on a last line without a newline
      out = out // inserts(k)%s; k = k + 1
    end do
  end function splice

  !> The group just read is an &include: read the named deck in place.
  recursive subroutine include_deck(ctx, expanded, error)
    type(parse_context_t), intent(inout) :: ctx
    character(len=:), allocatable, intent(out) :: expanded
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: path, norm, text, where, sub, problem
    type(source_file_t), allocatable :: grown(:)
    integer :: i, jsrc
    character(len=1), parameter :: nl = achar(10)

    associate (inc => ctx%entities(ctx%nent))
      where = ctx%sources(inc%source)%name // ':' // int_to_str(inc%line) // ": &include 'file': "
      if (.not. inc%values(1)%given) then
        call make_error(error, RD_ERR_INPUT, where // &
          'missing required parameter; expected a quoted deck file name')
        return
      end if
      where = ctx%sources(inc%values(1)%source)%name // ':' // int_to_str(inc%values(1)%line) // &
              ": &include 'file': "
      path = inc%values(1)%resolved
    end associate
    norm = normalize_path(path)
    do i = 1, size(ctx%stack)
      if (ctx%stack(i)%s == norm) then
        call make_error(error, RD_ERR_INPUT, where // "include cycle: '" // path // &
          "' is already being read; expected a deck that does not include itself")
        return
      end if
    end do
    if (size(ctx%stack) >= max_include_depth) then
      call make_error(error, RD_ERR_INPUT, where // 'includes nested deeper than ' // &
        int_to_str(max_include_depth) // '; expected fewer levels')
      return
    end if
    call read_text_file(path, text, problem)
    if (len(problem) > 0) then
      call make_error(error, RD_ERR_IO, where // "'" // path // "' " // problem // &
        '; expected a readable deck file')
      return
    end if
    ctx%nsrc = ctx%nsrc + 1
    allocate (grown(ctx%nsrc))
    grown(1:ctx%nsrc - 1) = ctx%sources(1:ctx%nsrc - 1)
    grown(ctx%nsrc)%name = path
    grown(ctx%nsrc)%dir = path_dir(path)
    call move_alloc(grown, ctx%sources)
    jsrc = ctx%nsrc
    call append_string(ctx%stack, norm)
    call parse_source(ctx, text, jsrc, sub, error)
    ctx%stack = ctx%stack(1:size(ctx%stack) - 1)
    if (allocated(error)) return
    if (len(sub) > 0) then
      if (sub(len(sub):len(sub)) /= nl) sub = sub // nl
    end if
    expanded = "! >>> begin include '" // path // "'" // nl // sub // &
               "! <<< end include '" // path // "'" // nl
  end subroutine include_deck

  !> Parse `&name ... /` starting at tok(k); on return k is past the end token.
  subroutine parse_group(ctx, tok, k, isrc, gi, error)
    type(parse_context_t), intent(inout) :: ctx
    type(token_t), intent(in) :: tok(:)
    integer, intent(inout) :: k
    integer, intent(in) :: isrc
    integer, intent(out) :: gi
    type(error_t), allocatable, intent(out) :: error
    type(deck_entity_t) :: ent
    character(len=:), allocatable :: gname, fname, pname, hint, where
    integer :: start_line, name_line, pi, index_value, i
    type(deck_string_t), allocatable :: names(:)
    type(item_t), allocatable :: items(:)
    logical :: has_index, ok

    fname = ctx%sources(isrc)%name
    gname = tok(k)%text
    start_line = tok(k)%line
    gi = find_group(ctx%schema, gname)
    if (gi == 0) then
      allocate (names(size(ctx%schema%groups)))
      do i = 1, size(names)
        names(i)%s = ctx%schema%groups(i)%name
      end do
      hint = suggest_name(gname, names)
      where = fname // ':' // int_to_str(start_line) // ': &' // gname // ': unknown group; expected '
      if (len(hint) > 0) then
        call make_error(error, RD_ERR_INPUT, where // 'a known group (did you mean &' // hint // '?)')
      else
        call make_error(error, RD_ERR_INPUT, where // 'one of ' // group_list(ctx%schema))
      end if
      return
    end if
    associate (g => ctx%schema%groups(gi))
      ent%group = gi; ent%source = isrc; ent%line = start_line
      ent%contributors = [isrc]
      allocate (ent%values(size(g%params)))
      k = k + 1
      do
        where = fname // ':' // int_to_str(tok(k)%line) // ': &' // g%name
        select case (tok(k)%kind)
        case (TK_END)
          k = k + 1
          exit
        case (TK_GROUP, TK_EOF)
          call make_error(error, RD_ERR_INPUT, fname // ':' // int_to_str(start_line) // ': &' // &
            g%name // ': unterminated group (' // token_display(tok(k)) // ' reached at line ' // &
            int_to_str(tok(k)%line) // "); expected '/' or &end to close it")
          return
        case (TK_COMMA)
          k = k + 1
          cycle
        case (TK_WORD)
          if (tok(k + 1)%kind /= TK_EQUALS .and. tok(k + 1)%kind /= TK_LPAREN) then
            call make_error(error, RD_ERR_INPUT, where // ": '" // token_display(tok(k)) // &
              "' is not an assignment; expected name = value")
            return
          end if
        case default
          call make_error(error, RD_ERR_INPUT, where // ": unexpected '" // &
            token_display(tok(k)) // "'; expected name = value or '/' to close the group")
          return
        end select
        ! --- name [ (index) ] = values ---
        pname = to_lower(tok(k)%text)
        name_line = tok(k)%line
        pi = find_param(g, pname)
        if (pi == 0) then
          allocate (names(size(g%params)))
          do i = 1, size(names)
            names(i)%s = g%params(i)%name
          end do
          hint = suggest_name(pname, names)
          if (len(hint) > 0) then
            call make_error(error, RD_ERR_INPUT, where // " '" // pname // &
              "': unknown parameter; expected a parameter of &" // g%name // &
              " (did you mean '" // hint // "'?)")
          else
            call make_error(error, RD_ERR_INPUT, where // " '" // pname // &
              "': unknown parameter; expected one of " // param_list(g))
          end if
          return
        end if
        where = where // " '" // pname // "': "
        k = k + 1
        has_index = .false.; index_value = 1
        if (tok(k)%kind == TK_LPAREN) then
          ok = tok(k + 1)%kind == TK_WORD .and. tok(k + 2)%kind == TK_RPAREN .and. &
               tok(k + 3)%kind == TK_EQUALS
          if (ok) ok = is_integer_text(tok(k + 1)%text)
          if (ok) call text_to_integer(tok(k + 1)%text, index_value, ok)
          if (.not. ok) then
            call make_error(error, RD_ERR_INPUT, where // 'malformed element index; ' // &
              'expected name(k) = value with an integer k')
            return
          end if
          has_index = .true.
          k = k + 3
        end if
        k = k + 1   ! past '='
        call collect_items(tok, k, items, where, error)
        if (allocated(error)) return
        call assign_value(ctx, ent%values(pi), g%params(pi), items, has_index, index_value, &
                          isrc, name_line, where, error)
        if (allocated(error)) return
      end do
    end associate
    call append_entity(ctx%entities, ctx%nent, ent)
  end subroutine parse_group

  function group_list(s) result(t)
    type(deck_schema_t), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, size(s%groups)
      if (i > 1) t = t // ', '
      t = t // '&' // s%groups(i)%name
    end do
  end function group_list

  function param_list(g) result(t)
    type(group_schema_t), intent(in) :: g
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, size(g%params)
      if (i > 1) t = t // ', '
      t = t // g%params(i)%name
    end do
  end function param_list

  !> Gather the value items after '=' up to the next `name =`, `name(`, or
  !> the end of the group, expanding repeat counts n*value.
  subroutine collect_items(tok, k, items, where, error)
    type(token_t), intent(in) :: tok(:)
    integer, intent(inout) :: k
    type(item_t), allocatable, intent(out) :: items(:)
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(out) :: error
    integer :: nrep, star, j, n
    logical :: ok
    character(len=:), allocatable :: value
    type(item_t), allocatable :: all_items(:)
    allocate (all_items(16))
    n = 0
    do
      select case (tok(k)%kind)
      case (TK_COMMA)
        k = k + 1
      case (TK_UNTERMINATED)
        call make_error(error, RD_ERR_INPUT, where // 'unterminated string ' // &
          trim(tok(k)%text(1:min(30, len(tok(k)%text)))) // '; expected a closing ' // &
          tok(k)%text(1:1) // ' on the same line')
        return
      case (TK_STRING)
        call push_item(all_items, n, TK_STRING, tok(k)%text)
        k = k + 1
      case (TK_WORD)
        if (tok(k + 1)%kind == TK_EQUALS .or. tok(k + 1)%kind == TK_LPAREN) exit
        star = index(tok(k)%text, '*')
        if (star == 0) then
          call push_item(all_items, n, TK_WORD, tok(k)%text)
          k = k + 1
          cycle
        end if
        ok = star > 1
        if (ok) ok = is_integer_text(tok(k)%text(1:star - 1))
        if (ok) call text_to_integer(tok(k)%text(1:star - 1), nrep, ok)
        if (ok) ok = nrep >= 1 .and. nrep <= 100000
        if (.not. ok) then
          call make_error(error, RD_ERR_INPUT, where // "malformed repeat count '" // &
            shown(tok(k)%text) // "'; expected n*value with a positive integer n, e.g. 3*0.0")
          return
        end if
        if (star < len(tok(k)%text)) then
          value = tok(k)%text(star + 1:)
          do j = 1, nrep
            call push_item(all_items, n, TK_WORD, value)
          end do
          k = k + 1
        else if (tok(k + 1)%kind == TK_STRING .and. tok(k + 1)%glued) then
          do j = 1, nrep
            call push_item(all_items, n, TK_STRING, tok(k + 1)%text)
          end do
          k = k + 2
        else
          call make_error(error, RD_ERR_INPUT, where // "repeat count '" // shown(tok(k)%text) // &
            "' without a value; expected n*value, e.g. 3*0.0 (null values are not supported)")
          return
        end if
      case default
        exit
      end select
    end do
    if (n == 0) then
      call make_error(error, RD_ERR_INPUT, where // 'no value given; expected a value after =')
    end if
    allocate (items(n))
    do j = 1, n
      call move_alloc(all_items(j)%text, items(j)%text)
      items(j)%kind = all_items(j)%kind
    end do
  end subroutine collect_items

  !> Append an item, doubling the storage when full so that a list of n values costs
  !> O(n) (explicit copies: gfortran 12 loses deferred-length components in array
  !> constructors of structure constructors).
  subroutine push_item(items, n, kind, text)
    type(item_t), allocatable, intent(inout) :: items(:)
    integer, intent(inout) :: n
    integer, intent(in) :: kind
    character(len=*), intent(in) :: text
    type(item_t), allocatable :: grown(:)
    integer :: i
    if (n == size(items)) then
      allocate (grown(max(16, 2 * n)))
      do i = 1, n
        call move_alloc(items(i)%text, grown(i)%text)
        grown(i)%kind = items(i)%kind
      end do
      call move_alloc(grown, items)
    end if
    n = n + 1
    items(n)%kind = kind
    items(n)%text = text
  end subroutine push_item

  !> Convert the items to the parameter's type, check them and store them.
  subroutine assign_value(ctx, v, p, items, has_index, k0, isrc, line, where, error)
    type(parse_context_t), intent(in) :: ctx
    type(param_value_t), intent(inout) :: v
    type(param_schema_t), intent(in) :: p
    type(item_t), intent(in) :: items(:)
    logical, intent(in) :: has_index
    integer, intent(in) :: k0, isrc, line
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(out) :: error
    integer :: n, capacity, last, i, current
    real(wp), allocatable :: x(:)
    integer, allocatable :: m(:)
    logical, allocatable :: b(:), setmask(:)
    type(deck_string_t), allocatable :: s(:)
    character(len=:), allocatable :: expect, from
    logical :: ok, is_list

    expect = expected_text(p)
    n = size(items)
    is_list = p%ptype == PT_REAL_ARRAY .or. p%ptype == PT_STRING_LIST
    if (.not. is_list) then
      capacity = 1
    else if (p%size > 0) then
      capacity = p%size
    else
      capacity = huge(1)
    end if
    if (has_index .and. .not. is_list) then
      call make_error(error, RD_ERR_INPUT, where // 'not an array, cannot take an index (' // &
        int_to_str(k0) // '); expected ' // expect)
      return
    end if
    current = 0
    if (allocated(v%set)) current = size(v%set)
    if (has_index .and. (k0 < 1 .or. k0 > capacity)) then
      call make_error(error, RD_ERR_INPUT, where // 'element index ' // int_to_str(k0) // &
        ' out of bounds; expected 1 to ' // int_to_str(capacity))
      return
    end if
    ! gaps in variable lists (table_force(3) = ... alone) are allowed here, as an
    ! override may fill them from an included deck; rd_deck_resolve rejects
    ! the gaps that remain after merging.
    if (has_index .and. p%size == 0 .and. k0 > 10000) then
      call make_error(error, RD_ERR_INPUT, where // 'element index ' // int_to_str(k0) // &
        ' too large; expected at most 10000 list elements')
      return
    end if
    last = k0 + n - 1
    if (last > capacity) then
      if (is_list) then
        from = ''
        if (has_index) from = ' from element ' // int_to_str(k0)
        call make_error(error, RD_ERR_INPUT, where // 'too many values (' // int_to_str(n) // &
          from // '); expected ' // expect)
      else
        call make_error(error, RD_ERR_INPUT, where // 'too many values (' // int_to_str(n) // &
          '); expected one value: ' // expect)
      end if
      return
    end if
    if (is_list .and. p%size > 0 .and. .not. has_index .and. n < p%size) then
      call make_error(error, RD_ERR_INPUT, where // 'too few values (' // int_to_str(n) // &
        '); expected ' // expect // ' (or name(k) = value to set element k)')
      return
    end if

    select case (p%ptype)
    case (PT_REAL, PT_REAL_ARRAY)
      allocate (x(n))
      do i = 1, n
        call convert_real(items(i), x(i), ok)
        if (.not. ok) return
      end do
    case (PT_INTEGER)
      allocate (m(n))
      do i = 1, n
        call convert_integer(items(i), m(i), ok)
        if (.not. ok) return
      end do
    case (PT_LOGICAL)
      allocate (b(n))
      do i = 1, n
        ok = items(i)%kind == TK_WORD
        if (ok) call text_to_logical(items(i)%text, b(i), ok)
        if (.not. ok) then
          call make_error(error, RD_ERR_INPUT, where // 'got ' // describe(items(i)) // &
            '; expected ' // expect)
          return
        end if
      end do
    case (PT_STRING, PT_STRING_LIST)
      allocate (s(n))
      do i = 1, n
        call convert_string(items(i), s(i), ok)
        if (.not. ok) return
      end do
    end select

    ! store, growing variable lists
    if (.not. has_index .or. .not. allocated(v%set)) then
      if (p%size > 0) then
        allocate (setmask(p%size)); setmask = .false.
      else
        allocate (setmask(last)); setmask = .false.
      end if
      if (has_index .and. allocated(v%set)) setmask(1:size(v%set)) = v%set
    else
      allocate (setmask(max(size(v%set), last))); setmask = .false.
      setmask(1:size(v%set)) = v%set
    end if
    call grow_storage(v, p%ptype, size(setmask), .not. has_index)
    setmask(k0:last) = .true.
    call move_alloc(setmask, v%set)
    select case (p%ptype)
    case (PT_REAL, PT_REAL_ARRAY); v%reals(k0:last) = x
    case (PT_INTEGER); v%integers(k0:last) = m
    case (PT_LOGICAL); v%logicals(k0:last) = b
    case (PT_STRING, PT_STRING_LIST); v%strings(k0:last) = s
    end select
    v%given = .true.
    v%whole = .not. has_index
    v%source = isrc
    v%line = line
    if (p%is_path) call resolve_path(v, p, ctx%sources(isrc)%dir, where, error)

  contains

    function describe(it) result(d)
      type(item_t), intent(in) :: it
      character(len=:), allocatable :: d
      logical :: lv, lok
      if (it%kind == TK_STRING) then
        d = "a string '" // shown(it%text) // "'"
      else if (is_integer_text(it%text)) then
        d = 'an integer ' // shown(it%text)
      else if (is_real_text(it%text)) then
        d = 'a real number ' // shown(it%text)
      else
        call text_to_logical(it%text, lv, lok)
        if (lok) then
          d = 'a logical ' // shown(it%text)
        else
          d = "'" // shown(it%text) // "'"
        end if
      end if
    end function describe

    subroutine convert_real(it, val, good)
      type(item_t), intent(in) :: it
      real(wp), intent(out) :: val
      logical, intent(out) :: good
      val = 0.0_wp
      good = it%kind == TK_WORD
      if (good) good = is_real_text(it%text)
      if (.not. good) then
        if (it%kind == TK_WORD .and. scan(it%text, '0123456789') > 0) then
          call make_error(error, RD_ERR_INPUT, where // "malformed number '" // shown(it%text) // &
            "'; expected " // expect // ', written like 1.5, -2e3 or 1.0d-3')
        else
          call make_error(error, RD_ERR_INPUT, where // 'got ' // describe(it) // &
            '; expected ' // expect)
        end if
        return
      end if
      call text_to_real(it%text, val, good)
      if (.not. good) then
        call make_error(error, RD_ERR_INPUT, where // "number '" // shown(it%text) // &
          "' overflows double precision; expected " // expect)
        return
      end if
      good = in_range(p, val)
      if (.not. good) call make_error(error, RD_ERR_INPUT, where // 'value ' // shown(it%text) // &
        ' out of range; expected ' // expect)
    end subroutine convert_real

    subroutine convert_integer(it, val, good)
      type(item_t), intent(in) :: it
      integer, intent(out) :: val
      logical, intent(out) :: good
      val = 0
      good = it%kind == TK_WORD
      if (good) good = is_integer_text(it%text)
      if (.not. good) then
        if (it%kind == TK_WORD .and. .not. is_real_text(it%text) .and. &
            scan(it%text, '0123456789') > 0) then
          call make_error(error, RD_ERR_INPUT, where // "malformed number '" // shown(it%text) // &
            "'; expected " // expect)
        else
          call make_error(error, RD_ERR_INPUT, where // 'got ' // describe(it) // &
            '; expected ' // expect // ' (no decimal point or exponent)')
        end if
        return
      end if
      call text_to_integer(it%text, val, good)
      if (.not. good) then
        call make_error(error, RD_ERR_INPUT, where // "integer '" // shown(it%text) // &
          "' too large; expected " // expect)
        return
      end if
      good = in_range(p, real(val, wp))
      if (.not. good) call make_error(error, RD_ERR_INPUT, where // 'value ' // shown(it%text) // &
        ' out of range; expected ' // expect)
    end subroutine convert_integer

    subroutine convert_string(it, val, good)
      type(item_t), intent(in) :: it
      type(deck_string_t), intent(out) :: val
      logical, intent(out) :: good
      integer :: j
      good = it%kind == TK_STRING
      if (.not. good) then
        call make_error(error, RD_ERR_INPUT, where // 'got ' // describe(it) // &
          ' without quotes; expected ' // expect)
        return
      end if
      val%s = it%text
      if (p%unique) then
        ! names become HDF5 group names and output paths (docs/output.md)
        if (len_trim(it%text) == 0) then
          call make_error(error, RD_ERR_INPUT, where // 'empty or blank name; expected a ' // &
            "non-blank name without '/' (it names the results' groups)")
          good = .false.
        else if (index(it%text, '/') > 0 .or. it%text == '.' .or. it%text == '..' .or. &
                 it%text(1:1) == ' ' .or. it%text(len(it%text):len(it%text)) == ' ') then
          call make_error(error, RD_ERR_INPUT, where // "name '" // shown(it%text) // &
            "' cannot name a results group; expected a name without '/', not '.' or '..', " // &
            'without leading or trailing blanks')
          good = .false.
        end if
        if (.not. good) return
      end if
      if (size(p%allowed) == 0) return
      good = .false.
      do j = 1, size(p%allowed)
        if (to_lower(it%text) == p%allowed(j)%s) then
          good = .true.; val%s = p%allowed(j)%s
        end if
      end do
      if (.not. good) then
        block
          character(len=:), allocatable :: hint
          hint = suggest_name(it%text, p%allowed)
          if (len(hint) > 0) hint = " (did you mean '" // hint // "'?)"
          call make_error(error, RD_ERR_INPUT, where // "'" // shown(it%text) // &
            "' is not an allowed value; expected " // expect // hint)
        end block
      end if
    end subroutine convert_string
  end subroutine assign_value

  pure logical function in_range(p, x)
    type(param_schema_t), intent(in) :: p
    real(wp), intent(in) :: x
    in_range = .true.
    if (p%has_min) then
      if (p%min_open) then
        in_range = in_range .and. x > p%min
      else
        in_range = in_range .and. x >= p%min
      end if
    end if
    if (p%has_max) then
      if (p%max_open) then
        in_range = in_range .and. x < p%max
      else
        in_range = in_range .and. x <= p%max
      end if
    end if
  end function in_range

  !> Make sure the typed storage covers n elements; a whole assignment restarts it.
  subroutine grow_storage(v, ptype, n, restart)
    type(param_value_t), intent(inout) :: v
    integer, intent(in) :: ptype, n
    logical, intent(in) :: restart
    real(wp), allocatable :: x(:)
    integer, allocatable :: m(:)
    logical, allocatable :: b(:)
    type(deck_string_t), allocatable :: s(:)
    integer :: keep
    select case (ptype)
    case (PT_REAL, PT_REAL_ARRAY)
      allocate (x(n)); x = 0.0_wp
      if (allocated(v%reals) .and. .not. restart) then
        keep = min(n, size(v%reals)); x(1:keep) = v%reals(1:keep)
      end if
      call move_alloc(x, v%reals)
    case (PT_INTEGER)
      allocate (m(n)); m = 0
      if (allocated(v%integers) .and. .not. restart) then
        keep = min(n, size(v%integers)); m(1:keep) = v%integers(1:keep)
      end if
      call move_alloc(m, v%integers)
    case (PT_LOGICAL)
      allocate (b(n)); b = .false.
      if (allocated(v%logicals) .and. .not. restart) then
        keep = min(n, size(v%logicals)); b(1:keep) = v%logicals(1:keep)
      end if
      call move_alloc(b, v%logicals)
    case default
      allocate (s(n))
      if (allocated(v%strings) .and. .not. restart) then
        keep = min(n, size(v%strings)); s(1:keep) = v%strings(1:keep)
      end if
      call move_alloc(s, v%strings)
    end select
  end subroutine grow_storage

  !> Resolve a path value against its deck's directory; check existence.
  subroutine resolve_path(v, p, dir, where, error)
    type(param_value_t), intent(inout) :: v
    type(param_schema_t), intent(in) :: p
    character(len=*), intent(in) :: dir, where
    type(error_t), allocatable, intent(out) :: error
    integer :: j
    character(len=:), allocatable :: raw
    raw = v%strings(1)%s
    do j = 1, size(p%path_keywords)
      if (to_lower(raw) == p%path_keywords(j)%s) then
        v%strings(1)%s = p%path_keywords(j)%s
        v%resolved = p%path_keywords(j)%s
        return
      end if
    end do
    if (len_trim(raw) == 0) then
      call make_error(error, RD_ERR_INPUT, where // 'empty file name; expected ' // &
        expected_text(p))
      return
    end if
    v%resolved = path_join(dir, raw)
    if (p%must_exist) then
      select case (file_kind(v%resolved))
      case (FILE_REGULAR)
      case (FILE_MISSING)
        call make_error(error, RD_ERR_INPUT, where // "file not found: '" // raw // &
          "' (looked for '" // v%resolved // "'); expected an existing file, " // &
          "relative to the directory of the deck that names it")
      case default
        call make_error(error, RD_ERR_INPUT, where // "'" // raw // "' " // &
          regular_file_problem(v%resolved) // '; expected a regular file')
      end select
    end if
  end subroutine resolve_path
end module rd_deck_parser
