!> The scene's coloured Jacobian (rd_scene_jacobian + rd_coloured_jacobian) on real decks:
!>  (c) the coupling graph of Manchester vehicle 1 (inputs/manchester_v1_tc1_elastic.nml) colours
!>      into {car}, {bogie1, ws3}, {bogie2, ws1}, {ws2, ws4}: 4 groups, 10 + 3 x 12 = 46
!>      RHS calls per Jacobian (the car's x is frozen) instead of 82;
!>  (a) on the 7-body TGV 001 vehicle (inputs/tgv_vehicle_straight.nml) at a perturbed
!>      static state (loaded wheel-rail contact), and on the same vehicle with a series yaw
!>      damper (an element with an internal state; equilibrium 'none': the state is
!>      perturbed anyway; the static solve with it is tested in test_scene_static_equilibrium),
!>      and on the same vehicle on flexible track (rail bodies on pads under wheelsets 1
!>      and 3: the contact couples each wheelset with its two rail bodies),
!>      the coloured Jacobian equals
!>      1. a dense forward-difference Jacobian written here with CVODE's increments, column
!>         by column, to the round-off of the two RHS values (a missed coupling would add
!>         another column's derivative, O(J)); the dense one is exactly zero outside the
!>         pattern;
!>      2. with increments delta_j = 1e-6 max(|y_j|, 0.1) (set through the error weights),
!>         a dense central-difference Jacobian within 2x the difference-quotient error
!>         estimated from the same differences at twice the step (first order forward,
!>         second order central) plus the round-off of fixed-frame kinematics; the central
!>         one is exactly zero outside the pattern;
!>  (b) the TGV vehicle run to 0.3 s (through a lateral force pulse) with &solver
!>      jacobian = 'coloured' and 'dense' (CVODE's own DQ): the two differ by no more than
!>      twice the dense run's integration error (against rtol 1e-10), the coloured run is as
!>      accurate, and it takes 46 instead of 82 RHS calls per Jacobian. The errors are
!>      taken over 5 starts that differ only by the rounding of the static solve (the car
!>      placed 0..4 um higher before it; the solve brings it to the same equilibrium within
!>      1e-15 m): from one start the two adaptive runs' global errors scatter by chance
!>      (measured, coloured / dense: 210/88, 77/281, 86/126, 180/45, 100/115 tolerance
!>      units), so one start could pass or fail the factor 2 on a rounding change; the
!>      largest over the starts does not.
program test_scene_coloured_jacobian
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary, file_text
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_scene_jacobian, only: body_coupling_t, multibody_coupling, distance2_colouring, &
                               scene_jacobian_sparsity
  use rd_coloured_jacobian, only: jacobian_sparsity_t, dq_minimum_increment, dq_increment
  use rd_rhs_context, only: rhs_context_t, RHS_OK
  use rd_integrator, only: integrator_stats_t
  implicit none

  character(len=*), parameter :: yaw_damper = new_line('a') // &
    "&element name = 'yawdamper1', type = 'series_spring_damper', body1 = 'car', " // &
    "body2 = 'bogie1', point1 = 11.85, 1.3, -0.7, point2 = -0.5, 1.3, 0.2, " // &
    "damping = 2.0e5, 0.0, 0.0, series_stiffness = 8.0e6 /" // new_line('a')
  character(len=:), allocatable :: tgv_text, damper_text, rails_text
  integer :: k

  tgv_text = file_text('inputs/tgv_vehicle_straight.nml')
  damper_text = tgv_text // yaw_damper
  k = index(damper_text, "equilibrium = 'preload'")
  damper_text = damper_text(:k - 1) // "equilibrium = 'none'" // damper_text(k + 23:)
  call test_manchester_colouring()
  call test_jacobian_against_dense(tgv_text, 'TGV', 82)
  call test_jacobian_against_dense(damper_text, 'TGV + yaw damper', 83)
  rails_text = tgv_text // rail_bodies('ws1', 'w1') // rail_bodies('ws3', 'w3')
  call test_jacobian_against_dense(rails_text, 'TGV + rail bodies', 98)
  call test_runs_agree()
  call test_summary('test_scene_coloured_jacobian')

contains

  !> Flexible track under wheelset `ws` (&wheelset `w`): two rail bodies in its frame on
  !> lateral and vertical pads (the contact couples the wheelset with both).
  function rail_bodies(ws, w) result(text)
    character(len=*), intent(in) :: ws, w
    character(len=:), allocatable :: text
    character, parameter :: nl = new_line('a')
    text = nl
    text = text // "&body name = '" // ws // "_rl', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, " // &
      "frame = '" // ws // "', frozen = 'x', 'yaw', 'roll', 'pitch' /" // nl // &
      "&body name = '" // ws // "_rr', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, " // &
      "frame = '" // ws // "', frozen = 'x', 'yaw', 'roll', 'pitch' /" // nl // &
      "&element name = '" // ws // "_pad_l', type = 'spring_damper', body1 = 'ground', body2 = '" // ws // &
      "_rl', stiffness = 0.0, 5e7, 1e8, damping = 0.0, 2e4, 5e4 /" // nl // &
      "&element name = '" // ws // "_pad_r', type = 'spring_damper', body1 = 'ground', body2 = '" // ws // &
      "_rr', stiffness = 0.0, 5e7, 1e8, damping = 0.0, 2e4, 5e4 /" // nl // &
      "&wheelset name = '" // w // "', left_rail_body = '" // ws // "_rl', right_rail_body = '" // ws // "_rr' /" // nl
  end function rail_bodies

  ! ---------------------------------------------------------------- (c)
  subroutine test_manchester_colouring()
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    type(body_coupling_t) :: coupling
    type(jacobian_sparsity_t) :: sparsity
    character(len=:), allocatable :: dense_reason
    integer, allocatable :: colour(:)
    integer :: n_colours
    ! deck order: car, bogie1, bogie2, ws1, ws2, ws3, ws4
    integer, parameter :: expected(7) = [1, 2, 3, 3, 4, 2, 4]

    call scene%load_file('inputs/manchester_v1_tc1_elastic.nml', error)
    if (.not. allocated(error)) call scene%build(error)
    call stop_on(error, 'Manchester deck')
    mbs => scene%system()
    call multibody_coupling(mbs, coupling)
    call check(.not. allocated(coupling%dense_reason), 'Manchester: a provider without stated coupling')
    call check(coupling%n_nodes == 7, 'Manchester: expected 7 nodes (bodies, no element states)')
    allocate (colour(coupling%n_nodes))
    call distance2_colouring(coupling%adjacent, colour, n_colours)
    write (*, '(a, 7i3)') 'Manchester colours (car, bogie1, bogie2, ws1..ws4):', colour
    call check(n_colours == 4, 'Manchester: not 4 colours')
    call check(all(colour == expected), 'Manchester: not {car}, {bogie1, ws3}, {bogie2, ws1}, {ws2, ws4}')
    call scene_jacobian_sparsity(mbs, sparsity, dense_reason, error)
    call stop_on(error, 'Manchester sparsity')
    write (*, '(a, i0, a, i0)') 'Manchester: RHS calls per Jacobian ', sparsity%n_groups, &
      ' (dense: ', mbs%state_size()
    call check(sparsity%n_groups == 46 .and. mbs%state_size() == 82, &
               'Manchester: expected 46 column groups for 82 states')
    call scene%destroy()
  end subroutine test_manchester_colouring

  ! ---------------------------------------------------------------- (a)
  subroutine test_jacobian_against_dense(text, label, n_expected)
    character(len=*), intent(in) :: text, label
    integer, intent(in) :: n_expected
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    type(jacobian_sparsity_t) :: sparsity
    type(rhs_context_t) :: context
    character(len=:), allocatable :: dense_reason
    real(wp), allocatable :: y(:), fy(:), ewt(:), yw(:), fw(:), jac(:, :), fwd(:, :), cd1(:, :), &
                             cd2(:, :), fwd2(:, :), delta(:), term_size(:)
    real(wp) :: h, min_inc, inc, tol, worst_fwd, worst_cd, est, roundoff, a1, a2, magnitude
    integer :: n, i, j, k, status, outside, inside_nonzero, kinks
    logical :: ok_fwd, ok_cd, ok_pattern

    call scene%load_string(text, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, label // ' deck')
    mbs => scene%system()
    n = mbs%state_size()
    call check(n == n_expected, label // ': unexpected state size')
    allocate (y(n), fy(n), ewt(n), yw(n), fw(n), jac(n, n), fwd(n, n), fwd2(n, n), cd1(n, n), &
              cd2(n, n), delta(n), term_size(n))
    call scene%get_state(y, error)
    ! a generic state near the static one: small offsets of every coordinate and rate
    do i = 1, n
      y(i) = y(i) + 1.0e-4_wp * sin(1.7_wp * i)
    end do
    call scene_jacobian_sparsity(mbs, sparsity, dense_reason, error)
    call stop_on(error, label // ' sparsity')
    call check(.not. allocated(dense_reason), label // ': fell back to dense')
    write (*, '(a, i0, a, i0, a)') label // ': ', n, ' states, ', sparsity%n_groups, &
      ' RHS calls per Jacobian'
    call check(sparsity%n_groups < n, label // ': colouring saves nothing')

    context%system => mbs
    allocate (context%sparsity, source=sparsity)
    status = context%evaluate_rhs(0.0_wp, y, fy)
    call check(status == RHS_OK, label // ': RHS failed at the test state')
    ewt = 1.0_wp / (1.0e-6_wp * abs(y) + 1.0e-8_wp)    ! CVODE's weights at the deck's rtol, atol
    h = 1.0e-4_wp
    status = context%evaluate_coloured_jacobian(0.0_wp, y, fy, h, ewt, yw, fw, jac)
    call check(status == RHS_OK, label // ': coloured Jacobian failed')
    call check(context%rhs_evals_jacobian == sparsity%n_groups, label // ': not one RHS call per group')

    ! 1. dense forward differences with the same (CVODE's) increments: the coloured
    !    entry must be the dense one up to the round-off of the two RHS values it is made
    !    of (a missed coupling would add another column's derivative, O(J)); outside the
    !    pattern the dense differences must be exactly zero.
    min_inc = dq_minimum_increment(h, fy, ewt)
    ok_fwd = .true.; ok_pattern = .true.
    worst_fwd = 0
    outside = 0
    do j = 1, n
      inc = dq_increment(y(j), ewt(j), min_inc)
      fwd(:, j) = column_difference(context, y, fy, j, inc, yw, fw) / inc
      do i = 1, n
        tol = 4.0_wp * epsilon(1.0_wp) * (abs(fy(i)) + abs(fy(i) + fwd(i, j) * inc)) / inc
        if (abs(jac(i, j) - fwd(i, j)) > tol) ok_fwd = .false.
        worst_fwd = max(worst_fwd, abs(jac(i, j) - fwd(i, j)))
        if (.not. sparsity%in_pattern(i, j)) then
          outside = outside + 1
          if (jac(i, j) /= 0.0_wp .or. fwd(i, j) /= 0.0_wp) ok_pattern = .false.
        end if
      end do
    end do

    ! 2. central differences. CVODE's increments are tiny where y_j is small (round-off
    !    dominated), so the coloured Jacobian is taken again with increments delta_j set
    !    through its error weights: ewt_j = w / delta_j and h chosen so that
    !    min_inc = 1000 |h| uround n ||fy||_WRMS(ewt) = w, i.e. min_inc / ewt_j = delta_j.
    do j = 1, n
      delta(j) = 1.0e-6_wp * max(abs(y(j)), 0.1_wp)
    end do
    ewt = 1.0_wp / delta
    h = 1.0_wp / (1000.0_wp * epsilon(1.0_wp) * n * sqrt(sum((fy * ewt)**2) / n))
    min_inc = dq_minimum_increment(h, fy, ewt)
    status = context%evaluate_coloured_jacobian(0.0_wp, y, fy, h, ewt, yw, fw, jac)
    call check(status == RHS_OK, label // ': coloured Jacobian (controlled increments) failed')
    do j = 1, n
      inc = dq_increment(y(j), ewt(j), min_inc)
      fwd2(:, j) = column_difference(context, y, fy, j, 2.0_wp * inc, yw, fw) / (2.0_wp * inc)
      cd1(:, j) = (column_difference(context, y, fy, j, inc, yw, fw) - &
                   column_difference(context, y, fy, j, -inc, yw, fw)) / (2.0_wp * inc)
      cd2(:, j) = (column_difference(context, y, fy, j, 2.0_wp * inc, yw, fw) - &
                   column_difference(context, y, fy, j, -2.0_wp * inc, yw, fw)) / (4.0_wp * inc)
    end do
    ! Round-off of f_i: eps times the size of its terms. The kinematics are evaluated in
    ! fixed-frame coordinates (positions ~ the distance L from the origin, speeds ~ V,
    ! spin ~ V / r0), so a state enters f_i with an absolute rounding ~ eps max(|y_k|, L):
    ! terms ~ |f_i| + sum_k |J_ik| max(|y_k|, L).
    magnitude = 0
    do k = 1, mbs%body_count()
      magnitude = max(magnitude, norm2(mbs%scratch%kin(k)%r), norm2(mbs%scratch%kin(k)%v), norm2(mbs%scratch%kin(k)%omega))
    end do
    do i = 1, n
      term_size(i) = abs(fy(i)) + sum(abs(cd1(i, :)) * max(abs(y), magnitude))
    end do
    ok_cd = .true.
    worst_cd = 0
    inside_nonzero = 0
    kinks = 0
    do j = 1, n
      inc = dq_increment(y(j), ewt(j), min_inc)
      do i = 1, n
        if (.not. sparsity%in_pattern(i, j)) then
          if (cd1(i, j) /= 0.0_wp .or. cd2(i, j) /= 0.0_wp) then
            ok_pattern = .false.
            write (*, '(a, 2i4, es12.4)') 'central difference non-zero outside the pattern at ', i, j, cd1(i, j)
          end if
          cycle
        end if
        if (cd1(i, j) /= 0.0_wp) inside_nonzero = inside_nonzero + 1
        ! Forward (coloured) F1 = jac at step inc, F2 at 2 inc; backward B = 2 cd - F.
        ! Smooth along y_j: F1 - f' = f'' inc / 2 + O(inc^2), estimated by |F1 - F2|; the
        ! central error by |cd1 - cd2| / 3 (second order). The asymmetry A = F - B is
        ! f'' step there (A2 = 2 A1); at a slope kink (the piecewise-linear profile and
        ! force tables) it is the slope jump whatever the step (A2 = A1), and the forward
        ! difference is the one-sided slope, |A1| / 2 away from the central one.
        roundoff = 8.0_wp * epsilon(1.0_wp) * term_size(i) / inc
        a1 = jac(i, j) - (2.0_wp * cd1(i, j) - jac(i, j))
        a2 = fwd2(i, j) - (2.0_wp * cd2(i, j) - fwd2(i, j))
        est = abs(jac(i, j) - fwd2(i, j)) + abs(cd1(i, j) - cd2(i, j)) / 3.0_wp + roundoff
        if (abs(a1) > 4.0_wp * roundoff .and. abs(a2 - a1) < 0.25_wp * abs(a1)) then
          kinks = kinks + 1
          est = est + 0.5_wp * abs(a1)
        end if
        if (abs(jac(i, j) - cd1(i, j)) > 2.0_wp * est) then
          ok_cd = .false.
          write (*, '(a, 2i4, 5es12.4)') 'coloured vs central at ', i, j, jac(i, j), cd1(i, j), est, a1, a2
        end if
        if (est > 0) worst_cd = max(worst_cd, abs(jac(i, j) - cd1(i, j)) / est)
      end do
    end do
    write (*, '(a, es10.3)') label // ': max |coloured - dense forward (same increments)| = ', worst_fwd
    write (*, '(a, f7.3)') label // ': max |coloured - central| / estimated FD error = ', worst_cd
    write (*, '(a, i0, a, i0, a)') label // ': ', outside, ' entries outside the pattern, ', &
      inside_nonzero, ' non-zero inside'
    write (*, '(a, i0)') label // ': entries at a slope kink (one-sided = forward) ', kinks
    call check(ok_fwd, label // ': coloured differs from the dense forward differences beyond round-off')
    call check(ok_cd, label // ': coloured differs from the central differences beyond the FD error')
    call check(ok_pattern, label // ': a non-zero derivative outside the pattern')
    call scene%destroy()
  end subroutine test_jacobian_against_dense

  !> f(y + step e_j) - f(y) (yw, fw scratch)
  function column_difference(context, y, fy, j, step, yw, fw) result(df)
    type(rhs_context_t), intent(inout) :: context
    real(wp), intent(in) :: y(:), fy(:)
    integer, intent(in) :: j
    real(wp), intent(in) :: step
    real(wp), intent(inout) :: yw(:), fw(:)
    real(wp) :: df(size(y))
    yw = y
    yw(j) = y(j) + step
    if (context%evaluate_rhs(0.0_wp, yw, fw) /= RHS_OK) &
      call check(.false., 'RHS failed in a dense difference')
    df = fw - fy
  end function column_difference

  ! ---------------------------------------------------------------- (b)
  subroutine test_runs_agree()
    real(wp), allocatable :: y_col(:), y_dense(:), y_ref(:)
    type(integrator_stats_t) :: st_col, st_dense, st_ref
    real(wp) :: diff, err_col, err_dense
    real(wp), parameter :: rtol = 1.0e-6_wp, atol = 1.0e-8_wp

    character(len=80) :: start
    integer :: i_start

    diff = 0
    err_col = 0
    err_dense = 0
    do i_start = 4, 0, -1
      ! the deck's car height 1.5 m raised by i_start um before the static solve
      write (start, '(a, f14.11, a)') "&body name = 'car', position = 0.0, 0.0, ", &
        1.5_wp + i_start * 1.0e-6_wp, " /"
      call run_to('coloured', "rtol = 1e-6", y_col, st_col, trim(start))
      call run_to('dense', "rtol = 1e-6", y_dense, st_dense, trim(start))
      call run_to('dense', "rtol = 1e-10, atol = 1e-12", y_ref, st_ref, trim(start))
      ! in units of the local tolerance rtol |y| + atol, largest component, largest start
      diff = max(diff, maxval(abs(y_col - y_dense) / (rtol * abs(y_ref) + atol)))
      err_col = max(err_col, maxval(abs(y_col - y_ref) / (rtol * abs(y_ref) + atol)))
      err_dense = max(err_dense, maxval(abs(y_dense - y_ref) / (rtol * abs(y_ref) + atol)))
    end do
    write (*, '(a, 3f9.3)') 'TGV runs to 0.3 s from 5 starts, largest / (rtol |y| + atol): ' // &
      '|coloured - dense|, errors of coloured, dense vs rtol 1e-10: ', diff, err_col, err_dense
    write (*, '(a, 2i8)') 'TGV run: jacobian evals (coloured, dense)          ', st_col%jacobian_evals, &
      st_dense%jacobian_evals
    write (*, '(a, 2i8)') 'TGV run: rhs evals for jacobians (coloured, dense) ', st_col%rhs_evals_jacobian, &
      st_dense%rhs_evals_jacobian
    write (*, '(a, 2i8)') 'TGV run: rhs evals of the method (coloured, dense) ', st_col%rhs_evals, &
      st_dense%rhs_evals
    ! The two runs differ by no more than the integration error of the dense one (a
    ! wrong Jacobian only slows Newton down, so a mild error here means a badly wrong one)
    ! and the coloured run is as accurate as the dense one.
    call check(diff <= 2.0_wp * err_dense, 'TGV run: coloured and dense differ beyond the integration error')
    call check(err_col <= 2.0_wp * err_dense, 'TGV run: the coloured run is less accurate than the dense one')
    call check(st_col%jacobian_evals > 0 .and. st_dense%jacobian_evals > 0, 'TGV run: no Jacobian evaluated')
    call check(st_col%rhs_evals_jacobian == 46 * st_col%jacobian_evals, &
               'TGV run: the coloured Jacobian does not take 46 RHS calls (4 colours)')
    call check(st_dense%rhs_evals_jacobian == size(y_dense) * st_dense%jacobian_evals, &
               'TGV run: the dense run is not CVODE''s own DQ (n RHS calls per Jacobian)')
  end subroutine test_runs_agree

  subroutine run_to(jacobian, tolerances, y, stats, extra)
    character(len=*), intent(in) :: jacobian, tolerances
    character(len=*), intent(in) :: extra    !< deck lines appended
    real(wp), allocatable, intent(out) :: y(:)
    type(integrator_stats_t), intent(out) :: stats
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    character(len=:), allocatable :: text
    integer :: k
    text = tgv_text
    k = index(text, "&solver method = 'bdf'")
    call check(k > 0, 'TGV deck: &solver line not found')
    text = text(:k + 7) // "jacobian = '" // jacobian // "', method = 'bdf', " // tolerances // " /" // &
           new_line('a') // '!' // text(k + 8:) // new_line('a') // extra // new_line('a')
    call scene%load_string(text, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    if (.not. allocated(error)) call scene%advance(0.3_wp, error)
    call stop_on(error, 'TGV run with jacobian = ' // jacobian)
    allocate (y(scene%state_size()))
    call scene%get_state(y, error)
    call scene%integrator_stats(stats)
    call scene%destroy()
  end subroutine run_to
end program test_scene_coloured_jacobian
