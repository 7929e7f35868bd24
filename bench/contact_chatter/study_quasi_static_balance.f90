!> The quasi-static balance of one wheelset at a scene's state (docs/theory_flange_chatter.md
!> section 12): advances DECK to T (or reads the state 't y1 ... yn' from STUDY_STATE_FILE),
!> solves the balance there as the right-hand side does, then
!> - prints the wheelset's pose, its wheels' forces and contact points at the solution;
!> - maps the residual (z'', roll'') of wheelset W over a grid of (z, roll) about the solution
!>   (+-DZ, +-DROLL, N x N points; the other wheelsets at their solution), and prints
!>   per grid point the residual and the determinant of its forward-difference Jacobian
!>   (a fold of the balance: det J changes sign);
!> - solves the balance again from every grid point as a start (the solve's warm start) and
!>   prints the distinct solutions reached: more than one means the right-hand side depends
!>   on where the previous evaluation left the solve.
!>
!>   study_quasi_static_balance DECK T W [DZ DROLL N]     (defaults 1e-4 m, 2e-3 rad, 9)
program study_quasi_static_balance
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  use rd_body_spec, only: DOF_Y, DOF_Z, DOF_YAW, DOF_ROLL
  use study_support, only: start_scene, stop_on
  use rd_multibody, only: multibody_t
  implicit none
  type(scene_t) :: scene
  type(error_t), allocatable :: error
  type(multibody_t), pointer :: mbs
  character(len=512) :: deck, arg, state_file
  real(wp) :: t, dz, droll, h
  real(wp), allocatable :: y(:), ydot(:), zr0(:, :), zr(:, :), r(:, :), rp(:, :), sols(:, :)
  integer :: w, n, nb, i, j, k, stat, unit, nsol, c
  logical :: found
  real(wp) :: jac(2, 2), det

  call get_command_argument(1, deck)
  call get_command_argument(2, arg); read (arg, *) t
  call get_command_argument(3, arg); read (arg, *) w
  dz = 1.0e-4_wp; droll = 2.0e-3_wp; n = 9
  if (command_argument_count() >= 6) then
    call get_command_argument(4, arg); read (arg, *) dz
    call get_command_argument(5, arg); read (arg, *) droll
    call get_command_argument(6, arg); read (arg, *) n
  end if
  call start_scene(trim(deck), scene)
  state_file = ''
  call get_environment_variable('STUDY_STATE_FILE', state_file, status=stat)
  allocate (y(scene%state_size()), ydot(scene%state_size()))
  if (stat == 0 .and. len_trim(state_file) > 0) then
    open (newunit=unit, file=trim(state_file), status='old', action='read')
    read (unit, *) t, y
    close (unit)
  else
    call scene%advance(t, error); call stop_on(error)
    call scene%get_state(y, error); call stop_on(error)
    t = scene%time()
  end if
  mbs => scene%system()
  nb = mbs%body_count()
  allocate (zr0(2, nb), zr(2, nb), r(2, nb), rp(2, nb), sols(2, n * n))
  call mbs%rhs(t, y, ydot, error); call stop_on(error)
  zr0 = reshape([(mbs%bodies(i)%q0([DOF_Z, DOF_ROLL]), i = 1, nb)], [2, nb])
  print '(a, f0.6, a, i0)', 'state at t = ', t, ' s, wheelset body ', w
  print '(a, 4es14.6)', 'y [m], yaw [rad], solved z [m], roll [rad]: ', mbs%scratch%kin(w)%q(DOF_Y), mbs%scratch%kin(w)%q(DOF_YAW), &
    zr0(:, w)
  call mbs%quasi_static_balance(t, y, zr0, r, error); call stop_on(error)
  print '(a, 2es12.4)', 'residual at the solution (z'''', roll''''): ', r(:, w)
  print '(a)', 'grid: dz [m]  droll [rad]  z'''' [m/s2]  roll'''' [rad/s2]  det J'
  h = 1.0e-8_wp
  nsol = 0
  do j = 1, n
    do i = 1, n
      zr = zr0
      zr(1, w) = zr0(1, w) + dz * (2 * real(i - 1, wp) / (n - 1) - 1)
      zr(2, w) = zr0(2, w) + droll * (2 * real(j - 1, wp) / (n - 1) - 1)
      call mbs%quasi_static_balance(t, y, zr, r, error); call stop_on(error)
      do c = 1, 2
        zr(c, w) = zr(c, w) + h
        call mbs%quasi_static_balance(t, y, zr, rp, error); call stop_on(error)
        jac(:, c) = (rp(:, w) - r(:, w)) / h
        zr(c, w) = zr(c, w) - h
      end do
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      print '(2es12.4, 3es14.5)', zr(:, w) - zr0(:, w), r(:, w), det
      ! the solve from this start: the right-hand side with q0 = this grid point
      call mbs%quasi_static_balance(t, y, zr, r, error); call stop_on(error)
      mbs%qs_jacobian_valid = .false.
      call mbs%rhs(t, y, ydot, error)
      if (allocated(error)) then
        print '(a)', '  solve from here: ' // error%message
        deallocate (error)
        cycle
      end if
      found = .false.
      do k = 1, nsol
        if (abs(sols(1, k) - mbs%bodies(w)%q0(DOF_Z)) < 1.0e-9_wp .and. &
            abs(sols(2, k) - mbs%bodies(w)%q0(DOF_ROLL)) < 1.0e-8_wp) found = .true.
      end do
      if (.not. found) then
        nsol = nsol + 1
        sols(:, nsol) = mbs%bodies(w)%q0([DOF_Z, DOF_ROLL])
      end if
    end do
  end do
  print '(a, i0)', 'distinct solutions reached from the grid starts: ', nsol
  do k = 1, nsol
    zr = zr0
    zr(:, w) = sols(:, k)
    call mbs%quasi_static_balance(t, y, zr, r, error); call stop_on(error)
    print '(a, 2es16.8, a, 2es11.3)', '  z, roll - solution: ', sols(:, k) - zr0(:, w), '   residual ', r(:, w)
  end do
  call scene%destroy()
end program study_quasi_static_balance
