!> What the build knows about its surroundings: the Python interpreter and package the
!> runner hands plots and campaigns to (configured by CMake, rd_build_config.inc.in).
module rd_build_info
  use, intrinsic :: iso_c_binding, only: c_char, c_int
  implicit none
  private
  public :: python_command, shell_quote, runner_path

  interface
    !> rd_executable_dir.c: the running executable's directory, 0 when unknown.
    function rd_executable_dir(buffer, capacity) result(length) bind(C, name='rd_executable_dir')
      import :: c_char, c_int
      character(kind=c_char), intent(out) :: buffer(*)
      integer(c_int), value :: capacity
      integer(c_int) :: length
    end function rd_executable_dir
  end interface

contains

  !> Shell prefix running the configured Python with the raildyn package on its path.
  !> `exec`: the interpreter replaces the shell, so that its exit status reaches the caller
  !> unchanged; otherwise a Ctrl-C that Python handles (campaigns: exit 130) also kills the
  !> waiting shell, and execute_command_line reports the signal number (2) as the status.
  function python_command() result(cmd)
    character(len=:), allocatable :: cmd
    include 'rd_build_config.inc'
    cmd = 'PYTHONPATH=' // shell_quote(python_package_path()) // '${PYTHONPATH:+:$PYTHONPATH} exec ' // &
          shell_quote(python_executable)
  end function python_command

  !> The folder holding the raildyn package: the installed one beside an installed runner
  !> (<bin>/<python_package_dir_from_bin>, cmake --install), else the build's source tree.
  function python_package_path() result(dir)
    character(len=:), allocatable :: dir
    include 'rd_build_config.inc'
    character(kind=c_char, len=4096) :: exe_dir
    integer :: length
    logical :: installed
    dir = python_package_dir
    length = rd_executable_dir(exe_dir, len(exe_dir))
    if (length == 0) return
    inquire (file=exe_dir(1:length) // '/' // python_package_dir_from_bin // '/raildyn/__init__.py', exist=installed)
    if (installed) dir = exe_dir(1:length) // '/' // python_package_dir_from_bin
  end function python_package_path

  !> The running executable as a path another program can start (its directory from
  !> /proc/self/exe, its name from the command line), so that the Python side of a command
  !> runs this very runner; the command line's own argument 0 when the directory is unknown.
  function runner_path() result(path)
    character(len=:), allocatable :: path
    character(kind=c_char, len=4096) :: exe_dir
    character(len=4096) :: arg0
    integer :: length
    call get_command_argument(0, arg0)
    path = trim(arg0)
    length = rd_executable_dir(exe_dir, len(exe_dir))
    if (length == 0) return
    path = exe_dir(1:length) // '/' // path(index(path, '/', back=.true.) + 1:)
  end function runner_path

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
