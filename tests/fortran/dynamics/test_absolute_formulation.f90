!> The track-frame formulation against an independent one: the same body integrated in
!> ABSOLUTE coordinates (Newton-Euler in the fixed frame: position, velocity, rotation
!> matrix R with dR/dt = R skew(omega_b), Euler's equation in body axes), with the forces of
!> the same two spring-dampers to the moving track frame computed here from the absolute
!> state. Both are integrated with rd_integrator's adaptive Dormand-Prince ('erk', rtol
!> 1e-11: the track-frame RHS jumps where dw/dsigma jumps, at clothoid ends, and a
!> fixed-step method would lose its order there) and compared in position and orientation:
!>  1. an exact canted circle (written in the test) at constant speed;
!>  2. rd_track: straight -> clothoid (cosine cant ramp) -> canted curve, with a speed ramp
!>     (dV/dt terms);
!>  3. rd_track: straight -> clothoid with a LINEAR cant ramp and a gradient change ->
!>     canted curve, the body 8 m behind its frame: the frame's angular velocity jumps at
!>     the clothoid ends, which the generalized velocities of the state absorb (theory.md 5);
!>  4. a wheelset body (spin integrated as the deviation beta, spinning at ~90 rad/s) on
!>     the same track: gyroscopic coupling with the frame's rotation.
!> The independent absolute-coordinate model of the test below.
module absolute_body_model
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: skew, cross
  use rd_ode_system, only: ode_system_t
  use rd_track_point, only: track_geometry_t, track_point_t
  use rd_speed_law, only: speed_law_t
  implicit none
  real(wp), parameter :: m = 1500, g = 9.80665_wp
  real(wp), parameter :: kk(3) = [2.0e5_wp, 1.0e5_wp, 4.0e5_wp], cc(3) = [2.0e3_wp, 1.0e3_wp, 3.0e3_wp]
  real(wp), parameter :: jj(3, 3) = reshape([500.0_wp, 0.0_wp, 40.0_wp, 0.0_wp, 900.0_wp, 0.0_wp, 40.0_wp, 0.0_wp, 800.0_wp], [3, 3])
  real(wp), parameter :: pts(3, 2) = reshape([1.2_wp, 0.0_wp, 0.2_wp, -1.2_wp, 0.0_wp, 0.2_wp], [3, 2])

  !> The independent model: z = (r, v, R(:), omega_body).
  type, extends(ode_system_t) :: absolute_body_t
    class(track_geometry_t), pointer :: track => null()
    type(speed_law_t) :: speed
    real(wp) :: sigma0 = 0
    real(wp) :: x_offset = 0     !< ground points' x in the track frame, added to pts
    real(wp) :: z_ground = 0     !< ground points' z in the track frame, added to pts
    real(wp) :: mass = m
    real(wp) :: inertia(3, 3) = jj
    real(wp) :: points(3, 2) = pts   !< attachment points on the body (and the frame)
  contains
    procedure :: rhs => abs_rhs
    procedure :: state_size => abs_size
  end type absolute_body_t

