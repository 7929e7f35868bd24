!> Flexible track: a wheelset on two rail bodies (mass m_r each, pads k_y, k_z, c_y, c_z to
!> the track frame; &wheelset left_rail_body / right_rail_body), knife-edge cylinders
!> (conicity 0: vertical contact normals) with a lateral flange stop, at V = 0 (no creep
!> forces), against closed forms written here:
!>  (a) statics, equilibrium 'preload': the pad preloads carry the rails' own weight, so
!>      each rail sinks by Q/k_z with Q = (m g + F)/2 (symmetry), and the wheelset by that
!>      plus the Hertz approach delta(Q) of a cylinder (radius r0) on a crowned rail
!>      (radius R), computed here from Hertz' elliptic-contact equations (Johnson,
!>      Contact Mechanics 1985, section 4.2; elliptic integrals by quadrature);
!>      equilibrium 'solve' (no preloads): the rail sinks by (Q + m_r g)/k_z;
!>  (b) lateral: the wheelset held (by the static solve) at y beyond the flange clearance
!>      c: the left flange stop (k_f) and the left rail pad (k_y) are springs in series,
!>      y_rail = k_f (y - c)/(k_f + k_y), and y_rail = -Y_left/k_y from the wheel's lateral
!>      force output; the right rail does not move laterally;
!>  (c) dynamics: an extra vertical load on the wheelset is released at t = 0+; the
!>      wheelset's vertical free vibration is fitted (linear prediction with a constant,
!>      x_{k+1} = a1 x_k + a2 x_{k-1} + b, least squares over 30-100 ms) and its
!>      eigenvalue compared with the least-damped eigenvalue of the 2-DOF linear model
!>      m z_w'' = -2 k_H (z_w - z_r), m_r z_r'' = k_H (z_w - z_r) - k_z z_r - c_z z_r'
!>      (k_H = 3 Q / (2 delta) the linearised Hertz stiffness) from LAPACK dgeev;
!>  (e) deck errors: unknown rail body, rail body = wheelset, rail body in a frame at
!>      another offset, rail body with free rotations.
program test_flexible_track
  use rd_kinds, only: wp, pi, standard_gravity
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_body_spec, only: DOF_Y, DOF_Z
  use rd_wheelset_contact, only: wheelset_contact_t
  implicit none
  external :: dgeev, dgesv

  character, parameter :: nl = new_line('a')
  real(wp), parameter :: m_ws = 1800.0_wp, m_r = 150.0_wp, f_load = 1.0e5_wp, r0 = 0.46_wp, &
                         crown = 0.3_wp, k_y = 5.0e7_wp, k_z = 1.0e8_wp, c_y = 2.0e4_wp, c_z = 5.0e4_wp, &
                         k_f = 2.0e7_wp, clearance = 5.0e-3_wp, shear = 8.2e10_wp, poisson = 0.28_wp

  call test_statics()
  call test_lateral()
  call test_vertical_vibration()
  call test_deck_errors()
  call test_summary('test_flexible_track')

