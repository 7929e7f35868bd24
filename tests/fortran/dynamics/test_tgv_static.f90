!> Static equilibrium of the TGV 001 model of thesis tables 5.1-5.6 (7 bodies, 8 primary and
!> 4 secondary three-axis spring-dampers) with each wheel held by a support spring to the
!> ground (kz 1.4e9 N/m, close to a Hertz contact stiffness; kx = ky = 1e7 N/m in place of
!> the creep forces). Preloads by rd_static_preload (minimum norm, thesis 5.2.1 d).
!> Checks: (1) the preloads against hand statics (each secondary spring carries a quarter
!> of the car body, each primary spring a quarter of a bogie plus half the car body, each
!> wheel an eighth of the vehicle); (2) the transient of the vehicle standing and running
!> at 80 m/s on straight track stays at the noise level (max |qddot| and drift over 2 s);
!> (3) without preloads, rd_static_preload's Newton solve of the static positions gives the
!> sag of springs in series by hand statics (wheel, primary, secondary deflections).
!>
!> Positions the thesis leaves unstated (table 5.2: sigma_k, x1..x3, h_b, h_c) are chosen
!> TGV-like: bogie wheelbase 3.0 m, bogie centres 18.7 m apart, r0 = 0.45 m (thesis
!> section 5.3.3), bogie CG 0.65 m and car body CG 1.90 m above the track plane, axle boxes
!> at +-1.0 m, secondary springs at +-1.23 m and 1.0 m above the track plane, wheel
!> supports at +-0.75 m (e0). Frames as in the thesis: one per wheelset; bogies referred
!> to their front wheelset's frame, the car body to wheelset 1's.
program test_tgv_static
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t, multibody_output_t
  use rd_static_preload, only: solve_static_preloads, solve_static_positions
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_dynamics_test_support, only: straight_track_t, rk4_integrate
  use rd_test_support, only: check, failure_count, test_summary
  implicit none
  real(wp), parameter :: g = 9.80665_wp, r0 = 0.45_wp, hb = 0.65_wp, hc = 1.90_wp
  real(wp), parameter :: m_ws = 1500, m_bf = 3020, m_cb = 43200
  real(wp), parameter :: offsets(4) = [0.0_wp, -3.0_wp, -18.7_wp, -21.7_wp]
  real(wp) :: drift, qdd, res, out(9)
  real(wp) :: v_run
  integer :: irun
  character(len=160) :: buf

  do irun = 1, 2
    v_run = merge(0.0_wp, 80.0_wp, irun == 1)
    call run(v_run, res, qdd, drift)
    write (buf, '(a,f5.1,a,es9.2,a,es9.2,a)') 'V = ', v_run, ' m/s: max |qddot| = ', qdd, ', drift over 2 s = ', drift, ' m'
    call check(qdd < 1e-9_wp .and. drift < 1e-9_wp, 'TGV 001 starts in static equilibrium', detail=trim(buf))
  end do

  call sag_check()

  call test_summary('test_tgv_static')

