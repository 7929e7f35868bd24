!> What the build knows about its surroundings: the Python interpreter and package the
!> runner hands plots and campaigns to (configured by CMake, rd_build_config.inc.in).
module rd_build_info
  implicit none
  private
  public :: python_command, shell_quote

contains

  !> Shell prefix running the configured Python with the raildyn package on its path.
  !> `exec`: the interpreter replaces the shell, so that its exit status reaches the caller
  !> unchanged; otherwise a Ctrl-C that Python handles (campaigns: exit 130) also kills the
  !> waiting shell, and execute_command_line reports the signal number (2) as the status.
  function python_command() result(cmd)
    character(len=:), allocatable :: cmd
    include 'rd_build_config.inc'
    cmd = 'PYTHONPATH=' // shell_quote(python_package_dir) // '${PYTHONPATH:+:$PYTHONPATH} exec ' // &
          shell_quote(python_executable)
  end function python_command

  !> Single-quote a word for /bin/sh.
  pure function shell_quote(word) result(quoted)
    character(len=*), intent(in) :: word
    character(len=:), allocatable :: quoted
    integer :: i
    quoted = "'"
    do i = 1, len(word)
      if (word(i:i) == "'") then
        quoted = quoted // "'\''"
      else
        quoted = quoted // word(i:i)
      end if
    end do
    quoted = quoted // "'"
  end function shell_quote
end module rd_build_info
