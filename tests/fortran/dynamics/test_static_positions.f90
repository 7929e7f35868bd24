!> rd_static_preload's position solve with held coordinates and an element with an internal
!> state, against closed forms. A 1000 kg block (rotations frozen) in a canted circular
!> track (R = 500 m, cant 0.1 rad; its frame at rest during the solve) hangs from the ground
!> (its track frame) on a linear spring (kx, kz; no lateral stiffness) and, in parallel, on a
!> series spring-damper along the same vertical line; its lateral position is held.
!> Weight in track components: m g (0, -sin phi, -cos phi) (A = Rz Rx(phi),
!> A^T (0, 0, -g) = -g (0, sin phi, cos phi)). At rest:
!>  - the series damper has stopped, so it carries nothing (dx_d/dt = T/c = 0: T = 0), and
!>    the spring alone carries the normal component: z = z0 - m g cos(phi) / kz (exact:
!>    the element is linear in track-frame axes and the block only translates along Z_T);
!>    with the damper state held at its start (as before) the block would sag only
!>    m g cos(phi) / (kz + k_series);
!>  - x stays 0 (no load along X_T);
!>  - y is held at its start, its residual acceleration is the unbalanced lateral
!>    component -g sin(phi) (the support the solve does not model);
!>  - every solved acceleration and the damper's rate vanish.
program test_static_positions
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t, DOF_X, DOF_Y, DOF_Z
  use rd_multibody, only: multibody_t
  use rd_static_preload, only: solve_static_positions
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_series_spring_damper, only: series_spring_damper_t
  use rd_dynamics_test_support, only: canted_circle_t
  use rd_test_support, only: check, stop_on, test_summary
  implicit none
  real(wp), parameter :: m = 1000, z0 = 1.0_wp, kz = 2.0e6_wp, ks = 5.0e6_wp, phi = 0.1_wp
  type(canted_circle_t), target :: track
  type(multibody_t) :: mb
  type(body_spec_t) :: b(1)
  type(linear_spring_damper_t) :: spring
  type(series_spring_damper_t) :: damper
  type(error_t), allocatable :: error
  real(wp), allocatable :: y(:), ydot(:)
  real(wp) :: residual, z_expected, tension
  integer :: n, kx, ky, kz_slot, kd
  logical :: held(6, 1)
  character(len=200) :: buf

  track%kappa = 1.0_wp / 500
  track%cant = phi
  b(1)%name = 'block'
  b(1)%mass = m
  b(1)%inertia = reshape([100, 0, 0, 0, 100, 0, 0, 0, 100], [3, 3])
  b(1)%q0 = [0.0_wp, 0.0_wp, z0, 0.0_wp, 0.0_wp, 0.0_wp]
  b(1)%frozen = [.false., .false., .false., .true., .true., .true.]
  call mb%build(b, [0.0_wp], track, constant_speed(20.0_wp), error, sigma0=50.0_wp)
  call stop_on(error, 'build')
  ! both from the ground point 0.5 m below the track origin to the block's point 1 m below
  ! its centre: 0.5 m long and vertical at the start, unstressed
  spring%body1 = 0; spring%body2 = 1
  spring%u1 = [0.0_wp, 0.0_wp, -0.5_wp]
  spring%u2 = [0.0_wp, 0.0_wp, -1.0_wp]
  spring%stiffness = [1.0e6_wp, 0.0_wp, kz]
  spring%free_length = [0.0_wp, 0.0_wp, 0.5_wp]
  call mb%add_element(spring, error)
  call stop_on(error, 'spring')
  damper%body1 = 0; damper%body2 = 1
  damper%u1 = [0.0_wp, 0.0_wp, -0.5_wp]
  damper%u2 = [0.0_wp, 0.0_wp, -1.0_wp]
  damper%stiffness = ks
  damper%damping = 1.0e5_wp
  damper%free_length = 0.5_wp
  call mb%add_element(damper, error)
  call stop_on(error, 'series damper')

  allocate (y(mb%state_size()), ydot(mb%state_size()))
  call mb%initial_state(y, error)
  call stop_on(error, 'initial state')
  n = mb%nfree
  kx = mb%free_slot(1, DOF_X)
  ky = mb%free_slot(1, DOF_Y)
  kz_slot = mb%free_slot(1, DOF_Z)
  kd = 2 * n + 1
  call check(abs(y(kd)) < 1.0e-15_wp, 'the series damper starts relaxed')

  held = .false.
  held(DOF_Y, 1) = .true.
  call solve_static_positions(mb, 0.0_wp, y, residual, error, held=held)
  call stop_on(error, 'static positions')

  z_expected = z0 - m * standard_gravity * cos(phi) / kz
  write (buf, '(a, es12.5, a, es12.5, a, es9.2)') 'z = ', y(kz_slot), ' m, closed form ', z_expected, &
    ', residual ', residual
  call check(abs(y(kz_slot) - z_expected) <= 1.0e-12_wp, 'z: the spring alone carries m g cos(phi)', detail=trim(buf))
  call check(abs(y(kx)) <= 1.0e-12_wp, 'x stays')
  call check(y(ky) == 0.0_wp, 'the held y keeps its value')

  ! the model at the solution, frame at rest (the solve's frozen time)
  mb%speed = constant_speed(0.0_wp)
  call mb%rhs(0.0_wp, y, ydot, error)
  call stop_on(error, 'rhs')
  tension = -mb%scratch%el_res(2)%force_local(1)
  write (buf, '(a, es10.3, a, es10.3, a, es10.3, a)') 'series tension ', tension, ' N, damper rate ', &
    ydot(kd), ' m/s, held y acceleration ', ydot(n + ky), ' m/s^2'
  call check(abs(tension) <= 1.0e-6_wp, 'the series damper carries no static force', detail=trim(buf))
  call check(abs(ydot(n + kx)) <= 1.0e-9_wp .and. abs(ydot(n + kz_slot)) <= 1.0e-9_wp, 'solved accelerations vanish')
  call check(abs(ydot(n + ky) + standard_gravity * sin(phi)) <= 1.0e-12_wp * standard_gravity, 'held y: residual = -g sin(phi)', detail=trim(buf))
  call check(residual <= 1.0e-9_wp, 'residual reported = max solved acceleration')

  call test_summary('test_static_positions')

end program test_static_positions
