!> Helpers shared by the contact-geometry tests: where the shared reference data lives,
!> and a check that stops the test program with a message.
module geometry_test_support
  use rd_kinds, only: wp
  implicit none
  private
  public :: shared_dir, check, failures

  integer :: failures = 0

contains

  !> RAILDYN_SHARED_DIR (set by ctest), else ../shared next to the source tree.
  function shared_dir() result(dir)
    character(len=:), allocatable :: dir
    character(len=1024) :: buf
    integer :: n, st
    call get_environment_variable('RAILDYN_SHARED_DIR', buf, n, st)
    if (st == 0 .and. n > 0) then
      dir = trim(buf)
      return
    end if
    call get_environment_variable('RAILDYN_SOURCE_DIR', buf, n, st)
    if (st == 0 .and. n > 0) then
      dir = trim(buf) // '/../shared'
    else
      dir = '../shared'
    end if
  end function shared_dir

  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (ok) then
      write (*, '(a)') 'ok    ' // what
    else
      write (*, '(a)') 'FAIL  ' // what
      failures = failures + 1
    end if
  end subroutine check

end module geometry_test_support
