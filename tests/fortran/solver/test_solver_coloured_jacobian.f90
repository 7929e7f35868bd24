!> Coloured difference-quotient Jacobians (rd_coloured_jacobian) on a chain of m masses
!> joined by cubic springs and dampers (x_i'' = s(x_{i+1} - x_i) - s(x_i - x_{i-1})
!> - c v_i, s(d) = k d + k3 d^3, ends fixed), whose Jacobian is known in closed form
!> and banded: the column of x_i touches the rows v_{i-1}, v_i, v_{i+1}, the column of v_i
!> the rows x_i, v_i. Masses three apart share no row, so 3 colours x 2 states = 6 RHS
!> calls per Jacobian for any m (the pattern is written here, independently of the scene).
!>  1. the pattern builder refuses two columns of one group that share a row;
!>  2. coloured Jacobian = analytic Jacobian within the forward-difference error bound
!>     |f''| inc / 2 + |f'''| inc^2 / 6 (exact Taylor remainder of the cubic) plus the
!>     round-off 4 eps |f| / inc, and exactly zero outside the pattern;
!>  3. BDF with the coloured Jacobian vs CVODE's dense difference quotients: same solution
!>     within the integration tolerance (both against a tight-tolerance reference),
!>     6 RHS calls per Jacobian counted in rhs_evals_jacobian.
program test_solver_coloured_jacobian
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_coloured_jacobian, only: jacobian_sparsity_t, build_jacobian_sparsity, &
                                  dq_minimum_increment, dq_increment
  use rd_rhs_context, only: rhs_context_t, RHS_OK
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t
  use rd_chain_test_problem, only: chain_t, chain_jacobian, spring, pos, m, n, k_cub, c_damp
  use rd_test_support, only: check, test_summary
  implicit none

  type(chain_t), target :: chain
  type(jacobian_sparsity_t) :: sparsity
  type(error_t), allocatable :: error

  call build_chain_sparsity(sparsity)
  call test_refuses_overlap()
  call test_against_analytic()
  call test_integration()
  call test_summary('test_solver_coloured_jacobian')

contains

  !> Colour of mass i: mod(i - 1, 3) + 1; group 2 (colour - 1) + 1 holds the x columns
  !> of that colour, the next group the v columns.
  subroutine build_chain_sparsity(sp)
    type(jacobian_sparsity_t), intent(out) :: sp
    integer :: column_group(n), row_start(n + 1), i
    integer, allocatable :: rows(:)
    allocate (rows(0))
    row_start(1) = 1
    do i = 1, m                 ! x columns
      column_group(i) = 2 * mod(i - 1, 3) + 1
      if (i > 1) rows = [rows, m + i - 1]
      rows = [rows, m + i]
      if (i < m) rows = [rows, m + i + 1]
      row_start(i + 1) = size(rows) + 1
    end do
    do i = 1, m                 ! v columns
      column_group(m + i) = 2 * mod(i - 1, 3) + 2
      rows = [rows, i, m + i]
      row_start(m + i + 1) = size(rows) + 1
    end do
    call build_jacobian_sparsity(sp, column_group, row_start, rows, error)
    call check(.not. allocated(error), 'the chain pattern was refused')
    call check(sp%n_groups == 6, 'the chain pattern does not have 6 groups')
  end subroutine build_chain_sparsity

  !> Masses two apart share the row of the mass between them: one group must be refused.
  subroutine test_refuses_overlap()
    type(jacobian_sparsity_t) :: bad
    integer :: column_group(n), row_start(n + 1), i
    column_group = [(2 * mod(i - 1, 2) + 1, i = 1, m), (2 * mod(i - 1, 2) + 2, i = 1, m)]
    row_start = sparsity%row_start
    call build_jacobian_sparsity(bad, column_group, row_start, sparsity%rows, error)
    call check(allocated(error), 'two colours on a chain were accepted (masses i, i+2 share a row)')
    if (allocated(error)) then
      write (*, '(a)') 'refused as expected: ' // error%message
      call check(index(error%message, 'disjoint') > 0, 'the refusal does not say what is expected')
    end if
  end subroutine test_refuses_overlap

  subroutine test_against_analytic()
    type(rhs_context_t) :: context
    real(wp) :: y(n), fy(n), ewt(n), y_work(n), f_work(n), jac(n, n), exact(n, n)
    real(wp) :: h, min_inc, inc, bound, d2, d3, worst, row_scale(n)
    integer :: i, j, status, calls_before
    real(wp), parameter :: rtol = 1.0e-6_wp, atol = 1.0e-9_wp

    ! a generic state: stretched springs (the cubic matters) and moving masses
    do i = 1, m
      y(i) = 1.0e-3_wp * sin(1.3_wp * i)
      y(m + i) = 0.05_wp * cos(0.7_wp * i)
    end do
    context%system => chain
    allocate (context%sparsity, source=sparsity)
    status = context%evaluate_rhs(0.0_wp, y, fy)
    ewt = 1.0_wp / (rtol * abs(y) + atol)       ! CVODE's error weights
    h = 1.0e-4_wp
    calls_before = chain%calls
    status = context%evaluate_coloured_jacobian(0.0_wp, y, fy, h, ewt, y_work, f_work, jac)
    call check(status == RHS_OK, 'coloured Jacobian failed')
    call check(chain%calls - calls_before == 6, 'coloured Jacobian did not take 6 RHS calls')
    call check(context%rhs_evals_jacobian == 6, 'rhs_evals_jacobian is not 6')
    exact = chain_jacobian(y)
    min_inc = dq_minimum_increment(h, fy, ewt)
    ! round-off of one RHS value: eps times the sum of its terms' magnitudes
    do i = 1, m
      row_scale(i) = abs(y(m + i))
      row_scale(m + i) = abs(spring(pos(y, i + 1) - y(i))) + abs(spring(y(i) - pos(y, i - 1))) &
                         + c_damp * abs(y(m + i))
    end do
    worst = 0.0_wp
    do j = 1, n
      inc = dq_increment(y(j), ewt(j), min_inc)
      do i = 1, n
        if (.not. sparsity%in_pattern(i, j)) then
          call check(jac(i, j) == 0.0_wp .and. exact(i, j) == 0.0_wp, &
                     'non-zero outside the pattern')
          cycle
        end if
        ! Taylor remainder of the cubic spring force along y_j: f'' and f''' of the row
        d2 = 0.0_wp
        d3 = 0.0_wp
        if (i > m .and. j <= m) then
          d2 = 6.0_wp * k_cub * (abs(pos(y, i - m + 1) - y(i - m)) + abs(y(i - m) - pos(y, i - m - 1)))
          d3 = 12.0_wp * k_cub
        end if
        bound = 0.5_wp * d2 * inc + d3 * inc**2 / 6.0_wp + 4.0_wp * epsilon(1.0_wp) * row_scale(i) / inc
        worst = max(worst, abs(jac(i, j) - exact(i, j)) / bound)
        call check(abs(jac(i, j) - exact(i, j)) <= bound, 'coloured entry outside the FD error bound')
      end do
    end do
    write (*, '(a, es10.3)') 'coloured vs analytic: largest error / FD bound = ', worst
  end subroutine test_against_analytic

  subroutine test_integration()
    real(wp) :: y0(n), y_ref(n), y_col(n), y_dense(n), err_col, err_dense, scale
    type(integrator_stats_t) :: st_col, st_dense
    integer :: i
    do i = 1, m
      y0(i) = 2.0e-3_wp * sin(0.9_wp * i)
      y0(m + i) = 0.0_wp
    end do
    call run(y0, 1.0e-11_wp, 'dense', y_ref)
    call run(y0, 1.0e-6_wp, 'dense', y_dense, st_dense)
    call run(y0, 1.0e-6_wp, 'coloured', y_col, st_col)
    scale = maxval(abs(y0(1:m)))
    err_dense = maxval(abs(y_dense(1:m) - y_ref(1:m))) / scale
    err_col = maxval(abs(y_col(1:m) - y_ref(1:m))) / scale
    write (*, '(a, 2es11.3)') 'relative position error at t = 0.2 s (dense, coloured): ', err_dense, err_col
    write (*, '(a, 2i7)') 'jacobian evals (dense, coloured):          ', st_dense%jacobian_evals, st_col%jacobian_evals
    write (*, '(a, 2i7)') 'rhs evals for jacobians (dense, coloured): ', st_dense%rhs_evals_jacobian, &
      st_col%rhs_evals_jacobian
    ! rtol 1e-6 over ~10 periods of the stiffest mode: within 1e-4 of the amplitude
    call check(err_col < 1.0e-4_wp, 'coloured run off the reference')
    call check(err_dense < 1.0e-4_wp, 'dense run off the reference')
    call check(st_col%rhs_evals_jacobian == 6 * st_col%jacobian_evals, &
               'coloured: rhs_evals_jacobian is not 6 per Jacobian')
    call check(st_dense%rhs_evals_jacobian == n * st_dense%jacobian_evals, &
               'dense: rhs_evals_jacobian is not n per Jacobian')
  end subroutine test_integration

  subroutine run(y0, rtol, jacobian, y, stats)
    real(wp), intent(in) :: y0(:), rtol
    character(len=*), intent(in) :: jacobian
    real(wp), intent(out) :: y(:)
    type(integrator_stats_t), intent(out), optional :: stats
    type(integrator_t) :: integ
    type(integrator_settings_t) :: settings
    settings%method = 'bdf'
    settings%rtol = rtol
    settings%atol = rtol * 1.0e-3_wp
    if (jacobian == 'coloured') then
      call integ%build(chain, 0.0_wp, y0, settings, error, jacobian_sparsity=sparsity)
    else
      call integ%build(chain, 0.0_wp, y0, settings, error)
    end if
    call check(.not. allocated(error), 'integrator build failed')
    y = y0
    call integ%advance(0.2_wp, y, error)
    call check(.not. allocated(error), 'advance failed')
    if (allocated(error)) write (*, '(a)') error%message
    if (present(stats)) call integ%get_stats(stats)
    call integ%destroy()
  end subroutine run

end program test_solver_coloured_jacobian
