!> advance(t_out, y, error, t_stop): the adaptive methods step as far as t_stop and return
!> their interpolant at t_out. Checked on the harmonic oscillator (closed form): samples
!> between two stops are within the tolerance of the exact solution, and a run that samples
!> between its stops takes exactly the steps (and returns bitwise the states at the stops)
!> of a run that stops at the same times without sampling (CVODE: also the same RHS calls;
!> ARKODE's Hermite interpolant may add one a sample). (A t_stop before t_out:
!> test_solver_failures, bad_input.)
program test_solver_stop_time
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t
  use rd_solver_test_problems, only: oscillator_t, report
  use rd_test_support, only: check, test_summary
  implicit none

  character(len=8), parameter :: methods(3) = [character(len=8) :: 'bdf', 'adams', 'erk']
  integer :: m

  do m = 1, size(methods)
    call sampled_between_stops(trim(methods(m)))
  end do
  call test_summary('test_solver_stop_time')

contains

  subroutine sampled_between_stops(method)
    character(len=*), intent(in) :: method
    integer, parameter :: n_stops = 20, n_sub = 7
    real(wp), parameter :: interval = 0.25_wp
    type(oscillator_t), target :: osc_a, osc_b
    type(integrator_t) :: a, b
    type(integrator_settings_t) :: s
    type(integrator_stats_t) :: stats_a, stats_b
    type(error_t), allocatable :: error
    real(wp) :: ya(2), yb(2), y0(2), ye(2), t, t_stop, err, max_err, max_err_stops
    integer :: i, j
    logical :: same_at_stops

    s%method = method
    s%rtol = 1.0e-8_wp
    s%atol = 1.0e-10_wp
    ! CVODE estimates the first step from the first t_out, which differs between the runs
    ! (a sample against the stop); fixed, the step sequences can be compared
    s%initial_step = 1.0e-4_wp
    y0 = [1.0_wp, 0.0_wp]
    ya = y0; yb = y0
    call a%build(osc_a, 0.0_wp, y0, s, error)
    call check(.not. allocated(error), method // ' build a')
    call b%build(osc_b, 0.0_wp, y0, s, error)
    call check(.not. allocated(error), method // ' build b')
    max_err = 0; max_err_stops = 0
    same_at_stops = .true.
    do i = 1, n_stops
      t_stop = interval * i
      ! a: n_sub interpolated samples on the way to the stop, then the stop itself
      do j = 1, n_sub
        t = t_stop - interval + interval * j / (n_sub + 1)
        call a%advance(t, ya, error, t_stop)
        call check(.not. allocated(error), method // ' sample advance')
        call check(a%time() == t, method // ': time() is not the sample time')
        ye = osc_a%exact(t, y0)
        err = max(abs(ya(1) - ye(1)), abs(ya(2) - ye(2)) / osc_a%omega)
        max_err = max(max_err, err)
      end do
      call a%advance(t_stop, ya, error, t_stop)
      call check(.not. allocated(error), method // ' stop advance a')
      ! b: straight to the stop
      call b%advance(t_stop, yb, error)
      call check(.not. allocated(error), method // ' stop advance b')
      ye = osc_b%exact(t_stop, y0)
      max_err_stops = max(max_err_stops, abs(yb(1) - ye(1)), abs(yb(2) - ye(2)) / osc_b%omega)
      same_at_stops = same_at_stops .and. all(ya == yb)
    end do
    call a%get_stats(stats_a)
    call b%get_stats(stats_b)
    write (*, '(a)') 'oscillator, ' // method // ', rtol 1e-8: samples between stops'
    call report('  max |error| of the interpolated samples (amplitude 1)', max_err)
    call report('  max |error| at the stops', max_err_stops)
    call report('  steps with samples', real(stats_a%steps, wp))
    call report('  steps without', real(stats_b%steps, wp))
    ! the interpolant is as accurate as the steps: the samples' error stays within twice
    ! the global error the method has at its stops
    call check(max_err <= 2 * max_err_stops, method // ': interpolated samples off the closed form')
    call report('  RHS calls with samples', real(stats_a%rhs_evals, wp))
    call report('  RHS calls without', real(stats_b%rhs_evals, wp))
    call check(stats_a%steps == stats_b%steps, method // ': sampling between the stops changed the steps')
    if (method == 'erk') then
      ! ARKODE's Hermite interpolant needs f at the step's end: at most one RHS call a sample
      call check(stats_a%rhs_evals >= stats_b%rhs_evals .and. &
                 stats_a%rhs_evals - stats_b%rhs_evals <= int(n_stops * n_sub, i8), &
                 method // ': more than one RHS call per interpolated sample')
    else
      call check(stats_a%rhs_evals == stats_b%rhs_evals, method // ': sampling cost RHS calls')
    end if
    call check(same_at_stops, method // ': the states at the stops differ bitwise')
    call check(stats_a%steps > int(n_stops, i8), method // ': fewer steps than stops (test too easy)')
  end subroutine sampled_between_stops

end program test_solver_stop_time
