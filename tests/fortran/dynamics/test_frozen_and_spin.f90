!> Frozen coordinates and the wheelset spin deviation.
!>  1. Freezing coordinates shrinks the state by two per coordinate and the frozen ones stay
!>     exactly (bitwise) at q0 with zero rate while the others move.
!>  2. A free wheelset body with no forces (g = 0) on straight track:
!>     - constant V: beta stays at beta0 (pure rolling) and theta = s/r0 + beta0;
!>     - initial spin deviation dbeta0: beta = beta0 + dbeta0 t (free rotation);
!>     - speed ramp: the absolute spin rate stays V0/r0 (no torque), so
!>       beta(t) = beta0 + (V0 t - s(t)) / r0 (closed form of the ramp written here).
!>  3. Frozen spin under a speed ramp: theta = s(t)/r0 + beta0 (rolling imposed).
!>  4. External loads in fixed, track and body frames with on/off times, and the C API
!>     override: the resulting accelerations against F/m and M/J.
program test_frozen_and_spin
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: speed_law_t, constant_speed, table_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_force_provider, only: force_provider_t
  use rd_external_loads, only: external_loads_t, external_load_t, LOAD_FRAME_FIXED, LOAD_FRAME_TRACK, LOAD_FRAME_BODY
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_integrator, only: integrator_t, integrator_settings_t
  use rd_dynamics_test_support, only: straight_track_t, canted_circle_t, rk4_integrate
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp
  class(track_geometry_t), pointer :: track
  type(speed_law_t) :: ramp
  type(error_t), allocatable :: error
  real(wp) :: t, s_exact, beta
  character(len=120) :: buf

  allocate (straight_track_t :: track)

  call frozen_check()

  ! 2a: constant speed, pure rolling
  beta = spin_run(constant_speed(30.0_wp), 0.3_wp, 0.0_wp, .false., 10.0_wp, t)
  write (buf, '(a,es10.3)') 'beta - beta0 = ', beta - 0.3_wp
  call check(abs(beta - 0.3_wp) < 1e-13_wp, 'free wheelset at constant V keeps beta', detail=trim(buf))
  ! 2b: spin deviation
  beta = spin_run(constant_speed(30.0_wp), 0.3_wp, 0.5_wp, .false., 10.0_wp, t)
  call check(abs(beta - (0.3_wp + 0.5_wp * 10)) < 1e-12_wp, 'free wheelset: beta = beta0 + dbeta0 t')
  ! 2c: speed ramp 10 -> 40 m/s in 3 s, run 4 s
  call table_speed(ramp, [0.0_wp, 3.0_wp], [10.0_wp, 40.0_wp], error)
  s_exact = 10 * 3 + 0.5_wp * 10 * 3**2 + 40 * 1       ! s(4)
  beta = spin_run(ramp, 0.3_wp, 0.0_wp, .false., 4.0_wp, t)
  write (buf, '(a,es10.3)') 'error ', beta - (0.3_wp + (10 * 4 - s_exact) / r0)
  call check(abs(beta - (0.3_wp + (10 * 4 - s_exact) / r0)) < 1e-10_wp * abs(10 * 4 - s_exact) / r0, 'free wheelset under a speed ramp keeps its absolute spin', detail=trim(buf))  ! rtol 1e-12, ~100 steps
  ! 3: frozen spin: theta reconstructs to s/r0 + beta0
  beta = spin_run(ramp, 0.3_wp, 0.0_wp, .true., 4.0_wp, t)
  write (buf, '(a,es10.3)') 'theta - (s/r0 + beta0) = ', t - (s_exact / r0 + 0.3_wp)
  call check(abs(t - (s_exact / r0 + 0.3_wp)) < 1e-12_wp * s_exact / r0, 'frozen spin: theta = s/r0 + beta0', detail=trim(buf))

  call loads_check()
  call errors_check()

  call test_summary('test_frozen_and_spin')

