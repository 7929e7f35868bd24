!> Every method against closed forms: harmonic oscillator (position, velocity, energy and
!> phase vs x = cos(wt)) and exponential decay (y = exp(-lambda t)). For rk4 and heun the
!> run is also compared with the exact per-step amplification matrix of the method
!> (R(hA) = sum_k (hA)^k / k!, k <= order) applied N times -- an independent formulation of
!> the same discrete scheme, so the comparison is at round-off level -- and with the
!> leading-term global error estimate w T (w h)^p / (p+1)!.
program test_solver_closed_forms
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t
  use rd_solver_test_problems, only: oscillator_t, decay_t, report
  use rd_test_support, only: check, test_summary
  implicit none

  character(len=8), parameter :: methods(5) = [character(len=8) :: 'bdf', 'adams', 'erk', &
                                                'rk4', 'heun']
  integer :: m

  do m = 1, size(methods)
    call oscillator_case(trim(methods(m)))
    call decay_case(trim(methods(m)))
  end do
  call test_summary('test_solver_closed_forms')

contains

  function settings_for(method) result(s)
    character(len=*), intent(in) :: method
    type(integrator_settings_t) :: s
    s%method = method
    s%rtol = 1.0e-8_wp
    s%atol = 1.0e-10_wp
    s%fixed_step = 1.0e-3_wp
  end function settings_for

  subroutine oscillator_case(method)
    character(len=*), intent(in) :: method
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(integrator_stats_t) :: stats
    type(error_t), allocatable :: error
    real(wp) :: y(2), y0(2), ye(2), t, err, max_err, energy0, energy_drift, phase_err
    real(wp) :: bound, h, amp(2, 2), step_matrix(2, 2), a(2, 2), ydiscrete(2), term(2, 2)
    integer :: i, k, order
    integer, parameter :: n_out = 100
    real(wp), parameter :: t_end = 10.0_wp

    s = settings_for(method)
    y0 = [1.0_wp, 0.0_wp]
    y = y0
    call integ%build(osc, 0.0_wp, y0, s, error)
    call check(.not. allocated(error), method // ' build: ' // msg(error))
    energy0 = 0.5_wp * (y0(2)**2 + osc%omega**2 * y0(1)**2)
    max_err = 0.0_wp
    energy_drift = 0.0_wp
    phase_err = 0.0_wp
    do i = 1, n_out
      t = t_end * real(i, wp) / n_out
      call integ%advance(t, y, error)
      call check(.not. allocated(error), method // ' advance: ' // msg(error))
      call check(abs(integ%time() - t) == 0.0_wp, method // ': time() is not exactly t_out')
      ye = osc%exact(t, y0)
      ! position error and velocity error scaled by omega (same units as the amplitude)
      err = max(abs(y(1) - ye(1)), abs(y(2) - ye(2)) / osc%omega)
      max_err = max(max_err, err)
      energy_drift = max(energy_drift, &
                         abs(0.5_wp * (y(2)**2 + osc%omega**2 * y(1)**2) - energy0) / energy0)
      phase_err = max(phase_err, abs(modulo(atan2(-y(2) / osc%omega, y(1)) - osc%omega * t + pi, &
                                             2.0_wp * pi) - pi))
    end do
    call integ%get_stats(stats)
    write (*, '(a)') 'oscillator w = 2 pi, T = 10 s, method ' // method
    call report('  max |error| (amplitude 1)', max_err)
    call report('  max relative energy drift', energy_drift)
    call report('  max phase error [rad]', phase_err)
    call report('  steps', real(stats%steps, wp))
    call report('  rhs evaluations', real(stats%rhs_evals, wp))
    call check(stats%steps > 0 .and. stats%rhs_evals >= stats%steps, method // &
               ': statistics inconsistent (rhs evaluations < steps)')
    call check(osc%calls == stats%rhs_evals + stats%rhs_evals_jacobian, method // &
               ': reported RHS evaluations differ from the calls the system counted')

    select case (method)
    case ('bdf', 'adams', 'erk')
      ! Tolerance-proportional accuracy: the local error per step is held at ~rtol, the
      ! global error grows with the integrated time; allow 50 rtol per period (10
      ! periods: 500 rtol) for position/velocity, energy and phase alike.
      bound = 500.0_wp * s%rtol
      call check(max_err < bound, method // ': oscillator error exceeds 500 rtol')
      call check(energy_drift < 2.0_wp * bound, method // ': energy drift exceeds 1000 rtol')
      call check(phase_err < 2.0_wp * bound, method // ': phase error exceeds 1000 rtol')
    case ('rk4', 'heun')
      order = merge(4, 2, method == 'rk4')
      h = s%fixed_step
      call check(stats%steps == nint(t_end / h), method // ': not exactly T/h fixed steps')
      ! Leading-term global error of an order-p RK on y' = i w y: w T (w h)^p / (p+1)!.
      bound = osc%omega * t_end * (osc%omega * h)**order / gamma(real(order + 2, wp))
      call report('  leading-term error estimate', bound)
      call check(max_err < 1.5_wp * bound .and. max_err > 0.5_wp * bound, method // &
                 ': global error not at the leading-term estimate of its order')
      ! Same scheme, independent formulation: y_N = R(hA)^N y0.
      a = reshape([0.0_wp, -osc%omega**2, 1.0_wp, 0.0_wp], [2, 2])
      step_matrix = 0.0_wp
      term = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
      do k = 0, order
        if (k > 0) term = matmul(term, h * a) / real(k, wp)
        step_matrix = step_matrix + term
      end do
      amp = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
      do k = 1, nint(t_end / h)
        amp = matmul(step_matrix, amp)
      end do
      ydiscrete = matmul(amp, y0)
      call report('  |y - R(hA)^N y0|', maxval(abs(y - ydiscrete) / [1.0_wp, osc%omega]))
      call check(maxval(abs(y - ydiscrete) / [1.0_wp, osc%omega]) < 1.0e-10_wp, method // &
                 ': result differs from the exact amplification matrix of the scheme')
    end select
    call integ%destroy()
  end subroutine oscillator_case

  subroutine decay_case(method)
    character(len=*), intent(in) :: method
    type(decay_t), target :: decay
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(1), t, rel_err, max_rel_err
    integer :: i

    s = settings_for(method)
    decay%lambda = 2.0_wp
    call integ%build(decay, 0.0_wp, [1.0_wp], s, error)
    call check(.not. allocated(error), method // ' build: ' // msg(error))
    max_rel_err = 0.0_wp
    do i = 1, 20
      t = 0.25_wp * i
      call integ%advance(t, y, error)
      call check(.not. allocated(error), method // ' advance: ' // msg(error))
      rel_err = abs(y(1) - exp(-decay%lambda * t)) / exp(-decay%lambda * t)
      max_rel_err = max(max_rel_err, rel_err)
    end do
    write (*, '(a)') 'decay lambda = 2, T = 5 s, method ' // method
    call report('  max relative error', max_rel_err)
    select case (method)
    case ('bdf', 'adams', 'erk')
      ! y decays to 4.5e-5, where atol = 1e-10 is 2e-6 relative: allow 500 (rtol + atol/y).
      call check(max_rel_err < 500.0_wp * (s%rtol + s%atol / exp(-decay%lambda * t)), &
                 method // ': decay error exceeds a small multiple of the tolerance')
    case ('rk4')
      ! Relative global error of RK4 on y' = -l y after time T: ~ l T (l h)^4 / 120.
      call check(max_rel_err < 1.5_wp * decay%lambda * t * (decay%lambda * s%fixed_step)**4 / 120.0_wp, &
                 'rk4: decay error above its leading-term estimate')
    case ('heun')
      call check(max_rel_err < 1.5_wp * decay%lambda * t * (decay%lambda * s%fixed_step)**2 / 6.0_wp, &
                 'heun: decay error above its leading-term estimate')
    end select
    call integ%destroy()
  end subroutine decay_case

  function msg(error) result(s)
    type(error_t), allocatable, intent(in) :: error
    character(len=:), allocatable :: s
    s = 'ok'
    if (allocated(error)) s = error%message
  end function msg
end program test_solver_closed_forms
