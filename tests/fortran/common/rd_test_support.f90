!> The checks every Fortran test program uses: one failure counter per program, checks that
!> print what failed, and a summary that sets the exit code (ctest reads it).
!>
!> A check prints `FAIL  what` when it fails (many tests word `what` as the failure); when it
!> passes it prints `ok    what` only with a measured value or a detail, the figure worth
!> seeing in the log. A test calls `test_summary` last: exit code 1 if any check failed.
module rd_test_support
  use rd_kinds, only: wp
  use rd_error, only: error_t
  implicit none
  private
  public :: check, check_close, check_within, check_status, stop_on, fail, failure_count, test_summary, file_text

  integer :: n_checks = 0
  integer :: n_failures = 0

contains

  !> Pass if `ok`; `value` (a measured number) and `detail` (text) are printed with the result.
  subroutine check(ok, what, value, detail)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    real(wp), intent(in), optional :: value
    character(len=*), intent(in), optional :: detail
    character(len=32) :: number
    character(len=:), allocatable :: line
    n_checks = n_checks + 1
    line = what
    if (present(value)) then
      write (number, '(es10.3)') value
      line = line // ' (' // trim(adjustl(number)) // ')'
    end if
    if (present(detail)) line = line // '  ' // detail
    if (.not. ok) then
      n_failures = n_failures + 1
      write (*, '(a)') 'FAIL  ' // line
    else if (present(value) .or. present(detail)) then
      write (*, '(a)') 'ok    ' // line
    end if
  end subroutine check

  !> Pass if `got` is within `rel_tol` of `expected` relative to `|expected|`; a NaN fails.
  subroutine check_close(got, expected, rel_tol, what)
    real(wp), intent(in) :: got, expected, rel_tol
    character(len=*), intent(in) :: what
    n_checks = n_checks + 1
    if (.not. (abs(got - expected) <= rel_tol * abs(expected))) then
      n_failures = n_failures + 1
      write (*, '(a,es16.8,a,es16.8,a,es10.3,a,es9.2)') 'FAIL  ' // what // ': got ', got, &
        ' expected ', expected, ' rel ', got / expected - 1, ' tol ', rel_tol
    end if
  end subroutine check_close

  !> Pass if `error` is not allocated; otherwise print its message and clear it, so that the
  !> test goes on with the next case.
  subroutine check_status(error, what)
    type(error_t), allocatable, intent(inout) :: error
    character(len=*), intent(in) :: what
    n_checks = n_checks + 1
    if (allocated(error)) then
      n_failures = n_failures + 1
      write (*, '(a)') 'FAIL  ' // what // ': ' // error%message
      deallocate (error)
    end if
  end subroutine check_status

  !> Stop the test (exit code 1) with the error's message when `error` is allocated: for set-up
  !> steps the rest of the test cannot go on without.
  subroutine stop_on(error, what)
    type(error_t), allocatable, intent(in) :: error
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      write (*, '(a)') 'FAIL  ' // what // ': ' // error%message
      error stop 1
    end if
  end subroutine stop_on

  !> Pass if |value| <= bound; the value and the bound are printed with `what`.
  subroutine check_within(what, value, bound)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: value, bound
    character(len=24) :: text
    write (text, '(es10.3,a,es9.2)') value, ' / ', bound
    call check(abs(value) <= bound, what // ' = ' // trim(text))
  end subroutine check_within

  !> Count one failed check: described by `what`, or printed by the caller (formatted numbers).
  subroutine fail(what)
    character(len=*), intent(in), optional :: what
    n_checks = n_checks + 1
    n_failures = n_failures + 1
    if (present(what)) write (*, '(a)') 'FAIL  ' // what
  end subroutine fail

  !> Failed checks so far (for checks that summarise a group of checks).
  integer function failure_count()
    failure_count = n_failures
  end function failure_count

  !> Print the count of checks and failures; exit code 1 if any check failed.
  subroutine test_summary(program_name)
    character(len=*), intent(in) :: program_name
    if (n_failures > 0) then
      write (*, '(a,i0,a,i0,a)') program_name // ': ', n_failures, ' of ', n_checks, ' check(s) failed'
      error stop 1
    end if
    write (*, '(a,i0,a)') program_name // ': all ', n_checks, ' checks passed'
  end subroutine test_summary

  !> The whole of a text file (e.g. a results file's deck copy); a file that cannot be
  !> opened stops the test.
  function file_text(path) result(text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text
    integer :: unit, size_bytes, ios
    open (newunit=unit, file=path, access='stream', form='unformatted', status='old', &
          action='read', iostat=ios)
    if (ios /= 0) then
      write (*, '(a)') 'cannot open ' // path
      error stop 1
    end if
    inquire (unit=unit, size=size_bytes)
    allocate (character(len=size_bytes) :: text)
    read (unit) text
    close (unit)
  end function file_text
end module rd_test_support