contains

  subroutine frozen_check()
    type(multibody_t), target :: mb
    type(body_spec_t) :: body(2)
    type(linear_spring_damper_t) :: spring
    real(wp), allocatable :: y(:), ydot(:)
    logical :: ok
    integer :: i
    do i = 1, 2
      body(i)%mass = 500
      body(i)%inertia = reshape([100.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 120.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 90.0_wp], [3, 3])
      body(i)%q0 = [0.1_wp, 0.02_wp, 0.5_wp * i, 0.01_wp, -0.02_wp, 0.03_wp]
      body(i)%qdot0 = [0.1_wp, 0.2_wp, 0.3_wp, 0.4_wp, 0.5_wp, 0.6_wp]
    end do
    body(1)%name = 'a'; body(2)%name = 'b'
    body(2)%frozen = [.true., .false., .true., .false., .true., .false.]
    call mb%build(body, [0.0_wp], track, constant_speed(20.0_wp), error)
    spring%body1 = 1; spring%body2 = 2
    spring%u1 = [0.3_wp, 0.2_wp, 0.1_wp]; spring%u2 = [-0.2_wp, 0.1_wp, -0.3_wp]
    spring%stiffness = [1.0e5_wp, 2.0e5_wp, 3.0e5_wp]
    call mb%add_element(spring, error)
    spring%body1 = 0; spring%body2 = 1; spring%u1 = 0; spring%u2 = 0
    call mb%add_element(spring, error)
    call check(mb%state_size() == 18, 'state size = 2 (6 + 3 free)')
    allocate (y(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)
    call rk4_integrate(mb, 0.0_wp, 1.0_wp, 1.0e-3_wp, y, ok)
    call mb%rhs(1.0_wp, y, ydot, error)
    call check(all(mb%scratch%kin(2)%q([1, 3, 5]) == body(2)%q0([1, 3, 5])), 'frozen coordinates stay exactly at q0')
    call check(all(mb%scratch%kin(2)%qdot([1, 3, 5]) == 0) .and. &
               all(mb%scratch%kin(2)%qddot([1, 3, 5]) == 0), 'frozen rates and accelerations are zero')
    call check(all(abs(mb%scratch%kin(2)%q([2, 4, 6]) - body(2)%q0([2, 4, 6])) > 1e-3_wp), 'free coordinates of the same body moved')
  end subroutine frozen_check

  !> Run a wheelset body with no forces; returns beta (state) and theta (kinematics).
  real(wp) function spin_run(law, beta0, dbeta0, frozen_spin, t_end, theta) result(beta)
    type(speed_law_t), intent(in) :: law
    real(wp), intent(in) :: beta0, dbeta0, t_end
    logical, intent(in) :: frozen_spin
    real(wp), intent(out) :: theta
    type(multibody_t), target :: mb
    type(body_spec_t) :: body(1)
    real(wp), allocatable :: y(:), ydot(:)
    logical :: ok
    type(integrator_t) :: integ
    type(integrator_settings_t) :: settings
    body(1)%name = 'wheelset'
    body(1)%mass = 1500
    body(1)%inertia = reshape([800.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 100.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 800.0_wp], [3, 3])
    body(1)%is_wheelset = .true.
    body(1)%r0 = r0
    body(1)%q0 = [0.0_wp, 0.0_wp, r0, 0.0_wp, 0.0_wp, beta0]
    body(1)%qdot0(6) = dbeta0
    body(1)%frozen(6) = frozen_spin
    call mb%build(body, [0.0_wp], track, law, error, gravity=0.0_wp)
    allocate (y(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)
    ! adaptive Dormand-Prince: the ramp's end makes dV/dt jump, which a fixed-step method
    ! would straddle
    settings%method = 'erk'; settings%rtol = 1.0e-12_wp; settings%atol = 1.0e-12_wp
    call integ%build(mb, 0.0_wp, y, settings, error)
    if (.not. allocated(error)) call integ%advance(t_end, y, error)
    ok = .not. allocated(error)
    call check(ok, 'integration')
    call integ%destroy()
    call mb%rhs(t_end, y, ydot, error)
    theta = mb%scratch%kin(1)%q(6)
    if (frozen_spin) then
      beta = beta0
    else
      beta = y(mb%free_slot(1, 6))
    end if
  end function spin_run

  subroutine loads_check()
    type(multibody_t), target :: mb
    type(body_spec_t) :: body(1)
    type(external_loads_t), target :: ext
    class(force_provider_t), pointer :: prov
    type(external_load_t) :: ld
    real(wp), allocatable :: y(:), ydot(:)
    real(wp), parameter :: phi_t = -0.1_wp
    real(wp) :: expect(3)
    class(track_geometry_t), pointer :: circle
    allocate (canted_circle_t :: circle)
    select type (circle)
    type is (canted_circle_t)
      circle%kappa = 0; circle%cant = phi_t           ! straight canted track, frame at rest
    end select
    body(1)%name = 'box'
    body(1)%mass = 100
    body(1)%inertia = reshape([10.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 20.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 40.0_wp], [3, 3])
    body(1)%q0(4) = 0.3_wp                             ! yawed by 0.3 rad in the frame
    call mb%build(body, [0.0_wp], circle, constant_speed(0.0_wp), error, gravity=0.0_wp)
    ld%body = 1; ld%frame = LOAD_FRAME_FIXED; ld%force = [0.0_wp, 0.0_wp, 50.0_wp]; ld%t_on = 1; ld%t_off = 2
    call ext%add_load(ld, 1, error)
    ld%frame = LOAD_FRAME_TRACK; ld%force = [10.0_wp, 0.0_wp, 0.0_wp]; ld%t_on = -1; ld%t_off = 10
    call ext%add_load(ld, 1, error)
    ld%frame = LOAD_FRAME_BODY; ld%force = 0; ld%moment = [0.0_wp, 0.0_wp, 8.0_wp]
    call ext%add_load(ld, 1, error)
    prov => ext
    call mb%add_provider(prov)
    allocate (y(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)
    ! t = 0: track-frame force along X_T, body-frame moment about the body z (= track z
    ! for a pure yaw): xdd = 10/m, yaw acceleration 8/Jz; the fixed-frame force is off
    call mb%rhs(0.0_wp, y, ydot, error)
    call check(abs(ydot(7) - 0.1_wp) < 1e-14_wp .and. abs(ydot(8)) < 1e-14_wp .and. abs(ydot(9)) < 1e-14_wp, 'track-frame load')
    call check(abs(ydot(10) - 0.2_wp) < 1e-14_wp, 'body-frame moment')
    ! t = 1.5: fixed-frame +Z force 50 N seen in the canted track frame: (0, sin, cos)(phi_t)
    call mb%rhs(1.5_wp, y, ydot, error)
    expect = [0.1_wp, 0.5_wp * sin(phi_t), 0.5_wp * cos(phi_t)]
    call check(maxval(abs(ydot(7:9) - expect)) < 1e-14_wp, 'fixed-frame load switched on')
    call mb%set_override_load(1, [0.0_wp, 0.0_wp, -50.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], error)
    call mb%rhs(1.5_wp, y, ydot, error)
    call check(maxval(abs(ydot(7:9) - [0.1_wp, 0.0_wp, 0.0_wp])) < 1e-14_wp, 'override load adds')
    call mb%set_override_load(2, [0.0_wp, 0.0_wp, -50.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], error)
    call check(allocated(error), 'override load: bad body index rejected')
  end subroutine loads_check
  !> Bad input gives one clear error; a singular configuration is reported, not a NaN.
  subroutine errors_check()
    type(multibody_t), target :: mb
    type(body_spec_t) :: body(1)
    real(wp), allocatable :: y(:), ydot(:)
    body(1)%name = 'bad'
    body(1)%inertia = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
    call mb%build(body, [0.0_wp], track, constant_speed(1.0_wp), error)
    call check(allocated(error), 'zero mass rejected')
    if (allocated(error)) print '(a)', '  message: ' // error%message
    body(1)%mass = 1
    body(1)%frame = 2
    call mb%build(body, [0.0_wp], track, constant_speed(1.0_wp), error)
    call check(allocated(error), 'frame index out of range rejected')
    body(1)%frame = 1
    call mb%build(body, [0.0_wp], track, constant_speed(1.0_wp), error)
    allocate (y(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)
    y(5) = 2 * atan(1.0_wp)          ! 90 deg roll
    call mb%rhs(0.0_wp, y, ydot, error)
    call check(allocated(error), '90 deg roll reported as an error')
    if (allocated(error)) print '(a)', '  message: ' // error%message
  end subroutine errors_check
end program test_frozen_and_spin
