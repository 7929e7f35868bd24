!> Failures stop cleanly with a message that names the method, the time reached, the last
!> step and the SUNDIALS flag, and quotes the RHS's own message; NaN never reaches the
!> caller's state; bad settings are refused with one clear input error. Also checks that
!> max_step and per-component tolerances are honoured.
program test_solver_failures
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT, RD_ERR_RUNTIME, RD_ERR_PHYSICS, RD_ERR_HANDLE
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t
  use rd_solver_test_problems, only: oscillator_t, failing_t, report, FAIL_FATAL, &
                                     FAIL_NAN, FAIL_RECOVERABLE_ALWAYS, FAIL_RECOVERABLE_FEW
  use rd_test_support, only: check, test_summary
  implicit none

  character(len=8), parameter :: methods(4) = [character(len=8) :: 'bdf', 'adams', 'erk', 'rk4']
  character(len=8), parameter :: prefixes(4) = [character(len=8) :: 'CV_', 'CV_', 'ARK_', '']
  integer :: m

  do m = 1, size(methods)
    call fatal_rhs(trim(methods(m)), trim(prefixes(m)))
    call nan_rhs(trim(methods(m)))
    call recoverable_rhs(trim(methods(m)), trim(prefixes(m)))
    call too_many_steps(trim(methods(m)), trim(prefixes(m)))
  end do
  do m = 1, size(methods)
    call recovered_rhs(trim(methods(m)))
  end do
  call bad_input()
  call limits_and_vector_tolerances()
  call test_summary('test_solver_failures')

