!> Linear modes of a scene about its state at a given time (docs/theory_flange_chatter.md):
!> the Jacobian of the right-hand side y' = f(t, y) by central differences, its eigenvalues
!> (LAPACK dgeev), and for every oscillatory mode above a frequency floor its frequency,
!> damping ratio and the two free coordinates that dominate its displacement part.
!>
!>   study_linear_modes DECK T_LIN [F_MIN_HZ [DECK2]]
!>
!> With DECK2 (a deck with the same bodies and states, e.g. another creep law) the state
!> reached by DECK at T_LIN is linearised with DECK2's right-hand side: the same pose seen
!> by two models.
!> A mode with a negative damping ratio grows: the scene's equations are unstable there
!> (flutter), whatever the integrator does.
!> Environment (used by flutter.py): STUDY_STATE_FILE (text 't y1 ... yn': linearise there
!> instead of integrating to T_LIN), STUDY_DUMP_JAC (write nfree and the Jacobian to a file),
!> STUDY_BLOCK_BODY (print that body's acceleration-by-coordinate block and its state slots),
!> STUDY_FD_STEP (the coordinate step, default 2e-9 m or rad).
program study_linear_modes
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  use study_support, only: start_scene, stop_on
  use rd_multibody, only: multibody_t
  implicit none
  type(scene_t) :: scene, scene2
  type(error_t), allocatable :: error
  type(multibody_t), pointer :: mbs
  character(len=512) :: deck, deck2, arg
  real(wp) :: t_lin, f_min, h, h_coord
  integer :: block_body, stat, kk, jj
  character(len=512) :: state_file
  real(wp) :: t_eval
  character(len=64) :: env
  real(wp), allocatable :: y(:), yp(:), fp(:), fm(:), jac(:, :), wr(:), wi(:), vr(:, :), work(:), vl(:, :)
  integer :: n, nfree, j, info, k, order(2), lwork
  character(len=8), parameter :: dof_name(6) = [character(len=8) :: 'x', 'y', 'z', 'yaw', 'roll', 'spin']

  call get_command_argument(1, deck)
  call get_command_argument(2, arg); read (arg, *) t_lin
  f_min = 20
  if (command_argument_count() > 2) then
    call get_command_argument(3, arg); read (arg, *) f_min
  end if
  deck2 = deck
  if (command_argument_count() > 3) call get_command_argument(4, deck2)
  call start_scene(trim(deck), scene)
  ! optional: STUDY_STATE_FILE = text file 't y(1) ... y(n)': linearise there instead of advancing
  state_file = ''
  call get_environment_variable('STUDY_STATE_FILE', state_file, status=stat)
  if (stat == 0 .and. len_trim(state_file) > 0) then
    t_lin = -1
  end if
  if (t_lin > 0) then
    call scene%advance(t_lin, error); call stop_on(error)
  end if
  n = scene%state_size()
  allocate (y(n), yp(n), fp(n), fm(n), jac(n, n), wr(n), wi(n), vr(n, n), vl(1, 1))
  call scene%get_state(y, error); call stop_on(error)
  t_eval = scene%time()
  if (t_lin < 0) then
    open (newunit=kk, file=trim(state_file), status='old', action='read')
    read (kk, *) t_eval, y
    close (kk)
    t_lin = t_eval
  end if
  mbs => scene%system()
  if (deck2 /= deck) then
    call start_scene(trim(deck2), scene2)
    if (scene2%state_size() /= n) then
      print '(a)', 'error: the second deck has another state size'
      stop 1
    end if
    mbs => scene2%system()
  end if
  nfree = 0
  do j = 1, mbs%body_count()
    do k = 1, 6
      if (mbs%free_slot(j, k) > 0) nfree = nfree + 1
    end do
  end do
  ! optional: STUDY_FD_STEP (coordinate step, m or rad), STUDY_BLOCK_BODY (print d(accel)/d(coord)
  ! of one body: the negative stiffness per unit mass/inertia)
  h_coord = 2.0e-9_wp
  call get_environment_variable('STUDY_FD_STEP', env, status=stat)
  if (stat == 0) read (env, *) h_coord
  block_body = 0
  call get_environment_variable('STUDY_BLOCK_BODY', env, status=stat)
  if (stat == 0) read (env, *) block_body
  do j = 1, n
    h = 1.0e-7_wp * max(1.0e-2_wp, abs(y(j)))
    if (j <= nfree) h = h_coord            ! coordinates: m or rad (Hertz approach ~50 um)
    yp = y; yp(j) = y(j) + h
    call mbs%rhs(t_eval, yp, fp, error); call stop_on(error)
    yp(j) = y(j) - h
    call mbs%rhs(t_eval, yp, fm, error); call stop_on(error)
    jac(:, j) = (fp - fm) / (2 * h)
  end do
  if (block_body > 0) then
    print '(a,i0,a)', 'd(accel)/d(coord) of body ', block_body, ' (rows: accel of x y z yaw roll spin; cols: coord)'
    print '(a,6i4)', 'free slots (x y z yaw roll spin, 0 = frozen):', (mbs%free_slot(block_body, kk), kk = 1, 6)
    do k = 1, 6
      if (mbs%free_slot(block_body, k) <= 0) cycle
      write (*, '(a8)', advance='no') dof_name(k)
      do kk = 1, 6
        jj = mbs%free_slot(block_body, kk)
        if (jj <= 0) cycle
        write (*, '(es12.3)', advance='no') jac(nfree + mbs%free_slot(block_body, k), jj)
      end do
      print *
    end do
  end if
  ! optional: STUDY_DUMP_JAC = file for the Jacobian (n rows of n values) and nfree on line 1
  call get_environment_variable('STUDY_DUMP_JAC', state_file, status=stat)
  if (stat == 0 .and. len_trim(state_file) > 0) then
    open (newunit=kk, file=trim(state_file), status='replace', action='write')
    write (kk, '(i0)') nfree
    do j = 1, n
      write (kk, '(*(es24.16))') jac(j, :)
    end do
    close (kk)
  end if
  lwork = 8 * n
  allocate (work(lwork))
  call dgeev('N', 'V', n, jac, n, wr, wi, vl, 1, vr, n, work, lwork, info)
  if (info /= 0) then
    print '(a,i0)', 'dgeev failed, info = ', info
    stop 1
  end if
  print '(a,a,a,f0.4,a,i0,a,a)', 'linear modes of ', trim(deck2), ' at the state of t = ', t_lin, ' s (', n, &
    ' states) of ', trim(deck)
  print '(a)', '  freq [Hz]  damping ratio   real [1/s]   dominant coordinates (share of |displacement|)'
  do j = 1, n
    if (wi(j) <= 0) cycle
    if (wi(j) / (2 * pi) < f_min) cycle
    call dominant(j, order)
    print '(f11.2, es15.4, es13.4, 3x, a)', wi(j) / (2 * pi), -wr(j) / hypot(wr(j), wi(j)), wr(j), &
      trim(coord_text(order(1), j)) // ', ' // trim(coord_text(order(2), j))
  end do
  call scene%destroy()

contains

  !> Two largest displacement components of the complex eigenvector (columns j, j+1).
  subroutine dominant(j, order)
    integer, intent(in) :: j
    integer, intent(out) :: order(2)
    real(wp) :: mag(nfree)
    mag = hypot(vr(1:nfree, j), vr(1:nfree, j + 1))
    order(1) = maxloc(mag, dim=1)
    mag(order(1)) = -1
    order(2) = maxloc(mag, dim=1)
  end subroutine dominant

  function coord_text(slot, j) result(s)
    integer, intent(in) :: slot, j
    character(len=64) :: s
    integer :: b, k
    real(wp) :: mag(nfree)
    mag = hypot(vr(1:nfree, j), vr(1:nfree, j + 1))
    s = '?'
    do b = 1, mbs%body_count()
      do k = 1, 6
        if (mbs%free_slot(b, k) == slot) write (s, '(a,i0,1x,a,1x,f4.2)') 'body ', b, trim(dof_name(k)), &
          mag(slot) / sum(mag)
      end do
    end do
  end function coord_text
end program study_linear_modes
