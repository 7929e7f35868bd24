!> Small text utilities of the deck reader: case folding, strict number
!> recognition, edit distance for "did you mean" suggestions, number
!> formatting for messages and the generated reference, and path handling.
!>
!> Numbers are recognised by an explicit grammar before conversion because
!> Fortran's list-directed READ accepts text that is not a number for a user
!> (gfortran reads '12OO.0' as 12, f90nml as a list): a deck value is only a
!> number if it matches  [sign] digits [. [digits]] [(e|d) [sign] digits]
!> (or  [sign] . digits [exponent]).
module rd_deck_text
  use rd_text, only: int_text, to_lower => lower_case
  use rd_kinds, only: wp
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: deck_string_t, append_string, in_list, joined, single_string, to_lower, int_to_str, real_to_str, edit_distance
  public :: is_integer_text, is_real_text, text_to_real, text_to_integer, text_to_logical
  public :: path_dir, path_base, path_stem, path_join, is_absolute_path

  !> A variable-length string, element of string lists.
  type :: deck_string_t
    character(len=:), allocatable :: s
  end type deck_string_t

contains

  !> Append to a string list (explicit copies: gfortran 12 may lose
  !> deferred-length components in array constructors of structure constructors).
  subroutine append_string(list, s)
    type(deck_string_t), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: s
    type(deck_string_t), allocatable :: grown(:)
    integer :: n
    n = 0
    if (allocated(list)) n = size(list)
    allocate (grown(n + 1))
    if (n > 0) grown(1:n) = list
    grown(n + 1)%s = s
    call move_alloc(grown, list)
  end subroutine append_string

  !> True when `word` is one of the strings of `list`.
  pure logical function in_list(word, list)
    character(len=*), intent(in) :: word
    type(deck_string_t), intent(in) :: list(:)
    integer :: j
    in_list = .false.
    do j = 1, size(list)
      if (list(j)%s == word) in_list = .true.
    end do
  end function in_list

  !> The strings of `list`, each between `quote`s, separated by ', ' ('' for none).
  pure function joined(list, quote) result(t)
    type(deck_string_t), intent(in) :: list(:)
    character(len=*), intent(in) :: quote
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, size(list)
      if (i > 1) t = t // ', '
      t = t // quote // list(i)%s // quote
    end do
  end function joined

  function single_string(s) result(list)
    character(len=*), intent(in) :: s
    type(deck_string_t), allocatable :: list(:)
    allocate (list(1))
    list(1)%s = s
  end function single_string

  pure function int_to_str(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    s = trim(int_text(i))
  end function int_to_str

  !> Shortest decimal text that reads back to exactly x (plain notation for
  !> moderate exponents, otherwise mantissa 'e' exponent, e.g. 8.2e10, 1e-6).
  function real_to_str(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=40) :: buf, fmt
    character(len=:), allocatable :: mant
    real(wp) :: back
    integer :: d, e, epos, ios, ndig
    logical :: neg
    if (x == 0.0_wp) then
      s = '0'; return
    end if
    if (.not. ieee_is_finite(x)) then
      s = 'inf'
      if (x < 0) s = '-inf'
      return
    end if
    if (abs(x) >= huge(x)) then
      s = 'huge'; return
    end if
    do d = 0, 17
      write (fmt, '(a,i0,a,i0,a)') '(es', d + 10, '.', d, 'e3)'
      write (buf, fmt) x
      read (buf, *, iostat=ios) back
      if (ios == 0 .and. back == x) exit
    end do
    buf = adjustl(buf)
    neg = buf(1:1) == '-'
    if (neg) buf = buf(2:)
    epos = index(buf, 'E')
    read (buf(epos + 1:), *) e
    ! digits of the mantissa without the point, trailing zeros removed
    mant = buf(1:1)
    if (epos > 3) mant = mant // buf(3:epos - 1)
    ndig = len(mant)
    do while (ndig > 1 .and. mant(ndig:ndig) == '0')
      ndig = ndig - 1
    end do
    mant = mant(1:ndig)
    if (e >= -4 .and. e <= 6) then
      if (e >= 0) then
        if (ndig <= e + 1) then
          s = mant // repeat('0', e + 1 - ndig)
        else
          s = mant(1:e + 1) // '.' // mant(e + 2:)
        end if
      else
        s = '0.' // repeat('0', -e - 1) // mant
      end if
    else
      s = mant(1:1)
      if (ndig > 1) s = s // '.' // mant(2:)
      s = s // 'e' // int_to_str(e)
    end if
    if (neg) s = '-' // s
  end function real_to_str

  !> Levenshtein distance (insertions, deletions, substitutions), case-insensitive.
  pure function edit_distance(a, b) result(dist)
    character(len=*), intent(in) :: a, b
    integer :: dist
    integer :: prev(0:len(b)), cur(0:len(b))
    integer :: i, j, cost
    character(len=len(a)) :: la
    character(len=len(b)) :: lb
    la = to_lower(a); lb = to_lower(b)
    do j = 0, len(b)
      prev(j) = j
    end do
    do i = 1, len(a)
      cur(0) = i
      do j = 1, len(b)
        cost = merge(0, 1, la(i:i) == lb(j:j))
        cur(j) = min(prev(j) + 1, cur(j - 1) + 1, prev(j - 1) + cost)
      end do
      prev = cur
    end do
    dist = prev(len(b))
  end function edit_distance

  pure logical function is_digit(c)
    character, intent(in) :: c
    is_digit = c >= '0' .and. c <= '9'
  end function is_digit

  !> [sign] digits
  pure logical function is_integer_text(t)
    character(len=*), intent(in) :: t
    integer :: i, i0
    is_integer_text = .false.
    if (len(t) == 0) return
    i0 = 1
    if (t(1:1) == '+' .or. t(1:1) == '-') i0 = 2
    if (i0 > len(t)) return
    do i = i0, len(t)
      if (.not. is_digit(t(i:i))) return
    end do
    is_integer_text = .true.
  end function is_integer_text

  !> [sign] (digits [. digits*] | . digits) [(e|d) [sign] digits]
  pure logical function is_real_text(t)
    character(len=*), intent(in) :: t
    integer :: i, n, ndig
    is_real_text = .false.
    n = len(t); i = 1
    if (n == 0) return
    if (t(1:1) == '+' .or. t(1:1) == '-') i = 2
    ndig = 0
    do while (i <= n)
      if (.not. is_digit(t(i:i))) exit
      ndig = ndig + 1; i = i + 1
    end do
    if (i <= n) then
      if (t(i:i) == '.') then
        i = i + 1
        do while (i <= n)
          if (.not. is_digit(t(i:i))) exit
          ndig = ndig + 1; i = i + 1
        end do
      end if
    end if
    if (ndig == 0) return
    if (i <= n) then
      if (index('eEdD', t(i:i)) == 0) return
      i = i + 1
      if (i <= n) then
        if (t(i:i) == '+' .or. t(i:i) == '-') i = i + 1
      end if
      if (i > n) return
      do while (i <= n)
        if (.not. is_digit(t(i:i))) return
        i = i + 1
      end do
    end if
    is_real_text = .true.
  end function is_real_text

  !> Convert text already accepted by is_real_text; ok = .false. on overflow.
  subroutine text_to_real(t, x, ok)
    character(len=*), intent(in) :: t
    real(wp), intent(out) :: x
    logical, intent(out) :: ok
    character(len=len(t)) :: u
    integer :: i, ios
    u = t
    do i = 1, len(u)
      if (u(i:i) == 'd' .or. u(i:i) == 'D') u(i:i) = 'e'
    end do
    ! Decide overflow from the text: converting 1e999 would raise the
    ! overflow exception (trapped in debug builds) before we could test it.
    x = 0.0_wp
    ok = abs(decimal_magnitude(u)) <= 300
    if (.not. ok) return
    read (u, *, iostat=ios) x
    ok = ios == 0
    if (ok) ok = ieee_is_finite(x)
    if (.not. ok) x = 0.0_wp
  end subroutine text_to_real

  !> Power of ten of a number's leading digit (0 for zero), from its text.
  pure integer function decimal_magnitude(t)
    character(len=*), intent(in) :: t
    integer :: i, epos, dot, first, e, ios
    decimal_magnitude = 0
    epos = scan(t, 'eE')
    e = 0
    if (epos > 0) then
      if (len(t) - epos > 6) then
        decimal_magnitude = 1000000   ! exponent of more than 6 digits
        if (index(t(epos + 1:), '-') > 0) decimal_magnitude = -decimal_magnitude
        return
      end if
      read (t(epos + 1:), *, iostat=ios) e
    else
      epos = len(t) + 1
    end if
    dot = index(t(1:epos - 1), '.')
    if (dot == 0) dot = epos
    first = 0
    do i = 1, epos - 1
      if (t(i:i) >= '1' .and. t(i:i) <= '9') then
        first = i; exit
      end if
    end do
    if (first == 0) return
    if (first < dot) then
      decimal_magnitude = dot - first - 1 + e
    else
      decimal_magnitude = dot - first + e
    end if
  end function decimal_magnitude

  subroutine text_to_integer(t, k, ok)
    character(len=*), intent(in) :: t
    integer, intent(out) :: k
    logical, intent(out) :: ok
    integer :: ios
    read (t, *, iostat=ios) k
    ok = ios == 0 .and. len(t) <= 10
    if (.not. ok) k = 0
  end subroutine text_to_integer

  !> .true. .false. .t. .f. t f true false (any case), as Fortran namelists.
  pure subroutine text_to_logical(t, val, ok)
    character(len=*), intent(in) :: t
    logical, intent(out) :: val, ok
    select case (to_lower(t))
    case ('.true.', '.t.', 't', 'true', '.true', '.t')
      val = .true.; ok = .true.
    case ('.false.', '.f.', 'f', 'false', '.false', '.f')
      val = .false.; ok = .true.
    case default
      val = .false.; ok = .false.
    end select
  end subroutine text_to_logical

  pure logical function is_absolute_path(p)
    character(len=*), intent(in) :: p
    is_absolute_path = .false.
    if (len(p) > 0) is_absolute_path = p(1:1) == '/'
  end function is_absolute_path

  !> Directory part of a path ('.' when there is none), without trailing '/'.
  pure function path_dir(p) result(d)
    character(len=*), intent(in) :: p
    character(len=:), allocatable :: d
    integer :: k
    k = index(p, '/', back=.true.)
    if (k == 0) then
      d = '.'
    else if (k == 1) then
      d = '/'
    else
      d = p(1:k - 1)
    end if
  end function path_dir

  pure function path_base(p) result(b)
    character(len=*), intent(in) :: p
    character(len=:), allocatable :: b
    b = p(index(p, '/', back=.true.) + 1:)
  end function path_base

  !> File name without directory and without its last extension.
  pure function path_stem(p) result(s)
    character(len=*), intent(in) :: p
    character(len=:), allocatable :: s
    integer :: k
    s = path_base(p)
    k = index(s, '.', back=.true.)
    if (k > 1) s = s(1:k - 1)
  end function path_stem

  !> dir/p unless p is absolute or dir is '.'
  pure function path_join(dir, p) result(j)
    character(len=*), intent(in) :: dir, p
    character(len=:), allocatable :: j
    if (is_absolute_path(p) .or. len(dir) == 0 .or. dir == '.') then
      j = p
    else if (dir(len(dir):len(dir)) == '/') then
      j = dir // p
    else
      j = dir // '/' // p
    end if
  end function path_join
end module rd_deck_text
