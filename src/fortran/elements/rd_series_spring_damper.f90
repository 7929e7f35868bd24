!> Spring in series with a damper along the line between two attachment points (yaw damper
!> with its end stiffness). The damper's elongation x_d is an internal ODE state:
!>   e = |p2 - p1| - L0,   T = k (e - x_d) (tension),   dx_d/dt = T / c,
!> force on body 2 = -T n, n = (p2 - p1)/|p2 - p1|; body 1 gets +T n at point 1 (on the
!> same line, so no spurious moment). Under a held elongation the force relaxes as
!> exp(-t k/c). The element starts relaxed (x_d = e(0), zero force), i.e. in the static
!> equilibrium of a series spring-damper.
module rd_series_spring_damper
  use rd_kinds, only: wp
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_element, only: force_element_t, element_result_t
  implicit none
  private
  public :: series_spring_damper_t

  type, extends(force_element_t) :: series_spring_damper_t
    real(wp) :: u1(3) = 0
    real(wp) :: u2(3) = 0
    real(wp) :: stiffness = 0      !< series spring k [N/m]
    real(wp) :: damping = 1        !< damper c [N s/m], > 0
    real(wp) :: free_length = 0    !< L0 [m]
  contains
    procedure :: evaluate => series_evaluate
    procedure :: state_count => series_state_count
    procedure :: state_units => series_state_units
    procedure :: initial_states => series_initial_states
    procedure :: reset_free_length => series_reset_free_length
  end type series_spring_damper_t

contains

  pure integer function series_state_count(self) result(n)
    class(series_spring_damper_t), intent(in) :: self
    n = 1
  end function series_state_count

  !> x_d is the damper's elongation [m].
  pure subroutine series_state_units(self, units)
    class(series_spring_damper_t), intent(in) :: self
    character(len=*), intent(out) :: units(:)
    units(1) = 'm'
  end subroutine series_state_units

  pure subroutine series_initial_states(self, k1, k2, x)
    class(series_spring_damper_t), intent(in) :: self
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(out) :: x(:)
    x(1) = norm2(k2%point_position(self%u2) - k1%point_position(self%u1)) - self%free_length
  end subroutine series_initial_states

  pure subroutine series_evaluate(self, t, k1, k2, x, res, xdot)
    class(series_spring_damper_t), intent(in) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(in) :: x(:)
    type(element_result_t), intent(out) :: res
    real(wp), intent(out) :: xdot(:)
    real(wp) :: p1(3), p2(3), len, n(3), e, tension
    p1 = k1%point_position(self%u1)
    p2 = k2%point_position(self%u2)
    len = norm2(p2 - p1)
    if (len > 0) then
      n = (p2 - p1) / len
    else
      n = 0
    end if
    e = len - self%free_length
    tension = self%stiffness * (e - x(1))
    xdot(1) = tension / self%damping
    res%deflection = [e, x(1), e - x(1)]      ! total, damper, spring elongation
    res%force_local = [-tension, 0.0_wp, 0.0_wp]   ! along the line p1 -> p2
    res%force = -tension * n
    res%moment = 0
    res%point2 = p2
    res%reaction_point = p1
  end subroutine series_evaluate

  !> Free length += deflection along the line (force_element_t reset_free_length).
  pure subroutine series_reset_free_length(self, deflection)
    class(series_spring_damper_t), intent(inout) :: self
    real(wp), intent(in) :: deflection(3)
    self%free_length = self%free_length + deflection(1)
  end subroutine series_reset_free_length
end module rd_series_spring_damper
