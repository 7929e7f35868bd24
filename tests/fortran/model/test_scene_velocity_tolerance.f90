!> &solver atol_velocity: the rates of the state get their own absolute tolerance
!> (rd_multibody absolute_tolerances, docs/theory_solver.md "Tolerances").
!>  (a) layout, on the TGV 001 vehicle with a series yaw damper (an element state): every
!>      free coordinate's slot, found through multibody%free_slot (body by body, dof by dof),
!>      gets atol, its rate's slot (nfree + slot) gets atol_velocity, the element state atol;
!>  (b) the vector reaches the integrator: a run to 0.3 s with atol_velocity = atol equals the
!>      run without it (scalar tolerances) to the last bit, and one with atol_velocity 100
!>      times atol takes fewer steps and differs from it;
!>  (c) accuracy against an independent reference: the run with atol_velocity = w_c atol,
!>      w_c = 100 1/s (above the vehicle's body and bogie modes, 1-15 Hz), stays within
!>      tolerance of a run at rtol 1e-10, atol 1e-12: its global error at 0.3 s, in units of
!>      the local tolerance rtol |y| + atol of the position slots and rtol |y| + atol_velocity
!>      of the rate slots, is no larger than 5 times the uniform-atol run's in its own units.
!>      Measured in CVODE's own norm, the weighted RMS over the components: the largest
!>      component alone moved by 10x under rounding changes alone (the same code with the
!>      reference BLAS or OpenBLAS, matmul in gfortran's library or inline: ratios 0.43 to
!>      4.0), the weighted RMS from 0.46 to 3.1 (2026-11-29). A velocity tolerance that
!>      scaled the error with its 100x would give ~100; one applied to the position slots
!>      fails (a).
program test_scene_velocity_tolerance
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary, file_text
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_integrator, only: integrator_stats_t
  implicit none

  character(len=*), parameter :: yaw_damper = new_line('a') // &
    "&element name = 'yawdamper1', type = 'series_spring_damper', body1 = 'car', " // &
    "body2 = 'bogie1', point1 = 11.85, 1.3, -0.7, point2 = -0.5, 1.3, 0.2, " // &
    "damping = 2.0e5, 0.0, 0.0, series_stiffness = 8.0e6 /" // new_line('a')
  real(wp), parameter :: rtol = 1.0e-6_wp, atol = 1.0e-8_wp
  character(len=:), allocatable :: tgv_text
  integer :: k

  tgv_text = file_text('inputs/tgv_vehicle_straight.nml') // yaw_damper
  k = index(tgv_text, "equilibrium = 'preload'")
  tgv_text = tgv_text(:k - 1) // "equilibrium = 'none'" // tgv_text(k + 23:)
  call test_layout()
  call test_runs()
  call test_summary('test_scene_velocity_tolerance')

contains

  subroutine test_layout()
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    real(wp), allocatable :: tol(:)
    logical, allocatable :: seen(:)
    integer :: ib, dof, slot, n
    call scene%load_string(tgv_text, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    call stop_on(error, 'TGV deck with a yaw damper')
    mbs => scene%system()
    tol = mbs%absolute_tolerances(1.0e-8_wp, 3.0e-6_wp)
    n = mbs%state_size()
    call check(size(tol) == n, 'layout: one tolerance per state component')
    allocate (seen(n), source=.false.)
    do ib = 1, mbs%body_count()
      do dof = 1, 6
        slot = mbs%free_slot(ib, dof)
        if (slot == 0) cycle
        call check(tol(slot) == 1.0e-8_wp, 'layout: a coordinate slot gets atol')
        call check(tol(mbs%nfree + slot) == 3.0e-6_wp, 'layout: its rate slot (nfree + slot) gets atol_velocity')
        seen([slot, mbs%nfree + slot]) = .true.
      end do
    end do
    call check(count(seen) == 2 * mbs%nfree, 'layout: every coordinate and rate slot reached through free_slot')
    call check(n - 2 * mbs%nfree == 1, 'layout: one element state (the series yaw damper)')
    call check(all(tol(2 * mbs%nfree + 1:) == 1.0e-8_wp), 'layout: the element state gets atol')
    call scene%destroy()
  end subroutine test_layout

  subroutine test_runs()
    real(wp), allocatable :: y_scalar(:), y_same(:), y_loose(:), y_ref(:), tol_v(:)
    type(integrator_stats_t) :: st_scalar, st_same, st_loose, st_ref
    real(wp) :: err_scalar, err_loose
    integer :: nfree
    call run_to("rtol = 1e-6, atol = 1e-8", y_scalar, st_scalar, nfree)
    call run_to("rtol = 1e-6, atol = 1e-8, atol_velocity = 1e-8", y_same, st_same, nfree)
    call run_to("rtol = 1e-6, atol = 1e-8, atol_velocity = 1e-6", y_loose, st_loose, nfree)
    call run_to("rtol = 1e-10, atol = 1e-12", y_ref, st_ref, nfree)
    write (*, '(a, 3i8)') 'TGV + yaw damper to 0.3 s, steps: scalar atol, atol_velocity = atol, = 100 atol: ', &
      st_scalar%steps, st_same%steps, st_loose%steps
    call check(all(y_same == y_scalar) .and. st_same%steps == st_scalar%steps, &
               'atol_velocity = atol: bit-identical to the scalar tolerance (state and steps)')
    call check(any(y_loose /= y_scalar), 'atol_velocity = 100 atol changes the state: it reaches the integrator')
    call check(st_loose%steps < st_scalar%steps, 'atol_velocity = 100 atol takes fewer steps')
    ! (c) errors in units of each run's own local tolerance
    allocate (tol_v(size(y_ref)), source=atol)
    tol_v(nfree + 1:2 * nfree) = 1.0e-6_wp
    err_scalar = norm2((y_scalar - y_ref) / (rtol * abs(y_ref) + atol)) / sqrt(real(size(y_ref), wp))
    err_loose = norm2((y_loose - y_ref) / (rtol * abs(y_ref) + tol_v)) / sqrt(real(size(y_ref), wp))
    write (*, '(a, 2f9.3)') 'weighted RMS error / local tolerance vs rtol 1e-10: scalar atol, atol_velocity = 100 atol: ', &
      err_scalar, err_loose
    call check(err_loose <= 5.0_wp * err_scalar, &
               'atol_velocity = 100 atol: within 5x the scalar run''s error, each in its own tolerance units (WRMS)')
  end subroutine test_runs

  subroutine run_to(tolerances, y, stats, nfree)
    character(len=*), intent(in) :: tolerances
    real(wp), allocatable, intent(out) :: y(:)
    type(integrator_stats_t), intent(out) :: stats
    integer, intent(out) :: nfree
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    character(len=:), allocatable :: text
    integer :: k
    text = tgv_text
    k = index(text, "&solver method = 'bdf'")
    call check(k > 0, 'TGV deck: &solver line found')
    text = text(:k + 7) // "method = 'bdf', " // tolerances // " /" // &
           new_line('a') // '!' // text(k + 8:) // new_line('a')
    call scene%load_string(text, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    if (.not. allocated(error)) call scene%advance(0.3_wp, error)
    call stop_on(error, 'TGV run with ' // tolerances)
    mbs => scene%system()
    nfree = mbs%nfree
    allocate (y(scene%state_size()))
    call scene%get_state(y, error)
    call stop_on(error, 'state')
    call scene%integrator_stats(stats)
    call scene%destroy()
  end subroutine run_to
end program test_scene_velocity_tolerance