contains

  function settings_for(method) result(s)
    character(len=*), intent(in) :: method
    type(integrator_settings_t) :: s
    s%method = method
    s%fixed_step = 1.0e-3_wp
  end function settings_for

  subroutine expect(error, code, pieces, what)
    type(error_t), allocatable, intent(in) :: error
    integer, intent(in) :: code
    character(len=*), intent(in) :: pieces(:)
    character(len=*), intent(in) :: what
    integer :: i
    call check(allocated(error), what // ': no error reported')
    write (*, '(a)') what // ' -> ' // error%message
    call check(error%code == code, what // ': wrong error code')
    do i = 1, size(pieces)
      call check(index(error%message, trim(pieces(i))) > 0, what // ': message lacks "' // &
                 trim(pieces(i)) // '"')
    end do
  end subroutine expect

  subroutine fatal_rhs(method, prefix)
    character(len=*), intent(in) :: method, prefix
    type(failing_t), target :: system
    type(integrator_t) :: integ
    type(error_t), allocatable :: error
    real(wp) :: y(1)
    character(len=40) :: pieces(5)

    system%mode = FAIL_FATAL
    call integ%build(system, 0.0_wp, [1.0_wp], settings_for(method), error)
    call check(.not. allocated(error), method // ' build')
    y = -99.0_wp
    call integ%advance(2.0_wp, y, error)
    ! The model's own code (physics limit) travels through the integrator.
    pieces(1) = "'" // method // "'"
    pieces(2) = 'time reached'
    pieces(3) = 'wheelset 1 derailed (test message)'
    pieces(4) = 'rhs at t ='
    pieces(5) = prefix
    call expect(error, RD_ERR_PHYSICS, pieces, method // ' fatal rhs')
    call check(index(error%message, 'step h =') > 0, method // ': message lacks the step size')
    ! y holds the last valid state, on the exact solution at the time reached: the last
    ! accepted step before the failure (CVODE, rk4), or the previous output for ERK,
    ! whose state at the failure time cannot be interpolated after a failed RHS call.
    if (method == 'erk') then
      call check(integ%time() == 0.0_wp .or. (integ%time() > 0.3_wp .and. integ%time() < 0.7_wp), &
                 'erk: time reached is neither the previous output nor near the failure')
    else
      call check(integ%time() > 0.3_wp .and. integ%time() <= 0.5_wp, &
                 method // ': time reached not just before the failure')
    end if
    call check(abs(y(1) - exp(-integ%time())) < 1.0e-4_wp, method // ': y is not the last valid state')
    ! No silent continuation after a failure: reinit is required, then it runs on.
    call integ%advance(2.0_wp, y, error)
    call expect(error, RD_ERR_HANDLE, [character(len=40) :: 'call reinit'], method // ' advance after failure')
    system%mode = 0
    call integ%reinit(integ%time(), y, error)
    call check(.not. allocated(error), method // ' reinit after failure')
    call integ%advance(2.0_wp, y, error)
    call check(.not. allocated(error), method // ' advance after reinit')
    call check(abs(y(1) - exp(-2.0_wp)) < 1.0e-4_wp, method // ': wrong solution after reinit')
    call integ%destroy()
  end subroutine fatal_rhs

  subroutine nan_rhs(method)
    character(len=*), intent(in) :: method
    type(failing_t), target :: system
    type(integrator_t) :: integ
    type(error_t), allocatable :: error
    real(wp) :: y(1)

    system%mode = FAIL_NAN
    call integ%build(system, 0.0_wp, [1.0_wp], settings_for(method), error)
    call check(.not. allocated(error), method // ' build')
    call integ%advance(2.0_wp, y, error)
    call expect(error, RD_ERR_RUNTIME, [character(len=40) :: 'non-finite derivative', &
                'time reached'], method // ' NaN rhs')
    call check(y(1) == y(1) .and. abs(y(1)) < 2.0_wp, method // ': NaN written to the caller state')
    call integ%destroy()
  end subroutine nan_rhs

  subroutine recoverable_rhs(method, prefix)
    character(len=*), intent(in) :: method, prefix
    type(failing_t), target :: system
    type(integrator_t) :: integ
    type(error_t), allocatable :: error
    real(wp) :: y(1)
    character(len=40) :: pieces(2)

    system%mode = FAIL_RECOVERABLE_ALWAYS
    call integ%build(system, 0.0_wp, [1.0_wp], settings_for(method), error)
    call check(.not. allocated(error), method // ' build')
    call integ%advance(1.0_wp, y, error)
    pieces(1) = 'contact search out of range'
    pieces(2) = prefix
    call expect(error, RD_ERR_RUNTIME, pieces, method // ' always-recoverable rhs')
    if (method == 'rk4') call check(index(error%message, 'failed in 64 substeps too') > 0, &
                                    'rk4: message does not say the substeps failed too')
    call integ%destroy()
  end subroutine recoverable_rhs

  !> Every method retries a step after a recoverable RHS failure with a smaller step and
  !> the run stays on the exact solution: CVODE by itself, ERKStep (which in SUNDIALS 6
  !> stops with ARK_UNREC_RHSFUNC_ERR) restarted by the glue from its last accepted step
  !> with a quarter step, a fixed step redone in 2, 4, 8 substeps; the latter two are
  !> counted in rhs_retries (3 failures: 3 retries).
  subroutine recovered_rhs(method)
    character(len=*), intent(in) :: method
    type(failing_t), target :: system
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(integrator_stats_t) :: stats
    type(error_t), allocatable :: error
    real(wp) :: y(1)

    system%mode = FAIL_RECOVERABLE_FEW
    s = settings_for(method)
    s%rtol = 1.0e-8_wp
    s%atol = 1.0e-12_wp
    call integ%build(system, 0.0_wp, [1.0_wp], s, error)
    call check(.not. allocated(error), method // ' build')
    call integ%advance(2.0_wp, y, error)
    if (allocated(error)) write (*, '(a)') error%message
    call check(.not. allocated(error), method // ': recoverable RHS failures not recovered')
    call check(system%failures == 3, method // ': the RHS did not fail 3 times')
    call integ%get_stats(stats)
    if (method == 'erk' .or. method == 'rk4') then
      call check(stats%rhs_retries == 3, method // ': rhs_retries is not 3')
    else
      call check(stats%rhs_retries == 0, method // ': rhs_retries counted for CVODE')
    end if
    call report(method // ' after 3 recovered failures: rel. error', abs(y(1) / exp(-2.0_wp) - 1.0_wp))
    call check(abs(y(1) / exp(-2.0_wp) - 1.0_wp) < 100.0_wp * s%rtol, &
               method // ': inaccurate after recovered RHS failures')
    call integ%destroy()
  end subroutine recovered_rhs

  subroutine too_many_steps(method, prefix)
    character(len=*), intent(in) :: method, prefix
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(2)
    character(len=40) :: pieces(2)

    s = settings_for(method)
    s%max_num_steps = 50
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call check(.not. allocated(error), method // ' build')
    call integ%advance(100.0_wp, y, error)
    if (method == 'rk4') then
      call expect(error, RD_ERR_RUNTIME, [character(len=40) :: 'max_num_steps', 'needs'], &
                  method // ' too many steps')
    else
      pieces(1) = prefix // 'TOO_MUCH_WORK'
      pieces(2) = 'time reached'
      call expect(error, RD_ERR_RUNTIME, pieces, method // ' too many steps')
      call check(integ%time() > 0.0_wp .and. integ%time() < 100.0_wp, &
                 method // ': time reached not reported')
    end if
    call integ%destroy()
  end subroutine too_many_steps

  subroutine bad_input()
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(2), y3(3)

    call integ%advance(1.0_wp, y, error)
    call expect(error, RD_ERR_HANDLE, [character(len=40) :: 'before build'], 'advance before build')
    s%method = 'euler'
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: "'euler'", "'bdf'", 'integrator build'], &
                'unknown method')
    s%method = 'rk4'
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'fixed_step'], 'rk4 without fixed_step')
    s = integrator_settings_t()
    s%rtol = -1.0_wp
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'rtol'], 'negative rtol')
    s = integrator_settings_t()
    s%atol_vector = [1.0e-8_wp]
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'atol_vector'], 'atol_vector size')
    s = integrator_settings_t()
    s%max_order = 6
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'max_order'], 'bdf order 6')
    s = integrator_settings_t()
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp, 0.0_wp], s, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'y0 has 3'], 'y0 size')
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call check(.not. allocated(error), 'valid build')
    call integ%advance(1.0_wp, y3, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 'y has 3'], 'advance y size')
    call integ%advance(1.0_wp, y, error)
    call check(.not. allocated(error), 'valid advance')
    call integ%advance(0.5_wp, y, error)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 't_out'], 'advance backwards')
    call integ%advance(2.0_wp, y, error, t_stop=1.5_wp)
    call expect(error, RD_ERR_INPUT, [character(len=40) :: 't_stop', 't_out'], 'stop time before t_out')
    ! advancing to the current time is a no-op returning the current state
    call integ%advance(1.0_wp, y, error)
    call check(.not. allocated(error), 'advance to the current time')
    call integ%destroy()
  end subroutine bad_input

  subroutine limits_and_vector_tolerances()
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(integrator_stats_t) :: stats
    type(error_t), allocatable :: error
    real(wp) :: y(2), err

    s%method = 'bdf'
    s%max_step = 1.0e-2_wp
    s%atol_vector = [1.0e-10_wp, 1.0e-9_wp]
    s%rtol = 1.0e-8_wp
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call check(.not. allocated(error), 'build with max_step and atol_vector')
    call integ%advance(1.0_wp, y, error)
    call check(.not. allocated(error), 'advance with max_step and atol_vector')
    call integ%get_stats(stats)
    err = maxval(abs(y - osc%exact(1.0_wp, [1.0_wp, 0.0_wp])) / [1.0_wp, osc%omega])
    call report('bdf max_step 1e-2: steps over 1 s', real(stats%steps, wp))
    call report('bdf max_step 1e-2: error at 1 s', err)
    call check(stats%steps >= 100, 'max_step not honoured (fewer than T / max_step steps)')
    call check(stats%last_step <= 1.0e-2_wp * (1.0_wp + 1.0e-12_wp), 'last step above max_step')
    call check(err < 50.0_wp * s%rtol, 'inaccurate with per-component tolerances')
    call integ%destroy()
  end subroutine limits_and_vector_tolerances
end program test_solver_failures
