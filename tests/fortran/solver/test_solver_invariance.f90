!> Invariance tests (MOM6 style) for every method:
!>  - 1000 small advances equal one advance to the same end time within the tolerance
!>    (SUNDIALS runs with tstop = t_out, so chunking only changes where steps end);
!>  - two integrators on two different systems, advanced alternately, give exactly
!>    (bit for bit) the results of each run alone: no shared state;
!>  - reinit at the current state continues on the closed-form solution, keeps the
!>    statistics accumulating, and accepts a discontinuous state (a jump in velocity).
program test_solver_invariance
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
    call chunked(trim(methods(m)))
    call interleaved(trim(methods(m)))
    call restart(trim(methods(m)))
  end do
  call test_summary('test_solver_invariance')

contains

  function settings_for(method) result(s)
    character(len=*), intent(in) :: method
    type(integrator_settings_t) :: s
    s%method = method
    s%rtol = 1.0e-8_wp
    s%atol = 1.0e-10_wp
    s%fixed_step = 1.0e-3_wp
  end function settings_for

  subroutine chunked(method)
    character(len=*), intent(in) :: method
    type(oscillator_t), target :: osc_one, osc_chunks
    type(integrator_t) :: one, chunks
    type(integrator_stats_t) :: stats_one, stats_chunks
    type(error_t), allocatable :: error
    real(wp) :: y_one(2), y_chunks(2), y0(2), diff, err_one, err_chunks
    integer :: i
    real(wp), parameter :: t_end = 2.0_wp

    y0 = [1.0_wp, 0.0_wp]
    call one%build(osc_one, 0.0_wp, y0, settings_for(method), error)
    call check(.not. allocated(error), method // ' build')
    call chunks%build(osc_chunks, 0.0_wp, y0, settings_for(method), error)
    call check(.not. allocated(error), method // ' build')
    call one%advance(t_end, y_one, error)
    call check(.not. allocated(error), method // ' single advance')
    do i = 1, 1000
      call chunks%advance(t_end * real(i, wp) / 1000.0_wp, y_chunks, error)
      call check(.not. allocated(error), method // ' chunked advance')
    end do
    call one%get_stats(stats_one)
    call chunks%get_stats(stats_chunks)
    diff = maxval(abs(y_one - y_chunks) / [1.0_wp, osc_one%omega])
    err_one = maxval(abs(y_one - osc_one%exact(t_end, y0)) / [1.0_wp, osc_one%omega])
    err_chunks = maxval(abs(y_chunks - osc_one%exact(t_end, y0)) / [1.0_wp, osc_one%omega])
    write (*, '(a)') 'chunked (1000 advances) vs one advance to 2 s, oscillator, ' // method
    call report('  |y_one - y_chunks|', diff)
    call report('  error one / chunked vs exact', err_one)
    call report('  ', err_chunks)
    call report('  steps one / chunked', real(stats_one%steps, wp))
    call report('  ', real(stats_chunks%steps, wp))
    select case (method)
    case ('rk4', 'heun')
      ! Same steps (the interval 2 ms is 2 fixed steps): equal to round-off.
      call check(stats_one%steps == stats_chunks%steps, method // ': step count changed')
      call check(diff < 1.0e-12_wp, method // ': chunked run differs beyond round-off')
    case default
      ! Both runs are tolerance-controlled approximations of the same solution: they
      ! must agree within 100 rtol (2 periods; cf. 50 rtol per period in closed_forms).
      call check(diff < 100.0_wp * 1.0e-8_wp, method // ': chunked run differs beyond tolerance')
      call check(err_chunks < 100.0_wp * 1.0e-8_wp, method // ': chunked run inaccurate')
    end select
    call one%destroy()
    call chunks%destroy()
  end subroutine chunked

  subroutine interleaved(method)
    character(len=*), intent(in) :: method
    type(oscillator_t), target :: osc_a, osc_alone
    type(decay_t), target :: decay_b, decay_alone
    type(integrator_t) :: a, b, alone
    type(error_t), allocatable :: error
    real(wp) :: ya(2), yb(1), ya_alone(2), yb_alone(1), ta(10), tb(10)
    integer :: i

    osc_a%omega = 3.0_wp
    osc_alone%omega = 3.0_wp
    decay_b%lambda = 7.0_wp
    decay_alone%lambda = 7.0_wp
    ! Different output times for the two integrators, advanced alternately.
    ta = [(0.13_wp * i, i = 1, 10)]
    tb = [(0.07_wp * i, i = 1, 10)]
    call a%build(osc_a, 0.0_wp, [0.5_wp, 1.0_wp], settings_for(method), error)
    call check(.not. allocated(error), method // ' build a')
    call b%build(decay_b, 0.0_wp, [3.0_wp], settings_for(method), error)
    call check(.not. allocated(error), method // ' build b')
    do i = 1, 10
      call a%advance(ta(i), ya, error)
      call check(.not. allocated(error), method // ' advance a')
      call b%advance(tb(i), yb, error)
      call check(.not. allocated(error), method // ' advance b')
    end do
    call alone%build(osc_alone, 0.0_wp, [0.5_wp, 1.0_wp], settings_for(method), error)
    do i = 1, 10
      call alone%advance(ta(i), ya_alone, error)
      call check(.not. allocated(error), method // ' advance alone')
    end do
    call alone%destroy()
    call alone%build(decay_alone, 0.0_wp, [3.0_wp], settings_for(method), error)
    do i = 1, 10
      call alone%advance(tb(i), yb_alone, error)
      call check(.not. allocated(error), method // ' advance alone')
    end do
    call check(all(ya == ya_alone) .and. all(yb == yb_alone), method // &
               ': interleaved integrators differ from runs alone (shared state)')
    call check(abs(yb(1) - 3.0_wp * exp(-7.0_wp * tb(10))) < 1.0e-5_wp, method // &
               ': interleaved decay is wrong')
    ya_alone = osc_a%exact(ta(10), [0.5_wp, 1.0_wp])
    call check(abs(ya(1) - ya_alone(1)) < 1.0e-5_wp, method // &
               ': interleaved oscillator is wrong')
    call a%destroy()
    call b%destroy()
    call alone%destroy()
    write (*, '(a)') 'interleaved integrators identical to runs alone: ' // method
  end subroutine interleaved

  subroutine restart(method)
    character(len=*), intent(in) :: method
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_stats_t) :: stats_before, stats_after
    type(error_t), allocatable :: error
    real(wp) :: y(2), y_jump(2), t1, t2, err
    real(wp), parameter :: tol = 100.0_wp * 1.0e-8_wp

    t1 = 0.6_wp
    t2 = 1.7_wp
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], settings_for(method), error)
    call integ%advance(t1, y, error)
    call check(.not. allocated(error), method // ' advance before reinit')
    call integ%get_stats(stats_before)
    ! Discontinuity: the velocity jumps (like a user changing the speed).
    y_jump = [y(1), y(2) + 2.0_wp]
    call integ%reinit(t1, y_jump, error)
    call check(.not. allocated(error), method // ' reinit')
    call integ%advance(t2, y, error)
    call check(.not. allocated(error), method // ' advance after reinit')
    call integ%get_stats(stats_after)
    ! Exact: the oscillator restarted at t1 from y_jump.
    err = maxval(abs(y - osc%exact(t2 - t1, y_jump)) / [1.0_wp, osc%omega])
    write (*, '(a)') 'reinit with a velocity jump at 0.6 s: ' // method
    call report('  error at 1.7 s vs closed form from the jump', err)
    select case (method)
    case ('heun')
      ! leading-term estimate w T (w h)^2 / 6 = 4.5e-5 for T = 1.1 s, h = 1 ms
      call check(err < 1.0e-4_wp, 'heun: wrong after reinit')
    case ('rk4')
      call check(err < 1.0e-9_wp, 'rk4: wrong after reinit')
    case default
      call check(err < tol, method // ': wrong after reinit')
    end select
    call check(stats_after%steps > stats_before%steps .and. stats_after%reinits == 1, &
               method // ': statistics reset by reinit')
    call integ%destroy()
  end subroutine restart
end program test_solver_invariance
