!> Spring in series with a damper (yaw damper): with the elongation held (the body frozen
!> in all coordinates, so the state is the damper elongation only) and the damper starting
!> undeflected, the force relaxes as T(t) = k e exp(-t k / c) (closed form); the element
!> starts relaxed by default (zero force); the force acts along the line of the points.
program test_series_spring_damper
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t, multibody_output_t
  use rd_series_spring_damper, only: series_spring_damper_t
  use rd_dynamics_test_support, only: straight_track_t, rk4_integrate
  use rd_test_support, only: check, test_summary
  implicit none
  type(multibody_t), target :: mb
  class(track_geometry_t), pointer :: track
  type(body_spec_t) :: body(1)
  type(series_spring_damper_t) :: sd
  type(error_t), allocatable :: error
  real(wp), allocatable :: y(:), ydot(:)
  real(wp), parameter :: k = 5.0e6_wp, c = 2.5e5_wp, l0 = 0.5_wp
  real(wp) :: t, out(9), err, tension, line(3)
  type(multibody_output_t) :: o
  integer :: i
  logical :: ok
  character(len=100) :: buf

  allocate (straight_track_t :: track)
  body(1)%name = 'held'
  body(1)%mass = 100
  body(1)%inertia = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  body(1)%q0 = [0.3_wp, 0.4_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
  body(1)%frozen = .true.
  call mb%build(body, [0.0_wp], track, constant_speed(10.0_wp), error)
  sd%body1 = 0; sd%body2 = 1
  sd%stiffness = k; sd%damping = c; sd%free_length = l0
  call mb%add_element(sd, error)
  call check(mb%state_size() == 1, 'state = the damper elongation only')
  allocate (y(1), ydot(1))
  call mb%initial_state(y, error)
  call mb%rhs(0.0_wp, y, ydot, error)
  call mb%calc_output(0.0_wp, y, o, error)
  out = [o%elements(1)%deflection, o%elements(1)%force_local, o%elements(1)%force]
  call check(abs(out(4)) < 1e-9_wp .and. abs(ydot(1)) < 1e-15_wp, 'starts relaxed')

  ! move the held body so the elongation is 0.02 m, damper undeflected
  body(1)%q0(1:2) = [0.3_wp, 0.4_wp] * (l0 + 0.02_wp) / 0.5_wp
  call mb%build(body, [0.0_wp], track, constant_speed(10.0_wp), error)
  call mb%add_element(sd, error)
  y = 0
  err = 0
  t = 0
  do i = 1, 20
    call rk4_integrate(mb, t, t + 0.01_wp, 1.0e-4_wp, y, ok)
    t = t + 0.01_wp
    call mb%calc_output(t, y, o, error)
    out = [o%elements(1)%deflection, o%elements(1)%force_local, o%elements(1)%force]
    tension = -out(4)
    err = max(err, abs(tension - k * 0.02_wp * exp(-t * k / c)) / (k * 0.02_wp))
  end do
  write (buf, '(a,es9.2,a,f6.3,a)') 'max relative error ', err, ' (tau = c/k = ', c / k, ' s)'
  call check(ok .and. err < 1e-9_wp, 'relaxation T = k e exp(-t k/c)', detail=trim(buf))
  line = [0.6_wp, 0.8_wp, 0.0_wp]
  call check(maxval(abs(out(7:9) + tension * line)) < 1e-9_wp, 'force along the line, pulling body 2 back')
  call test_summary('test_series_spring_damper')
end program test_series_spring_damper
