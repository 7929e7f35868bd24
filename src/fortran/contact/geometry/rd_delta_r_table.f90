!> A rolling-radius difference function as a table: Delta r = r_left - r_right [m] against
!> the wheelset's lateral shift y [m] (+ left, docs/conventions.md), linear between rows.
!> It comes from a profile scan or from a file: two columns of numbers (comma, blank or tab
!> separated, '#' comments), y strictly increasing, no header. This is the input of EN 15302's
!> conicity calculation (rd_equivalent_conicity); the table need not be symmetric and
!> Delta r(0) need not be 0.
module rd_delta_r_table
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_text, only: int_text, real_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_IO
  use rd_numeric_table, only: read_numeric_table
  use rd_file_kind, only: regular_file_problem
  implicit none
  private
  public :: delta_r_table_t, build_delta_r_table, read_delta_r_file, DELTA_R_MAX_VALUE

  !> Largest |y| and |Delta r| accepted [m]: a wheelset never moves 0.1 m on the track, so a
  !> larger number means the table is in millimetres.
  real(wp), parameter :: DELTA_R_MAX_VALUE = 0.1_wp

  type :: delta_r_table_t
    real(wp), allocatable :: y(:)        !< lateral shift, strictly increasing [m]
    real(wp), allocatable :: delta_r(:)  !< r_left - r_right at y [m]
  end type delta_r_table_t

contains

  !> Table from arrays (at least 2 rows, y strictly increasing, finite values within
  !> DELTA_R_MAX_VALUE); `origin` prefixes the messages.
  subroutine build_delta_r_table(table, y, delta_r, error, origin)
    type(delta_r_table_t), intent(out) :: table
    real(wp), intent(in) :: y(:), delta_r(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: origin
    character(len=:), allocatable :: where
    integer :: i
    where = 'Delta r table'
    if (present(origin)) where = origin
    if (size(y) /= size(delta_r)) then
      call make_error(error, RD_ERR_INPUT, where // ': y and Delta r differ in length')
      return
    end if
    if (size(y) < 2) then
      call make_error(error, RD_ERR_INPUT, where // ': ' // trim(int_text(size(y))) // &
                      ' rows, at least 2 are needed (y_m, delta_r_m)')
      return
    end if
    do i = 1, size(y)
      if (.not. (ieee_is_finite(y(i)) .and. ieee_is_finite(delta_r(i)))) then
        call make_error(error, RD_ERR_INPUT, where // ': row ' // trim(int_text(i)) // ' is not finite')
        return
      end if
      if (abs(y(i)) > DELTA_R_MAX_VALUE .or. abs(delta_r(i)) > DELTA_R_MAX_VALUE) then
        call make_error(error, RD_ERR_INPUT, where // ': row ' // trim(int_text(i)) // ': ' // too_large())
        return
      end if
      if (i > 1) then
        if (.not. (y(i) > y(i - 1))) then
          call make_error(error, RD_ERR_INPUT, where // ': row ' // trim(int_text(i)) // ': y ' // &
                          trim(real_text(y(i))) // ' m does not increase; y must be strictly increasing')
          return
        end if
      end if
    end do
    table%y = y
    table%delta_r = delta_r
  end subroutine build_delta_r_table

  !> Read `path`: one row per line, `y_m, delta_r_m` (exactly two numbers), y strictly
  !> increasing, blank lines and '#' comments skipped (rd_numeric_table). Errors name
  !> path:line and what is expected; a file that cannot be opened is an i/o error.
  subroutine read_delta_r_file(path, table, error)
    character(len=*), intent(in) :: path
    type(delta_r_table_t), intent(out) :: table
    type(error_t), allocatable, intent(out) :: error
    character(len=*), parameter :: columns = '(y_m, delta_r_m: lateral shift and rolling-radius ' // &
      'difference in metres, no header)'
    character(len=:), allocatable :: problem
    real(wp), allocatable :: rows(:, :)
    integer, allocatable :: line_of(:)
    integer :: i
    problem = regular_file_problem(path)
    if (len(problem) > 0) then
      call make_error(error, RD_ERR_IO, path // ': ' // problem // '; expected a Delta r file ' // columns)
      return
    end if
    call read_numeric_table(path, 2, 'Delta r file', columns, 'y', 2, rows, line_of, error)
    if (allocated(error)) return
    do i = 1, size(line_of)
      if (any(abs(rows(:, i)) > DELTA_R_MAX_VALUE)) then
        call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(line_of(i))) // ': ' // too_large())
        return
      end if
    end do
    call build_delta_r_table(table, rows(1, :), rows(2, :), error, origin=path)
  end subroutine read_delta_r_file

  pure function too_large() result(s)
    character(len=:), allocatable :: s
    s = 'a value exceeds ' // trim(real_text(DELTA_R_MAX_VALUE)) // ' m; y and Delta r are given in metres ' // &
        '(millimetres given?)'
  end function too_large
end module rd_delta_r_table
