!> Integrator settings and statistics (the parameters an integrator is built from and
!> the counters it reports). See docs/theory_solver.md for the meaning of each field.
module rd_integrator_settings
  use rd_text, only: sci_text, lower_case
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: integrator_settings_t, integrator_stats_t, validate_settings, method_id_from_name
  public :: METHOD_BDF, METHOD_ADAMS, METHOD_ERK, METHOD_RK4, METHOD_HEUN, method_names

  !> Method identifiers. The SUNDIALS ones equal the ids the C glue expects.
  integer, parameter :: METHOD_BDF = 1    !< CVODE BDF, Newton + dense LAPACK
  integer, parameter :: METHOD_ADAMS = 2  !< CVODE Adams-Moulton, fixed-point iteration
  integer, parameter :: METHOD_ERK = 3    !< ARKODE ERKStep, Dormand-Prince 5(4)
  integer, parameter :: METHOD_RK4 = 4    !< classical Runge-Kutta, fixed step
  integer, parameter :: METHOD_HEUN = 5   !< Heun (explicit trapezoid), fixed step
  character(len=*), parameter :: method_names = "'bdf', 'adams', 'erk', 'rk4' or 'heun'"

  type :: integrator_settings_t
    character(len=16) :: method = 'bdf'   !< 'bdf' | 'adams' | 'erk' | 'rk4' | 'heun'
    real(wp) :: rtol = 1.0e-6_wp          !< relative tolerance [-]
    real(wp) :: atol = 1.0e-8_wp          !< absolute tolerance, all components [state units]
    !> Per-component absolute tolerances (size = state size); replaces `atol` if allocated.
    real(wp), allocatable :: atol_vector(:)
    real(wp) :: max_step = 0.0_wp         !< largest step [s]; 0 = unlimited
    real(wp) :: min_step = 0.0_wp         !< smallest step [s]; 0 = no bound
    real(wp) :: initial_step = 0.0_wp     !< first step [s]; 0 = estimated by SUNDIALS
    integer :: max_num_steps = 100000     !< steps allowed in one advance call
    real(wp) :: fixed_step = 0.0_wp       !< step of 'rk4'/'heun' [s] (required > 0 there)
    integer :: max_order = 0              !< cap on the BDF (<= 5) or Adams (<= 12) order; 0 = default
    !> most BDF steps between two Jacobian evaluations (CVODE's msbj; its default 51)
    integer :: jacobian_max_age = 51
  end type integrator_settings_t

  !> Counters, cumulative since `build` (reinit does not reset them).
  type :: integrator_stats_t
    integer(i8) :: steps = 0                   !< accepted steps
    integer(i8) :: rhs_evals = 0               !< RHS calls by the method itself
    integer(i8) :: rhs_evals_jacobian = 0      !< RHS calls for difference-quotient Jacobians
    integer(i8) :: jacobian_evals = 0          !< Jacobian evaluations (DQ or analytic)
    integer(i8) :: linear_setups = 0           !< Newton matrix factorizations (LU)
    integer(i8) :: error_test_failures = 0     !< steps rejected by the local error test
    integer(i8) :: nonlinear_conv_failures = 0 !< Newton / fixed-point convergence failures
    integer(i8) :: reinits = 0                 !< calls to reinit
    !> steps redone after a recoverable RHS failure by raildyn itself, where the engine has
    !> no retry: ERKStep restarted with a quarter step, a fixed step redone in substeps
    !> (CVODE's own retries are among its Newton failures)
    integer(i8) :: rhs_retries = 0
    real(wp) :: last_step = 0.0_wp             !< size of the last accepted step [s]
    real(wp) :: next_step = 0.0_wp             !< step size to be tried next [s]
    integer :: current_order = 0               !< order used on the last step
  end type integrator_stats_t

contains

  !> Map a method name (case-insensitive, blanks ignored) to its id; 0 if unknown.
  pure function method_id_from_name(name) result(id)
    character(len=*), intent(in) :: name
    integer :: id
    select case (lower_case(trim(adjustl(name))))
    case ('bdf'); id = METHOD_BDF
    case ('adams'); id = METHOD_ADAMS
    case ('erk'); id = METHOD_ERK
    case ('rk4'); id = METHOD_RK4
    case ('heun'); id = METHOD_HEUN
    case default; id = 0
    end select
  end function method_id_from_name

  !> Check the settings for a state of size n; one clear message per problem (the first).
  subroutine validate_settings(settings, n, error)
    type(integrator_settings_t), intent(in) :: settings
    integer, intent(in) :: n
    type(error_t), allocatable, intent(out) :: error
    integer :: id
    character(len=32) :: buf

    id = method_id_from_name(settings%method)
    call require(id /= 0, "method = '" // trim(settings%method) // "' is unknown; expected " // method_names)
    call require(settings%rtol >= 0.0_wp .and. settings%rtol < 1.0_wp, 'rtol = ' // &
                 trim(sci_text(settings%rtol, 4)) // ' is invalid; expected 0 <= rtol < 1 (e.g. 1e-6)')
    if (allocated(settings%atol_vector)) then
      write (buf, '(i0, " /= ", i0)') size(settings%atol_vector), n
      call require(size(settings%atol_vector) == n, 'atol_vector has the wrong size (' // &
                   trim(buf) // '); expected one tolerance per state component')
      call require(all(settings%atol_vector >= 0.0_wp), 'atol_vector has a negative or NaN entry; ' // &
                   'expected absolute tolerances >= 0')
      call require(.not. (settings%rtol <= 0.0_wp .and. any(settings%atol_vector <= 0.0_wp)), &
                   'rtol = 0 with a zero entry in atol_vector; expected at least one positive tolerance per component')
    else
      call require(settings%atol >= 0.0_wp, 'atol = ' // trim(sci_text(settings%atol, 4)) // &
                   ' is invalid; expected atol >= 0 (e.g. 1e-8)')
      call require(.not. (settings%rtol <= 0.0_wp .and. settings%atol <= 0.0_wp), 'rtol and atol are both zero; ' // &
                   'expected at least one positive tolerance')
    end if
    call require(settings%max_step >= 0.0_wp, 'max_step = ' // trim(sci_text(settings%max_step, 4)) // &
                 ' is invalid; expected max_step >= 0 s (0 = unlimited)')
    call require(settings%min_step >= 0.0_wp, 'min_step = ' // trim(sci_text(settings%min_step, 4)) // &
                 ' is invalid; expected min_step >= 0 s')
    call require(.not. (settings%max_step > 0.0_wp .and. settings%min_step > settings%max_step), &
                 'min_step > max_step; expected min_step <= max_step')
    call require(settings%initial_step >= 0.0_wp, 'initial_step = ' // trim(sci_text(settings%initial_step, 4)) // &
                 ' is invalid; expected initial_step >= 0 s (0 = automatic)')
    call require(settings%max_num_steps > 0, 'max_num_steps must be a positive integer ' // &
                 '(steps allowed per advance, e.g. 100000)')
    select case (id)
    case (METHOD_BDF)
      call require(settings%max_order >= 0 .and. settings%max_order <= 5, &
                   "max_order is invalid for method 'bdf'; expected 1..5 (0 = default 5)")
      call require(settings%jacobian_max_age >= 1, 'jacobian_max_age must be a positive integer ' // &
                   '(steps between Jacobian evaluations, default 51)')
    case (METHOD_ADAMS)
      call require(settings%max_order >= 0 .and. settings%max_order <= 12, &
                   "max_order is invalid for method 'adams'; expected 1..12 (0 = default 12)")
    case (METHOD_RK4, METHOD_HEUN)
      call require(settings%fixed_step > 0.0_wp .and. settings%fixed_step < huge(1.0_wp), 'fixed_step = ' // &
                   trim(sci_text(settings%fixed_step, 4)) // " is invalid for method '" // &
                   trim(adjustl(settings%method)) // "'; expected a step size > 0 s")
    end select
  contains
    !> The first failed requirement is the error.
    subroutine require(ok, message)
      logical, intent(in) :: ok
      character(len=*), intent(in) :: message
      if (.not. ok .and. .not. allocated(error)) call make_error(error, RD_ERR_INPUT, message)
    end subroutine require
  end subroutine validate_settings

end module rd_integrator_settings
