!> Static equilibrium of a scene (&simulation equilibrium, rd_static_preload) where it used to
!> fail:
!>  (a) the TGV 001 bogie started inside the designed track's clothoid (sigma = 1060 m, cant
!>      15 mm): the solve used to slide the wheelsets off the rail ("wheelset pose not finite
!>      or out of range"). Checked after the solve, with the model evaluated at V = 0:
!>      1. the accelerations of every solved coordinate vanish (the wheelsets' lateral
!>         position and spin are held: their residual is what the creep forces carry);
!>      2. the wheel loads (Q, along each wheelset's Z_T) add up to the weight resolved
!>         normal to the canted track: sum Q = g (m_b cos phi_b + m_w cos phi_1 + m_w cos phi_2),
!>         with the cant phi(sigma) = asin(h(sigma) / 1.5 m), h ramped linearly from 0 at
!>         sigma = 1000 m to 50 mm at 1200 m (the deck's track, written here independently).
!>         Bound 0.5 N (of 44 kN): the bogie's weight reaches the wheelsets through frames
!>         whose cant differs by 1.5 m x 1.67e-4 rad/m = 2.5e-4 rad, which moves
!>         m_b g |phi| 2.5e-4 ~ 0.07 N between Q and the held lateral direction; the bogie's
!>         lateral load (m_b g sin phi ~ 300 N) projects on Z_T with the same angle (0.07 N);
!>         each wheelset carries its own weight and, the bogie being symmetric about its
!>         centre, half the bogie's (same bound);
!>      3. the run then starts without a jump: in the first 0.1 s at 20 m/s each wheelset
!>         moves laterally by less than X = V |psi0| t + V^2 kappa t^2 / 2
!>         + |V^2 kappa - g phi| t^2 / 2 (1.8 mm here), the motion of a wheelset that rolls
!>         without lateral slip (dy/dt = V psi) and does not steer: psi0, its static yaw
!>         relative to its frame (bogie-parallel: ~ the frame heading change over 1.5 m,
!>         5e-4 rad), falls behind the frame turning at V kappa; plus the free acceleration
!>         of the cant deficiency. Creep forces and the primary suspension only steer it
!>         back. (The wheel loads are not compared over the release: the creep forces of
!>         rolling, absent in the static state, switch on at once and their vertical
!>         components move Q by ~2%.)
!>  (c) Manchester vehicle 1 (S1002/60E1 profiles, lateral bump stops) started inside the
!>      R = 150 m curve with 100 mm cant (sigma = 120 m): the car must sit 0.30 m inward of
!>      the centreline (chord offset of its bogies) and lean, from a start with the bump
!>      stops 0.3 m deep and the wheels 0.2 mm above the rails. Checked: the solved
!>      accelerations vanish, and the global vertical balance holds: the suspension forces
!>      cancel in pairs, so the rails' vertical forces (fixed Z) and the held supports'
!>      vertical components (m y'' along each wheelset's Y_T) carry the total weight,
!>      within the residual accelerations times the total mass (4e-3 N of 436 kN).
!>  (b) the TGV vehicle with a series yaw damper (an element with an internal state): the
!>      solve used to fail because the damper started with the tension k |p2 - p1| (its
!>      state was set before the free length) and, fixed during the solve, acted as a spring.
!>      Checked: with equilibrium 'none' the damper starts relaxed (zero force); with
!>      'preload' the solve converges, the damper carries no static force (a series
!>      spring-damper at rest: dx_d/dt = T/c = 0, closed form T = 0) and every body sits
!>      where it sits without the damper (an independent scene), within 1e-9 m / rad.
program test_scene_static_equilibrium
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_speed_law, only: speed_law_t, constant_speed
  use rd_body_spec, only: DOF_Y, DOF_PITCH, DOF_YAW
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_series_spring_damper, only: series_spring_damper_t
  implicit none

  character(len=*), parameter :: nl = new_line('a')
  character(len=*), parameter :: yaw_damper = nl // &
    "&element name = 'yawdamper1', type = 'series_spring_damper', body1 = 'car', " // &
    "body2 = 'bogie1', point1 = 11.85, 1.3, -0.7, point2 = -0.5, 1.3, 0.2, " // &
    "damping = 2.0e5, 0.0, 0.0, series_stiffness = 8.0e6 /" // nl

  call test_curve_start()
  call test_tight_curve_start()
  call test_series_damper()
  call test_summary('test_scene_static_equilibrium')

contains

  ! ---------------------------------------------------------------- (a)
  subroutine test_curve_start()
    real(wp), parameter :: sigma0 = 1060.0_wp, speed = 20.0_wp, t_run = 0.1_wp
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    type(speed_law_t) :: saved
    real(wp), allocatable :: y(:), ydot(:), y1(:)
    real(wp) :: worst, q_sum, q_ws(2), expected, expected_ws(2), m_b, m_w(2), phi_b, phi_w(2), &
                psi0, bound, dy, kappa
    integer :: ib, j, k, w, n, i_bogie, i_ws(2)
    type(wheelset_contact_t), pointer :: contact

    call scene%load_string("&include file = 'tgv_bogie_curve.nml' /" // nl // &
                           "&simulation start_sigma = 1060.0, t_end = 1.0 /" // nl, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, 'TGV bogie started in the clothoid (sigma = 1060 m)')
    mbs => scene%system()
    n = mbs%nfree
    allocate (y(scene%state_size()), ydot(scene%state_size()))
    call scene%get_state(y, error)
    call stop_on(error, 'state')
    i_bogie = body_named(mbs, 'bogie1')
    i_ws = [body_named(mbs, 'ws1'), body_named(mbs, 'ws2')]
    contact => contact_of(mbs)

    ! 1. accelerations at V = 0 (the static problem) of every coordinate not held
    saved = mbs%speed
    mbs%speed = constant_speed(0.0_wp)
    call mbs%rhs(0.0_wp, y, ydot, error)
    call stop_on(error, 'RHS at the static state')
    worst = 0
    do ib = 1, mbs%body_count()
      do j = 1, 6
        k = mbs%free_slot(ib, j)
        if (k == 0) cycle
        if (any(ib == i_ws) .and. (j == DOF_Y .or. j == DOF_PITCH)) cycle
        worst = max(worst, abs(ydot(n + k)))
      end do
    end do
    write (*, '(a, es10.3, a)') 'curve start: largest acceleration of a solved coordinate ', worst, ' m/s^2 or rad/s^2'
    call check(worst <= 1.0e-7_wp, 'curve start: the solved accelerations do not vanish')

    ! 2. wheel loads against the weight resolved normal to the canted track
    m_b = mbs%bodies(i_bogie)%mass
    m_w = [mbs%bodies(i_ws(1))%mass, mbs%bodies(i_ws(2))%mass]
    phi_b = cant(sigma0)
    phi_w = [cant(sigma0 + 1.5_wp), cant(sigma0 - 1.5_wp)]
    do w = 1, 2
      q_ws(w) = sum(contact%results(w)%wheel(:)%force_track(3))
    end do
    q_sum = sum(q_ws)
    expected = standard_gravity * (m_b * cos(phi_b) + sum(m_w * cos(phi_w)))
    expected_ws = standard_gravity * (m_w * cos(phi_w) + 0.5_wp * m_b * cos(phi_b))
    write (*, '(a, f12.4, a, f12.4, a, es10.3, a)') 'curve start: sum Q ', q_sum, ' N, expected ', expected, &
      ' N (difference ', q_sum - expected, ' N)'
    write (*, '(a, 2f12.4, a, 2f12.4, a)') 'curve start: Q per wheelset ', q_ws, ' N, expected ', expected_ws, ' N'
    call check(abs(q_sum - expected) <= 0.5_wp, 'curve start: the wheel loads do not add up to the weight')
    call check(all(abs(q_ws - expected_ws) <= 0.5_wp), 'curve start: a wheelset does not carry its share')
    mbs%speed = saved

    ! 3. the run starts without a jump
    psi0 = maxval(abs([y(mbs%free_slot(i_ws(1), DOF_YAW)), y(mbs%free_slot(i_ws(2), DOF_YAW))]))
    call scene%advance(t_run, error)
    call stop_on(error, 'curve start: run to 0.1 s')
    allocate (y1(size(y)))
    call scene%get_state(y1, error)
    ! a wheelset rolling without lateral slip and not steering: dy/dt = V psi, where psi,
    ! its yaw relative to the frame, starts at psi0 and falls behind the frame turning at
    ! V kappa; plus the free acceleration of the cant deficiency V^2 kappa - g phi
    kappa = (sigma0 + 1.5_wp - 1000.0_wp) / (200.0_wp * 1000.0_wp)
    bound = speed * psi0 * t_run + 0.5_wp * speed**2 * kappa * t_run**2 &
            + 0.5_wp * abs(speed**2 * kappa - standard_gravity * sin(cant(sigma0 + 1.5_wp))) * t_run**2
    do w = 1, 2
      dy = abs(y1(mbs%free_slot(i_ws(w), DOF_Y)) - y(mbs%free_slot(i_ws(w), DOF_Y)))
      write (*, '(a, i0, a, es10.3, a, es10.3, a)') 'curve start: wheelset ', w, ' lateral motion in 0.1 s ', &
        dy, ' m (bound ', bound, ' m)'
      call check(dy <= bound, 'curve start: wheelset lateral jump after the release')
    end do
    call scene%destroy()
  end subroutine test_curve_start

  !> Cant angle of the designed track (tracks/tgv_designed_track.nml): superelevation ramped
  !> linearly over the 200 m clothoid from sigma = 1000 m to 50 mm, over a 1.5 m cant base.
  pure real(wp) function cant(sigma)
    real(wp), intent(in) :: sigma
    cant = asin(0.050_wp * min(max((sigma - 1000.0_wp) / 200.0_wp, 0.0_wp), 1.0_wp) / 1.5_wp)
  end function cant

  ! ---------------------------------------------------------------- (c)
  subroutine test_tight_curve_start()
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    type(wheelset_contact_t), pointer :: contact
    real(wp), allocatable :: y(:), ydot(:)
    real(wp) :: worst, total_mass, contact_z, held_z, balance, bound
    integer :: ib, j, k, n, iw
    logical :: is_wheelset

    call scene%load_string("&include file = 'manchester_v1_tc1_elastic.nml' /" // nl // &
                           "&simulation start_sigma = 120.0, t_end = 1.0 /" // nl, 'inputs', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, 'Manchester vehicle 1 started in the R = 150 m curve (sigma = 120 m)')
    mbs => scene%system()
    contact => contact_of(mbs)
    n = mbs%nfree
    allocate (y(scene%state_size()), ydot(scene%state_size()))
    call scene%get_state(y, error)
    mbs%speed = constant_speed(0.0_wp)
    call mbs%rhs(0.0_wp, y, ydot, error)
    call stop_on(error, 'RHS at the static state')
    worst = 0
    total_mass = 0
    contact_z = 0
    held_z = 0
    do ib = 1, mbs%body_count()
      total_mass = total_mass + mbs%bodies(ib)%mass
      is_wheelset = any(contact%models(:)%body == ib)
      do j = 1, 6
        k = mbs%free_slot(ib, j)
        if (k == 0) cycle
        if (is_wheelset .and. (j == DOF_Y .or. j == DOF_PITCH)) cycle
        worst = max(worst, abs(ydot(n + k)))
      end do
      if (is_wheelset) then
        ! the held lateral support: the unbalanced force m y'' along the wheelset's Y_T
        ! (frames at rest: y'' is the acceleration along Y_T), fixed-frame Z component
        held_z = held_z + mbs%bodies(ib)%mass * ydot(n + mbs%free_slot(ib, DOF_Y)) * mbs%scratch%kin(ib)%track%a(3, 2)
      end if
    end do
    do iw = 1, size(contact%results)
      contact_z = contact_z + contact%results(iw)%force(3)
    end do
    write (*, '(a, es10.3, a)') 'tight curve start: largest acceleration of a solved coordinate ', worst, &
      ' m/s^2 or rad/s^2'
    call check(worst <= 1.0e-7_wp, 'tight curve start: the solved accelerations do not vanish')
    ! Global vertical balance: the suspension forces cancel in pairs, so the rails' forces
    ! plus the held supports carry the total weight; the track is level along its length
    ! (the frozen car x carries no vertical force). Bound: the solved residual accelerations
    ! (<= 1e-7 m/s^2) times the total mass.
    balance = contact_z - held_z - total_mass * standard_gravity
    bound = 1.0e-7_wp * total_mass
    write (*, '(a, f12.3, a, es10.3, a, es10.3, a)') 'tight curve start: rails carry ', contact_z, &
      ' N vertically; weight - held supports off by ', balance, ' N (bound ', bound, ' N)'
    call check(abs(balance) <= bound, 'tight curve start: the rails do not carry the weight')
    ! and the run starts (flange contact comes with the creep forces)
    call scene%advance(0.05_wp, error)
    call stop_on(error, 'tight curve start: run to 0.05 s')
    call scene%destroy()
  end subroutine test_tight_curve_start

  ! ---------------------------------------------------------------- (b)
  subroutine test_series_damper()
    character(len=:), allocatable :: base, relaxed
    type(scene_t) :: with_damper, without, start_none
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs, mbs0
    real(wp), allocatable :: y(:), y0(:), ydot(:)
    real(wp) :: tension, worst
    integer :: e, ib, j, k, k0

    base = "&include file = 'tgv_vehicle_straight.nml' /" // nl // "&simulation t_end = 1.0 /" // nl
    ! equilibrium 'none': the damper must start relaxed
    relaxed = "&include file = 'tgv_vehicle_straight.nml' /" // nl // &
              "&simulation t_end = 1.0, equilibrium = 'none' /" // nl // yaw_damper
    call start_none%load_string(relaxed, 'inputs', error)
    if (.not. allocated(error)) call start_none%build(error)
    if (.not. allocated(error)) call start_none%initialize(.false., error)
    call stop_on(error, 'TGV + yaw damper, equilibrium none')
    mbs => start_none%system()
    allocate (y(mbs%state_size()), ydot(mbs%state_size()))
    call start_none%get_state(y, error)
    call mbs%rhs(0.0_wp, y, ydot, error)
    call stop_on(error, 'RHS, equilibrium none')
    e = damper_index(mbs)
    tension = -mbs%scratch%el_res(e)%force_local(1)
    write (*, '(a, es10.3, a)') 'series damper, equilibrium none: initial tension ', tension, ' N'
    call check(abs(tension) <= 1.0e-6_wp, 'series damper: does not start relaxed')
    call start_none%destroy()
    deallocate (y, ydot)

    ! equilibrium 'preload': converges, relaxed damper, same state as without the damper
    call with_damper%load_string(base // yaw_damper, 'inputs', error)
    if (.not. allocated(error)) call with_damper%build(error)
    if (.not. allocated(error)) call with_damper%initialize(.false., error)
    call stop_on(error, 'TGV + yaw damper, equilibrium preload')
    call without%load_string(base, 'inputs', error)
    if (.not. allocated(error)) call without%build(error)
    if (.not. allocated(error)) call without%initialize(.false., error)
    call stop_on(error, 'TGV, equilibrium preload')
    mbs => with_damper%system()
    mbs0 => without%system()
    allocate (y(mbs%state_size()), ydot(mbs%state_size()), y0(mbs0%state_size()))
    call with_damper%get_state(y, error)
    call without%get_state(y0, error)
    mbs%speed = constant_speed(0.0_wp)
    call mbs%rhs(0.0_wp, y, ydot, error)
    call stop_on(error, 'RHS, equilibrium preload')
    e = damper_index(mbs)
    tension = -mbs%scratch%el_res(e)%force_local(1)
    write (*, '(a, es10.3, a)') 'series damper, after the static solve: tension ', tension, ' N'
    call check(abs(tension) <= 1.0e-2_wp, 'series damper: carries a static force after the solve')
    worst = 0
    do ib = 1, mbs%body_count()
      do j = 1, 6
        k = mbs%free_slot(ib, j)
        k0 = mbs0%free_slot(ib, j)
        if (k == 0 .or. k0 == 0) cycle
        worst = max(worst, abs(y(k) - y0(k0)))
      end do
    end do
    write (*, '(a, es10.3, a)') 'series damper: largest coordinate difference to the vehicle without it ', worst, &
      ' m or rad'
    call check(worst <= 1.0e-9_wp, 'series damper: the static state differs from the one without the damper')
    call with_damper%destroy()
    call without%destroy()
  end subroutine test_series_damper

  integer function damper_index(mbs) result(e)
    type(multibody_t), intent(in) :: mbs
    do e = 1, mbs%element_count()
      select type (el => mbs%elements(e)%e)
      type is (series_spring_damper_t)
        return
      end select
    end do
    write (*, '(a)') 'FAILED: no series spring-damper in the scene'
    error stop 1
  end function damper_index

  integer function body_named(mbs, name) result(ib)
    type(multibody_t), intent(in) :: mbs
    character(len=*), intent(in) :: name
    do ib = 1, mbs%body_count()
      if (mbs%bodies(ib)%name == name) return
    end do
    write (*, '(a)') 'FAILED: no body ' // name
    error stop 1
  end function body_named

  function contact_of(mbs) result(contact)
    type(multibody_t), intent(in) :: mbs
    type(wheelset_contact_t), pointer :: contact
    integer :: i
    do i = 1, size(mbs%providers)
      select type (p => mbs%providers(i)%p)
      type is (wheelset_contact_t)
        contact => p
        return
      end select
    end do
    write (*, '(a)') 'FAILED: no wheelset contact in the scene'
    error stop 1
  end function contact_of
end program test_scene_static_equilibrium
