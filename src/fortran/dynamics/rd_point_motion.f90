!> Motion of a point fixed on a body (a sensor): position, absolute velocity and absolute
!> acceleration, from the body's kinematics after an RHS evaluation (q, dq/dt and the
!> d2q/dt2 of the equations of motion), never from differences of outputs.
!>
!> Frames as docs/conventions.md: A track -> fixed, B body -> track, Omega = V w the track
!> frame's angular velocity (track components). The point P sits at u in the body frame;
!> on a wheelset at u in the non-spinning intermediate frame A Rz(psi) Rx(phi) (the axle
!> boxes, where the suspension attaches), so that a sensor there does not turn with the wheel.
!>
!> With w_P = w_bar + B u the point's position relative to the track frame (track
!> components), its absolute acceleration in track components is the CG's relation
!> (docs/theory.md eq. T1, thesis eq. 4.61) applied to w_P:
!>   a_P = p'' + w_P'' + 2 Omega x w_P' + Omega' x w_P + Omega x (Omega x w_P),
!>   w_P'  = w' + omega_rel x (B u),
!>   w_P'' = w'' + alpha_rel x (B u) + omega_rel x (omega_rel x (B u)),
!> with omega_rel = B H a' and alpha_rel = B (H' a' + H a'') the angular velocity and
!> acceleration of the body relative to the track frame (track components; dB/dt
!> = B skew(H a'), so d(B H a')/dt = B (H' a' + H a'')).
module rd_point_motion
  use rd_kinds, only: wp
  use rd_rotation, only: cross
  use rd_body_kinematics, only: body_kinematics_t, body_rotation, angle_rate_matrix, &
                                angle_rate_matrix_dot
  implicit none
  private
  public :: point_motion_t, compute_point_motion

  !> One point's motion at one instant. `_track`: the body's track frame components;
  !> `_body`: body frame components (wheelset: intermediate frame).
  type :: point_motion_t
    real(wp) :: position_track(3) = 0      !< P relative to the track frame origin [m]
    real(wp) :: position_fixed(3) = 0      !< P in the fixed frame [m]
    real(wp) :: velocity_track(3) = 0      !< absolute velocity of P [m/s]
    real(wp) :: acceleration_track(3) = 0  !< absolute acceleration of P [m/s^2]
    real(wp) :: velocity_body(3) = 0
    real(wp) :: acceleration_body(3) = 0
    !> what an accelerometer at P reads: acceleration minus gravity, body components [m/s^2]
    real(wp) :: specific_force_body(3) = 0
  end type point_motion_t

contains

  !> Motion of the point u (body frame; wheelset: intermediate frame) of the body whose
  !> kinematics `kin` an RHS evaluation filled (kin%qddot); gravity along -Z [m/s^2].
  pure function compute_point_motion(kin, u, gravity) result(m)
    type(body_kinematics_t), intent(in) :: kin
    real(wp), intent(in) :: u(3), gravity
    type(point_motion_t) :: m
    real(wp) :: angles(3), rates(3), accels(3), b(3, 3), h(3, 3), hd(3, 3)
    real(wp) :: at(3, 3), om(3), al(3), p0dd(3), bu(3), w_rel(3), alpha_rel(3)
    real(wp) :: wp_pos(3), wp_vel(3), wp_acc(3), v_track(3), a_track(3)
    angles = kin%q(4:6)
    rates = kin%qdot(4:6)
    accels = kin%qddot(4:6)
    if (kin%is_wheelset) then
      ! the intermediate frame: the body frame without the spin about the axle
      angles(3) = 0; rates(3) = 0; accels(3) = 0
    end if
    b = body_rotation(angles)
    h = angle_rate_matrix(angles(2), angles(3))
    hd = angle_rate_matrix_dot(angles(2), angles(3), rates(2), rates(3))
    at = transpose(kin%track%a)
    om = kin%omega_frame
    al = kin%alpha_frame
    bu = matmul(b, u)
    w_rel = matmul(b, matmul(h, rates))
    alpha_rel = matmul(b, matmul(hd, rates) + matmul(h, accels))
    wp_pos = kin%q(1:3) + bu
    wp_vel = kin%qdot(1:3) + cross(w_rel, bu)
    wp_acc = kin%qddot(1:3) + cross(alpha_rel, bu) + cross(w_rel, cross(w_rel, bu))
    ! origin of the track frame: p' = V dp/dsigma, p'' = V^2 d2p/dsigma2 + dV/dt dp/dsigma
    p0dd = matmul(at, kin%speed**2 * kin%track%d2r + kin%accel * kin%track%dr)
    v_track = kin%speed * matmul(at, kin%track%dr) + wp_vel + cross(om, wp_pos)
    a_track = p0dd + wp_acc + 2 * cross(om, wp_vel) + cross(al, wp_pos) + cross(om, cross(om, wp_pos))
    m%position_track = wp_pos
    m%position_fixed = kin%track%r + matmul(kin%track%a, wp_pos)
    m%velocity_track = v_track
    m%acceleration_track = a_track
    m%velocity_body = matmul(v_track, b)
    m%acceleration_body = matmul(a_track, b)
    ! gravity g = (0, 0, -g) in the fixed frame: an accelerometer reads a - g
    m%specific_force_body = matmul(a_track - matmul(at, [0.0_wp, 0.0_wp, -gravity]), b)
  end function compute_point_motion
end module rd_point_motion
