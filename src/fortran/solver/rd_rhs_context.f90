!> The object an integrator hands to its stepping engine (SUNDIALS through the C glue,
!> or the fixed-step Runge-Kutta loop): the ODE system, an optional analytic Jacobian or
!> coloured difference-quotient sparsity (rd_coloured_jacobian), and the last failure
!> the right-hand side reported (kept so `advance` can quote it).
!>
!> Every RHS evaluation of every method goes through `evaluate_rhs`, which turns the
!> system's error object into SUNDIALS' return convention (0 ok, > 0 recoverable,
!> < 0 fatal; which errors are recoverable: rd_error) and refuses non-finite derivatives
!> (recoverable), so a NaN never enters the state silently.
module rd_rhs_context
  use rd_text, only: int_text, sci_text
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, error_context, nonfinite_error, retry_error, finite
  use rd_ode_system, only: ode_system_t
  use rd_coloured_jacobian, only: jacobian_sparsity_t, dq_minimum_increment, dq_increment
  implicit none
  private
  public :: rhs_context_t, jacobian_i, RHS_OK, RHS_RECOVERABLE, RHS_FATAL

  integer, parameter :: RHS_OK = 0
  integer, parameter :: RHS_RECOVERABLE = 1
  integer, parameter :: RHS_FATAL = -1

  abstract interface
    !> Analytic (or coloured finite-difference) Jacobian J(i, j) = d ydot(i) / d y(j) at
    !> (t, y), where ydot = f(t, y) is given. Used by method 'bdf' only.
    subroutine jacobian_i(system, t, y, ydot, jac, error)
      import :: ode_system_t, wp, error_t
      class(ode_system_t), intent(inout) :: system
      real(wp), intent(in) :: t
      real(wp), intent(in) :: y(:)
      real(wp), intent(in) :: ydot(:)
      real(wp), intent(out) :: jac(:, :)
      type(error_t), allocatable, intent(out) :: error
    end subroutine jacobian_i
  end interface

  type :: rhs_context_t
    class(ode_system_t), pointer :: system => null()
    procedure(jacobian_i), pointer, nopass :: jacobian => null()
    !> Column groups of the coloured difference-quotient Jacobian (method 'bdf'); used
    !> instead of `jacobian` when allocated.
    type(jacobian_sparsity_t), allocatable :: sparsity
    !> RHS calls made by coloured Jacobians (SUNDIALS does not see them as its own).
    integer(i8) :: rhs_evals_jacobian = 0
    type(error_t), allocatable :: rhs_error   !< last failure reported by the RHS or Jacobian
    !> Set by an unrecoverable RHS failure; until cleared (next advance / reinit) every
    !> evaluation fails at once. SUNDIALS does not always stop on the first negative
    !> return (CVODE 6.4's fixed-point iteration retries it like a recoverable one, then
    !> shrinks h until t + h == t), so the latch makes the failure final and fast.
    logical :: fatal = .false.
  contains
    procedure :: evaluate_rhs
    procedure :: evaluate_jacobian
    procedure :: evaluate_coloured_jacobian
  end type rhs_context_t

contains

  !> ydot = f(t, y) with the failure convention above.
  function evaluate_rhs(self, t, y, ydot) result(status)
    class(rhs_context_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    integer :: status
    type(error_t), allocatable :: error

    if (self%fatal) then
      ydot = 0.0_wp
      status = RHS_FATAL
      return
    end if
    call self%system%rhs(t, y, ydot, error)
    status = RHS_OK
    if (.not. allocated(error)) then
      if (all(finite(ydot))) return
      call nonfinite_error(error, ydot, 'derivative in component ' // &
                           trim(int_text(findloc(finite(ydot), .false., 1))))
    end if
    call error_context(error, 'rhs at t = ' // trim(sci_text(t, 8)) // ' s')
    status = merge(RHS_RECOVERABLE, RHS_FATAL, error%recoverable)
    self%fatal = .not. error%recoverable
    call move_alloc(error, self%rhs_error)
  end function evaluate_rhs

  !> jac = df/dy at (t, y) through the user's Jacobian procedure.
  function evaluate_jacobian(self, t, y, ydot, jac) result(status)
    class(rhs_context_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(in) :: ydot(:)
    real(wp), intent(out) :: jac(:, :)
    integer :: status
    type(error_t), allocatable :: error

    if (self%fatal) then
      jac = 0.0_wp
      status = RHS_FATAL
      return
    end if
    call self%jacobian(self%system, t, y, ydot, jac, error)
    if (allocated(error)) then
      call error_context(error, 'jacobian at t = ' // trim(sci_text(t, 8)) // ' s')
      call move_alloc(error, self%rhs_error)
      self%fatal = .true.
      status = RHS_FATAL
      return
    end if
    status = RHS_OK
    if (all(finite(jac))) return
    call retry_error(self%rhs_error, 'jacobian at t = ' // trim(sci_text(t, 8)) // ' s: non-finite entry (NaN or Inf)')
    status = RHS_RECOVERABLE
  end function evaluate_jacobian

  !> jac = df/dy at (t, y) by coloured forward differences (rd_coloured_jacobian): one RHS
  !> call per column group, CVODE's increments from its current step h and error weights
  !> ewt, exact zeros outside the pattern. y_work and f_work are scratch of size n (CVODE's
  !> temporary vectors), so nothing is allocated. A failed RHS call returns its status
  !> (recoverable: CVODE retries the step with a smaller h, as with its own DQ Jacobian).
  function evaluate_coloured_jacobian(self, t, y, fy, h, ewt, y_work, f_work, jac) result(status)
    class(rhs_context_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(in) :: fy(:)
    real(wp), intent(in) :: h
    real(wp), intent(in) :: ewt(:)
    real(wp), intent(out) :: y_work(:)
    real(wp), intent(out) :: f_work(:)
    real(wp), intent(out) :: jac(:, :)
    integer :: status
    real(wp) :: min_inc, inc
    integer :: g, k, j, r, i

    jac = 0.0_wp
    if (self%fatal) then
      status = RHS_FATAL
      return
    end if
    status = RHS_OK
    min_inc = dq_minimum_increment(h, fy, ewt)
    y_work = y
    associate (sp => self%sparsity)
      do g = 1, sp%n_groups
        do k = sp%group_start(g), sp%group_start(g + 1) - 1
          j = sp%group_columns(k)
          y_work(j) = y(j) + dq_increment(y(j), ewt(j), min_inc, sp%min_increment)
        end do
        status = self%evaluate_rhs(t, y_work, f_work)
        self%rhs_evals_jacobian = self%rhs_evals_jacobian + 1
        if (status /= RHS_OK) return
        do k = sp%group_start(g), sp%group_start(g + 1) - 1
          j = sp%group_columns(k)
          inc = dq_increment(y(j), ewt(j), min_inc, sp%min_increment)
          do r = sp%row_start(j), sp%row_start(j + 1) - 1
            i = sp%rows(r)
            jac(i, j) = (f_work(i) - fy(i)) / inc
          end do
          y_work(j) = y(j)
        end do
      end do
    end associate
  end function evaluate_coloured_jacobian
end module rd_rhs_context
