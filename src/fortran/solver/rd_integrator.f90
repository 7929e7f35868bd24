!> Time integrators for y' = f(t, y) of any `ode_system_t` (rd_ode_system):
!>
!> | method  | engine                         | use                                          |
!> |---------|--------------------------------|----------------------------------------------|
!> | 'bdf'   | CVODE BDF 1-5, modified Newton, dense LU by LAPACK (custom SUNLinearSolver) | stiff (default) |
!>
!> The BDF Newton matrix uses CVODE's dense difference-quotient Jacobian (one RHS call per
!> state), an analytic `jacobian`, or coloured difference quotients from a
!> `jacobian_sparsity` (rd_coloured_jacobian: one RHS call per column group, same
!> increments as CVODE's).
!> | 'adams' | CVODE Adams-Moulton 1-12, fixed-point (functional) iteration | smooth, non-stiff |
!> | 'erk'   | ARKODE ERKStep, Dormand-Prince 5(4) | non-stiff, cheap steps                 |
!> | 'rk4'   | classical Runge-Kutta, fixed step (Fortran) | deterministic, real-time style   |
!> | 'heun'  | explicit trapezoid, fixed step (Fortran)    | cheap, low accuracy              |
!>
!> Shape (OpenFAST-like): `build` fixes the parameters, `advance` integrates to exactly
!> the requested output time (never beyond: SUNDIALS runs with a stop time at t_out, so
!> stepping in chunks equals one long run within the tolerance), `reinit` restarts after a
!> discontinuity, `get_stats` reports counters, `destroy` frees everything. Each integrator
!> owns its SUNDIALS context and its rhs_context_t: no module-global state.
!>
!> The system passed to `build` must have the TARGET attribute (or be a pointer) and must
!> outlive the integrator. Do not copy an initialised integrator_t (the copy would share
!> the SUNDIALS memory); pass it by reference.
module rd_integrator
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_loc, c_int, &
                                         c_long, c_int64_t, c_double, c_char
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_text, only: int_text, sci_text
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME, &
                      RD_ERR_HANDLE
  use rd_ode_system, only: ode_system_t
  use rd_integrator_settings, only: integrator_settings_t, integrator_stats_t, &
                                    validate_settings, method_id_from_name, METHOD_BDF, &
                                    METHOD_ADAMS, METHOD_ERK, METHOD_RK4, METHOD_HEUN
  use rd_rhs_context, only: rhs_context_t, jacobian_i, RHS_OK, RHS_RECOVERABLE
  use rd_coloured_jacobian, only: jacobian_sparsity_t
  use rd_fixed_step, only: fixed_step_work_t, rk4_step, heun_step
  use rd_sundials_glue, only: rd_glue_create, rd_glue_destroy, rd_glue_set_tolerances, &
                              rd_glue_set_limits, rd_glue_use_jacobian, rd_glue_set_jacobian_age, rd_glue_advance, &
                              rd_glue_reinit, rd_glue_get_stats, rd_glue_flag_name, &
                              rd_glue_last_message, c_string_to_fortran
  implicit none
  private
  public :: integrator_t, integrator_settings_t, integrator_stats_t, jacobian_i, jacobian_sparsity_t

  integer, parameter :: msg_len = 1024
  !> a fixed step whose RHS fails recoverably is redone in at most this many substeps
  integer, parameter :: max_substeps = 64

  !> SUNDIALS return flags (identical in CVODE and ARKODE) meaning "the RHS failed".
  integer, parameter :: flag_rhsfunc_fail = -8, flag_first_rhsfunc_err = -9, &
                        flag_reptd_rhsfunc_err = -10, flag_unrec_rhsfunc_err = -11, &
                        flag_lsetup_fail = -6

  type :: integrator_t
    private
    integer :: method = 0                         !< METHOD_* id; 0 = not initialised
    type(integrator_settings_t) :: settings
    integer :: n = 0                              !< state size
    real(wp) :: t = 0.0_wp                        !< time of the state in y [s]
    real(wp), allocatable :: y(:)                 !< state at t
    type(rhs_context_t), pointer :: context => null()  !< system + last RHS failure (stable address for C)
    type(c_ptr) :: glue = c_null_ptr              !< SUNDIALS handle (bdf, adams, erk)
    type(fixed_step_work_t) :: work               !< stage arrays (rk4, heun)
    type(integrator_stats_t) :: fixed_stats       !< counters of the fixed-step methods
    type(integrator_stats_t) :: before_reinit     !< SUNDIALS counters summed over earlier reinits
    integer(i8) :: reinits = 0
    !> Set when an advance failed: the engine's internal state may differ from y, so the
    !> caller must reinit (from the returned y or another state) before advancing again.
    logical :: failed = .false.
  contains
    procedure :: build
    procedure :: advance
    procedure :: reinit
    procedure :: get_stats
    procedure :: destroy
    procedure :: time => current_time
    procedure :: method_name
    procedure :: is_initialized
    procedure, private :: advance_fixed
    procedure, private :: fixed_step_with_retry
    procedure, private :: report_sundials_failure
    procedure, private :: sundials_text
    procedure, private :: engine_stats
  end type integrator_t

contains

  !> Build the integrator for `system` from (t0, y0). `jacobian` (optional, method 'bdf'
  !> only, ignored by the others) replaces CVODE's difference-quotient Jacobian;
  !> `jacobian_sparsity` (same) replaces it by coloured difference quotients (one RHS call
  !> per column group). At most one of the two.
  subroutine build(self, system, t0, y0, settings, error, jacobian, jacobian_sparsity)
    class(integrator_t), intent(inout) :: self
    class(ode_system_t), target, intent(inout) :: system
    real(wp), intent(in) :: t0
    real(wp), intent(in) :: y0(:)
    type(integrator_settings_t), intent(in) :: settings
    type(error_t), allocatable, intent(out) :: error
    procedure(jacobian_i), optional :: jacobian
    type(jacobian_sparsity_t), intent(in), optional :: jacobian_sparsity

    character(kind=c_char) :: cmsg(msg_len)
    real(c_double), allocatable, target :: atol_copy(:)
    type(c_ptr) :: atol_ptr
    integer(c_int) :: flag

    call self%destroy()
    self%n = system%state_size()
    if (self%n <= 0) then
      call make_error(error, RD_ERR_INPUT, 'the system has no state (state_size() <= 0); ' // &
                      'expected at least one state variable')
      call error_context(error, 'integrator build')
      return
    end if
    if (size(y0) /= self%n) then
      call make_error(error, RD_ERR_INPUT, 'y0 has ' // trim(int_text(size(y0))) // ' components but ' // &
                      'the system has ' // trim(int_text(self%n)) // '; expected one value per state')
      call error_context(error, 'integrator build')
      return
    end if
    if (.not. ieee_is_finite(t0) .or. .not. all(ieee_is_finite(y0))) then
      call make_error(error, RD_ERR_INPUT, 't0 or y0 is not finite (NaN or Inf); ' // &
                      'expected a finite initial state')
      call error_context(error, 'integrator build')
      return
    end if
    call validate_settings(settings, self%n, error)
    if (allocated(error)) then
      call error_context(error, 'integrator build')
      return
    end if
    if (present(jacobian) .and. present(jacobian_sparsity)) then
      call make_error(error, RD_ERR_INPUT, 'both an analytic jacobian and a jacobian_sparsity ' // &
                      'were given; expected at most one')
      call error_context(error, 'integrator build')
      return
    end if
    if (present(jacobian_sparsity)) then
      if (jacobian_sparsity%n /= self%n) then
        call make_error(error, RD_ERR_INPUT, 'jacobian_sparsity is for ' // trim(int_text(jacobian_sparsity%n)) // &
                        ' states but the system has ' // trim(int_text(self%n)) // '; expected one column per state')
        call error_context(error, 'integrator build')
        return
      end if
    end if

    self%settings = settings
    self%method = method_id_from_name(settings%method)
    self%t = t0
    self%y = y0
    allocate (self%context)
    self%context%system => system
    if (present(jacobian)) self%context%jacobian => jacobian
    if (present(jacobian_sparsity) .and. self%method == METHOD_BDF) &
      allocate (self%context%sparsity, source=jacobian_sparsity)

    select case (self%method)
    case (METHOD_BDF, METHOD_ADAMS, METHOD_ERK)
      self%glue = rd_glue_create(int(self%method, c_int), int(self%n, c_int64_t), t0, y0, &
                                 c_loc(self%context), cmsg, int(msg_len, c_int))
      if (.not. c_associated(self%glue)) then
        call make_error(error, RD_ERR_RUNTIME, self%method_name() // ': ' // &
                        c_string_to_fortran(cmsg))
      end if
      if (.not. allocated(error)) then
        atol_ptr = c_null_ptr
        if (allocated(settings%atol_vector)) then
          atol_copy = settings%atol_vector
          atol_ptr = c_loc(atol_copy)
        end if
        flag = rd_glue_set_tolerances(self%glue, settings%rtol, settings%atol, atol_ptr)
        if (flag == 0) flag = rd_glue_set_limits(self%glue, settings%max_step, &
                                                 settings%min_step, settings%initial_step, &
                                                 int(settings%max_num_steps, c_long), &
                                                 int(settings%max_order, c_int))
        if (flag == 0 .and. (present(jacobian) .or. present(jacobian_sparsity)) .and. &
            self%method == METHOD_BDF) flag = rd_glue_use_jacobian(self%glue)
        if (flag == 0 .and. self%method == METHOD_BDF) &
          flag = rd_glue_set_jacobian_age(self%glue, int(settings%jacobian_max_age, c_long))
        if (flag /= 0) call make_error(error, RD_ERR_RUNTIME, self%method_name() // &
                                       ': ' // self%sundials_text(int(flag)))
      end if
    case (METHOD_RK4, METHOD_HEUN)
      call self%work%allocate_work(self%n)
    end select
    if (allocated(error)) then
      call self%destroy()
      call error_context(error, 'integrator build')
    end if
  end subroutine build

  !> Integrate from the current time to exactly t_out (>= current time) and return the
  !> state there. On failure `error` names the method, the time reached, the last step
  !> size, the SUNDIALS flag and message, and the RHS's own message if it failed; y then
  !> holds the last valid state (at time()), never a non-finite one, and the integrator
  !> refuses to advance until `reinit` is called.
  !> t_stop (>= t_out, default t_out): the adaptive methods may step as far as t_stop and
  !> return their interpolant at t_out, so that samples between two stops cost no steps and
  !> do not change the step sequence (rd_scene's interval means). Nothing that the RHS
  !> depends on may change before t_stop (inputs set between advances need t_stop = t_out).
  !> The fixed-step methods land on t_out whatever t_stop is.
  subroutine advance(self, t_out, y, error, t_stop)
    class(integrator_t), intent(inout) :: self
    real(wp), intent(in) :: t_out
    real(wp), intent(inout) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: t_stop

    real(c_double) :: t_reached, t_limit
    integer(c_int) :: flag, valid
    integer :: bad
    real(wp) :: y_before(self%n)

    if (self%method == 0) then
      call make_error(error, RD_ERR_HANDLE, 'integrator used before build')
      return
    end if
    if (self%failed) then
      call make_error(error, RD_ERR_HANDLE, self%method_name() // ': the previous advance ' // &
                      'failed; call reinit(t, y) before advancing again')
      return
    end if
    if (size(y) /= self%n) then
      call make_error(error, RD_ERR_INPUT, 'advance: y has ' // trim(int_text(size(y))) // &
                      ' components; expected ' // trim(int_text(self%n)))
      return
    end if
    if (.not. ieee_is_finite(t_out) .or. t_out < self%t) then
      call make_error(error, RD_ERR_INPUT, 'advance: t_out = ' // trim(sci_text(t_out, 8)) // &
                      ' s is not a finite time >= the current time ' // trim(sci_text(self%t, 8)) // ' s')
      return
    end if
    t_limit = t_out
    if (present(t_stop)) then
      if (.not. (t_stop >= t_out)) then
        call make_error(error, RD_ERR_INPUT, 'advance: t_stop = ' // trim(sci_text(t_stop, 8)) // &
                        ' s is not a time >= t_out = ' // trim(sci_text(t_out, 8)) // ' s')
        return
      end if
      t_limit = t_stop
    end if
    ! An interval below the time resolution: nothing to integrate (SUNDIALS would refuse
    ! it as CV_TOO_CLOSE).
    if (t_out - self%t <= 4.0_wp * epsilon(1.0_wp) * max(abs(self%t), abs(t_out))) then
      y = self%y
      return
    end if
    if (allocated(self%context%rhs_error)) deallocate (self%context%rhs_error)
    self%context%fatal = .false.

    select case (self%method)
    case (METHOD_RK4, METHOD_HEUN)
      call self%advance_fixed(t_out, error)
      if (allocated(error)) then
        self%failed = .true.
        y = self%y
        return
      end if
    case default
      y_before = self%y
      flag = rd_glue_advance(self%glue, t_out, t_limit, self%y, t_reached, valid)
      if (flag < 0) then
        ! Return the state at the last time SUNDIALS reached if it is known and finite,
        ! else keep the state of the previous output.
        if (valid /= 0 .and. first_non_finite(self%y) == 0) then
          self%t = t_reached
        else
          self%y = y_before
        end if
        call self%report_sundials_failure(int(flag), t_out, self%t, error)
        self%failed = .true.
        y = self%y
        return
      end if
      self%t = t_out
    end select

    bad = first_non_finite(self%y)
    if (bad /= 0) then
      call make_error(error, RD_ERR_RUNTIME, self%method_name() // ': the state became ' // &
                      'non-finite (NaN or Inf) in component ' // trim(int_text(bad)) // ' by t = ' // &
                      trim(sci_text(self%t, 8)) // ' s; output not written')
      self%failed = .true.
      return
    end if
    y = self%y
  end subroutine advance

  !> Fixed-step loop: n = round(interval / fixed_step) steps when the interval is a whole
  !> number of steps, else the next larger n with the step shrunk to interval / n, so the
  !> run lands exactly on t_out with a deterministic number of RHS calls.
  subroutine advance_fixed(self, t_out, error)
    class(integrator_t), intent(inout) :: self
    real(wp), intent(in) :: t_out
    type(error_t), allocatable, intent(out) :: error

    real(wp) :: t_start, interval, ratio, h, t_step
    integer(i8) :: nsteps, i
    integer :: status

    t_start = self%t
    interval = t_out - t_start
    ratio = interval / self%settings%fixed_step
    if (ratio > real(self%settings%max_num_steps, wp) + 0.5_wp) then
      call make_error(error, RD_ERR_RUNTIME, self%method_name() // ': advancing from t = ' // &
                      trim(sci_text(t_start, 8)) // ' s to ' // trim(sci_text(t_out, 8)) // ' s needs ' // &
                      trim(sci_text(ratio, 8)) // ' steps of ' // trim(sci_text(self%settings%fixed_step, 8)) // &
                      ' s, more than max_num_steps = ' // trim(int_text(self%settings%max_num_steps)))
      return
    end if
    if (abs(ratio - anint(ratio)) <= 1.0e-9_wp * max(1.0_wp, ratio)) then
      nsteps = max(1_i8, nint(ratio, i8))
    else
      nsteps = ceiling(ratio, i8)
    end if
    h = interval / real(nsteps, wp)
    do i = 1, nsteps
      ! Step times from the interval start (no accumulated round-off); the last lands on t_out.
      t_step = t_start + real(i - 1, wp) * h
      call self%fixed_step_with_retry(t_step, h, status)
      if (status /= RHS_OK) then
        self%t = t_step
        if (allocated(self%context%rhs_error)) then
          call move_alloc(self%context%rhs_error, error)
        else
          call make_error(error, RD_ERR_RUNTIME, 'rhs failed without a message')
        end if
        if (status == RHS_RECOVERABLE) call error_context(error, &
          'the step failed in ' // trim(int_text(max_substeps)) // ' substeps too')
        call error_context(error, self%method_name() // ' failed advancing to ' // &
                           trim(sci_text(t_out, 8)) // ' s (time reached ' // trim(sci_text(t_step, 8)) // &
                           ' s, step h = ' // trim(sci_text(h, 8)) // ' s)')
        return
      end if
      self%fixed_stats%steps = self%fixed_stats%steps + 1
      self%fixed_stats%last_step = h
    end do
    self%t = t_out
  end subroutine advance_fixed

  !> One fixed step from (t, y). A recoverable RHS failure (rd_error's retry errors, e.g. the
  !> quasi-static contact solve did not converge at a stage's state) redoes the step from its
  !> start in 2, 4, ... max_substeps equal substeps, what an adaptive method does with a
  !> smaller step; the step still ends at t + h, so the run keeps its fixed grid and output
  !> times, and only such a step costs more RHS calls (counted in rhs_retries).
  subroutine fixed_step_with_retry(self, t, h, status)
    class(integrator_t), intent(inout) :: self
    real(wp), intent(in) :: t, h
    integer, intent(out) :: status
    integer :: parts, j
    self%work%ystart = self%y
    parts = 1
    do
      do j = 1, parts
        if (self%method == METHOD_RK4) then
          call rk4_step(self%context, t + real(j - 1, wp) * (h / parts), h / parts, self%y, self%work, status)
          self%fixed_stats%rhs_evals = self%fixed_stats%rhs_evals + merge(4, 0, status == RHS_OK)
        else
          call heun_step(self%context, t + real(j - 1, wp) * (h / parts), h / parts, self%y, self%work, status)
          self%fixed_stats%rhs_evals = self%fixed_stats%rhs_evals + merge(2, 0, status == RHS_OK)
        end if
        if (status /= RHS_OK) exit
      end do
      if (status /= RHS_RECOVERABLE .or. parts >= max_substeps) return
      self%y = self%work%ystart
      parts = 2 * parts
      self%fixed_stats%rhs_retries = self%fixed_stats%rhs_retries + 1
    end do
  end subroutine fixed_step_with_retry

  !> Build the failure message of a SUNDIALS advance.
  subroutine report_sundials_failure(self, flag, t_out, t_reached, error)
    class(integrator_t), intent(inout) :: self
    integer, intent(in) :: flag
    real(wp), intent(in) :: t_out, t_reached
    type(error_t), allocatable, intent(out) :: error
    type(integrator_stats_t) :: stats
    character(len=:), allocatable :: text
    integer :: code
    logical :: rhs_flag

    call self%get_stats(stats)
    text = self%method_name() // ' failed advancing to ' // trim(sci_text(t_out, 8)) // &
           ' s (time reached ' // trim(sci_text(t_reached, 8)) // ' s, last step h = ' // &
           trim(sci_text(stats%last_step, 8)) // ' s): ' // self%sundials_text(flag)
    code = RD_ERR_RUNTIME
    rhs_flag = any(flag == [flag_rhsfunc_fail, flag_first_rhsfunc_err, flag_reptd_rhsfunc_err, &
                            flag_unrec_rhsfunc_err, flag_lsetup_fail])
    if (allocated(self%context%rhs_error)) then
      if (rhs_flag .or. self%context%fatal) then
        text = text // '; ' // self%context%rhs_error%message
        code = self%context%rhs_error%code    ! keep e.g. a physics-limit code from the model
      else
        text = text // '; earlier recoverable failure: ' // self%context%rhs_error%message
      end if
    end if
    call make_error(error, code, text)
  end subroutine report_sundials_failure

  !> "CV_TOO_MUCH_WORK (flag -1): <SUNDIALS' message>".
  function sundials_text(self, flag) result(text)
    class(integrator_t), intent(in) :: self
    integer, intent(in) :: flag
    character(len=:), allocatable :: text
    character(kind=c_char) :: buf(msg_len)
    character(len=:), allocatable :: detail

    call rd_glue_flag_name(self%glue, int(flag, c_int), buf, int(msg_len, c_int))
    text = c_string_to_fortran(buf) // ' (flag ' // trim(int_text(flag)) // ')'
    call rd_glue_last_message(self%glue, buf, int(msg_len, c_int))
    detail = c_string_to_fortran(buf)
    if (len(detail) > 0) text = text // ': ' // detail
  end function sundials_text

  !> Restart from (t, y) after a discontinuity (e.g. a change of speed or of a parameter):
  !> the multistep history is discarded and the step size re-estimated. Settings are kept;
  !> statistics keep accumulating.
  subroutine reinit(self, t, y, error)
    class(integrator_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    type(integrator_stats_t) :: stats
    integer(c_int) :: flag

    if (self%method == 0) then
      call make_error(error, RD_ERR_HANDLE, 'integrator reinit before build')
      return
    end if
    if (size(y) /= self%n) then
      call make_error(error, RD_ERR_INPUT, 'reinit: y has ' // trim(int_text(size(y))) // &
                      ' components; expected ' // trim(int_text(self%n)))
      return
    end if
    if (.not. ieee_is_finite(t) .or. .not. all(ieee_is_finite(y))) then
      call make_error(error, RD_ERR_INPUT, 'reinit: t or y is not finite (NaN or Inf); ' // &
                      'expected a finite state')
      return
    end if
    if (c_associated(self%glue)) then
      ! SUNDIALS resets its counters on reinit: bank them first.
      call self%engine_stats(stats)
      self%before_reinit = stats
      flag = rd_glue_reinit(self%glue, t, y)
      if (flag /= 0) then
        call make_error(error, RD_ERR_RUNTIME, self%method_name() // ' reinit: ' // &
                        self%sundials_text(int(flag)))
        return
      end if
    end if
    self%t = t
    self%y = y
    self%context%fatal = .false.
    self%failed = .false.
    self%reinits = self%reinits + 1
  end subroutine reinit

  !> Counters cumulative since build (see integrator_stats_t). The RHS calls of coloured
  !> Jacobians are counted by the context (CVODE only counts its own difference quotients).
  subroutine get_stats(self, stats)
    class(integrator_t), intent(in) :: self
    type(integrator_stats_t), intent(out) :: stats
    call self%engine_stats(stats)
    if (associated(self%context)) &
      stats%rhs_evals_jacobian = stats%rhs_evals_jacobian + self%context%rhs_evals_jacobian
  end subroutine get_stats

  !> The engine's counters (SUNDIALS' summed over reinits, or the fixed-step loop's).
  subroutine engine_stats(self, stats)
    class(integrator_t), intent(in) :: self
    type(integrator_stats_t), intent(out) :: stats
    integer(c_long) :: counts(9)
    real(c_double) :: reals(3)
    integer(c_int) :: flag

    if (c_associated(self%glue)) then
      flag = rd_glue_get_stats(self%glue, counts, reals)
      stats%steps = self%before_reinit%steps + counts(1)
      stats%rhs_evals = self%before_reinit%rhs_evals + counts(2)
      stats%rhs_evals_jacobian = self%before_reinit%rhs_evals_jacobian + counts(3)
      stats%jacobian_evals = self%before_reinit%jacobian_evals + counts(4)
      stats%linear_setups = self%before_reinit%linear_setups + counts(5)
      stats%error_test_failures = self%before_reinit%error_test_failures + counts(6)
      stats%nonlinear_conv_failures = self%before_reinit%nonlinear_conv_failures + counts(7)
      stats%current_order = int(counts(8))
      stats%rhs_retries = self%before_reinit%rhs_retries + counts(9)
      stats%last_step = reals(1)
      stats%next_step = reals(2)
    else
      stats = self%fixed_stats
      if (self%method == METHOD_RK4) stats%current_order = 4
      if (self%method == METHOD_HEUN) stats%current_order = 2
      stats%next_step = self%settings%fixed_step
    end if
    stats%reinits = self%reinits
  end subroutine engine_stats

  !> Free the SUNDIALS memory and work arrays; the integrator can be built again.
  subroutine destroy(self)
    class(integrator_t), intent(inout) :: self
    if (c_associated(self%glue)) call rd_glue_destroy(self%glue)
    self%glue = c_null_ptr
    if (associated(self%context)) deallocate (self%context)
    self%context => null()
    if (allocated(self%y)) deallocate (self%y)
    self%method = 0
    self%n = 0
    self%t = 0.0_wp
    self%reinits = 0
    self%failed = .false.
    self%fixed_stats = integrator_stats_t()
    self%before_reinit = integrator_stats_t()
  end subroutine destroy

  !> Time of the current state [s].
  pure function current_time(self) result(t)
    class(integrator_t), intent(in) :: self
    real(wp) :: t
    t = self%t
  end function current_time

  pure logical function is_initialized(self)
    class(integrator_t), intent(in) :: self
    is_initialized = self%method /= 0
  end function is_initialized

  !> Human-readable name of the method, used in every message.
  pure function method_name(self) result(name)
    class(integrator_t), intent(in) :: self
    character(len=:), allocatable :: name
    select case (self%method)
    case (METHOD_BDF); name = "integrator 'bdf' (CVODE BDF)"
    case (METHOD_ADAMS); name = "integrator 'adams' (CVODE Adams-Moulton)"
    case (METHOD_ERK); name = "integrator 'erk' (ARKODE ERKStep Dormand-Prince 5(4))"
    case (METHOD_RK4); name = "integrator 'rk4' (fixed-step Runge-Kutta 4)"
    case (METHOD_HEUN); name = "integrator 'heun' (fixed-step Heun)"
    case default; name = 'integrator (not initialised)'
    end select
  end function method_name

  pure integer function first_non_finite(v) result(idx)
    real(wp), intent(in) :: v(:)
    integer :: i
    idx = 0
    do i = 1, size(v)
      if (.not. ieee_is_finite(v(i))) then
        idx = i
        return
      end if
    end do
  end function first_non_finite
end module rd_integrator