contains

  !> The test scene: wheelset 'ws' on rails 'rl', 'rr'; `extra` is appended to the deck.
  function deck(equilibrium, y0, extra, ws_frozen) result(text)
    character(len=*), intent(in) :: equilibrium, extra
    real(wp), intent(in) :: y0
    character(len=*), intent(in), optional :: ws_frozen
    character(len=:), allocatable :: text, frozen
    character(len=32) :: ys
    frozen = ''
    if (present(ws_frozen)) frozen = ", frozen = '" // ws_frozen // "'" 
    write (ys, '(es23.15)') y0
    text = "&simulation title = 'flexible track', t_end = 0.1, speed = 0.0, equilibrium = '" // &
      equilibrium // "' /" // nl // &
      "&solver method = 'bdf', rtol = 1e-9, atol = 1e-12, initial_step = 1e-7, max_step = 2e-4 /" // nl // &
      "&output interval = 0.01 /" // nl // &
      "&body name = 'ws', mass = 1800.0, ixx = 1000.0, iyy = 100.0, izz = 1000.0, position = 0.0, " // &
      trim(ys) // ", 0.46" // frozen // " /" // nl // &
      "&body name = 'rl', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame = 'ws', " // &
      "frozen = 'x', 'yaw', 'roll', 'pitch' /" // nl // &
      "&body name = 'rr', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame = 'ws', " // &
      "frozen = 'x', 'yaw', 'roll', 'pitch' /" // nl // &
      "&wheelset name = 'w1', body = 'ws', contact = 'knife_edge', nominal_radius = 0.46, " // &
      "contact_distance = 1.5, conicity = 0.0, rail_crown_radius = 0.3, flange_clearance = 5e-3, " // &
      "flange_stiffness = 2e7, creep_law = 'linear', shear_modulus = 8.2e10, poisson = 0.28, " // &
      "left_rail_body = 'rl', right_rail_body = 'rr' /" // nl // &
      "&element name = 'pad_l', type = 'spring_damper', body1 = 'ground', body2 = 'rl', " // &
      "stiffness = 0.0, 5e7, 1e8, damping = 0.0, 2e4, 5e4 /" // nl // &
      "&element name = 'pad_r', type = 'spring_damper', body1 = 'ground', body2 = 'rr', " // &
      "stiffness = 0.0, 5e7, 1e8, damping = 0.0, 2e4, 5e4 /" // nl // &
      "&external_force body = 'ws', frame = 'track', force = 0.0, 0.0, -1e5 /" // nl // extra
  end function deck

  ! ------------------------------------------------------------------ (a)
  subroutine test_statics()
    call statics_case(1)
    call statics_case(2)
  end subroutine test_statics

  subroutine statics_case(im)
    integer, intent(in) :: im
    type(scene_t) :: scene
    real(wp) :: q, z_rail, z_ws, delta, y(6)
    character(len=8) :: modes(2) = [character(len=8) :: 'preload', 'solve']
    q = 0.5_wp * (m_ws * standard_gravity + f_load)
    delta = hertz_approach(q)
      call build(scene, deck(trim(modes(im)), 0.0_wp, ''), 'statics ' // trim(modes(im)))
      call coordinates(scene, y)
      z_ws = y(1); z_rail = y(3)
      if (im == 1) then
        write (*, '(a, es14.6, a, es14.6, a)') 'statics preload: left rail z ', z_rail, ' m, closed form -Q/k_z ', &
          -q / k_z, ' m'
        call check(abs(z_rail + q / k_z) < 1.0e-9_wp, 'statics preload: left rail sinks by Q/k_z')
        call check(abs(y(5) + q / k_z) < 1.0e-9_wp, 'statics preload: right rail sinks by Q/k_z')
        write (*, '(a, es14.6, a, es14.6, a, es10.3)') 'statics preload: wheelset z - r0 ', z_ws - r0, &
          ' m, closed form -Q/k_z - delta ', -q / k_z - delta, ' m, delta (Hertz) ', delta
        call check(abs(z_ws - r0 + q / k_z + delta) < 1.0e-9_wp, &
                   'statics preload: wheelset sinks by Q/k_z + Hertz approach')
      else
        write (*, '(a, es14.6, a, es14.6, a)') 'statics solve: left rail z ', z_rail, &
          ' m, closed form -(Q + m_r g)/k_z ', -(q + m_r * standard_gravity) / k_z, ' m'
        call check(abs(z_rail + (q + m_r * standard_gravity) / k_z) < 1.0e-9_wp, &
                   'statics solve: rail sinks by (Q + m_r g)/k_z')
        call check(abs(z_ws - r0 + (q + m_r * standard_gravity) / k_z + delta) < 1.0e-9_wp, &
                   'statics solve: wheelset sinks by (Q + m_r g)/k_z + Hertz approach')
      end if
      call check(abs(y(2)) < 1.0e-12_wp .and. abs(y(4)) < 1.0e-12_wp, 'statics: rails moved laterally')
      call scene%destroy()
  end subroutine statics_case

  ! ------------------------------------------------------------------ (b)
  subroutine test_lateral()
    type(scene_t) :: scene
    type(wheelset_contact_t), pointer :: contact
    real(wp) :: y(6), y_ws, expected, y_left
    y_ws = clearance + 3.0e-3_wp
    ! 'solve': with 'preload' the pad preloads would take the flange force of the deck's
    ! (pressed) configuration, leaving the rail where the deck put it
    ! The wheelset's roll frozen: the flange force at rail height would roll it, tilting the
    ! cylinders' contact normals and adding N sin(roll) to both rails' lateral loads.
    call build(scene, deck('solve', y_ws, '', 'roll'), 'lateral')
    call coordinates(scene, y, contact)
    expected = k_f * (y_ws - clearance) / (k_f + k_y)
    y_left = -contact%results(1)%wheel(1)%force_track(2) / k_y
    write (*, '(a, es14.6, a, es14.6, a, es14.6, a)') 'lateral: left rail y ', y(2), ' m, series springs ', &
      expected, ' m, -Y_left/k_y ', y_left, ' m'
    call check(abs(y(2) - expected) < 1.0e-10_wp, 'lateral: left rail y = k_f (y - c)/(k_f + k_y)')
    call check(abs(y(2) - y_left) < 1.0e-10_wp, 'lateral: left rail y = -Y_left/k_y')
    call check(abs(y(4)) < 1.0e-12_wp, 'lateral: right rail moved laterally')
    call scene%destroy()
  end subroutine test_lateral

  ! ------------------------------------------------------------------ (c)
  subroutine test_vertical_vibration()
    call vibration_case(0.0_wp)
    call vibration_case(2.0e5_wp)
  end subroutine test_vertical_vibration

  !> c_n: the contact damping, a damper between wheel and rail in the linear model (the
  !> approach rate is relative to the rail material: with it taken against a fixed rail
  !> the damper would act between the wheel and the ground).
  subroutine vibration_case(c_n)
    real(wp), intent(in) :: c_n
    type(scene_t) :: scene
    character(len=16) :: cs
    type(error_t), allocatable :: error
    type(multibody_t), pointer :: mbs
    integer, parameter :: n_samples = 701
    real(wp), parameter :: dt = 1.0e-4_wp, t_fit = 0.03_wp, df = 4000.0_wp
    real(wp) :: x(n_samples), q, delta, k_h, a(4, 4), wr(4), wi(4), vl(1, 4), vr(1, 4), work(64)
    real(wp) :: ntn(3, 3), ntb(3), row(3), coef(3), re_mu, abs2_mu, lam_fit_re, lam_fit_im, lam_re, lam_im, dlam
    integer :: i, k, info, iz, ipiv(3), best
    ! the extra load is on during the static solve (t = 0) and off for t > 1e-9 s
    write (cs, '(es12.4)') c_n
    call build(scene, replace(deck('preload', 0.0_wp, "&external_force body = 'ws', frame = 'track', " // &
      "force = 0.0, 0.0, -4000.0, t_end = 1e-9 /" // nl), "poisson = 0.28,", "poisson = 0.28, contact_damping = " // &
      trim(cs) // ","), 'vibration')
    mbs => scene%system()
    iz = mbs%free_slot(1, DOF_Z)
    do i = 1, n_samples
      call scene%advance(t_fit + (i - 1) * dt, error)
      call stop_on(error, 'vibration run')
      x(i) = state_value(scene, iz)
    end do
    ! about the mean: the normal equations of the fit lose the digits of the position
    x = x - sum(x) / n_samples
    ! x_{k+1} = a1 x_k + a2 x_{k-1} + b: one damped mode mu = exp(lambda dt) with
    ! a1 = 2 Re(mu), a2 = -|mu|^2 (the constant absorbs the equilibrium position)
    ntn = 0; ntb = 0
    do k = 2, n_samples - 1
      row = [x(k), x(k - 1), 1.0_wp]
      do i = 1, 3
        ntn(:, i) = ntn(:, i) + row * row(i)
      end do
      ntb = ntb + row * x(k + 1)
    end do
    coef = ntb
    call dgesv(3, 1, ntn, 3, ipiv, coef, 3, info)
    call check(info == 0, 'vibration c_n = ' // trim(cs) // ': fit singular')
    re_mu = 0.5_wp * coef(1)
    abs2_mu = -coef(2)
    call check(abs2_mu > re_mu**2, 'vibration c_n = ' // trim(cs) // ': the response is not oscillatory')
    lam_fit_re = 0.5_wp * log(abs2_mu) / dt
    lam_fit_im = atan2(sqrt(max(abs2_mu - re_mu**2, 0.0_wp)), re_mu) / dt
    ! the 2-DOF linear model (state z_w, z_r, z_w', z_r'), about the unloaded equilibrium
    q = 0.5_wp * (m_ws * standard_gravity + f_load)
    delta = hertz_approach(q)
    k_h = 1.5_wp * q / delta
    a = 0
    a(1, 3) = 1; a(2, 4) = 1
    a(3, 1) = -2 * k_h / m_ws; a(3, 2) = 2 * k_h / m_ws
    a(3, 3) = -2 * c_n / m_ws; a(3, 4) = 2 * c_n / m_ws
    a(4, 1) = k_h / m_r; a(4, 2) = -(k_h + k_z) / m_r
    a(4, 3) = c_n / m_r; a(4, 4) = -(c_z + c_n) / m_r
    call dgeev('N', 'N', 4, a, 4, wr, wi, vl, 1, vr, 1, work, size(work), info)
    call check(info == 0, 'vibration c_n = ' // trim(cs) // ': dgeev failed')
    best = maxloc(wr, dim=1, mask=wi > 0)
    lam_re = wr(best); lam_im = wi(best)
    write (*, '(a, f10.3, a, f10.3, a)') 'vibration c_n = ' // trim(cs) // ': 2-DOF model least-damped eigenvalue ', lam_re, ' +- i ', &
      lam_im, ' 1/s'
    write (*, '(a, f10.3, a, f10.3, a, es10.3)') 'vibration c_n = ' // trim(cs) // ': fitted to the simulation          ', lam_fit_re, &
      ' +- i ', lam_fit_im, ' 1/s; k_H ', k_h
    write (*, '(a, 4f12.3)') 'vibration c_n = ' // trim(cs) // ': all model eigenvalues (re, im of the two with im > 0): ', &
      pack(wr, wi > 0), pack(wi, wi > 0)
    dlam = hypot(lam_fit_re - lam_re, lam_fit_im - lam_im) / hypot(lam_re, lam_im)
    write (*, '(a, es10.3)') 'vibration c_n = ' // trim(cs) // ': relative eigenvalue difference ', dlam
    ! 1e-3: the Hertz nonlinearity over the motion (approach 74 um +- 1.6 um) shifts the
    ! frequency at second order (~1e-4); the fast rail mode is 11 decay times down at 30 ms
    call check(dlam < 1.0e-3_wp, 'vibration c_n = ' // trim(cs) // ': eigenvalue differs from the 2-DOF model by more than 0.1 %')
    call scene%destroy()
  end subroutine vibration_case

  ! ------------------------------------------------------------------ (e)
  subroutine test_deck_errors()
    character(len=:), allocatable :: base
    base = deck('preload', 0.0_wp, '')
    call expect_error(replace(base, "left_rail_body = 'rl'", "left_rail_body = 'rail9'"), &
                      'unknown rail body', ['left_rail_body', 'rail9         '])
    call expect_error(replace(base, "right_rail_body = 'rr'", "right_rail_body = 'ws'"), &
                      'rail body = wheelset', ['right_rail_body', 'wheelset itself'])
    call expect_error(replace(base, "right_rail_body = 'rr'", "right_rail_body = 'rl'"), &
                      'same rail twice', ['right_rail_body', 'left rail body '])
    call expect_error(replace(base, "'rl', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame = 'ws'", &
                              "'rl', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame_offset = 2.5"), &
                      'other frame offset', ['left_rail_body', 'frame_offset  '])
    call expect_error(replace(base, "'rr', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame = 'ws', " // &
                              "frozen = 'x', 'yaw', 'roll', 'pitch'", &
                              "'rr', mass = 150.0, ixx = 10.0, iyy = 10.0, izz = 10.0, frame = 'ws', frozen = 'x'"), &
                      'rotations not frozen', ['right_rail_body', 'frozen         '])
    call expect_error(deck('preload', 0.0_wp, &
                           "&body name = 'ws2', mass = 1800.0, ixx = 1000.0, iyy = 100.0, izz = 1000.0, " // &
                           "frame = 'ws', position = 2.5, 0.0, 0.46 /" // nl // &
                           "&wheelset name = 'w2', body = 'ws2', contact = 'knife_edge', nominal_radius = 0.46, " // &
                           "contact_distance = 1.5, creep_law = 'linear', left_rail_body = 'rl' /" // nl), &
                      'rail body under two wheelsets', ['left_rail_body', 'already under ', "'w1'          "])
  end subroutine test_deck_errors

  subroutine expect_error(text, label, words)
    character(len=*), intent(in) :: text, label, words(:)
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    integer :: i
    call scene%load_string(text, '.', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    if (.not. allocated(error)) then
      call check(.false., 'deck error ' // label // ': accepted')
      return
    end if
    write (*, '(a)') 'deck error ' // label // ': ' // error%message
    do i = 1, size(words)
      call check(index(error%message, trim(words(i))) > 0, 'deck error ' // label // ': message lacks "' // &
                 trim(words(i)) // '"')
    end do
    call check(index(error%message, new_line('a')) == 0, 'deck error ' // label // ': not one line')
  end subroutine expect_error

  ! ------------------------------------------------------------------ helpers
  !> Normal approach of two bodies pressed by P: wheel cylinder (curvature 1/r0 in the
  !> rolling direction x) on a rail crowned laterally (1/R). Johnson (1985) section 4.2 with
  !> A = 1/(2 r0) < B = 1/(2 R), semi-axes a (along x) >= b, e^2 = 1 - (b/a)^2:
  !>   B/A = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)),
  !>   A = p0 b (K - E) / (E* e^2 a^2),  p0 = 3 P / (2 pi a b),  delta = p0 b K / E*,
  !> E* = E / (2 (1 - nu^2)) for equal materials, E = 2 G (1 + nu).
  real(wp) function hertz_approach(p) result(delta)
    real(wp), intent(in) :: p
    real(wp) :: aa, bb, e_star, lo, hi, e, kk, ee, a
    integer :: it
    aa = 0.5_wp / r0
    bb = 0.5_wp / crown
    e_star = 2 * shear * (1 + poisson) / (2 * (1 - poisson**2))
    lo = 1.0e-6_wp; hi = 1 - 1.0e-12_wp
    do it = 1, 200
      e = 0.5_wp * (lo + hi)
      call elliptic(e, kk, ee)
      if ((ee / (1 - e**2) - kk) / (kk - ee) > bb / aa) then
        hi = e
      else
        lo = e
      end if
    end do
    call elliptic(e, kk, ee)
    a = (3 * p * (kk - ee) / (2 * pi * aa * e_star * e**2))**(1.0_wp / 3)
    delta = 3 * p * kk / (2 * pi * a * e_star)
  end function hertz_approach

  !> Complete elliptic integrals K(e), E(e) by composite Simpson on [0, pi/2].
  subroutine elliptic(e, kk, ee)
    real(wp), intent(in) :: e
    real(wp), intent(out) :: kk, ee
    integer, parameter :: n = 4000
    real(wp) :: h, s, w
    integer :: i
    h = 0.5_wp * pi / n
    kk = 0; ee = 0
    do i = 0, n
      w = merge(1.0_wp, merge(4.0_wp, 2.0_wp, mod(i, 2) == 1), i == 0 .or. i == n)
      s = sqrt(1 - (e * sin(i * h))**2)
      kk = kk + w / s
      ee = ee + w * s
    end do
    kk = kk * h / 3; ee = ee * h / 3
  end subroutine elliptic

  subroutine build(scene, text, label)
    type(scene_t), intent(inout) :: scene
    character(len=*), intent(in) :: text, label
    type(error_t), allocatable :: error
    call scene%load_string(text, '.', error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, label)
  end subroutine build

  !> (z_ws, y_rl, z_rl, y_rr, z_rr, y_ws) at the scene's state, the contact results
  !> refreshed by an RHS there.
  subroutine coordinates(scene, c, contact)
    type(scene_t), intent(inout) :: scene
    real(wp), intent(out) :: c(6)
    type(wheelset_contact_t), pointer, intent(out), optional :: contact
    type(multibody_t), pointer :: mbs
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:), ydot(:)
    integer :: i
    mbs => scene%system()
    allocate (y(scene%state_size()), ydot(scene%state_size()))
    call scene%get_state(y, error)
    call stop_on(error, 'state')
    call mbs%rhs(0.0_wp, y, ydot, error)
    call stop_on(error, 'RHS at the static state')
    c = [mbs%scratch%kin(1)%q(3), mbs%scratch%kin(2)%q(2), mbs%scratch%kin(2)%q(3), mbs%scratch%kin(3)%q(2), mbs%scratch%kin(3)%q(3), mbs%scratch%kin(1)%q(2)]
    call check(mbs%free_slot(2, DOF_Y) > 0 .and. mbs%free_slot(2, DOF_Z) > 0 .and. &
               count([(mbs%free_slot(2, i) > 0, i = 1, 6)]) == 2, 'rail body: expected free y and z only')
    if (present(contact)) then
      do i = 1, size(mbs%providers)
        select type (p => mbs%providers(i)%p)
        type is (wheelset_contact_t)
          contact => p
        end select
      end do
    end if
  end subroutine coordinates

  real(wp) function state_value(scene, k) result(v)
    type(scene_t), intent(in) :: scene
    integer, intent(in) :: k
    real(wp), allocatable :: y(:)
    type(error_t), allocatable :: error
    allocate (y(scene%state_size()))
    call scene%get_state(y, error)
    call stop_on(error, 'state')
    v = y(k)
  end function state_value

  function replace(text, old, new) result(out)
    character(len=*), intent(in) :: text, old, new
    character(len=:), allocatable :: out
    integer :: k
    k = index(text, old)
    if (k == 0) then
      write (*, '(a)') 'FAILED: test deck lacks "' // old // '"'
      error stop 1
    end if
    out = text(:k - 1) // new // text(k + len(old):)
  end function replace
end program test_flexible_track
