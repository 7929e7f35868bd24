!> Scratch text files for the track tests (survey and irregularity readers): a unique name
!> under $TMPDIR (or /tmp), write lines, delete.
module track_test_files
  use rd_kinds, only: wp
  implicit none
  private
  public :: scratch_name, write_file, delete_file

contains

  !> $TMPDIR/raildyn_<stem>_<12 random digits>.txt
  function scratch_name(stem) result(path)
    character(len=*), intent(in) :: stem
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
    path = trim(dir) // '/raildyn_' // stem // '_' // tag // '.txt'
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

  subroutine delete_file(path)
    character(len=*), intent(in) :: path
    integer :: unit
    open (newunit=unit, file=path, status='old')
    close (unit, status='delete')
  end subroutine delete_file

end module track_test_files