contains

  subroutine sag_check()
    type(multibody_t), target :: mb
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:)
    real(wp) :: d_wheel, d_pri, d_sec, expect(7), got(7), residual
    integer :: i
    call build(mb, 0.0_wp)
    allocate (y(mb%state_size()))
    call mb%initial_state(y, error)
    call solve_static_positions(mb, 0.0_wp, y, residual, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // error%message; error stop 1
    end if
    d_wheel = (m_cb + 2 * m_bf + 4 * m_ws) * g / 8 / 1.4e9_wp
    d_pri = (m_cb / 2 + m_bf) * g / 4 / 9.75e5_wp
    d_sec = m_cb * g / 4 / 5.3e5_wp
    expect = [(d_wheel, i = 1, 4), d_wheel + d_pri, d_wheel + d_pri, d_wheel + d_pri + d_sec]
    do i = 1, 7
      got(i) = mb%bodies(i)%q0(3) - y(mb%free_slot(i, 3))
    end do
    write (buf, '(a,3f10.6,a,3f10.6,a,es9.2)') 'sag ws/bogie/body ', got([1, 5, 7]), ' hand ', expect([1, 5, 7]), &
      ' residual ', residual
    call check(maxval(abs(got - expect)) < 1e-9_wp, 'no preloads: static positions = springs in series', detail=trim(buf))
  end subroutine sag_check

  subroutine run(v, residual, qdd_max, drift_max)
    real(wp), intent(in) :: v
    real(wp), intent(out) :: residual, qdd_max, drift_max
    type(multibody_t), target :: mb
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:), y0(:), ydot(:)
    real(wp) :: fz
    integer :: k, e
    logical :: ok
    type(multibody_output_t) :: o
    call build(mb, v)
    call check(mb%state_size() == 84, '42 free coordinates')
    allocate (y(mb%state_size()), y0(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)
    call solve_static_preloads(mb, 0.0_wp, y, residual, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // error%message; error stop 1
    end if
    ! hand statics (vertical element components = preload z, element axes vertical here)
    call mb%rhs(0.0_wp, y, ydot, error)
    qdd_max = maxval(abs(ydot(43:84)))
    call mb%calc_output(0.0_wp, y, o, error)
    do e = 1, mb%element_count()
      out = [o%elements(e)%deflection, o%elements(e)%force_local, o%elements(e)%force]
      fz = out(6)
      select case (mb%elements(e)%e%name)
      case ('secondary')
        ok = abs(fz - m_cb * g / 4) < 1e-6_wp * m_cb * g
      case ('primary')
        ok = abs(fz - (m_cb / 2 + m_bf) * g / 4) < 1e-6_wp * m_cb * g
      case default
        ok = abs(fz - (m_cb + 2 * m_bf + 4 * m_ws) * g / 8) < 1e-6_wp * m_cb * g
      end select
      if (.not. ok) then
        write (buf, '(a,i0,a,f12.3)') 'element ', e, ' ' // mb%elements(e)%e%name // ' Fz = ', fz
        call check(.false., 'preload = hand statics', detail=trim(buf))
      end if
    end do
    call check(failure_count() == 0, 'preloads match the hand statics (secondary, primary, wheel)')
    y0 = y
    call rk4_integrate(mb, 0.0_wp, 2.0_wp, 2.0e-4_wp, y, ok)
    drift_max = 0
    do k = 1, 42
      drift_max = max(drift_max, abs(y(k) - y0(k)))
    end do
  end subroutine run

  !> The TGV 001 model (no preloads).
  subroutine build(mb, v)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: v
    class(track_geometry_t), pointer :: track
    type(body_spec_t) :: b(7)
    type(linear_spring_damper_t) :: sp
    type(error_t), allocatable :: error
    real(wp) :: xb(2), xws(4), side
    integer :: i, j, ib
    allocate (straight_track_t :: track)
    ! ---- bodies (table 5.1, 5.2)
    do i = 1, 4
      b(i)%name = 'wheelset' // achar(48 + i)
      b(i)%mass = m_ws
      b(i)%inertia = diag([799.35_wp, 93.75_wp, 799.35_wp])
      b(i)%is_wheelset = .true.
      b(i)%r0 = r0
      b(i)%frame = i
      b(i)%q0 = [0.0_wp, 0.0_wp, r0, 0.0_wp, 0.0_wp, 0.0_wp]
    end do
    do i = 5, 6
      b(i)%name = 'bogie' // achar(48 + i - 4)
      b(i)%mass = m_bf
      b(i)%inertia = diag([2130.912_wp, 4063.712_wp, 4063.712_wp])
      b(i)%frame = merge(1, 3, i == 5)
      b(i)%q0 = [-1.5_wp, 0.0_wp, hb, 0.0_wp, 0.0_wp, 0.0_wp]
    end do
    b(7)%name = 'carbody'
    b(7)%mass = m_cb
    b(7)%inertia = diag([69677.28_wp, 2430000.0_wp, 2430000.0_wp])
    b(7)%frame = 1
    b(7)%q0 = [-1.5_wp - 9.35_wp, 0.0_wp, hc, 0.0_wp, 0.0_wp, 0.0_wp]
    call mb%build(b, offsets, track, constant_speed(v), error, sigma0=100.0_wp)
    if (allocated(error)) then
      print *, error%message; error stop 1
    end if
    xws = offsets                               ! wheelset x along the vehicle
    xb = [offsets(1) - 1.5_wp, offsets(3) - 1.5_wp]
    ! ---- primary suspension (tables 5.3, 5.4): wheelset (body 1) -> bogie (body 2)
    do i = 1, 4
      ib = merge(5, 6, i <= 2)
      do j = 1, 2
        side = merge(1.0_wp, -1.0_wp, j == 1)
        sp = linear_spring_damper_t()
        sp%name = 'primary'
        sp%body1 = i; sp%body2 = ib
        sp%u1 = [0.0_wp, side * 1.0_wp, 0.0_wp]
        sp%u2 = [xws(i) - xb(ib - 4), side * 1.0_wp, r0 - hb]
        sp%stiffness = [3.90e7_wp, 7.85e6_wp, 9.75e5_wp]
        sp%damping = [0.0_wp, 0.0_wp, 1.08e4_wp]
        call mb%add_element(sp, error)
      end do
    end do
    ! ---- secondary suspension (tables 5.5, 5.6): bogie (body 1) -> car body (body 2)
    do ib = 5, 6
      do j = 1, 2
        side = merge(1.0_wp, -1.0_wp, j == 1)
        sp = linear_spring_damper_t()
        sp%name = 'secondary'
        sp%body1 = ib; sp%body2 = 7
        sp%u1 = [0.0_wp, side * 1.23_wp, 1.0_wp - hb]
        sp%u2 = [xb(ib - 4) - (-10.85_wp), side * 1.23_wp, 1.0_wp - hc]
        sp%stiffness = [1.73e5_wp, 1.73e5_wp, 5.3e5_wp]
        sp%damping = [0.0_wp, 3.5e4_wp, 1.5e4_wp]
        call mb%add_element(sp, error)
      end do
    end do
    ! ---- wheel supports: ground (track frame) -> wheelset, at the contact points
    do i = 1, 4
      do j = 1, 2
        side = merge(1.0_wp, -1.0_wp, j == 1)
        sp = linear_spring_damper_t()
        sp%name = 'support'
        sp%body1 = 0; sp%body2 = i
        sp%u1 = [0.0_wp, side * 0.75_wp, 0.0_wp]
        sp%u2 = [0.0_wp, side * 0.75_wp, -r0]
        sp%stiffness = [1.0e7_wp, 1.0e7_wp, 1.4e9_wp]
        sp%damping = [0.0_wp, 0.0_wp, 0.0_wp]
        call mb%add_element(sp, error)
      end do
    end do
  end subroutine build

  pure function diag(d) result(m)
    real(wp), intent(in) :: d(3)
    real(wp) :: m(3, 3)
    m = 0
    m(1, 1) = d(1); m(2, 2) = d(2); m(3, 3) = d(3)
  end function diag
end program test_tgv_static
