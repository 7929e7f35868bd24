!> Torsional spring-damper on three axes: a pure couple from the relative rotation of two
!> bodies (anti-roll bar, yaw stiffness of a bogie-body connection), the rotational
!> counterpart of thesis eq. 4.115.
!>
!> Element frames: E1 = R1att axes1 on body 1 and E2 = R2att axes2 on body 2; they coincide
!> in the reference configuration. The deflection is the rotation vector (axis times angle)
!> of R = E1^T E2 in element axes (exact for any single-axis rotation), its rate the relative
!> angular velocity E1^T (omega2 - omega1). Moment on body 2 (element axes):
!>   m = m0 - K theta - C theta',   body 1 gets -m.
module rd_torsion_spring_damper
  use rd_kinds, only: wp
  use rd_rotation, only: unskew
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_element, only: force_element_t, element_result_t
  implicit none
  private
  public :: torsion_spring_damper_t, rotation_vector

  type, extends(force_element_t) :: torsion_spring_damper_t
    real(wp) :: axes1(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])  !< element axes on body 1
    real(wp) :: axes2(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])  !< element axes on body 2
    real(wp) :: stiffness(3) = 0   !< [N m/rad]
    real(wp) :: damping(3) = 0     !< [N m s/rad]
    real(wp) :: preload(3) = 0     !< moment on body 2 at zero deflection [N m]
  contains
    procedure :: evaluate => torsion_evaluate
  end type torsion_spring_damper_t

contains

  !> Rotation vector (axis * angle, angle in [0, pi)) of a rotation matrix.
  pure function rotation_vector(r) result(v)
    real(wp), intent(in) :: r(3, 3)
    real(wp) :: v(3)
    real(wp) :: s(3), sn, cs, angle
    s = unskew(r)                       ! sin(angle) * axis
    sn = norm2(s)
    cs = 0.5_wp * (r(1, 1) + r(2, 2) + r(3, 3) - 1)
    angle = atan2(sn, cs)
    if (sn > 1.0e-12_wp) then
      v = s * (angle / sn)
    else
      v = s                             ! angle/sin(angle) -> 1 (error O(angle^3) < 1e-36)
    end if
  end function rotation_vector

  pure subroutine torsion_evaluate(self, t, k1, k2, x, res, xdot)
    class(torsion_spring_damper_t), intent(in) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(in) :: x(:)
    type(element_result_t), intent(out) :: res
    real(wp), intent(out) :: xdot(:)
    real(wp) :: e1(3, 3), e2(3, 3), rate(3)
    e1 = matmul(k1%rot_attach, self%axes1)
    e2 = matmul(k2%rot_attach, self%axes2)
    res%deflection = rotation_vector(matmul(transpose(e1), e2))
    rate = matmul(k2%omega_attach - k1%omega_attach, e1)
    res%force_local = self%preload - self%stiffness * res%deflection - self%damping * rate
    res%moment = matmul(e1, res%force_local)
    res%force = 0
    res%point2 = k2%r
    res%reaction_point = k1%r
  end subroutine torsion_evaluate
end module rd_torsion_spring_damper
