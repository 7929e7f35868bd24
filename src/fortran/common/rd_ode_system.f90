!> The contract between a physical model and the integrators: y' = f(t, y).
!>
!> The multibody system extends `ode_system_t`; the integrators in src/fortran/solver
!> only know this interface (SUNDIALS' examples: the problem module holds parameters and
!> the right-hand side, the driver wires the integrator; the physics never knows which
!> integrator runs it).
module rd_ode_system
  use rd_kinds, only: wp
  use rd_error, only: error_t
  implicit none
  private
  public :: ode_system_t

  type, abstract :: ode_system_t
  contains
    procedure(rhs_i), deferred :: rhs
    procedure(size_i), deferred :: state_size
  end type ode_system_t

  abstract interface
    !> Evaluate ydot = f(t, y). On failure allocate `error`, recoverable when a smaller
    !> step may succeed (rd_error's policy: retry_error, nonfinite_error).
    subroutine rhs_i(self, t, y, ydot, error)
      import :: ode_system_t, wp, error_t
      class(ode_system_t), intent(inout) :: self
      real(wp), intent(in) :: t
      real(wp), intent(in) :: y(:)
      real(wp), intent(out) :: ydot(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine rhs_i
    pure function size_i(self) result(n)
      import :: ode_system_t
      class(ode_system_t), intent(in) :: self
      integer :: n
    end function size_i
  end interface
end module rd_ode_system
