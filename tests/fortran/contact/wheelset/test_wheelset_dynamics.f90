!> The contact provider inside the multibody equations (rd_multibody), integrated with a
!> classical RK4 written here: a knife-edge conical wheelset (lambda = 0.2, r0 = 0.46 m,
!> e0 = 0.75 m; Manchester vehicle 1 wheelset mass and inertia, 100 kN extra vertical load,
!> linear creep, x and spin frozen: it rolls at V/r0) at V = 5 m/s.
!>
!> 1. Klingel: lightly restrained (yaw spring 1e5 N m/rad only), started 2 mm off centre,
!>    it oscillates with the kinematic wavelength L = 2 pi sqrt(r0 e0 / lambda) (oracles.md;
!>    Klingel 1883: 8.25 m). On knife-edge rails the wheelset rolls by phi = Dr / e0, which
!>    moves the contact across the tread by r0 phi: the radius difference grows to
!>    Dr = lambda_e y with lambda_e = lambda / (1 - lambda r0 / e0) (checked in
!>    test_wheelset_creepage), but pure rolling (eta = 0) then reads ydot + r0 dphi/dt = V psi,
!>    so ydot (1 + r0 lambda_e / e0) = V psi and, with dpsi/dt = -V lambda_e y / (e0 r0),
!>    omega^2 = V^2 lambda_e / (e0 r0 (1 + r0 lambda_e / e0)) = V^2 lambda / (e0 r0) exactly:
!>    the textbook wavelength holds with the cone's own lambda.
!> 2. Curving: in a level left curve R = 300 m it settles at the pure-rolling offset
!>    y = -r0 e0 / (lambda_e R) (outwards): a steady state needs the radius difference
!>    Dr = r0 e0 / R, and Dr = lambda_e y here (oracles.md's r0 e0 / (lambda R) = 5.75 mm
!>    neglects the roll-induced contact shift; it is printed for comparison). A yaw spring of 5e6 N m/rad damps the kinematic oscillation; at the
!>    steady state it needs a yaw angle of ~1e-5 rad only, which moves y by < 0.1%.
program test_wheelset_dynamics
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_force_provider, only: force_provider_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use wheelset_test_support, only: circle_track_t, restraint_t, pose_kinematics, rel_err
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, e0 = 0.75_wp, lambda = 0.2_wp, v = 5.0_wp
  real(wp), parameter :: mass = 1813.0_wp, load = 1.0e5_wp, dt = 2.0e-4_wp
  real(wp), parameter :: lambda_e = lambda / (1 - lambda * r0 / e0)
  type(wheelset_contact_t), target :: ws
  type(restraint_t), target :: restraint
  type(circle_track_t), target :: track
  type(wheelset_contact_spec_t) :: spec
  type(error_t), allocatable :: error
  real(wp) :: z0, l_ref, l_sim, y_ref, y_end
  real(wp), allocatable :: hist(:)
  integer :: i, ncross
  real(wp) :: tcross(64)

  spec%body = 1
  spec%model = 'knife_edge'
  spec%knife_conicity = lambda
  spec%knife_e0 = e0
  spec%nominal_radius = r0
  spec%creep_law = 'linear'
  spec%contact_damping = 3.0e5_wp     ! ~10% of critical on the vertical Hertz mode
  call ws%build([spec], 1, error)
  if (allocated(error)) error stop error%message
  z0 = static_height()

  ! ---- 1. Klingel wavelength
  track%kappa = 0
  restraint%k_yaw = 1.0e5_wp
  call simulate(2.0e-3_wp, 4.0_wp, hist)
  ncross = 0
  do i = 2, size(hist)
    if (hist(i - 1) * hist(i) < 0 .and. ncross < size(tcross)) then
      ncross = ncross + 1
      tcross(ncross) = dt * (i - 2 + hist(i - 1) / (hist(i - 1) - hist(i)))
    end if
  end do
  call check(ncross >= 3, 'Klingel: the wheelset oscillates (at least 3 zero crossings)')
  if (ncross >= 3) then
    l_sim = v * 2 * (tcross(ncross) - tcross(1)) / (ncross - 1)
    l_ref = 2 * acos(-1.0_wp) * sqrt(r0 * e0 / lambda)
    write (*, '(a,f7.3,a,f7.3,a,f7.3,a,es10.3,a)') 'wavelength ', l_sim, ' m; 2 pi sqrt(r0 e0/lambda) = ', l_ref, &
      ' m; (with lambda_e: ', 2 * acos(-1.0_wp) * sqrt(r0 * e0 / lambda_e), ' m); amplitude after 4 s ', &
      maxval(abs(hist(size(hist) - nint(1.6_wp / dt):))), ' m'
    call check(rel_err(l_sim, l_ref) < 0.01_wp, 'Klingel: wavelength within 1% of 2 pi sqrt(r0 e0 / lambda)')
  end if

  ! ---- 2. pure-rolling offset in a curve
  track%kappa = 1.0_wp / 300.0_wp
  restraint%k_yaw = 5.0e6_wp
  call simulate(0.0_wp, 8.0_wp, hist)
  y_end = hist(size(hist))
  y_ref = -r0 * e0 / (lambda_e * 300.0_wp)
  write (*, '(a,es12.5,a,es12.5,a,es12.5,a,es10.3)') 'curve R 300: y = ', y_end, ' m; -r0 e0/(lambda_e R) = ', y_ref, &
    '; textbook ', -r0 * e0 / (lambda * 300.0_wp), '; |y(7 s) - y(8 s)| = ', abs(hist(nint(7.0_wp / dt)) - y_end)
  call check(rel_err(y_end, y_ref) < 0.01_wp, 'curve: pure-rolling offset -r0 e0 / (lambda_e R) within 1%')
  call check(abs(hist(nint(7.0_wp / dt)) - y_end) < 1.0e-3_wp * abs(y_ref), 'curve: settled (y changes < 0.1% in the last second)')
  call test_summary('test_wheelset_dynamics')

