!> Kinematics of one rigid body referred to a moving track frame (thesis 4.5.1, eqs. 4.6,
!> 4.27, 4.33-4.35, 4.38, A.11-A.21), and the Z-X-Y angle algebra shared by the equations
!> of motion, the force elements and the contact.
!>
!> Notation (docs/theory.md): A track -> fixed, B = Rz(psi) Rx(phi) Ry(theta) body -> track,
!> Omega = V w the frame's angular velocity (track components), H the matrix with
!> omega_rel(body components) = H (dpsi, dphi, dtheta)/dt.
module rd_body_kinematics
  use rd_kinds, only: wp
  use rd_rotation, only: rot_x, rot_y, rot_z, cross
  use rd_track_point, only: track_point_t
  implicit none
  private
  public :: body_kinematics_t, body_rotation, angle_rate_matrix, angle_rate_matrix_dot
  public :: compute_body_kinematics, ground_kinematics, inverse_angle_rate, frame_rate_shift, fixed_angles, &
            rotation_factors

  !> Everything about one body's motion at one instant. Vectors in fixed-frame components
  !> unless the name says otherwise.
  type :: body_kinematics_t
    real(wp) :: q(6) = 0        !< (x, y, z, psi, phi, theta) relative to the track frame
    real(wp) :: qdot(6) = 0     !< their time derivatives (wheelset: full spin rate V/r0 + dbeta/dt)
    real(wp) :: qddot(6) = 0    !< their second derivatives (filled by an RHS evaluation)
    real(wp) :: sigma = 0       !< arc length of the body's track frame [m]
    real(wp) :: speed = 0       !< V = dsigma/dt [m/s]
    real(wp) :: accel = 0       !< dV/dt [m/s^2]
    type(track_point_t) :: track                !< the track frame at sigma
    real(wp) :: omega_frame(3) = 0   !< Omega = V w, track components [rad/s]
    real(wp) :: alpha_frame(3) = 0   !< dOmega/dt = dV/dt w + V^2 dw/dsigma, track components
    real(wp) :: b(3, 3) = 0          !< B: body -> track
    real(wp) :: rot(3, 3) = 0        !< A B: body -> fixed
    real(wp) :: r(3) = 0             !< CG position [m]
    real(wp) :: v(3) = 0             !< absolute CG velocity [m/s]
    real(wp) :: acc(3) = 0           !< absolute CG acceleration [m/s^2] (after an RHS)
    real(wp) :: omega(3) = 0         !< absolute angular velocity, fixed components [rad/s]
    real(wp) :: omega_body(3) = 0    !< absolute angular velocity, body components [rad/s]
    !> Frame to which force elements attach: the body frame, except for a wheelset, whose
    !> suspension attaches to the non-spinning axle boxes: the intermediate frame
    !> A Rz(psi) Rx(phi) (thesis 4.6.3.2).
    logical :: is_wheelset = .false.
    real(wp) :: rot_attach(3, 3) = 0
    real(wp) :: omega_attach(3) = 0  !< angular velocity of that frame, fixed components
  contains
    procedure :: point_position
    procedure :: point_velocity
  end type body_kinematics_t

