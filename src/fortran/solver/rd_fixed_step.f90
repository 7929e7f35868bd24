!> Fixed-step explicit Runge-Kutta steps for deterministic, real-time-style runs.
!>
!> - 'rk4': the classical 4-stage, 4th-order method (Kutta 1901; Hairer, Norsett & Wanner,
!>   Solving ODEs I, table II.1.1): global error O(h^4).
!> - 'heun': the explicit trapezoidal rule (Heun 1900), 2 stages, global error O(h^2).
!>
!> Work arrays are allocated once (build) and reused: no allocation per step.
module rd_fixed_step
  use rd_kinds, only: wp
  use rd_rhs_context, only: rhs_context_t, RHS_OK
  implicit none
  private
  public :: fixed_step_work_t, rk4_step, heun_step

  type :: fixed_step_work_t
    real(wp), allocatable :: k1(:), k2(:), k3(:), k4(:), ystage(:)
    real(wp), allocatable :: ystart(:)   !< a step's start, for its retry in substeps
  contains
    procedure :: allocate_work
  end type fixed_step_work_t

contains

  subroutine allocate_work(self, n)
    class(fixed_step_work_t), intent(inout) :: self
    integer, intent(in) :: n
    if (allocated(self%k1)) deallocate (self%k1, self%k2, self%k3, self%k4, self%ystage, self%ystart)
    allocate (self%k1(n), self%k2(n), self%k3(n), self%k4(n), self%ystage(n), self%ystart(n))
  end subroutine allocate_work

  !> One classical RK4 step from (t, y) to (t + h, y); status /= RHS_OK leaves y unchanged.
  subroutine rk4_step(context, t, h, y, work, status)
    type(rhs_context_t), intent(inout) :: context
    real(wp), intent(in) :: t, h
    real(wp), intent(inout) :: y(:)
    type(fixed_step_work_t), intent(inout) :: work
    integer, intent(out) :: status

    status = context%evaluate_rhs(t, y, work%k1)
    if (status /= RHS_OK) return
    work%ystage = y + 0.5_wp * h * work%k1
    status = context%evaluate_rhs(t + 0.5_wp * h, work%ystage, work%k2)
    if (status /= RHS_OK) return
    work%ystage = y + 0.5_wp * h * work%k2
    status = context%evaluate_rhs(t + 0.5_wp * h, work%ystage, work%k3)
    if (status /= RHS_OK) return
    work%ystage = y + h * work%k3
    status = context%evaluate_rhs(t + h, work%ystage, work%k4)
    if (status /= RHS_OK) return
    y = y + (h / 6.0_wp) * (work%k1 + 2.0_wp * work%k2 + 2.0_wp * work%k3 + work%k4)
  end subroutine rk4_step

  !> One Heun step (explicit trapezoid): y+ = y + h/2 (f(t, y) + f(t + h, y + h f(t, y))).
  subroutine heun_step(context, t, h, y, work, status)
    type(rhs_context_t), intent(inout) :: context
    real(wp), intent(in) :: t, h
    real(wp), intent(inout) :: y(:)
    type(fixed_step_work_t), intent(inout) :: work
    integer, intent(out) :: status

    status = context%evaluate_rhs(t, y, work%k1)
    if (status /= RHS_OK) return
    work%ystage = y + h * work%k1
    status = context%evaluate_rhs(t + h, work%ystage, work%k2)
    if (status /= RHS_OK) return
    y = y + (0.5_wp * h) * (work%k1 + work%k2)
  end subroutine heun_step
end module rd_fixed_step