contains
  pure function abs_size(self) result(n)
    class(absolute_body_t), intent(in) :: self
    integer :: n
    n = 18
  end function abs_size

  subroutine abs_rhs(self, t, y, ydot, error)
    class(absolute_body_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    type(track_point_t) :: tp
    real(wp) :: r(3, 3), a(3, 3), wa(3), v, f(3), mom(3), p1(3), p2(3), v1(3), v2(3), d(3), dd(3), fl(3), wb(3)
    integer :: i
    v = self%speed%speed(t)
    tp = self%track%evaluate(self%sigma0 + self%speed%distance(t))
    a = tp%a
    wa = matmul(a, v * tp%omega)               ! frame angular velocity, fixed components
    r = reshape(y(7:15), [3, 3])
    wb = y(16:18)
    f = [0.0_wp, 0.0_wp, -self%mass * g]
    mom = 0
    do i = 1, 2
      p1 = tp%r + matmul(a, self%points(:, i) + [self%x_offset, 0.0_wp, self%z_ground])   ! on the track frame
      p2 = y(1:3) + matmul(r, self%points(:, i))                   ! on the body
      v1 = v * tp%dr + cross(wa, p1 - tp%r)
      v2 = y(4:6) + cross(matmul(r, wb), p2 - y(1:3))
      d = matmul(transpose(a), p2 - p1)                    ! track axes
      dd = matmul(transpose(a), v2 - v1 - cross(wa, p2 - p1))
      fl = [0.0_wp, 0.0_wp, self%mass * g / 2] - kk * d - cc * dd
      f = f + matmul(a, fl)
      mom = mom + cross(p2 - y(1:3), matmul(a, fl))
    end do
    ydot(1:3) = y(4:6)
    ydot(4:6) = f / self%mass
    ydot(7:15) = reshape(matmul(r, skew(wb)), [9])
    ydot(16:18) = solve3(self%inertia, matmul(transpose(r), mom) - cross(wb, matmul(self%inertia, wb)))
  end subroutine abs_rhs

  !> 3x3 solve by Cramer's rule.
  pure function solve3(mm, b) result(x)
    real(wp), intent(in) :: mm(3, 3), b(3)
    real(wp) :: x(3), det
    integer :: j
    real(wp) :: t(3, 3)
    det = dot_product(mm(:, 1), cross(mm(:, 2), mm(:, 3)))
    do j = 1, 3
      t = mm
      t(:, j) = b
      x(j) = dot_product(t(:, 1), cross(t(:, 2), t(:, 3))) / det
    end do
  end function solve3
end module absolute_body_model

program test_absolute_formulation
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: skew, cross
  use rd_ode_system, only: ode_system_t
  use rd_track_point, only: track_geometry_t, track_point_t
  use rd_track, only: track_t, track_settings_t, segment_spec_t, build_track
  use rd_speed_law, only: speed_law_t, constant_speed, table_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_integrator, only: integrator_t, integrator_settings_t
  use rd_dynamics_test_support, only: canted_circle_t, zxy_rotation, zxy_omega_body
  use rd_test_support, only: check, test_summary
  use absolute_body_model
  implicit none

  class(track_geometry_t), pointer :: circle, segtrack
  type(track_t), pointer :: tr
  type(speed_law_t) :: law
  type(error_t), allocatable :: error
  type(track_settings_t) :: settings
  type(segment_spec_t) :: specs(3)

  allocate (canted_circle_t :: circle)
  select type (circle)
  type is (canted_circle_t)
    circle%kappa = 1.0_wp / 300
    circle%cant = -0.12_wp
    circle%cant_amplitude = 0.05_wp      ! smooth cant variation: roll rate of the frame
    circle%cant_scale = 20.0_wp
  end select
  call compare('canted circle R = 300 m, varying cant, constant V', circle, constant_speed(35.0_wp), 0.0_wp, 4.0_wp)

  specs(1)%kind = 'straight'; specs(1)%length = 30
  specs(2)%kind = 'clothoid'; specs(2)%length = 100; specs(2)%curvature_end = 1.0_wp / 500
  specs(2)%superelevation_end = -0.15_wp; specs(2)%cant_ramp = 'cosine'
  specs(3)%kind = 'curve'; specs(3)%length = 300; specs(3)%curvature_end = 1.0_wp / 500
  specs(3)%superelevation_end = -0.15_wp
  allocate (tr)
  call build_track(tr, settings, specs, error)
  if (allocated(error)) then
    print '(a)', 'FAIL: build_track: ' // error%message; error stop 1
  end if
  segtrack => tr
  call table_speed(law, [0.0_wp, 4.0_wp], [30.0_wp, 45.0_wp], error)
  call compare('rd_track straight-clothoid-curve, speed ramp', segtrack, law, 10.0_wp, 5.0_wp)

  specs(2)%cant_ramp = 'linear'; specs(2)%gradient_end = 0.01_wp
  allocate (tr)
  call build_track(tr, settings, specs, error)
  if (allocated(error)) then
    print '(a)', 'FAIL: build_track: ' // error%message; error stop 1
  end if
  segtrack => tr
  call compare('rd_track linear cant ramp and gradient change, body 8 m behind its frame', segtrack, law, 20.0_wp, 5.0_wp, &
               x_offset=-8.0_wp)

  call compare('wheelset spinning at V/r0 on the linear-ramp track', segtrack, law, 20.0_wp, 5.0_wp, wheelset=.true.)

  call test_summary('test_absolute_formulation')

contains

  subroutine compare(label, track, speed, sigma0, t_end, x_offset, wheelset)
    real(wp), intent(in), optional :: x_offset
    logical, intent(in), optional :: wheelset
    character(*), intent(in) :: label
    class(track_geometry_t), pointer, intent(in) :: track
    type(speed_law_t), intent(in) :: speed
    real(wp), intent(in) :: sigma0, t_end
    type(multibody_t), target :: mb
    type(absolute_body_t), target :: ab
    type(integrator_t) :: int_mb, int_ab
    type(integrator_settings_t) :: settings
    type(body_spec_t) :: body(1)
    type(linear_spring_damper_t) :: spring
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:), ydot(:)
    real(wp) :: z(18), t, dr, drot, scale, a(3, 3), om(3), v0, rates(3)
    type(track_point_t) :: tp
    integer :: i, step
    logical :: ok, ok2
    character(len=120) :: buf

    body(1)%name = 'body'
    body(1)%mass = m
    body(1)%inertia = jj
    body(1)%q0 = [0.01_wp, 0.02_wp, 0.03_wp, 0.05_wp, -0.04_wp, 0.03_wp]
    body(1)%qdot0 = [0.1_wp, -0.2_wp, 0.05_wp, 0.3_wp, 0.2_wp, -0.25_wp]
    if (present(x_offset)) body(1)%q0(1) = x_offset
    ab%mass = m; ab%inertia = jj; ab%points = pts
    if (present(wheelset)) then
      ! a wheelset spinning at V/r0 (+ a deviation): strong gyroscopic coupling; springs at
      ! axle-box points on the axle, which the spin does not move
      body(1)%name = 'wheelset'
      body(1)%is_wheelset = wheelset
      body(1)%r0 = 0.45_wp
      body(1)%inertia = reshape([800.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 100.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 800.0_wp], [3, 3])
      body(1)%q0(3) = 0.45_wp
      body(1)%q0(6) = 0.3_wp
      ab%inertia = body(1)%inertia
      ab%points = reshape([0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, -1.0_wp, 0.0_wp], [3, 2])
    end if
    call mb%build(body, [0.0_wp], track, speed, error, sigma0=sigma0)
    do i = 1, 2
      spring%body1 = 0; spring%body2 = 1
      spring%u1 = ab%points(:, i) + [body(1)%q0(1), 0.0_wp, body(1)%q0(3) - 0.03_wp]
      spring%u2 = ab%points(:, i)
      spring%stiffness = kk; spring%damping = cc
      spring%preload = [0.0_wp, 0.0_wp, m * g / 2]
      call mb%add_element(spring, error)
    end do
    allocate (y(mb%state_size()), ydot(mb%state_size()))
    call mb%initial_state(y, error)

    ! initial absolute state, from the relative one by the kinematics written here
    ab%track => track; ab%speed = speed; ab%sigma0 = sigma0; ab%x_offset = body(1)%q0(1)
    ab%z_ground = body(1)%q0(3) - 0.03_wp
    tp = track%evaluate(sigma0)
    a = tp%a
    v0 = speed%speed(0.0_wp)
    om = v0 * tp%omega                        ! frame angular velocity, track components
    z(1:3) = tp%r + matmul(a, body(1)%q0(1:3))
    z(4:6) = v0 * tp%dr + matmul(a, cross(om, body(1)%q0(1:3)) + body(1)%qdot0(1:3))
    z(7:15) = reshape(matmul(a, zxy_rotation(body(1)%q0(4:6))), [9])
    rates = body(1)%qdot0(4:6)
    if (body(1)%is_wheelset) rates(3) = rates(3) + v0 / body(1)%r0     ! theta_dot = V/r0 + dbeta/dt
    z(16:18) = matmul(transpose(zxy_rotation(body(1)%q0(4:6))), om) + zxy_omega_body(body(1)%q0(4:6), rates)

    settings%method = 'erk'
    settings%rtol = 1.0e-11_wp
    settings%atol = 1.0e-13_wp
    settings%max_num_steps = 1000000
    call int_mb%build(mb, 0.0_wp, y, settings, error)
    if (.not. allocated(error)) call int_ab%build(ab, 0.0_wp, z, settings, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: integrator build: ' // error%message; error stop 1
    end if
    dr = 0; drot = 0; scale = 0; t = 0
    do step = 1, nint(t_end / 0.25_wp)
      t = step * 0.25_wp
      call int_mb%advance(t, y, error)
      ok = .not. allocated(error)
      call int_ab%advance(t, z, error)
      ok2 = .not. allocated(error)
      call mb%rhs(t, y, ydot, error)
      dr = max(dr, norm2(mb%scratch%kin(1)%r - z(1:3)))
      drot = max(drot, maxval(abs(mb%scratch%kin(1)%rot - reshape(z(7:15), [3, 3]))))
      scale = max(scale, norm2(mb%scratch%kin(1)%q(1:3) - body(1)%q0(1:3)))   ! amplitude of the relative motion
    end do
    write (buf, '(a,es9.2,a,es9.2,a,f7.4,a)') 'max |dr| = ', dr, ' m, max |dR| = ', drot, &
      ' (relative motion ', scale, ' m)'
    call check(ok .and. ok2 .and. dr < 1e-6_wp * scale, label // ': positions agree', detail=trim(buf))
    call check(drot < 1e-6_wp, label // ': orientations agree')
    call int_mb%destroy()
    call int_ab%destroy()
    write (buf, '(a,f8.2,a)') 'frame travelled ', mb%scratch%kin(1)%sigma - sigma0, ' m'
    call check(mb%scratch%kin(1)%sigma - sigma0 > 100, label // ': run covers the track', detail=trim(buf))
  end subroutine compare

end program test_absolute_formulation