contains

  !> B = Rz(psi) Rx(phi) Ry(theta) (thesis 4.3.2, A.31), angles = (psi, phi, theta).
  pure function body_rotation(angles) result(b)
    real(wp), intent(in) :: angles(3)
    real(wp) :: b(3, 3), bzx(3, 3)
    call rotation_factors(angles, bzx, b)
  end function body_rotation

  !> Z-X-Y angles (psi, phi, theta) of a rotation R = Rz(psi) Rx(phi) Ry(theta): R32 = sin(phi),
  !> R12 = -sin(psi)cos(phi), R22 = cos(psi)cos(phi), R31 = -cos(phi)sin(theta), R33 = cos(phi)cos(theta).
  pure function fixed_angles(r) result(angles)
    real(wp), intent(in) :: r(3, 3)
    real(wp) :: angles(3)
    angles = [atan2(-r(1, 2), r(2, 2)), asin(max(-1.0_wp, min(1.0_wp, r(3, 2)))), atan2(-r(3, 1), r(3, 3))]
  end function fixed_angles

  !> H(phi, theta): relative angular velocity in BODY components = H (dpsi, dphi, dtheta).
  !> Columns: B^T e_z, Ry^T e_x, e_y (thesis A.21, which orders the angles (x, y, z)).
  pure function angle_rate_matrix(phi, theta) result(h)
    real(wp), intent(in) :: phi, theta
    real(wp) :: h(3, 3)
    real(wp) :: cf, sf, ct, st
    cf = cos(phi); sf = sin(phi); ct = cos(theta); st = sin(theta)
    h(:, 1) = [-st * cf, sf, ct * cf]
    h(:, 2) = [ct, 0.0_wp, st]
    h(:, 3) = [0.0_wp, 1.0_wp, 0.0_wp]
  end function angle_rate_matrix

  !> dH/dt for angle rates (dpsi, dphi, dtheta).
  pure function angle_rate_matrix_dot(phi, theta, dphi, dtheta) result(hd)
    real(wp), intent(in) :: phi, theta, dphi, dtheta
    real(wp) :: hd(3, 3)
    real(wp) :: cf, sf, ct, st
    cf = cos(phi); sf = sin(phi); ct = cos(theta); st = sin(theta)
    hd(:, 1) = [-ct * cf * dtheta + st * sf * dphi, cf * dphi, -st * cf * dtheta - ct * sf * dphi]
    hd(:, 2) = [-st * dtheta, 0.0_wp, ct * dtheta]
    hd(:, 3) = 0
  end function angle_rate_matrix_dot

  !> H^{-1} w: angle rates (dpsi, dphi, dtheta) from a body-component angular velocity w
  !> (det H = cos(phi)).
  pure function inverse_angle_rate(phi, theta, w) result(ad)
    real(wp), intent(in) :: phi, theta, w(3)
    real(wp) :: ad(3)
    real(wp) :: ct, st
    ct = cos(theta); st = sin(theta)
    ad(1) = (-st * w(1) + ct * w(3)) / cos(phi)
    ad(2) = ct * w(1) + st * w(3)
    ad(3) = w(2) - sin(phi) * ad(1)
  end function inverse_angle_rate

  !> The shift c(q, Omega) between the relative rates and the generalized velocities the
  !> state holds, nu = qdot + c (docs/theory.md section 5): c = (Omega x w_bar,
  !> H^{-1} B^T Omega). nu is continuous where the frame's angular velocity jumps.
  !> `b`: B(q(4:6)) when the caller has it (rotation_factors), else computed here.
  pure function frame_rate_shift(q, omega_frame, b) result(c)
    real(wp), intent(in) :: q(6), omega_frame(3)
    real(wp), intent(in), optional :: b(3, 3)
    real(wp) :: c(6)
    c(1:3) = cross(omega_frame, q(1:3))
    if (present(b)) then
      c(4:6) = inverse_angle_rate(q(5), q(6), matmul(omega_frame, b))
    else
      c(4:6) = inverse_angle_rate(q(5), q(6), matmul(omega_frame, body_rotation(q(4:6))))
    end if
  end function frame_rate_shift

  !> The factors of B = Rz(psi) Rx(phi) Ry(theta) that compute_body_kinematics uses, angles =
  !> (psi, phi, theta): bzx = Rz Rx (a wheelset's intermediate frame) and B = bzx Ry, each
  !> sine and cosine once (the right-hand side needs B twice per body: the rate shift and the
  !> kinematics).
  pure subroutine rotation_factors(angles, bzx, b)
    real(wp), intent(in) :: angles(3)
    real(wp), intent(out) :: bzx(3, 3), b(3, 3)
    real(wp) :: rz(3, 3), rx(3, 3), ry(3, 3)
    ! factors in local arrays: gfortran then multiplies inline (a matmul of function results
    ! is a library call with two allocated temporaries)
    rz = rot_z(angles(1))
    rx = rot_x(angles(2))
    ry = rot_y(angles(3))
    bzx = matmul(rz, rx)
    b = matmul(bzx, ry)
  end subroutine rotation_factors

  !> Fill the kinematics of a body with coordinates q, rates qdot relative to the track
  !> frame `tp` moving at speed v_frame (acceleration a_frame).
  !> `bzx`, `b`: the rotation factors of q(4:6) (rotation_factors) when the caller has them.
  pure subroutine compute_body_kinematics(kin, tp, v_frame, a_frame, q, qdot, is_wheelset, bzx_given, b_given)
    type(body_kinematics_t), intent(inout) :: kin
    type(track_point_t), intent(in) :: tp
    real(wp), intent(in) :: v_frame, a_frame, q(6), qdot(6)
    logical, intent(in) :: is_wheelset
    real(wp), intent(in), optional :: bzx_given(3, 3), b_given(3, 3)
    real(wp) :: h(3, 3), w_rel_track(3), bzx(3, 3)
    kin%q = q
    kin%qdot = qdot
    kin%sigma = tp%sigma
    kin%speed = v_frame
    kin%accel = a_frame
    kin%track = tp
    kin%is_wheelset = is_wheelset
    kin%omega_frame = v_frame * tp%omega
    kin%alpha_frame = a_frame * tp%omega + v_frame**2 * tp%domega
    if (present(bzx_given) .and. present(b_given)) then
      bzx = bzx_given
      kin%b = b_given
    else
      call rotation_factors(q(4:6), bzx, kin%b)
    end if
    kin%rot = matmul(tp%a, kin%b)
    ! eq. 4.33: r_G = p + A w
    kin%r = tp%r + matmul(tp%a, q(1:3))
    ! eq. 4.35 with dA/dt w = A (Omega x w) and dp/dt = V dp/dsigma
    w_rel_track = cross(kin%omega_frame, q(1:3)) + qdot(1:3)
    kin%v = v_frame * tp%dr + matmul(tp%a, w_rel_track)
    ! eq. 4.38: omega_body = B^T Omega + H dangles/dt
    h = angle_rate_matrix(q(5), q(6))
    kin%omega_body = matmul(kin%omega_frame, kin%b) + matmul(h, qdot(4:6))
    kin%omega = matmul(kin%rot, kin%omega_body)
    if (is_wheelset) then
      kin%rot_attach = matmul(tp%a, bzx)
      ! the intermediate frame lacks only the spin about the body y axis
      kin%omega_attach = kin%omega - qdot(6) * kin%rot(:, 2)
    else
      kin%rot_attach = kin%rot
      kin%omega_attach = kin%omega
    end if
  end subroutine compute_body_kinematics

  !> "Ground" for a force element: the track frame of the body `kin` is referred to,
  !> as a body at rest in that frame (q = 0).
  pure function ground_kinematics(kin) result(g)
    type(body_kinematics_t), intent(in) :: kin
    type(body_kinematics_t) :: g
    real(wp), parameter :: zero6(6) = 0
    call compute_body_kinematics(g, kin%track, kin%speed, kin%accel, zero6, zero6, .false.)
    g%acc = kin%speed**2 * kin%track%d2r + kin%accel * kin%track%dr
  end function ground_kinematics

  !> Position (fixed frame) of a point with coordinates u in the attachment frame
  !> (body frame; intermediate frame for a wheelset), thesis eq. 4.6 / 4.105.
  pure function point_position(self, u) result(p)
    class(body_kinematics_t), intent(in) :: self
    real(wp), intent(in) :: u(3)
    real(wp) :: p(3)
    p = self%r + matmul(self%rot_attach, u)
  end function point_position

  !> Absolute velocity (fixed frame) of that point, thesis eq. 4.27 / 4.111.
  pure function point_velocity(self, u) result(v)
    class(body_kinematics_t), intent(in) :: self
    real(wp), intent(in) :: u(3)
    real(wp) :: v(3)
    v = self%v + cross(self%omega_attach, matmul(self%rot_attach, u))
  end function point_velocity
end module rd_body_kinematics
