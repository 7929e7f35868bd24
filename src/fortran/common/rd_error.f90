!> Error objects that travel up to the runner and the C API (fpm style).
!>
!> A routine that can fail takes `type(error_t), allocatable, intent(out) :: error`.
!> "Not allocated" means success; callers write `if (allocated(error)) return`
!> and may prepend their own context with `error_context`, so a failure deep
!> inside reads like a one-line traceback. Library code never calls `stop`.
module rd_error
  implicit none
  private
  public :: error_t, make_error, error_context
  public :: RD_OK, RD_ERR_INPUT, RD_ERR_RUNTIME, RD_ERR_PHYSICS, RD_ERR_IO, &
            RD_ERR_INTERNAL, RD_ERR_HANDLE, status_name

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

  pure function status_name(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    select case (code)
    case (RD_OK); name = 'ok'
    case (RD_ERR_INPUT); name = 'input error'
    case (RD_ERR_RUNTIME); name = 'runtime error'
    case (RD_ERR_PHYSICS); name = 'physics limit'
    case (RD_ERR_IO); name = 'i/o error'
    case (RD_ERR_HANDLE); name = 'invalid handle or call order'
    case default; name = 'internal error'
    end select
  end function status_name
end module rd_error
