!> Stiff linear problems with closed-form solutions, BDF against explicit methods:
!>  1. y' = -1000 (y - cos t) - sin t, y(0) = 1, exact y = cos t (eigenvalue -1000);
!>  2. y' = A y, A = V diag(-1, -1e5) V^-1 (coupled, non-symmetric, eigenvalues -1 and
!>     -1e5), exact y = V diag(e^-t, e^-1e5 t) V^-1 y0.
!> BDF must reach the tolerance-level error in few steps, ERK needs many (its step is
!> bounded by stability, |h lambda| < ~3.3 for Dormand-Prince), and the analytic Jacobian
!> must give the same answer without difference-quotient RHS calls.
program test_solver_stiff
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t
  use rd_solver_test_problems, only: stiff_cosine_t, stiff_pair_t, stiff_pair_jacobian, &
                                     report
  use rd_test_support, only: check, test_summary
  implicit none

  type(integrator_stats_t) :: bdf_stats, erk_stats, jac_stats, rk4_stats
  real(wp) :: bdf_err, erk_err, jac_err, rk4_err

  ! --- 1. stiff scalar -----------------------------------------------------------
  call run_cosine('bdf', bdf_err, bdf_stats)
  call run_cosine('erk', erk_err, erk_stats)
  call run_cosine('rk4', rk4_err, rk4_stats)
  write (*, '(a)') "stiff scalar y' = -1000 (y - cos t) - sin t on [0, 10] s, rtol 1e-6"
  call report('  bdf max |error|', bdf_err)
  call report('  bdf steps', real(bdf_stats%steps, wp))
  call report('  bdf rhs evals (method + DQ Jacobian)', &
              real(bdf_stats%rhs_evals + bdf_stats%rhs_evals_jacobian, wp))
  call report('  erk max |error|', erk_err)
  call report('  erk steps', real(erk_stats%steps, wp))
  call report('  erk rhs evals', real(erk_stats%rhs_evals, wp))
  call report('  rk4 (h = 1e-3 s) max |error|', rk4_err)
  ! The solution has amplitude 1: errors within 10 rtol.
  call check(bdf_err < 10.0_wp * 1.0e-6_wp, 'bdf: stiff scalar error above 10 rtol')
  call check(erk_err < 10.0_wp * 1.0e-6_wp, 'erk: stiff scalar error above 10 rtol')
  call check(rk4_err < 1.0e-6_wp, 'rk4: stiff scalar error above 1e-6')
  ! Stability bound of ERK: at least T |lambda| / 3.3 = 3000 steps; BDF far fewer.
  call check(erk_stats%steps > 3000, 'erk: fewer steps than its stability limit allows')
  call check(bdf_stats%steps * 10 < erk_stats%steps, 'bdf: not 10x fewer steps than erk')
  call check_stats_consistent('bdf', bdf_stats, 1)

  ! --- 2. stiff coupled pair -------------------------------------------------------
  call run_pair('bdf', .false., bdf_err, bdf_stats)
  call run_pair('bdf', .true., jac_err, jac_stats)
  call run_pair('erk', .false., erk_err, erk_stats)
  write (*, '(a)') 'stiff pair, eigenvalues -1 and -1e5, on [0, 5] s, rtol 1e-6, atol 1e-10'
  call report('  bdf (DQ Jacobian) max |error|', bdf_err)
  call report('  bdf (DQ Jacobian) steps', real(bdf_stats%steps, wp))
  call report('  bdf (DQ Jacobian) jacobian evals', real(bdf_stats%jacobian_evals, wp))
  call report('  bdf (DQ Jacobian) rhs evals for Jacobian', real(bdf_stats%rhs_evals_jacobian, wp))
  call report('  bdf (analytic Jacobian) max |error|', jac_err)
  call report('  bdf (analytic Jacobian) steps', real(jac_stats%steps, wp))
  call report('  erk max |error|', erk_err)
  call report('  erk steps', real(erk_stats%steps, wp))
  call check(bdf_err < 10.0_wp * 1.0e-6_wp, 'bdf: stiff pair error above 10 rtol')
  call check(jac_err < 10.0_wp * 1.0e-6_wp, 'bdf+jacobian: stiff pair error above 10 rtol')
  call check(erk_err < 10.0_wp * 1.0e-6_wp, 'erk: stiff pair error above 10 rtol')
  ! ERK: T |lambda_max| / 3.3 = 1.5e5 steps at least (max_num_steps raised below).
  call check(erk_stats%steps > 100000, 'erk: fewer steps than the stability limit allows')
  call check(bdf_stats%steps < 1000, 'bdf: more than 1000 steps on a linear stiff pair')
  call check_stats_consistent('bdf', bdf_stats, 2)
  call check(jac_stats%rhs_evals_jacobian == 0 .and. jac_stats%jacobian_evals > 0, &
             'bdf+jacobian: analytic Jacobian not used (DQ RHS calls reported)')
  ! Same Newton matrix up to DQ round-off: similar work (step counts differ by tens of
  ! percent with round-off, e.g. between -O0 and -O2, hence the factor 2). A transposed
  ! Jacobian -- A is not symmetric -- was checked to fail this (3e5 steps) and the
  ! accuracy check above.
  call check(jac_stats%steps < 2 * bdf_stats%steps, &
             'bdf+jacobian: more than twice the steps of the DQ Jacobian run')
  call test_summary('test_solver_stiff')

