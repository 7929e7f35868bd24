!> One line of a plain numeric table file (surveyed track points, track irregularities):
!> '#' starts a comment, blanks, tabs, commas and carriage returns separate the tokens, and
!> the first columns must be numbers. List-directed reads alone would accept '/' (end of
!> record) and 'n*' (repeat count) and read 'NaN'/'Inf', so those are refused here: a table
!> with a slash or an infinite value is a broken file, never data.
module rd_numeric_line
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  implicit none
  private
  public :: numeric_line_t, parse_numeric_line

  type :: numeric_line_t
    logical :: blank = .true.          !< nothing but blanks and a comment
    integer :: n_tokens = 0            !< tokens on the line (all, not only the parsed ones)
    integer :: bad_column = 0          !< first parsed column that is not a finite number (0: none)
    logical :: bad_is_nonfinite = .false.  !< that column is a number, but NaN or infinite
    character(len=:), allocatable :: bad_token
  end type numeric_line_t

contains

  !> Strip the comment and turn separators into blanks in `line` (callers quote the cleaned
  !> line in their messages), count its tokens and read the first size(values) of them.
  subroutine parse_numeric_line(line, values, info)
    character(len=*), intent(inout) :: line
    real(wp), intent(out) :: values(:)
    type(numeric_line_t), intent(out) :: info
    integer :: hash, k, first, last, ios
    values = 0
    hash = index(line, '#')
    if (hash > 0) line(hash:) = ' '
    do k = 1, len_trim(line)
      if (line(k:k) == ',' .or. line(k:k) == char(9) .or. line(k:k) == char(13)) line(k:k) = ' '
    end do
    info%blank = len_trim(line) == 0
    if (info%blank) return
    last = 0
    do
      first = verify(line(last + 1:), ' ')
      if (first == 0) exit
      first = last + first
      last = index(line(first:), ' ') - 1
      if (last < 0) then
        last = len(line)
      else
        last = first + last - 1
      end if
      info%n_tokens = info%n_tokens + 1
      if (info%n_tokens <= size(values) .and. info%bad_column == 0) then
        read (line(first:last), *, iostat=ios) values(info%n_tokens)
        if (ios /= 0 .or. scan(line(first:last), '/*') /= 0) then
          info%bad_column = info%n_tokens
          info%bad_token = line(first:last)
        else if (.not. ieee_is_finite(values(info%n_tokens))) then
          info%bad_column = info%n_tokens
          info%bad_is_nonfinite = .true.
          info%bad_token = line(first:last)
        end if
      end if
      if (last >= len(line)) exit
    end do
  end subroutine parse_numeric_line

end module rd_numeric_line
