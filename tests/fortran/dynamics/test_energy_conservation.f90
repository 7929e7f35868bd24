!> Energy of a conservative system: one body on four preloaded three-axis springs to its
!> track frame, gravity, the frame moving at constant V on straight level track (a
!> Galilean frame, so the energy measured in it is conserved). The energy is computed here
!> independently of the code's kinematics: angular velocity from unskew(B^T dB/dt) by the
!> product rule, spring deflections from the points' positions in the frame, potential
!> 1/2 d.K d - f0.d + m g z. Large angles (0.2-0.3 rad) and a full inertia tensor (Ixz) so
!> that the gyroscopic and H-matrix terms matter.
program test_energy_conservation
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_dynamics_test_support, only: straight_track_t, rk4_integrate, zxy_rotation, zxy_omega_body
  use rd_test_support, only: check, test_summary
  implicit none
  type(multibody_t), target :: mb
  class(track_geometry_t), pointer :: track
  type(body_spec_t) :: body(1)
  type(linear_spring_damper_t) :: spring
  type(error_t), allocatable :: error
  real(wp), allocatable :: y(:)
  real(wp) :: corners(3, 4), e0, e, emax, scale, t
  real(wp), parameter :: m = 1200, g = 9.80665_wp, k(3) = [1.0e5_wp, 2.0e5_wp, 3.0e5_wp]
  integer :: i, run
  real(wp) :: drift(2)
  logical :: ok
  character(len=80) :: buf

  allocate (straight_track_t :: track)
  body(1)%name = 'box'
  body(1)%mass = m
  body(1)%inertia = reshape([400.0_wp, 0.0_wp, 35.0_wp, 0.0_wp, 650.0_wp, 0.0_wp, 35.0_wp, 0.0_wp, 520.0_wp], [3, 3])
  body(1)%q0 = [0.02_wp, -0.03_wp, 0.015_wp, 0.2_wp, -0.3_wp, 0.25_wp]
  body(1)%qdot0 = [0.1_wp, -0.05_wp, 0.08_wp, 0.6_wp, -0.9_wp, 0.7_wp]
  call mb%build(body, [0.0_wp], track, constant_speed(30.0_wp), error, sigma0=5.0_wp)
  if (allocated(error)) then
    print *, error%message; error stop 1
  end if
  corners = reshape([1.1_wp, 0.8_wp, 0.3_wp, 1.1_wp, -0.8_wp, 0.3_wp, -1.1_wp, 0.8_wp, 0.3_wp, -1.1_wp, -0.8_wp, 0.3_wp], [3, 4])
  do i = 1, 4
    spring%body1 = 0; spring%body2 = 1
    spring%u1 = corners(:, i)       ! on the track frame (ground)
    spring%u2 = corners(:, i)       ! on the body
    spring%stiffness = k
    spring%preload = [0.0_wp, 0.0_wp, m * g / 4]
    call mb%add_element(spring, error)
  end do
  allocate (y(mb%state_size()))
  ! Run twice (h and h/2): a conservative model's energy error is the integrator's, which
  ! converges (RK4: the drift falls about 2^4-2^5 times); a model error would not.
  do run = 1, 2
    call mb%initial_state(y, error)
    e0 = energy(y)
    scale = 0.5_wp * m * sum(body(1)%qdot0(1:3)**2) + 0.5_wp * dot_product(zxy_omega_body(body(1)%q0(4:6), &
            body(1)%qdot0(4:6)), matmul(body(1)%inertia, zxy_omega_body(body(1)%q0(4:6), body(1)%qdot0(4:6))))
    emax = 0
    t = 0
    do i = 1, 40
      call rk4_integrate(mb, t, t + 0.5_wp, 2.5e-4_wp / run, y, ok)
      t = t + 0.5_wp
      emax = max(emax, abs(energy(y) - e0))
    end do
    drift(run) = emax / scale
  end do
  write (buf, '(a,2es10.3,a)') 'max |E - E0| / E_kin0 = ', drift, ' over 20 s (h = 0.25, 0.125 ms)'
  call check(ok .and. drift(2) < 1e-7_wp, 'energy conserved to the integration error', detail=trim(buf))
  call check(drift(1) / drift(2) > 16, 'energy error is the integrator''s (converges >= 4th order)')
  ! the motion really is large: the angles left the linear range
  write (buf, '(a,3f8.4)') 'final angles ', y(4:6)
  call check(maxval(abs(y(4:6))) > 0.05_wp, 'large-angle motion', detail=trim(buf))
  call test_summary('test_energy_conservation')
contains
  real(wp) function energy(y) result(en)
    real(wp), intent(in) :: y(:)
    real(wp) :: b(3, 3), w(3), d(3), om(3)
    integer :: j
    b = zxy_rotation(y(4:6))
    om = zxy_omega_body(y(4:6), y(10:12))
    en = 0.5_wp * m * sum(y(7:9)**2) + 0.5_wp * dot_product(om, matmul(body(1)%inertia, om)) + m * g * y(3)
    do j = 1, 4
      w = y(1:3) + matmul(b, corners(:, j))
      d = w - corners(:, j)
      en = en + 0.5_wp * sum(k * d**2) - m * g / 4 * d(3)
    end do
  end function energy
end program test_energy_conservation
