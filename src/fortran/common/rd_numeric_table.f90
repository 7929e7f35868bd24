!> A plain numeric table file read whole (track irregularities, rolling-radius difference
!> tables): one row of exactly `ncol` numbers per line (rd_numeric_line: blanks, tabs or
!> commas, '#' comments, blank lines skipped), the first column strictly increasing. Errors
!> name path:line and what is expected; the file line of every row is returned so that the
!> caller's own checks can name it too.
module rd_numeric_table
  use rd_kinds, only: wp
  use rd_text, only: int_text, real_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_IO
  use rd_numeric_line, only: numeric_line_t, parse_numeric_line
  use rd_line_reader, only: read_line
  implicit none
  private
  public :: read_numeric_table

contains

  !> rows(ncol, n) and line_of(n) from `path`. `what` names the file in the open error
  !> ("irregularity file"), `columns` describes the columns in messages ("(sigma ...,
  !> metres)"), `first_name` the first column ("sigma"); at least `min_rows` rows.
  subroutine read_numeric_table(path, ncol, what, columns, first_name, min_rows, rows, line_of, error)
    character(len=*), intent(in) :: path, what, columns, first_name
    integer, intent(in) :: ncol, min_rows
    real(wp), allocatable, intent(out) :: rows(:, :)
    integer, allocatable, intent(out) :: line_of(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=4096) :: line
    character(len=256) :: message
    real(wp) :: row(ncol)
    integer :: unit, ios, line_no, n
    type(numeric_line_t) :: info

    open (newunit=unit, file=path, status='old', action='read', iostat=ios, iomsg=message)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, path // ': cannot open ' // what // ' (' // trim(message) // ')')
      return
    end if
    allocate (rows(ncol, 256), line_of(256))
    n = 0
    line_no = 0
    do
      call read_line(unit, path, line_no, line, ios, error)
      if (allocated(error)) then
        close (unit); return
      end if
      if (ios /= 0) exit
      call parse_numeric_line(line, row, info)
      if (info%blank) cycle
      if (info%bad_column > 0) then
        if (info%bad_is_nonfinite) then
          call fail(': column ' // trim(int_text(info%bad_column)) // ' is not finite (' // info%bad_token // ')')
        else
          call fail(': column ' // trim(int_text(info%bad_column)) // ' "' // info%bad_token // &
                    '" is not a number; expected ' // trim(int_text(ncol)) // ' numbers ' // columns)
        end if
        return
      end if
      if (info%n_tokens /= ncol) then
        call fail(': ' // trim(int_text(info%n_tokens)) // ' columns, expected ' // trim(int_text(ncol)) // ' ' // columns)
        return
      end if
      if (n > 0) then
        if (.not. (row(1) > rows(1, n))) then
          call fail(': ' // first_name // ' ' // trim(real_text(row(1))) // ' m does not increase (line ' // &
                    trim(int_text(line_of(n))) // ' has ' // trim(real_text(rows(1, n))) // ' m); ' // first_name // &
                    ' must be strictly increasing')
          return
        end if
      end if
      if (n == size(line_of)) then
        rows = reshape(rows, [ncol, 2 * n], pad=[0.0_wp])
        line_of = [line_of, line_of]
      end if
      n = n + 1
      rows(:, n) = row
      line_of(n) = line_no
    end do
    close (unit)
    if (n < min_rows) then
      call make_error(error, RD_ERR_INPUT, path // ': ' // trim(int_text(n)) // ' data lines found, at least ' // &
                      trim(int_text(min_rows)) // ' are needed ' // columns)
      return
    end if
    rows = rows(:, 1:n)
    line_of = line_of(1:n)
  contains
    subroutine fail(text)
      character(len=*), intent(in) :: text
      close (unit)
      call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(line_no)) // text)
    end subroutine fail
  end subroutine read_numeric_table
end module rd_numeric_table
