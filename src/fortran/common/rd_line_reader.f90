!> Line by line reading of the text input files (profiles, survey points, track
!> irregularities) that never cuts a line silently: a line longer than the caller's
!> buffer is an error naming file and line (a cut line can still parse as numbers, or
!> lose the digits of a number).
module rd_line_reader
  use, intrinsic :: iso_fortran_env, only: iostat_end, iostat_eor
  use rd_text, only: int_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_IO
  implicit none
  private
  public :: read_line

contains

  !> The next line of `unit` into `line` (its length is the longest line accepted);
  !> `nline` counts the lines read. ios: 0 for a line, iostat_end at the end of the
  !> file, anything else with `error` set.
  subroutine read_line(unit, path, nline, line, ios, error)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: path
    integer, intent(inout) :: nline
    character(len=*), intent(out) :: line
    integer, intent(out) :: ios
    type(error_t), allocatable, intent(inout) :: error
    character(len=len(line) + 1) :: buffer
    integer :: n
    line = ' '
    read (unit, '(a)', advance='no', size=n, iostat=ios) buffer
    if (ios == iostat_end) return
    nline = nline + 1
    if (ios == 0 .or. n > len(line)) then
      ! the buffer filled without reaching the end of the line
      call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(nline)) // &
        ': line longer than ' // trim(int_text(len(line))) // ' characters; expected one ' // &
        'entry per line')
      ios = 1
      return
    end if
    if (ios == iostat_eor) ios = 0
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, path // ':' // trim(int_text(nline)) // ': cannot be read')
      return
    end if
    line = buffer(1:n)
  end subroutine read_line
end module rd_line_reader
