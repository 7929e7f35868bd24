!> Error objects that travel up to the runner and the C API (fpm style).
!>
!> A routine that can fail takes `type(error_t), allocatable, intent(out) :: error`.
!> "Not allocated" means success; callers write `if (allocated(error)) return`
!> and may prepend their own context with `error_context`, so a failure deep
!> inside reads like a one-line traceback. Library code never calls `stop`.
!>
!> The failure policy (docs/output.md "Killed and failed runs"): only `retry_error` and
!> `nonfinite_error` make an error recoverable (an integrator retries a smaller step; fatal
!> when it gives up); every other error is fatal. A run ending on an error records
!> `run_status(error)`; its code is the C API's status and the runner's exit status.
module rd_error
  use rd_kinds, only: wp
  implicit none
  private
  public :: error_t, make_error, error_context, retry_error, nonfinite_error, run_status
  public :: RD_OK, RD_ERR_INPUT, RD_ERR_RUNTIME, RD_ERR_PHYSICS, RD_ERR_IO, &
            RD_ERR_INTERNAL, RD_ERR_HANDLE, finite

  !> Status codes shared with the C API (src/c_api/raildyn.h must match).
  integer, parameter :: RD_OK = 0
  integer, parameter :: RD_ERR_INPUT = 1     !< bad deck, profile file or argument
  integer, parameter :: RD_ERR_RUNTIME = 2   !< integrator failure, NaN in the state
  integer, parameter :: RD_ERR_PHYSICS = 3   !< derailment, wheel lift-off beyond limits
  integer, parameter :: RD_ERR_IO = 4        !< cannot read or write a file
  integer, parameter :: RD_ERR_INTERNAL = 5  !< a bug: an invariant of the code broke
  integer, parameter :: RD_ERR_HANDLE = 6    !< invalid C API handle or call order

  type :: error_t
    integer :: code = RD_ERR_INTERNAL
    character(len=:), allocatable :: message
    logical :: recoverable = .false.   !< a smaller step may succeed (set by retry_error only)
  end type error_t

contains

  !> Allocate `error` with a status code and a message.
  pure subroutine make_error(error, code, message)
    type(error_t), allocatable, intent(out) :: error
    integer, intent(in) :: code
    character(len=*), intent(in) :: message
    allocate (error)
    error%code = code
    error%message = message
  end subroutine make_error

  !> Prepend context ("routine: " or "file:line: ") to an existing error.
  pure subroutine error_context(error, context)
    type(error_t), allocatable, intent(inout) :: error
    character(len=*), intent(in) :: context
    if (.not. allocated(error)) return
    error%message = context // ': ' // error%message
  end subroutine error_context

  !> A runtime error that a smaller integrator step may avoid (recoverable).
  pure subroutine retry_error(error, message)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in) :: message
    call make_error(error, RD_ERR_RUNTIME, message)
    error%recoverable = .true.
  end subroutine retry_error

  !> If `values` holds a NaN or Inf: a recoverable error naming `what` (a trial state too
  !> far off gives one; the integrator retries with a smaller step). The caller's context
  !> says when.
  pure subroutine nonfinite_error(error, values, what)
    type(error_t), allocatable, intent(inout) :: error
    real(wp), intent(in) :: values(:)
    character(len=*), intent(in) :: what
    if (.not. all(finite(values))) call retry_error(error, 'non-finite ' // what // ' (NaN or Inf)')
  end subroutine nonfinite_error

  !> What the results file of a run records at its end (/meta status, docs/output.md).
  pure function run_status(error) result(status)
    type(error_t), allocatable, intent(in) :: error
    character(len=:), allocatable :: status
    status = 'completed'
    if (allocated(error)) status = 'failed: ' // error%message
  end function run_status


  !> Whether x is a number (not NaN, not infinite). Not ieee_is_finite, for the hot paths
  !> (contact): gfortran saves and restores the FP environment around procedures using
  !> ieee_arithmetic (~1 us per call). NaN is tested first with /= (quiet), so the ordered
  !> comparison never sees a NaN (Debug traps).
  elemental logical function finite(x)
    real(wp), intent(in) :: x
    if (x /= x) then
      finite = .false.
    else
      finite = abs(x) <= huge(x)
    end if
  end function finite
end module rd_error
