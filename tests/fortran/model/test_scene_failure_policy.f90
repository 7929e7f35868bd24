!> The failure policy (rd_error; docs/output.md "Killed and failed runs") on a whole scene:
!>  (a) a NaN in a force once, during a trial step, is recoverable: CVODE retries with a
!>      smaller step and the run completes on the closed-form solution, like a run without it;
!>  (b) a NaN that persists ends the run when CVODE gives up: the message names what was
!>      non-finite (the load on body "mass") and when (the time reached, the evaluation's
!>      time), the results file records it as the runner and the C API record every failed
!>      run (status 'failed: <message>', end time: the scene does it for both), every row
!>      before it is readable and on the closed form, and the scene refuses to step on.
!> The NaN comes from a test-only force provider added to the scene's multibody system.
!> Reference (independent of the code): the damped mass on a spring, without gravity, from
!> its unstressed length z_s with the rate v0: z(t) = z_s + v0 / w_d exp(-zeta w t) sin(w_d t),
!> w = sqrt(k / m), zeta = c / (2 sqrt(k m)), w_d = w sqrt(1 - zeta^2).
!> A test-only force provider: a NaN added to body 1's vertical force from t_from on, at the
!> first call only (once) or at every call.
module rd_nan_load
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_force_provider, only: force_provider_t, body_load_t
  use rd_body_kinematics, only: body_kinematics_t
  implicit none
  private
  public :: nan_load_t, nan_forces_given

  !> NaN forces given by all nan_load_t so far
  integer :: nan_forces_given = 0

  type, extends(force_provider_t) :: nan_load_t
    real(wp) :: t_from = huge(1.0_wp)
    logical :: once = .false.
    logical :: given = .false.
  contains
    procedure :: add_forces => nan_add_forces
  end type nan_load_t

contains

  subroutine nan_add_forces(self, t, kin, forces, error)
    class(nan_load_t), intent(inout) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin(:)
    type(body_load_t), intent(inout) :: forces(:)
    type(error_t), allocatable, intent(out) :: error
    if (t < self%t_from .or. (self%once .and. self%given)) return
    forces(1)%force(3) = forces(1)%force(3) + ieee_value(1.0_wp, ieee_quiet_nan)
    self%given = .true.
    nan_forces_given = nan_forces_given + 1
  end subroutine nan_add_forces
end module rd_nan_load

program test_scene_failure_policy
  use, intrinsic :: iso_c_binding, only: c_char, c_loc, c_ptr
  use hdf5
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_RUNTIME, RD_ERR_HANDLE
  use rd_test_support, only: check, stop_on, test_summary
  use test_files, only: delete_file
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_force_provider, only: force_provider_t
  use rd_nan_load, only: nan_load_t, nan_forces_given
  use rd_results_state, only: results_state_t, read_last_state
  implicit none

  real(wp), parameter :: m = 1000.0_wp, k = 4.0e5_wp, c = 400.0_wp, v0 = 0.1_wp, z_s = 1.0_wp
  character(len=*), parameter :: deck = &
    "&simulation title = 'mass', t_end = 1.0, speed = 10.0, gravity = 0.0, equilibrium = 'none' /" // &
    new_line('a') // "&solver method = 'bdf', rtol = 1e-9, atol = 1e-12 /" // new_line('a') // &
    "&output interval = 0.05 /" // new_line('a') // &
    "&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 10.0, izz = 10.0, position = 0.0, 0.0, 1.0, " // &
    "velocity = 0.0, 0.0, 0.1, frozen = 'x', 'y', 'yaw', 'roll', 'pitch' /" // new_line('a') // &
    "&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass', " // &
    "point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, 400.0 /" // new_line('a')
  !> rtol 1e-9 over 20 periods: a few 1e-9 m; 1e-7 m is 2e-5 of the amplitude v0 / w_d
  real(wp), parameter :: z_tol = 1.0e-7_wp
  character(len=512) :: tmpdir
  integer :: hdferr

  call get_environment_variable('TMPDIR', tmpdir)
  if (len_trim(tmpdir) == 0) tmpdir = '/tmp'
  call h5open_f(hdferr)
  call nan_once_is_recovered()
  call persistent_nan_ends_the_run()
  call test_summary('test_scene_failure_policy')

