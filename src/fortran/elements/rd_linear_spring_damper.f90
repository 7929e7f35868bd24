!> Linear three-axis spring-damper with actuator (thesis eq. 4.115 and 4.116, table 5.4).
!>
!> Force on body 2 in element axes: f = f0 + f_act - K (d - L0) - C d', with d the
!> attachment points' separation in element axes (rd_element_geometry), L0 the free
!> separation, f0 the preload (the force on body 2 at zero deflection: positive z pushes
!> body 2 up along the element z axis) and f_act an actuator force.
!>
!> Body 1's reaction -F acts at point 2 (not point 1): with axes that turn with body 1 this
!> is what the potential 1/2 (d-L0)^T K (d-L0) - f0.(d-L0) yields (the moment of the
!> element's offset p2 - p1 belongs to body 1), so the element is exactly conservative and
!> keeps the total angular momentum. For coincident points it is the thesis' element.
module rd_linear_spring_damper
  use rd_kinds, only: wp
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_element, only: force_element_t, element_result_t
  use rd_element_geometry, only: point_pair_t, point_pair
  implicit none
  private
  public :: linear_spring_damper_t

  type, extends(force_element_t) :: linear_spring_damper_t
    real(wp) :: u1(3) = 0            !< attachment on body 1 (its attachment frame) [m]
    real(wp) :: u2(3) = 0            !< attachment on body 2 [m]
    !> element axes relative to body 1's attachment frame (ground: the track frame), columns
    real(wp) :: axes(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    real(wp) :: stiffness(3) = 0     !< [N/m]
    real(wp) :: damping(3) = 0       !< [N s/m]
    real(wp) :: free_length(3) = 0   !< unstressed separation in element axes [m]
    real(wp) :: preload(3) = 0       !< force on body 2 at zero deflection [N]
    real(wp) :: actuator(3) = 0      !< actuator force on body 2 [N]
    logical :: preload_free(3) = .true.  !< components the static solver may adjust
  contains
    procedure :: evaluate => linear_evaluate
    procedure :: preload_count => linear_preload_count
    procedure :: set_preload => linear_set_preload
    procedure :: reset_free_length => linear_reset_free_length
  end type linear_spring_damper_t

contains

  pure subroutine linear_evaluate(self, t, k1, k2, x, res, xdot)
    class(linear_spring_damper_t), intent(in) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(in) :: x(:)
    type(element_result_t), intent(out) :: res
    real(wp), intent(out) :: xdot(:)
    type(point_pair_t) :: pp
    pp = point_pair(k1, k2, self%u1, self%u2, self%axes)
    res%deflection = pp%d - self%free_length
    res%force_local = self%preload + self%actuator - self%stiffness * res%deflection - self%damping * pp%ddot
    res%force = matmul(pp%axes, res%force_local)
    res%moment = 0
    res%point2 = pp%p2
    res%reaction_point = pp%p2
  end subroutine linear_evaluate

  pure integer function linear_preload_count(self) result(n)
    class(linear_spring_damper_t), intent(in) :: self
    n = count(self%preload_free)
  end function linear_preload_count

  pure subroutine linear_set_preload(self, p)
    class(linear_spring_damper_t), intent(inout) :: self
    real(wp), intent(in) :: p(:)
    self%preload = unpack(p, self%preload_free, self%preload)
  end subroutine linear_set_preload

  !> Free length += deflection (force_element_t reset_free_length).
  pure subroutine linear_reset_free_length(self, deflection)
    class(linear_spring_damper_t), intent(inout) :: self
    real(wp), intent(in) :: deflection(3)
    self%free_length = self%free_length + deflection
  end subroutine linear_reset_free_length
end module rd_linear_spring_damper
