!> docs/input_reference.md documents exactly the schema: every group and
!> parameter, nothing else, with the same type, unit, default and valid
!> range / allowed values. The tables are parsed back here (numbers read
!> with Fortran's own READ, intervals and lists taken apart by this test),
!> so a hand edit of a table or a schema change without regenerating the
!> document fails.
program test_deck_reference_doc
  use rd_kinds, only: wp
  use rd_deck_schema, only: deck_schema_t, param_schema_t, build_deck_schema, PT_REAL, &
                            PT_INTEGER, PT_STRING, PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST, &
                            DEF_REQUIRED, DEF_VALUE, DEF_OPTIONAL, DEF_PREVIOUS, DEF_DECK_STEM
  use rd_test_support, only: check, failure_count, test_summary
  implicit none
  type(deck_schema_t) :: s
  character(len=4096) :: env, line
  character(len=:), allocatable :: path, cell(:)
  integer :: u, ios, st, g, j, k, nrows
  logical :: in_tables
  logical, allocatable :: seen(:, :)
  integer, parameter :: maxp = 64

  s = build_deck_schema()
  allocate (seen(size(s%groups), maxp)); seen = .false.
  call get_environment_variable('RAILDYN_SOURCE_DIR', env, status=st)
  if (st /= 0) env = '.'
  path = trim(env) // '/docs/input_reference.md'
  open (newunit=u, file=path, status='old', action='read', iostat=ios)
  if (ios /= 0) then
    print '(a)', 'FAIL: cannot open ' // path
    error stop 1
  end if
  in_tables = .false.; g = 0; nrows = 0
  do
    read (u, '(a)', iostat=ios) line
    if (ios /= 0) exit
    if (trim(line) == '<!-- BEGIN schema -->') in_tables = .true.
    if (trim(line) == '<!-- END schema -->') in_tables = .false.
    if (.not. in_tables) cycle
    if (line(1:5) == '### &') then
      g = 0
      do k = 1, size(s%groups)
        if (s%groups(k)%name == trim(line(6:))) g = k
      end do
      call check(g > 0, 'documented group not in the schema: ' // trim(line))
      if (g > 0) call check(all(.not. seen(g, :)), 'group documented twice: ' // trim(line))
      if (g > 0) then
        ! the sentence after the heading says whether the group repeats
        read (u, '(a)') line
        read (u, '(a)') line
        call check(index(line, '(repeatable)') > 0 .eqv. s%groups(g)%repeatable, &
                   'repeatable flag of &' // s%groups(g)%name)
      end if
      cycle
    end if
    if (line(1:3) /= '| `') cycle
    call split_row(trim(line), cell)
    call check(size(cell) == 6, 'row with ' // trim(line))
    if (size(cell) /= 6 .or. g == 0) cycle
    j = 0
    do k = 1, size(s%groups(g)%params)
      if ('`' // s%groups(g)%params(k)%name // '`' == cell(1)) j = k
    end do
    call check(j > 0, '&' // s%groups(g)%name // ': documented parameter not in the schema: ' // &
               trim(cell(1)))
    if (j == 0) cycle
    call check(.not. seen(g, j), 'parameter documented twice: ' // trim(cell(1)))
    seen(g, j) = .true.
    nrows = nrows + 1
    call check_row(s%groups(g)%name, s%groups(g)%params(j), cell)
  end do
  close (u)
  do g = 1, size(s%groups)
    do j = 1, size(s%groups(g)%params)
      call check(seen(g, j), 'not documented: &' // s%groups(g)%name // ' ' // &
                 s%groups(g)%params(j)%name)
    end do
  end do
  if (failure_count() > 0) print '(a)', 'regenerate the tables with rd_deck_schema_doc'
  call test_summary('test_deck_reference_doc')
  print '(a,i0,a)', 'test_deck_reference_doc: ', nrows, ' parameters documented as in the schema'

contains

  !> "| a | b | c |" -> [a, b, c] (trimmed)
  subroutine split_row(row, cells)
    character(len=*), intent(in) :: row
    character(len=:), allocatable, intent(out) :: cells(:)
    integer :: k, n, a, b
    integer :: bars(64)
    n = 0
    do k = 1, len(row)
      if (row(k:k) == '|') then
        n = n + 1; bars(n) = k
      end if
    end do
    allocate (character(len=len(row)) :: cells(max(0, n - 1)))
    do k = 1, n - 1
      a = bars(k) + 1; b = bars(k + 1) - 1
      cells(k) = adjustl(row(a:b))
    end do
  end subroutine split_row

  subroutine check_row(gname, p, c)
    character(len=*), intent(in) :: gname
    type(param_schema_t), intent(in) :: p
    character(len=*), intent(in) :: c(:)
    character(len=:), allocatable :: id, expect_type, def, valid
    id = '&' // gname // ' ' // p%name // ': '
    ! type
    select case (p%ptype)
    case (PT_REAL); expect_type = 'real'
    case (PT_INTEGER); expect_type = 'integer'
    case (PT_LOGICAL); expect_type = 'logical'
    case (PT_STRING)
      expect_type = 'string'
      if (p%is_path) expect_type = 'path'
      if (len(p%ref_group) > 0) expect_type = 'name of a &' // p%ref_group
    case (PT_REAL_ARRAY)
      expect_type = 'real list'
      if (p%size > 0) then
        block
          character(len=16) :: buf
          write (buf, '(a,i0,a)') 'real(', p%size, ')'
          expect_type = trim(buf)
        end block
      end if
    case (PT_STRING_LIST); expect_type = 'string list'
    end select
    call check(trim(c(2)) == expect_type, id // 'type "' // trim(c(2)) // '" vs ' // expect_type)
    call check(trim(c(3)) == p%unit, id // 'unit "' // trim(c(3)) // '" vs ' // p%unit)
    call check(index(c(6), p%meaning) == 1, id // 'meaning')

    ! default
    def = trim(c(4))
    select case (p%default_kind)
    case (DEF_REQUIRED)
      call check(def == 'required', id // 'default should be required: ' // def)
    case (DEF_OPTIONAL)
      call check(def == 'none', id // 'default should be none: ' // def)
    case (DEF_DECK_STEM)
      call check(def == 'deck stem + ' // p%default_strings(1)%s, id // 'default ' // def)
    case (DEF_VALUE, DEF_PREVIOUS)
      if (p%default_kind == DEF_PREVIOUS) then
        call check(index(def, 'previous, first ') == 1, id // 'previous default: ' // def)
        def = def(len('previous, first ') + 1:)
      end if
      select case (p%ptype)
      case (PT_REAL, PT_REAL_ARRAY)
        call check(same_reals(def, p%default_reals), id // 'default ' // def)
      case (PT_INTEGER)
        block
          integer :: m, ios2
          read (def, *, iostat=ios2) m
          call check(ios2 == 0 .and. m == p%default_integer, id // 'default ' // def)
        end block
      case (PT_LOGICAL)
        block
          logical :: b
          integer :: ios2
          read (def, *, iostat=ios2) b
          call check(ios2 == 0 .and. (b .eqv. p%default_logical), id // 'default ' // def)
        end block
      case (PT_STRING)
        call check(def == "'" // p%default_strings(1)%s // "'", id // 'default ' // def)
      case (PT_STRING_LIST)
        if (size(p%default_strings) == 0) then
          call check(def == 'empty', id // 'default ' // def)
        else
          call check(same_list(def, p%default_strings), id // 'default ' // def)
        end if
      end select
    end select

    ! valid values
    valid = trim(c(5))
    if (size(p%allowed) > 0) then
      call check(same_list(after(valid, merge('any of: ', 'one of: ', p%ptype == PT_STRING_LIST)), &
                           p%allowed), id // 'allowed values ' // valid)
    else if (size(p%ref_keywords) > 0) then
      call check(same_list(after(valid, 'a &' // p%ref_group // ' name or: '), p%ref_keywords), &
                 id // 'reference keywords ' // valid)
    else if (size(p%path_keywords) > 0) then
      call check(same_list(after(valid, 'a file or one of: '), p%path_keywords), &
                 id // 'path keywords ' // valid)
    else
      call check_range(id, valid, p)
    end if
  end subroutine check_row

  !> Text after a prefix, or a marker that matches no list when it is absent.
  function after(text, prefix) result(rest)
    character(len=*), intent(in) :: text, prefix
    character(len=:), allocatable :: rest
    if (index(text, prefix) == 1) then
      rest = text(len(prefix) + 1:)
    else
      rest = '<missing "' // prefix // '">'
    end if
  end function after

  logical function same_list(text, items)
    use rd_deck_text, only: deck_string_t
    character(len=*), intent(in) :: text
    type(deck_string_t), intent(in) :: items(:)
    integer :: start, n, comma
    start = 1; n = 0
    same_list = .true.
    do while (start <= len(text))
      comma = index(text(start:), ', ')
      n = n + 1
      if (n > size(items)) then
        same_list = .false.; return
      end if
      if (comma == 0) then
        same_list = same_list .and. text(start:) == items(n)%s
        exit
      end if
      same_list = same_list .and. text(start:start + comma - 2) == items(n)%s
      start = start + comma + 1
    end do
    same_list = same_list .and. n == size(items)
  end function same_list

  logical function same_reals(text, x)
    character(len=*), intent(in) :: text
    real(wp), intent(in) :: x(:)
    real(wp) :: y(16)
    integer :: n, k, ios2, start, sp
    character(len=:), allocatable :: word
    if (text == 'empty') then
      same_reals = size(x) == 0; return
    end if
    n = 0; start = 1
    same_reals = .false.
    do while (start <= len(text))
      sp = index(text(start:), ' ')
      if (sp == 0) then
        word = text(start:); start = len(text) + 1
      else
        word = text(start:start + sp - 2); start = start + sp
      end if
      n = n + 1
      if (n > size(y)) return
      if (word == 'huge') then
        y(n) = huge(1.0_wp)
      else
        read (word, *, iostat=ios2) y(n)
        if (ios2 /= 0) return
      end if
    end do
    if (n /= size(x)) return
    same_reals = all([(y(k) == x(k), k=1, n)])
  end function same_reals

  !> "[a, b]" "(a, b]" "> a" ">= a" "< b" "<= b" or empty.
  subroutine check_range(id, text, p)
    character(len=*), intent(in) :: id, text
    type(param_schema_t), intent(in) :: p
    real(wp) :: a, b
    integer :: comma, ios2, ios3
    logical :: ok
    if (len(text) == 0) then
      call check(.not. p%has_min .and. .not. p%has_max, id // 'range missing')
      return
    end if
    ok = .false.
    if (text(1:1) == '[' .or. text(1:1) == '(') then
      comma = index(text, ',')
      read (text(2:comma - 1), *, iostat=ios2) a
      read (text(comma + 1:len(text) - 1), *, iostat=ios3) b
      ok = ios2 == 0 .and. ios3 == 0 .and. p%has_min .and. p%has_max
      if (ok) ok = a == p%min .and. b == p%max .and. &
                   ((text(1:1) == '(') .eqv. p%min_open) .and. &
                   ((text(len(text):len(text)) == ')') .eqv. p%max_open)
    else if (index(text, '>= ') == 1 .or. index(text, '> ') == 1) then
      read (text(index(text, ' ') + 1:), *, iostat=ios2) a
      ok = ios2 == 0 .and. p%has_min .and. .not. p%has_max
      if (ok) ok = a == p%min .and. ((text(2:2) == ' ') .eqv. p%min_open)
    else if (index(text, '<= ') == 1 .or. index(text, '< ') == 1) then
      read (text(index(text, ' ') + 1:), *, iostat=ios2) b
      ok = ios2 == 0 .and. p%has_max .and. .not. p%has_min
      if (ok) ok = b == p%max .and. ((text(2:2) == ' ') .eqv. p%max_open)
    end if
    call check(ok, id // 'range "' // text // '"')
  end subroutine check_range
end program test_deck_reference_doc
