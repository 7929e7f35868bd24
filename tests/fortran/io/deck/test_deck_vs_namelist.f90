!> Independent oracle for the value syntax: the compiler's own namelist READ.
!> The same deck text is read by rd_deck and by gfortran's intrinsic
!> namelist input (variables preset to the defaults of the specification,
!> typed here); every value must agree exactly: number forms (1.5d1,
!> 981e-2, .5, 1.0E+3), repeat counts, element assignment after a whole
!> assignment, blank-separated lists, strings with doubled quotes, T/F.
program test_deck_vs_namelist
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_deck, only: deck_t, read_deck_string, deck_string_t
  use rd_test_support, only: check, check_status, fail, test_summary
  implicit none
  character(len=1), parameter :: nl = achar(10)
  character(len=:), allocatable :: text
  type(deck_t) :: deck
  type(error_t), allocatable :: error
  integer :: u, ios, k, n

  ! namelist variables (names as in the deck schema)
  character(len=64) :: title, name, frame
  real(wp) :: t_end, gravity, start_sigma, speed_times(8), speed_values(8)
  real(wp) :: mass, ixx, iyy, izz, ixy, position(3), orientation(3), velocity(3), frame_offset
  character(len=8) :: frozen(6)
  integer :: max_num_steps
  real(wp) :: rtol
  namelist /simulation/ title, t_end, gravity, start_sigma, speed_times, speed_values
  namelist /body/ name, mass, ixx, iyy, izz, ixy, position, orientation, velocity, frame_offset, &
                  frozen, frame
  namelist /solver/ max_num_steps, rtol

  real(wp) :: x
  real(wp), allocatable :: v(:)
  character(len=:), allocatable :: s
  integer :: m
  logical :: b
  type(deck_string_t), allocatable :: list(:)

  text = &
    '&simulation title = ''it''''s "q"'', t_end = 1.5d1, gravity = 981e-2, start_sigma = .5,' // nl // &
    '   speed_times = 0, 1.0, 2e0, 3.d0,' // nl // &
    '   speed_values = 2*1.0, 2*2.5 /' // nl // &
    '&body name = ''b1'', mass = 1.0E+3, ixx = 1, iyy = 2, izz = 3, ixy = -0.5,' // nl // &
    '   position = 3*0.25, position(2) = -1.5, velocity = 1 2 3, frozen = ''yaw'', ''roll'',' // nl // &
    '   frame_offset = -1.28 /' // nl // &
    '&body name = "b2", mass = 2e3, ixx = 4, iyy = 5, izz = 6, orientation(3) = 0.125,' // nl // &
    '   frame = ''b1'' /' // nl // &
    '&solver max_num_steps = 250, rtol = 1.0D-7 /' // nl // &
    '&wheelset name = ''w'', body = ''b1'', contact = ''knife_edge'', spin_creep = F /' // nl
  call read_deck_string(deck, text, '.', 'oracle.nml', error)
  if (allocated(error)) then
    print '(a)', 'FAIL: rd_deck: ' // error%message
    error stop 1
  end if

  open (newunit=u, status='scratch', action='readwrite', form='formatted')
  write (u, '(a)') text
  ! --- &simulation (defaults of the specification first) ---
  title = ''; t_end = -1; gravity = 9.80665_wp; start_sigma = 0
  speed_times = -huge(1.0_wp); speed_values = -huge(1.0_wp)
  rewind (u)
  read (u, nml=simulation, iostat=ios); call io_ok('simulation')
  call deck%get('simulation', 1, 'title', s, error); call check_read(s == trim(title), 'title ' // s)
  call deck%get('simulation', 1, 't_end', x, error); call check_read(x == t_end, 't_end')
  call deck%get('simulation', 1, 'gravity', x, error); call check_read(x == gravity, 'gravity')
  call deck%get('simulation', 1, 'start_sigma', x, error); call check_read(x == start_sigma, '.5')
  ! --- &wheelset: a logical written as F ---
  call deck%get('wheelset', 1, 'spin_creep', b, error)
  call check_read(b .eqv. wheelset_spin_creep(u) .and. .not. b, 'logical F')
  n = count(speed_times > -huge(1.0_wp))
  call deck%get('simulation', 1, 'speed_times', v, error)
  call check_read(size(v) == n, 'speed_times length')
  if (size(v) == n) call check_read(all(v == speed_times(1:n)), 'speed_times values')
  n = count(speed_values > -huge(1.0_wp))
  call deck%get('simulation', 1, 'speed_values', v, error)
  call check_read(size(v) == n, 'speed_values length')
  if (size(v) == n) call check_read(all(v == speed_values(1:n)), 'speed_values with repeat counts')

  ! --- two &body groups ---
  rewind (u)
  do k = 1, 2
    name = ''; mass = -1; ixx = -1; iyy = -1; izz = -1; ixy = 0; position = 0; orientation = 0
    velocity = 0; frame_offset = 0; frozen = ''; frame = 'own'
    read (u, nml=body, iostat=ios); call io_ok('body')
    call deck%get('body', k, 'name', s, error); call check_read(s == trim(name), 'name')
    call deck%get('body', k, 'mass', x, error); call check_read(x == mass, 'mass')
    call deck%get('body', k, 'ixx', x, error); call check_read(x == ixx, 'ixx')
    call deck%get('body', k, 'iyy', x, error); call check_read(x == iyy, 'iyy')
    call deck%get('body', k, 'izz', x, error); call check_read(x == izz, 'izz')
    call deck%get('body', k, 'ixy', x, error); call check_read(x == ixy, 'ixy')
    call deck%get('body', k, 'position', v, error)
    call check_read(all(v == position), 'position (repeat count, then element)')
    call deck%get('body', k, 'orientation', v, error)
    call check_read(all(v == orientation), 'orientation(3)')
    call deck%get('body', k, 'velocity', v, error)
    call check_read(all(v == velocity), 'blank-separated velocity')
    call deck%get('body', k, 'frame_offset', x, error); call check_read(x == frame_offset, 'frame_offset')
    call deck%get('body', k, 'frame', s, error); call check_read(s == trim(frame), 'frame')
    call deck%get('body', k, 'frozen', list, error)
    m = count(frozen /= '')
    call check_read(size(list) == m, 'frozen length')
    if (size(list) == m) then
      do n = 1, m
        call check_read(list(n)%s == trim(frozen(n)), 'frozen ' // list(n)%s)
      end do
    end if
  end do

  ! --- &solver ---
  max_num_steps = 100000; rtol = 1.0e-6_wp
  rewind (u)
  read (u, nml=solver, iostat=ios); call io_ok('solver')
  call deck%get('solver', 1, 'max_num_steps', m, error)
  call check_read(m == max_num_steps, 'integer')
  call deck%get('solver', 1, 'rtol', x, error); call check_read(x == rtol, 'rtol 1.0D-7')
  close (u)

  call test_summary('test_deck_vs_namelist')
  print '(a)', 'test_deck_vs_namelist: rd_deck agrees with the intrinsic namelist READ'

contains

  !> A value read with `deck%get`: the read succeeded and the value is the namelist's.
  subroutine check_read(cond, what)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      call check_status(error, what)
    else
      call check(cond, what)
    end if
  end subroutine check_read

  !> spin_creep of the &wheelset group by the intrinsic namelist read (its own scope:
  !> the group's 'body' parameter would clash with the &body namelist above)
  logical function wheelset_spin_creep(unit)
    integer, intent(in) :: unit
    character(len=64) :: name, body, contact
    logical :: spin_creep
    namelist /wheelset/ name, body, contact, spin_creep
    spin_creep = .true.
    rewind (unit)
    read (unit, nml=wheelset, iostat=ios); call io_ok('wheelset')
    wheelset_spin_creep = spin_creep
  end function wheelset_spin_creep

  subroutine io_ok(what)
    character(len=*), intent(in) :: what
    if (ios /= 0) then
      call fail()
      print '(a,i0)', 'FAIL: intrinsic namelist read of ' // what // ', iostat ', ios
    end if
  end subroutine io_ok
end program test_deck_vs_namelist