contains

  real(wp) function z_exact(t)
    real(wp), intent(in) :: t
    real(wp) :: w, zeta, wd
    w = sqrt(k / m)
    zeta = c / (2 * sqrt(k * m))
    wd = w * sqrt(1 - zeta**2)
    z_exact = z_s + v0 / wd * exp(-zeta * w * t) * sin(wd * t)
  end function z_exact

  function tmpfile(name) result(path)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: path
    character(len=16) :: pid
    write (pid, '(i0)') getpid()
    path = trim(tmpdir) // '/rd_test_failure_policy_' // trim(pid) // '_' // name
  end function tmpfile

  !> The scene of the deck writing `path`, with the provider added; initialized.
  subroutine start(scene, provider, path)
    type(scene_t), intent(inout) :: scene
    class(force_provider_t), pointer, intent(in) :: provider
    character(len=*), intent(in) :: path
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    call scene%load_string(deck, '.', error)
    call stop_on(error, 'load')
    call scene%set_output_file(path)
    call scene%build(error)
    call stop_on(error, 'build')
    mbs => scene%system()
    call mbs%add_provider(provider)
    call scene%initialize(.true., error)
    call stop_on(error, 'initialize')
  end subroutine start

  subroutine nan_once_is_recovered()
    type(scene_t) :: clean, nan
    type(nan_load_t), pointer :: never, single
    class(force_provider_t), pointer :: p
    type(error_t), allocatable :: error
    real(wp) :: y_clean(2), y_nan(2)
    allocate (never, single)
    single%t_from = 0.26_wp             ! between two output times: a step's evaluation
    single%once = .true.
    p => never
    call start(clean, p, tmpfile('clean.h5'))
    p => single
    call start(nan, p, tmpfile('once.h5'))
    call clean%advance(1.0_wp, error)
    call stop_on(error, 'run without a NaN')
    nan_forces_given = 0
    call nan%advance(1.0_wp, error)
    call check(.not. allocated(error), 'a NaN force once: the run goes on (CVODE retries the step)')
    if (allocated(error)) write (*, '(a)') '  ' // error%message
    call check(nan_forces_given == 1, 'a NaN force once: the provider gave exactly one NaN')
    call check(nan%time() == 1.0_wp, 'a NaN force once: the run reaches t_end')
    call clean%get_state(y_clean, error)
    call stop_on(error, 'state')
    call nan%get_state(y_nan, error)
    call stop_on(error, 'state')
    write (*, '(a, 2es11.3)') 'z(1 s) - closed form [m], without / with the NaN: ', &
      y_clean(1) - z_exact(1.0_wp), y_nan(1) - z_exact(1.0_wp)
    call check(abs(y_clean(1) - z_exact(1.0_wp)) < z_tol, 'run without a NaN: z(1 s) on the closed form')
    call check(abs(y_nan(1) - z_exact(1.0_wp)) < z_tol, 'a NaN force once: z(1 s) on the closed form')
    call clean%finalize(error)
    call nan%finalize(error)
    call clean%destroy()
    call nan%destroy()
    call delete_file(tmpfile('clean.h5'))
    call delete_file(tmpfile('once.h5'))
  end subroutine nan_once_is_recovered

  subroutine persistent_nan_ends_the_run()
    type(scene_t) :: scene
    type(nan_load_t), pointer :: always
    class(force_provider_t), pointer :: p
    type(error_t), allocatable :: error, again
    type(results_state_t) :: last
    character(len=:), allocatable :: path, status
    real(wp) :: end_time
    allocate (always)
    always%t_from = 0.52_wp
    p => always
    path = tmpfile('persistent.h5')
    call start(scene, p, path)
    call scene%advance(1.0_wp, error)
    call check(allocated(error), 'a NaN force from 0.52 s on: the run fails')
    if (.not. allocated(error)) return
    write (*, '(a)') 'persistent NaN -> ' // error%message
    call check(error%code == RD_ERR_RUNTIME, 'persistent NaN: a runtime error (exit status 2)')
    call check(index(error%message, 'non-finite load on body "mass"') > 0, &
               'persistent NaN: the message names what was non-finite')
    call check(index(error%message, 'rhs at t = 5.2') > 0 .and. index(error%message, 'time reached') > 0, &
               'persistent NaN: the message says when (the evaluation and the time reached)')
    call check(scene%time() > 0.5_wp .and. scene%time() <= 0.52_wp, &
               'persistent NaN: the scene stopped at the last time it reached before 0.52 s')
    call scene%advance(1.0_wp, again)
    call check(allocated(again), 'persistent NaN: no stepping on after the failure')
    if (allocated(again)) call check(again%code == RD_ERR_HANDLE .and. index(again%message, error%message) > 0, &
                                     'persistent NaN: a later advance is refused with the failure')
    call file_meta(path, status, end_time)
    call check(status == 'failed: ' // error%message, 'persistent NaN: results file status is failed: <message>')
    call check(end_time == scene%time(), 'persistent NaN: results file end_time is the time reached')
    call read_last_state(path, last, error)
    call stop_on(error, 'the failed run''s results file')
    call check(abs(last%time - 0.5_wp) < 1e-12_wp, 'persistent NaN: the last row is the output at 0.5 s')
    call check(abs(last%y(1) - z_exact(0.5_wp)) < z_tol, 'persistent NaN: the rows written are on the closed form')
    call scene%destroy()
    call delete_file(path)
  end subroutine persistent_nan_ends_the_run

  !> /meta status and end_time of a closed results file.
  subroutine file_meta(path, status, end_time)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: status
    real(wp), intent(out), target :: end_time
    integer(hid_t) :: file, attr, atype
    integer(size_t) :: n
    character(kind=c_char), allocatable, target :: chars(:)
    type(c_ptr) :: ptr
    integer :: i
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
    call h5aopen_by_name_f(file, 'meta', 'status', attr, hdferr)
    call h5aget_type_f(attr, atype, hdferr)
    call h5tget_size_f(atype, n, hdferr)
    allocate (chars(n))
    ptr = c_loc(chars)
    call h5aread_f(attr, atype, ptr, hdferr)
    call h5tclose_f(atype, hdferr)
    call h5aclose_f(attr, hdferr)
    allocate (character(len=n) :: status)
    do i = 1, int(n)
      status(i:i) = chars(i)
    end do
    if (index(status, achar(0)) > 0) status = status(:index(status, achar(0)) - 1)
    call h5aopen_by_name_f(file, 'meta', 'end_time', attr, hdferr)
    ptr = c_loc(end_time)
    call h5aread_f(attr, H5T_NATIVE_DOUBLE, ptr, hdferr)
    call h5aclose_f(attr, hdferr)
    call h5fclose_f(file, hdferr)
  end subroutine file_meta

end program test_scene_failure_policy
