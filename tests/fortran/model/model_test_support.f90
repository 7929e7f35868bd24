!> Shared helpers of the scene-level tests (label model): a failure counter with `check`, and
!> `stop_on` for errors after which a test cannot go on.
module model_test_support
  use rd_error, only: error_t
  implicit none
  private
  public :: failures, check, stop_on

  integer :: failures = 0

contains

  !> Count and print a failed check; the test program stops non-zero at its end.
  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (.not. ok) then
      failures = failures + 1
      write (*, '(a)') 'FAILED: ' // what
    end if
  end subroutine check

  !> Stop the test with the error's message when `error` is allocated.
  subroutine stop_on(error, what)
    type(error_t), allocatable, intent(in) :: error
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      write (*, '(a)') 'FAILED: ' // what // ': ' // error%message
      error stop 1
    end if
  end subroutine stop_on

end module model_test_support