contains

  !> Height at which the contact carries weight + load at the centred pose (bisection).
  real(wp) function static_height() result(z)
    real(wp) :: zlo, zhi, f(3), m(3)
    integer :: it
    zlo = r0 - 2.0e-3_wp; zhi = r0 + 2.0e-3_wp
    do it = 1, 100
      z = 0.5_wp * (zlo + zhi)
      call ws%evaluate(1, 0.0_wp, pose_kinematics(track, 0.0_wp, v, [0.0_wp, 0.0_wp, z, 0.0_wp, 0.0_wp, 0.0_wp], &
                       [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0]), f, m, error)
      if (allocated(error)) error stop error%message
      if (f(3) > mass * standard_gravity + load) then
        zlo = z
      else
        zhi = z
      end if
    end do
  end function static_height

  !> RK4 from y(0) = y0 (other coordinates at static equilibrium) to t_end; lateral
  !> displacement history at every step.
  subroutine simulate(y0, t_end, hist)
    real(wp), intent(in) :: y0, t_end
    real(wp), allocatable, intent(out) :: hist(:)
    type(multibody_t) :: mb
    type(body_spec_t) :: body
    class(track_geometry_t), pointer :: tp
    class(force_provider_t), pointer :: pp
    real(wp), allocatable :: y(:), k1(:), k2(:), k3(:), k4(:)
    real(wp) :: t
    integer :: n, step, iy
    body%name = 'wheelset'
    body%mass = mass
    body%inertia = reshape([1120.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 112.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1120.0_wp], [3, 3])
    body%is_wheelset = .true.
    body%r0 = r0
    body%frozen = [.true., .false., .false., .false., .false., .true.]
    body%q0 = [0.0_wp, y0, z0, 0.0_wp, 0.0_wp, 0.0_wp]
    tp => track
    call mb%build([body], [0.0_wp], tp, constant_speed(v), error)
    if (allocated(error)) error stop error%message
    restraint%body = 1
    restraint%vertical_load = load
    pp => ws
    call mb%add_provider(pp)
    pp => restraint
    call mb%add_provider(pp)
    n = mb%state_size()
    allocate (y(n), k1(n), k2(n), k3(n), k4(n))
    call mb%initial_state(y, error)
    if (allocated(error)) error stop error%message
    iy = mb%free_slot(1, 2)
    allocate (hist(nint(t_end / dt) + 1))
    hist(1) = y(iy)
    t = 0
    do step = 1, size(hist) - 1
      call mb%rhs(t, y, k1, error)
      if (.not. allocated(error)) call mb%rhs(t + dt / 2, y + dt / 2 * k1, k2, error)
      if (.not. allocated(error)) call mb%rhs(t + dt / 2, y + dt / 2 * k2, k3, error)
      if (.not. allocated(error)) call mb%rhs(t + dt, y + dt * k3, k4, error)
      if (allocated(error)) error stop error%message
      y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
      t = step * dt
      hist(step + 1) = y(iy)
    end do
  end subroutine simulate

end program test_wheelset_dynamics
