!> rd_point_motion against differences of positions written independently here: a body
!> with every coordinate moving (prescribed sines) on a canted circle whose cant varies, at
!> an accelerating speed. The position of the point is p(sigma) + A (w + B u) with A and B
!> from the test support's own rotations; its velocity and acceleration by central
!> differences in time (Richardson-extrapolated) must equal the module's, which uses the
!> analytic rates and d2q/dt2 instead. A wheelset's sensor is on the non-spinning
!> intermediate frame Rz(psi) Rx(phi): the differences of that frame's point must agree.
program test_point_motion
  use rd_kinds, only: wp
  use rd_rotation, only: rot_x, rot_z
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_point_motion, only: point_motion_t, compute_point_motion
  use rd_track_point, only: track_point_t
  use rd_dynamics_test_support, only: canted_circle_t, zxy_rotation
  use rd_test_support, only: check, test_summary
  implicit none
  type(canted_circle_t) :: track
  real(wp), parameter :: v0 = 30.0_wp, acc = 0.7_wp, s0 = 12.0_wp, g = 9.81_wp
  real(wp), parameter :: q0(6) = [0.3_wp, 0.02_wp, 1.1_wp, 0.05_wp, -0.03_wp, 0.08_wp]
  real(wp), parameter :: qa(6) = [0.05_wp, 0.01_wp, 0.02_wp, 0.03_wp, 0.04_wp, 0.06_wp]
  real(wp), parameter :: freq(6) = [3.1_wp, 5.3_wp, 7.7_wp, 4.1_wp, 6.7_wp, 2.9_wp]
  real(wp), parameter :: u(3) = [2.5_wp, -1.1_wp, 0.8_wp]
  real(wp), parameter :: h = 1.0e-3_wp
  track%kappa = 1.0_wp / 300.0_wp
  track%cant = -0.1_wp
  track%cant_amplitude = 0.03_wp
  track%cant_scale = 7.0_wp
  call compare('body', .false., 0.37_wp)
  call compare('body later', .false., 1.91_wp)
  call compare('wheelset intermediate frame', .true., 0.37_wp)
  call test_summary('test_point_motion')

contains

  subroutine motion(t, q, qd, qdd)
    real(wp), intent(in) :: t
    real(wp), intent(out) :: q(6), qd(6), qdd(6)
    q = q0 + qa * sin(freq * t)
    qd = qa * freq * cos(freq * t)
    qdd = -qa * freq**2 * sin(freq * t)
  end subroutine motion

  !> The point in the fixed frame, from positions only.
  function point_at(t, on_wheelset) result(r)
    real(wp), intent(in) :: t
    logical, intent(in) :: on_wheelset
    real(wp) :: r(3), q(6), qd(6), qdd(6), b(3, 3)
    type(track_point_t) :: tp
    call motion(t, q, qd, qdd)
    tp = track%evaluate(s0 + v0 * t + acc * t**2 / 2)
    if (on_wheelset) then
      b = matmul(rot_z(q(4)), rot_x(q(5)))
    else
      b = zxy_rotation(q(4:6))
    end if
    r = tp%r + matmul(tp%a, q(1:3) + matmul(b, u))
  end function point_at

  subroutine compare(label, on_wheelset, t)
    character(len=*), intent(in) :: label
    logical, intent(in) :: on_wheelset
    real(wp), intent(in) :: t
    type(body_kinematics_t) :: kin
    type(point_motion_t) :: m
    type(track_point_t) :: tp
    real(wp) :: q(6), qd(6), qdd(6), v_fd(3), a_fd(3), at(3, 3), b(3, 3), r(3)
    character(len=200) :: detail
    call motion(t, q, qd, qdd)
    tp = track%evaluate(s0 + v0 * t + acc * t**2 / 2)
    call compute_body_kinematics(kin, tp, v0 + acc * t, acc, q, qd, on_wheelset)
    kin%qddot = qdd
    m = compute_point_motion(kin, u, g)
    v_fd = (4 * d1(t, on_wheelset, h / 2) - d1(t, on_wheelset, h)) / 3
    a_fd = (4 * d2(t, on_wheelset, h / 2) - d2(t, on_wheelset, h)) / 3
    at = transpose(tp%a)
    r = point_at(t, on_wheelset)
    if (on_wheelset) then
      b = matmul(rot_z(q(4)), rot_x(q(5)))
    else
      b = zxy_rotation(q(4:6))
    end if
    write (detail, '(a,3es11.3)') 'position error', m%position_fixed - r
    call check(maxval(abs(m%position_fixed - r)) < 1e-12_wp, label // ': position fixed', detail=trim(detail))
    call check(maxval(abs(m%position_track - matmul(at, r - tp%r))) < 1e-12_wp, label // ': position track')
    write (detail, '(a,3es11.3)') 'velocity error', matmul(tp%a, m%velocity_track) - v_fd
    call check(maxval(abs(matmul(tp%a, m%velocity_track) - v_fd)) < 1e-7_wp, label // ': velocity track', detail=trim(detail))
    write (detail, '(a,3es11.3,a,3f10.4)') 'acceleration error', matmul(tp%a, m%acceleration_track) - a_fd, &
      ' of', a_fd
    call check(maxval(abs(matmul(tp%a, m%acceleration_track) - a_fd)) < 1e-6_wp, label // ': acceleration track', detail=trim(detail))
    call check(maxval(abs(matmul(b, m%velocity_body) - m%velocity_track)) < 1e-12_wp .and. &
               maxval(abs(matmul(b, m%acceleration_body) - m%acceleration_track)) < 1e-12_wp, label // ': body components')
    ! an accelerometer reads a - g, g = (0, 0, -g) fixed
    call check(maxval(abs(matmul(tp%a, matmul(b, m%specific_force_body)) - &
               (a_fd - [0.0_wp, 0.0_wp, -g]))) < 1e-6_wp, label // ': specific force')
  end subroutine compare

  !> Central first difference of the point's position over +-step.
  function d1(t, on_wheelset, step) result(d)
    real(wp), intent(in) :: t, step
    logical, intent(in) :: on_wheelset
    real(wp) :: d(3)
    d = (point_at(t + step, on_wheelset) - point_at(t - step, on_wheelset)) / (2 * step)
  end function d1

  !> Central second difference.
  function d2(t, on_wheelset, step) result(d)
    real(wp), intent(in) :: t, step
    logical, intent(in) :: on_wheelset
    real(wp) :: d(3)
    d = (point_at(t + step, on_wheelset) - 2 * point_at(t, on_wheelset) + point_at(t - step, on_wheelset)) / step**2
  end function d2
end program test_point_motion
