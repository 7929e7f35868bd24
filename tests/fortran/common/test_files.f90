!> Files of the Fortran test programs: the repository's reference data (found through the
!> source tree, never a directory beside it) and scratch files with names unique to one run,
!> so that two test runs at once (two build trees, two developers) never share a file.
module test_files
  use rd_kinds, only: wp
  implicit none
  private
  public :: source_path, reference_path, scratch_name, write_file, delete_file

contains

  !> A path inside the source tree: $RAILDYN_SOURCE_DIR (set by ctest) / relative, else
  !> relative as given (ctest's working directory is the source tree).
  function source_path(relative) result(path)
    character(len=*), intent(in) :: relative
    character(len=:), allocatable :: path
    character(len=4096) :: dir
    integer :: length, status
    call get_environment_variable('RAILDYN_SOURCE_DIR', dir, length, status)
    if (status == 0 .and. length > 0) then
      path = trim(dir) // '/' // relative
    else
      path = relative
    end if
  end function source_path

  !> A file of validation/reference/ (third-party and published reference data with their
  !> provenance, validation/reference/README.md).
  function reference_path(relative) result(path)
    character(len=*), intent(in) :: relative
    character(len=:), allocatable :: path
    path = source_path('validation/reference/' // relative)
  end function reference_path

  !> $TMPDIR/raildyn_<stem>_<12 random digits><suffix> (suffix default '.txt'); the digits
  !> come from a seed the runtime draws from the operating system.
  function scratch_name(stem, suffix) result(path)
    character(len=*), intent(in) :: stem
    character(len=*), intent(in), optional :: suffix
    character(len=:), allocatable :: path
    character(len=512) :: dir
    real(wp) :: r
    integer :: status, length
    character(len=12) :: tag
    call get_environment_variable('TMPDIR', dir, length, status)
    if (status /= 0 .or. length == 0) dir = '/tmp'
    call random_seed()
    call random_number(r)
    write (tag, '(i12.12)') int(r * 1.0e12_wp, kind=8)
    path = trim(dir) // '/raildyn_' // stem // '_' // tag
    if (present(suffix)) then
      path = path // suffix
    else
      path = path // '.txt'
    end if
  end function scratch_name

  subroutine write_file(path, lines)
    character(len=*), intent(in) :: path, lines(:)
    integer :: unit, k
    open (newunit=unit, file=path, status='replace', action='write')
    do k = 1, size(lines)
      write (unit, '(a)') trim(lines(k))
    end do
    close (unit)
  end subroutine write_file

  !> Delete a file if it exists.
  subroutine delete_file(path)
    character(len=*), intent(in) :: path
    integer :: unit, ios
    open (newunit=unit, file=path, status='old', iostat=ios)
    if (ios == 0) close (unit, status='delete')
  end subroutine delete_file

end module test_files
