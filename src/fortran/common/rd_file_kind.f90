!> What a path names: a regular file, a directory, something else (FIFO, device,
!> socket) or nothing. Input files (decks, includes, profiles, tables) must be
!> regular files: a directory reads as an empty file, /dev/zero as an endless one,
!> and a FIFO blocks the reader forever.
module rd_file_kind
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  implicit none
  private
  public :: file_kind, regular_file_problem
  public :: FILE_MISSING, FILE_REGULAR, FILE_DIRECTORY, FILE_SPECIAL

  integer, parameter :: FILE_MISSING = 0, FILE_REGULAR = 1, FILE_DIRECTORY = 2, FILE_SPECIAL = 3

  interface
    function rd_file_kind_c(path) result(kind) bind(C, name='rd_file_kind_c')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: kind
    end function rd_file_kind_c
  end interface

contains

  !> FILE_MISSING, FILE_REGULAR, FILE_DIRECTORY or FILE_SPECIAL (links followed).
  integer function file_kind(path)
    character(len=*), intent(in) :: path
    file_kind = int(rd_file_kind_c(path // c_null_char))
  end function file_kind

  !> '' for a regular file, else what the path is instead ("is a directory", ...),
  !> for messages of the form "<file>: <problem>; expected a regular file".
  function regular_file_problem(path) result(problem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: problem
    select case (file_kind(path))
    case (FILE_REGULAR); problem = ''
    case (FILE_DIRECTORY); problem = 'is a directory'
    case (FILE_SPECIAL); problem = 'is not a regular file (a device, FIFO or socket)'
    case default; problem = 'does not exist or cannot be examined'
    end select
  end function regular_file_problem
end module rd_file_kind
