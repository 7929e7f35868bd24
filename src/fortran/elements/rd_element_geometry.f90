!> Geometry shared by the point-to-point elements (thesis eqs. 4.105-4.114): attachment
!> points, element axes and the deflection and its rate in element axes.
!>
!> Element axes are fixed to body 1's attachment frame (body frame; a wheelset's
!> non-spinning intermediate frame; the track frame for ground). The deflection rate is
!> the time derivative of the deflection in those rotating axes,
!>   d' = E^T (v2 - v1 - omega1 x (p2 - p1)),
!> so a rigid rotation of the pair produces no damping force; the thesis' eq. 4.113 omits
!> the omega1 term (it differentiates only the points' positions).
module rd_element_geometry
  use rd_kinds, only: wp
  use rd_rotation, only: cross
  use rd_body_kinematics, only: body_kinematics_t
  implicit none
  private
  public :: point_pair_t, point_pair

  type :: point_pair_t
    real(wp) :: p1(3), p2(3)      !< attachment points, fixed frame [m]
    real(wp) :: axes(3, 3)        !< element axes -> fixed (columns: element x, y, z)
    real(wp) :: d(3)              !< E^T (p2 - p1), element axes [m]
    real(wp) :: ddot(3)           !< its time derivative in the rotating element axes [m/s]
  end type point_pair_t

contains

  !> u1, u2: attachment points in body 1's and body 2's attachment frames; axes: element
  !> axes relative to body 1's attachment frame (columns).
  pure function point_pair(k1, k2, u1, u2, axes) result(pp)
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(in) :: u1(3), u2(3), axes(3, 3)
    type(point_pair_t) :: pp
    real(wp) :: dv(3)
    pp%p1 = k1%point_position(u1)
    pp%p2 = k2%point_position(u2)
    pp%axes = matmul(k1%rot_attach, axes)
    pp%d = matmul(pp%p2 - pp%p1, pp%axes)
    dv = k2%point_velocity(u2) - k1%point_velocity(u1) - cross(k1%omega_attach, pp%p2 - pp%p1)
    pp%ddot = matmul(dv, pp%axes)
  end function point_pair
end module rd_element_geometry
