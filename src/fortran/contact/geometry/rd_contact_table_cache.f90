!> Contact tables built once and kept on disk (docs/theory_contact_geometry.md section 10):
!> a table is stored under a key that hashes everything it depends on, so a table whose
!> inputs changed is never found, and a file that does not hold exactly the expected key,
!> format and sizes is ignored (rebuilt and replaced), never used.
!>
!> Key: 64-bit FNV-1a over the table format version, the table options, every array of
!> the two contact-ready surfaces (rd_contact_surfaces) and the node evaluation's output at
!> fixed probe poses (rd_contact_table node_probe). The surfaces are the profiles' content
!> after placement (gauge, gauge depth, inclination, precant, back-to-back, flange back,
!> nominal radius) and pre-processing (resampling, curvature filter), so these are all
!> covered without listing them one by one; the probe covers the code that turns them into
!> nodes (a table of a runner whose strip geometry differs has another key).
!>
!> Directory: $RAILDYN_CACHE_DIR if set, else $XDG_CACHE_HOME/raildyn, else
!> $HOME/.cache/raildyn (the XDG base directory rule); created when missing. A directory
!> that cannot be created or written only costs the caching (the table is built each time).
!> A file is written under a temporary name and renamed, so concurrent runs (campaigns)
!> never read a partly written table.
module rd_contact_table_cache
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  use, intrinsic :: iso_fortran_env, only: int64, int8
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_contact_surfaces, only: wheel_surface_t, rail_surface_t
  use rd_contact_table, only: contact_table_t, contact_table_options_t, build_contact_table, &
    node_probe, TABLE_SLOTS, TABLE_QUANTITIES
  implicit none
  private
  public :: obtain_contact_table, contact_table_key, contact_table_cache_dir, contact_table_file

  !> Change whenever the table's content or meaning changes (code version of the format).
  character(len=*), parameter :: TABLE_FORMAT = 'raildyn contact table 6'

  interface
    function c_mkdir(path, mode) result(status) bind(C, name='mkdir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: status
    end function c_mkdir
    function c_rename(old, new) result(status) bind(C, name='rename')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: status
    end function c_rename
    function c_getpid() result(pid) bind(C, name='getpid')
      import :: c_int
      integer(c_int) :: pid
    end function c_getpid
  end interface

contains

  !> The table of (wheel, rail, options): from the cache when a valid file with its key is
  !> there, else built and stored. `from_cache` tells which; `path` is the cache file ('' when
  !> there is no usable cache directory). `directory` replaces the user cache directory.
  subroutine obtain_contact_table(wheel, rail, options, table, error, from_cache, path, directory)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    type(contact_table_options_t), intent(in) :: options
    type(contact_table_t), intent(out) :: table
    type(error_t), allocatable, intent(out) :: error
    logical, intent(out), optional :: from_cache
    character(len=:), allocatable, intent(out), optional :: path
    character(len=*), intent(in), optional :: directory
    character(len=16) :: key
    character(len=:), allocatable :: dir, file
    logical :: found
    call contact_table_key(wheel, rail, options, key, error)
    if (allocated(error)) return
    if (present(directory)) then
      dir = directory
      if (.not. make_directories(dir)) dir = ''
    else
      dir = contact_table_cache_dir()
    end if
    file = ''
    if (len(dir) > 0) file = contact_table_file(dir, key)
    found = .false.
    if (len(file) > 0) call read_table(file, key, table, found)
    if (.not. found) then
      call build_contact_table(wheel, rail, options, table, error)
      if (allocated(error)) return
      if (len(file) > 0) call write_table(file, key, table)
    end if
    if (present(from_cache)) from_cache = found
    if (present(path)) path = file
  end subroutine obtain_contact_table

  !> 16 hex digits of the FNV-1a hash of everything the table depends on.
  subroutine contact_table_key(wheel, rail, options, key, error)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    type(contact_table_options_t), intent(in) :: options
    character(len=16), intent(out) :: key
    type(error_t), allocatable, intent(out) :: error
    integer(int64) :: h
    real(wp), allocatable :: probe(:)
    key = ''
    call node_probe(wheel, rail, options, probe, error)
    if (allocated(error)) return
    h = fnv_offset()
    call add_text(h, TABLE_FORMAT)
    call add_reals(h, [options%shift_max, options%shift_step, options%roll_max, real(options%roll_nodes, wp), &
                       options%reference_approach, options%slot_angle, options%root_angle, &
                       options%face_angle, options%yaw_max, real(options%yaw_nodes, wp)])
    call add_reals(h, [real(wheel%n, wp), wheel%nominal_radius, wheel%y_tape])
    call add_reals(h, wheel%s); call add_reals(h, wheel%y); call add_reals(h, wheel%r)
    call add_reals(h, wheel%slope); call add_reals(h, wheel%kappa)
    call add_reals(h, [real(rail%n, wp), rail%y_gauge_point, rail%u_gauge_point, real(rail%coarse_stride, wp)])
    call add_reals(h, rail%u); call add_reals(h, rail%y); call add_reals(h, rail%z)
    call add_reals(h, rail%ny); call add_reals(h, rail%nz); call add_reals(h, rail%kappa)
    call add_reals(h, probe)
    write (key, '(z16.16)') h
  end subroutine contact_table_key

  !> The cache directory (created when missing), '' when none can be had.
  function contact_table_cache_dir() result(dir)
    character(len=:), allocatable :: dir
    character(len=:), allocatable :: base
    dir = env('RAILDYN_CACHE_DIR')
    if (len(dir) == 0) then
      base = env('XDG_CACHE_HOME')
      if (len(base) == 0) then
        base = env('HOME')
        if (len(base) > 0) base = base // '/.cache'
      end if
      if (len(base) > 0) dir = base // '/raildyn'
    end if
    if (len(dir) == 0) return
    if (.not. make_directories(dir)) dir = ''
  end function contact_table_cache_dir

  function contact_table_file(dir, key) result(file)
    character(len=*), intent(in) :: dir, key
    character(len=:), allocatable :: file
    file = dir // '/contact-table-' // key // '.bin'
  end function contact_table_file

  ! ---------------------------------------------------------------------------------

  subroutine read_table(file, key, table, found)
    character(len=*), intent(in) :: file
    character(len=16), intent(in) :: key
    type(contact_table_t), intent(inout) :: table
    logical, intent(out) :: found
    character(len=len(TABLE_FORMAT)) :: format_read
    character(len=16) :: key_read
    integer :: unit, ios, nu, nphi, npsi, nq, ns
    logical :: exists
    found = .false.
    inquire (file=file, exist=exists)
    if (.not. exists) return
    open (newunit=unit, file=file, access='stream', form='unformatted', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    read (unit, iostat=ios) format_read, key_read, nu, nphi, npsi, nq, ns
    if (ios /= 0 .or. format_read /= TABLE_FORMAT .or. key_read /= key .or. nq /= TABLE_QUANTITIES .or. &
        ns /= TABLE_SLOTS .or. nu < 2 .or. nu > 100000 .or. nphi < 1 .or. nphi > 1000 .or. npsi < 2 .or. npsi > 1000) then
      close (unit)
      return
    end if
    table%nu = nu
    table%nphi = nphi
    table%npsi = npsi
    allocate (table%values(nq, nu, nphi, ns), table%slopes(nq, nu, nphi, ns))
    allocate (table%yaw_change(nq, nu, npsi, ns), table%yaw_slopes(nq, nu, npsi, ns))
    read (unit, iostat=ios) table%options, table%y_tape, table%r0, table%s_cut, table%s_root_end, &
      table%s_face_start, table%u0, table%du, table%phi0, table%dphi, table%dpsi, table%values, table%slopes, &
      table%yaw_change, table%yaw_slopes
    close (unit)
    if (ios /= 0) then
      deallocate (table%values, table%slopes, table%yaw_change, table%yaw_slopes)
      return
    end if
    found = .true.
  end subroutine read_table

  subroutine write_table(file, key, table)
    character(len=*), intent(in) :: file
    character(len=16), intent(in) :: key
    type(contact_table_t), intent(in) :: table
    character(len=:), allocatable :: temporary
    character(len=16) :: pid
    integer :: unit, ios
    write (pid, '(i0)') c_getpid()
    temporary = file // '.' // trim(pid) // '.tmp'
    open (newunit=unit, file=temporary, access='stream', form='unformatted', status='replace', action='write', &
          iostat=ios)
    if (ios /= 0) return
    write (unit, iostat=ios) TABLE_FORMAT, key, table%nu, table%nphi, table%npsi, TABLE_QUANTITIES, TABLE_SLOTS
    if (ios == 0) write (unit, iostat=ios) table%options, table%y_tape, table%r0, table%s_cut, table%s_root_end, &
      table%s_face_start, table%u0, table%du, table%phi0, table%dphi, table%dpsi, table%values, table%slopes, &
      table%yaw_change, table%yaw_slopes
    if (ios /= 0) then
      close (unit, status='delete')
      return
    end if
    close (unit)
    if (c_rename(temporary // c_null_char, file // c_null_char) /= 0) then
      open (newunit=unit, file=temporary, status='old', iostat=ios)
      if (ios == 0) close (unit, status='delete')
    end if
  end subroutine write_table

  !> mkdir -p; .true. when the directory exists afterwards.
  logical function make_directories(dir) result(ok)
    character(len=*), intent(in) :: dir
    integer :: i, status
    do i = 2, len(dir)
      if (dir(i:i) == '/') status = c_mkdir(dir(1:i - 1) // c_null_char, int(o'755', c_int))
    end do
    status = c_mkdir(dir // c_null_char, int(o'755', c_int))
    inquire (file=dir // '/.', exist=ok)
  end function make_directories

  function env(name) result(value)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: value
    integer :: length, status
    call get_environment_variable(name, length=length, status=status)
    if (status /= 0 .or. length == 0) then
      value = ''
      return
    end if
    allocate (character(len=length) :: value)
    call get_environment_variable(name, value, status=status)
    if (status /= 0) value = ''
  end function env

  pure integer(int64) function fnv_offset()
    fnv_offset = -3750763034362895579_int64   ! 0xCBF29CE484222325
  end function fnv_offset

  subroutine add_bytes(h, bytes)
    integer(int64), intent(inout) :: h
    integer(int8), intent(in) :: bytes(:)
    integer(int64), parameter :: prime = 1099511628211_int64
    integer :: i
    ! the product wraps modulo 2^64, as FNV-1a is defined
    do i = 1, size(bytes)
      h = ieor(h, iand(int(bytes(i), int64), 255_int64))
      h = h * prime
    end do
  end subroutine add_bytes

  subroutine add_reals(h, x)
    integer(int64), intent(inout) :: h
    real(wp), intent(in) :: x(:)
    if (size(x) > 0) call add_bytes(h, transfer(x, [0_int8]))
  end subroutine add_reals

  subroutine add_text(h, s)
    integer(int64), intent(inout) :: h
    character(len=*), intent(in) :: s
    if (len(s) > 0) call add_bytes(h, transfer(s, [0_int8]))
  end subroutine add_text
end module rd_contact_table_cache