contains

  !> Meaning of the counters: CVODE's dense difference-quotient Jacobian costs exactly
  !> n RHS calls per Jacobian; each Jacobian is followed by an LU (linear setup).
  subroutine check_stats_consistent(method, stats, n)
    character(len=*), intent(in) :: method
    type(integrator_stats_t), intent(in) :: stats
    integer, intent(in) :: n
    call check(stats%steps > 0 .and. stats%rhs_evals >= stats%steps, method // &
               ': rhs evaluations < steps')
    call check(stats%jacobian_evals > 0 .and. stats%rhs_evals_jacobian == n * stats%jacobian_evals, &
               method // ': DQ Jacobian RHS calls /= n * Jacobian evaluations')
    call check(stats%linear_setups >= stats%jacobian_evals, method // &
               ': fewer linear setups than Jacobian evaluations')
    call check(stats%current_order >= 1 .and. stats%current_order <= 5, method // &
               ': BDF order outside 1..5')
    call check(stats%last_step > 0.0_wp, method // ': last step size not positive')
  end subroutine check_stats_consistent

  subroutine run_cosine(method, max_err, stats)
    character(len=*), intent(in) :: method
    real(wp), intent(out) :: max_err
    type(integrator_stats_t), intent(out) :: stats
    type(stiff_cosine_t), target :: system
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(1), t
    integer :: i

    s%method = method
    s%rtol = 1.0e-6_wp
    s%atol = 1.0e-8_wp
    s%fixed_step = 1.0e-3_wp
    call integ%build(system, 0.0_wp, [1.0_wp], s, error)
    call check(.not. allocated(error), method // ' build failed')
    max_err = 0.0_wp
    do i = 1, 100
      t = 0.1_wp * i
      call integ%advance(t, y, error)
      if (allocated(error)) write (*, '(a)') error%message
      call check(.not. allocated(error), method // ' advance failed')
      max_err = max(max_err, abs(y(1) - cos(t)))
    end do
    call integ%get_stats(stats)
    call integ%destroy()
  end subroutine run_cosine

  subroutine run_pair(method, analytic, max_err, stats)
    character(len=*), intent(in) :: method
    logical, intent(in) :: analytic
    real(wp), intent(out) :: max_err
    type(integrator_stats_t), intent(out) :: stats
    type(stiff_pair_t), target :: system
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(2), y0(2), t
    integer :: i

    s%method = method
    s%rtol = 1.0e-6_wp
    s%atol = 1.0e-10_wp
    s%max_num_steps = 1000000
    y0 = [1.0_wp, -1.0_wp]   ! excites both modes (V^-1 y0 = [1.67, -1.33])
    if (analytic) then
      call integ%build(system, 0.0_wp, y0, s, error, jacobian=stiff_pair_jacobian)
    else
      call integ%build(system, 0.0_wp, y0, s, error)
    end if
    call check(.not. allocated(error), method // ' build failed')
    max_err = 0.0_wp
    do i = 1, 50
      t = 0.1_wp * i
      call integ%advance(t, y, error)
      if (allocated(error)) write (*, '(a)') error%message
      call check(.not. allocated(error), method // ' advance failed')
      ! Absolute error against the exact solution (|y0| = 1).
      max_err = max(max_err, maxval(abs(y - system%exact(t, y0))))
    end do
    call integ%get_stats(stats)
    call integ%destroy()
  end subroutine run_pair
end program test_solver_stiff
