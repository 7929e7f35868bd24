!> Where a run spends its integrator steps (docs/theory_flange_chatter.md): advances a deck
!> in slices of DT and prints per slice the accepted steps, error-test and Newton failures,
!> the last step size and the order, the right-hand-side calls of the method and of the
!> difference-quotient Jacobians and the Jacobian evaluations (a ringing or chattering
!> wheelset shows as steps).
!>
!>   study_step_history DECK DT
program study_step_history
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  use study_support, only: start_scene, stop_on
  use rd_integrator, only: integrator_stats_t
  implicit none
  type(scene_t) :: scene
  type(error_t), allocatable :: error
  type(integrator_stats_t) :: s0, s1
  character(len=512) :: deck, arg
  real(wp) :: dt, t
  call get_command_argument(1, deck)
  call get_command_argument(2, arg); read (arg, *) dt
  call start_scene(trim(deck), scene)
  print '(a)', '    t_end [s]    steps  err.fail  newt.fail   last h [s] order      rhs  rhs.jac   jac'
  t = 0
  s0 = integrator_stats_t()
  do while (t < scene%end_time() - 1.0e-9_wp)
    t = min(t + dt, scene%end_time())
    call scene%advance(t, error); call stop_on(error)
    call scene%integrator_stats(s1)
    print "(f13.3, i9, i10, i11, es13.3, i6, i9, i9, i6)", t, s1%steps - s0%steps, s1%error_test_failures - s0%error_test_failures, &
      s1%nonlinear_conv_failures - s0%nonlinear_conv_failures, s1%last_step, s1%current_order, &
      s1%rhs_evals - s0%rhs_evals, s1%rhs_evals_jacobian - s0%rhs_evals_jacobian, s1%jacobian_evals - s0%jacobian_evals
    s0 = s1
  end do
  call scene%destroy()
end program study_step_history
