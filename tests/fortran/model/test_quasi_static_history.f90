!> The quasi-static solve does not depend on its call history (rd_multibody
!> solve_quasi_static). The solve starts at a new time from the linear extrapolation in time
!> of its last two solutions (for the state an older kept solution solved, from that one) and keeps
!> chord Jacobians between calls (secant updates); both only choose the start and the
!> iteration matrix, so the answer must be the balance at
!> (t, y) whatever came before. On the acceptance deck inputs/manchester_v1_tc1.nml (and on it
!> with the energy-consistent strip force, `strip_normal_force = 'potential'`), at
!> points of the run on straight track, in the transition and in the curve with wheelset 1
!> on its flange (17 s: sigma ~ 105 m), the right-hand side is evaluated
!>  (a) as the run left it (history and Jacobians of the integration), and
!>  (b) with the history cleared, the chord Jacobians marked stale and every wheelset's
!>      height and roll moved away from the balance (+30 um, -0.2 mrad) before the call;
!> and the two are compared:
!>  - the balance itself: each wheelset's (z, roll) agree within 1e-10 (m, rad). The solve
!>    converges when its update is below 1e-13 (m, rad), and Newton's error after such an
!>    update is of that order; 1e-10 leaves room for the rounding of the residual near the
!>    root (det J ~ 1e12 1/s^4, residual rounding ~1e-7 m/s^2) but not for a start
!>    dependence of a tread / flange-root fold, which differs by micrometres;
!>  - the accelerations of all coordinates agree within 1e-6 g: the force of a millionth of
!>    a wheelset's weight (0.02 N), far below what any output resolves. (Their own scale is
!>    no measure: in a steady curve they are near zero. A balance 1e-12 m apart moves them by
!>    ~1e-6 m/s^2 through a contact stiffness of ~1e6 1/s^2 per unit mass.)
!> After (b) the run goes on to the next point from the perturbed evaluation (the history
!> then holds one cold solve), so a start that broke the balance would also show there.
program test_quasi_static_history
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary, file_text
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_body_spec, only: DOF_Z, DOF_ROLL
  implicit none

  real(wp), parameter :: times(3) = [5.0_wp, 11.0_wp, 17.0_wp]
  character(len=*), parameter :: where(3) = [character(len=24) :: 'straight track', &
                                                              'transition', 'curve, flange contact']
  character(len=:), allocatable :: text
  type(error_t), allocatable :: error
  type(multibody_t), pointer :: mbs
  real(wp), allocatable :: y(:), ydot_a(:), ydot_b(:), zr_a(:, :), zr_b(:, :)
  real(wp) :: dz, dydot, scale
  integer :: ib, nb, k

  text = file_text('inputs/manchester_v1_tc1.nml')
  call history_check(text, 'the acceptance deck')
  ! the same with the energy-consistent strip force, whose balance after a cold start is
  ! reached after more than 8 Newton iterations: the acceptance that cut such an iteration
  ! short made it depend on the start by 1e-8..1e-7 m (rd_multibody solve_quasi_static)
  call history_check("&include file = 'manchester_v1_tc1.nml' /" // new_line('a') // potential_lines(), &
                     'the acceptance deck, potential strip force')
  call test_summary('test_quasi_static_history')

contains

  !> The checks at the three times on the deck `deck_text`.
  subroutine history_check(deck_text, label)
    character(len=*), intent(in) :: deck_text, label
    type(scene_t), target :: scene
    write (*, '(a)') '--- ' // label
    call scene%load_string(deck_text, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, label)
    mbs => scene%system()
    nb = mbs%body_count()
    if (allocated(y)) deallocate (y, ydot_a, ydot_b, zr_a, zr_b)
    allocate (y(mbs%state_size()), ydot_a(mbs%state_size()), ydot_b(mbs%state_size()), zr_a(2, nb), zr_b(2, nb))
    call check(count([(any(mbs%bodies(ib)%quasi_static), ib = 1, nb)]) == 4, 'the deck has four quasi-static wheelsets')
    do k = 1, size(times)
      call scene%advance(times(k), error); call stop_on(error, 'advance')
      call scene%get_state(y, error); call stop_on(error, 'state')
      ! (a) with the run's history
      call mbs%rhs(times(k), y, ydot_a, error); call stop_on(error, 'rhs (a)')
      zr_a = pose()
      ! (b) cold: no history, stale Jacobians, a start away from the balance
      mbs%qs_history_count = 0
      mbs%qs_jacobian_valid = .false.
      do ib = 1, nb
        if (.not. any(mbs%bodies(ib)%quasi_static)) cycle
        mbs%bodies(ib)%q0(DOF_Z) = mbs%bodies(ib)%q0(DOF_Z) + 3.0e-5_wp
        mbs%bodies(ib)%q0(DOF_ROLL) = mbs%bodies(ib)%q0(DOF_ROLL) - 2.0e-4_wp
      end do
      call mbs%rhs(times(k), y, ydot_b, error); call stop_on(error, 'rhs (b)')
      zr_b = pose()
      dz = maxval(abs(zr_a - zr_b))
      scale = maxval(abs(ydot_a))
      dydot = maxval(abs(ydot_a - ydot_b))
      write (*, '(a, f5.1, 3a, es10.2, a, es10.2, a, es10.2, a)') 't = ', times(k), ' s (', trim(where(k)), &
        '): balance differs by ', dz, ' (m, rad); accelerations by ', dydot, ' m/s^2 (largest ', scale, ')'
      call check(dz <= 1.0e-10_wp, 'the balance does not depend on the call history at ' // trim(where(k)))
      call check(dydot <= 1.0e-6_wp * standard_gravity, 'the accelerations do not depend on the call history at ' // trim(where(k)))
    end do
    call scene%destroy()
  end subroutine history_check

  !> `&wheelset strip_normal_force = 'potential'` for the deck's four wheelsets
  function potential_lines() result(t)
    character(len=:), allocatable :: t
    integer :: i
    t = ''
    do i = 1, 4
      t = t // "&wheelset name = 'w" // achar(iachar('0') + i) // "', strip_normal_force = 'potential' /" // new_line('a')
    end do
  end function potential_lines

  !> (z, roll) of every body, (2, body)
  function pose() result(p)
    real(wp) :: p(2, nb)
    integer :: i
    do i = 1, nb
      p(:, i) = mbs%bodies(i)%q0([DOF_Z, DOF_ROLL])
    end do
  end function pose
end program test_quasi_static_history
