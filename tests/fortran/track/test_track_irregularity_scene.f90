!> Track irregularities in a scene (deck `&track irregularity_file`, path relative to the
!> deck): a single TGV 001 wheelset (knife-edge cones, Kalker linear creep, the parameters of
!> inputs/tgv_wheelset.nml) at 10 m/s.
!>
!> (1) Sinusoidal alignment a(s) = A sin(k s), wavelength 200 m, A = 2 mm (the kinematic
!>     wavelength is 2 pi sqrt(r0 (e0 - r0 lam) / lam) = 11.1 m: far below resonance). The
!>     wheelset is held by a yaw spring k_psi = 1e6 N m/rad only (two longitudinal springs to
!>     the design track; no lateral spring, which would pull it back to the design line).
!>     Independent oracle: the quasi-static steering of a wheelset (no lateral slip,
!>     psi = dy/ds; yaw moment of the longitudinal creep forces balancing the yaw spring,
!>     Wickens / Knothe & Stichel, "Rail Vehicle Dynamics" 2017, sec. 6.2):
!>         lam_e y_r / r0 + e0 psi' + beta psi = 0,   beta = k_psi / (2 e0 f11),
!>     with y_r = y - a the position relative to the displaced rails and
!>     lam_e = lam e0 / (e0 - r0 lam) the knife-edge's effective conicity
!>     (docs/validation.md). For a = A sin(k s) the steady state is y_r = Re(Y e^{iks}) with
!>         Y = -i A (e0 k^2 - i beta k) / (lam_e / r0 - e0 k^2 + i beta k):
!>     |Y| = 0.85 % of A, mostly the lag behind the alignment needed to yaw against the spring.
!>     f11 = G a b C11 is read from the run's own creepage and creep force (the linear law's
!>     coefficient, tested elsewhere). Checked on the last full wavelength (transient of the
!>     fade-in decayed): the fitted sine and cosine parts of y - a equal Y within 3 % of |Y|
!>     (the model neglects lateral creep slip, the gravitational stiffness, spin creep and
!>     inertia: each < 1 % here), and max |y - a| <= 1.03 |Y| + 0.1 um: the wheelset follows
!>     the alignment to 0.9 % of its amplitude (without the irregularity applied it would be
!>     100 %, with a sign error 200 %).
!> (2) Pure gauge widening of 2 mm (record from 20 m, fade 10 m) on a centred symmetric
!>     wheelset: no lateral motion (|y|, e0 |psi|, e0 |phi| < 1e-7 m, i.e. 1e-4 of the rail
!>     offsets: the run without irregularities has its own 1e-8 m of numerical lateral noise,
!>     which the changed vertical settling re-phases; a gauge applied to one rail or with a sign
!>     error would move the wheelset by 1 mm), both contact points move out by 1 mm (rail point y = +-(e0 + 1 mm)), and the wheelset drops by lam * 1 mm (each
!>     cone meets its rail 1 mm further out: r = r0 - lam * 1 mm; closed form of the cone).
program test_track_irregularity_scene
  use test_files, only: delete_file
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  use rd_test_support, only: check, stop_on, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.45_wp, e0 = 0.75_wp, lam = 0.10033_wp, v = 10.0_wp
  real(wp), parameter :: amplitude = 2.0e-3_wp, wavelength = 200.0_wp, k_psi = 1.0e6_wp
  character(len=:), allocatable :: dir

  dir = scratch_dir()
  call random_seed()
  call test_alignment()
  call test_gauge()
  call test_summary('test_track_irregularity_scene')

contains

  function deck_text(file, fade, t_end, interval) result(text)
    character(len=*), intent(in) :: file
    real(wp), intent(in) :: fade, t_end, interval
    character(len=:), allocatable :: text
    character(len=32) :: sfade, send, sint
    character(len=*), parameter :: nl = new_line('a')
    write (sfade, '(f0.3)') fade
    write (send, '(f0.3)') t_end
    write (sint, '(f0.4)') interval
    text = "&simulation title = 'irregularity', t_end = " // trim(send) // ", speed = 10.0, equilibrium = 'none' /" // nl // &
      "&solver method = 'bdf', rtol = 1e-6 /" // nl // &
      "&output interval = " // trim(sint) // " /" // nl // &
      "&track irregularity_file = '" // file // "', irregularity_fade = " // trim(sfade) // " /" // nl // &
      "&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35, position = 0.0, 0.0, 0.45 /" // nl // &
      "&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45, " // &
      "contact_distance = 1.5, conicity = 0.10033, creep_law = 'linear', creep_saturation = 'none', " // &
      "shear_modulus = 8.4e10, poisson = 0.25, contact_damping = 5.0e5 /" // nl // &
      ! yaw spring k_psi = 2 kx (1 m)^2 = 1e6 N m/rad, no lateral or vertical stiffness
      "&element name = 'spring1', type = 'spring_damper', body1 = 'ground', body2 = 'ws1', " // &
      "point1 = 0.0, 1.0, 0.45, point2 = 0.0, 1.0, 0.0, stiffness = 5.0e5, 0.0, 0.0 /" // nl // &
      "&element name = 'spring2', type = 'spring_damper', body1 = 'ground', body2 = 'ws1', " // &
      "point1 = 0.0, -1.0, 0.45, point2 = 0.0, -1.0, 0.0, stiffness = 5.0e5, 0.0, 0.0 /" // nl // &
      "&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /" // nl
  end function deck_text

  subroutine test_alignment()
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    character(len=:), allocatable :: file
    real(wp), parameter :: interval = 0.02_wp, t_end = 45.0_wp
    integer, parameter :: nsteps = nint(t_end / interval)
    real(wp) :: q(6), s(1), pl(23), pr(23), k, lam_e, beta, f11, sxx, sxf, err_max, fit(3)
    real(wp) :: m(3, 3), rhs(3), phase, e, basis(3), offsets(4), channel_err
    complex(wp) :: y_pred
    integer :: i, j
    character(len=40) :: line
    file = 'raildyn_alignment_' // tag() // '.txt'
    ! the record: 0 .. 500 m every 0.5 m (linear interpolation error A (k h)^2 / 8 = 0.06 um)
    call write_record(dir // '/' // file, 0.0_wp, 500.0_wp, 0.5_wp, 'alignment')
    call scene%load_string(deck_text(file, 50.0_wp, t_end, interval), dir, error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, 'alignment scene')
    k = 2 * pi / wavelength
    m = 0; rhs = 0; sxx = 0; sxf = 0; err_max = 0; channel_err = 0
    do i = 1, nsteps
      call scene%advance(i * interval, error)
      call stop_on(error, 'alignment run')
      call scene%get_output('bodies/ws1/position_track', q, error)
      if (.not. allocated(error)) call scene%get_output('track/frames/1/sigma', s, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/left/patch1', pl, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/right/patch1', pr, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/rail_offsets', offsets, error)
      call stop_on(error, 'alignment outputs')
      ! the output channel: both rails at the alignment of the wheelset's track position
      ! (faded in over 50 m), linear interpolation of the 0.5 m record: <= 0.06 um
      if (s(1) + q(1) >= 50.0_wp) channel_err = max(channel_err, &
        maxval(abs(offsets - amplitude * sin(k * (s(1) + q(1))) * [1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp])))
      ! f11 of the linear law: Fx = -f11 xi (patch channels 4 = xi, 7 = creep_force_x)
      sxx = sxx + pl(4)**2 + pr(4)**2
      sxf = sxf - pl(4) * pl(7) - pr(4) * pr(7)
      if (s(1) >= 250.0_wp .and. s(1) <= 450.0_wp) then
        phase = k * (s(1) + q(1))
        e = q(2) - amplitude * sin(phase)
        basis = [1.0_wp, sin(phase), cos(phase)]
        do j = 1, 3
          m(:, j) = m(:, j) + basis * basis(j)
        end do
        rhs = rhs + basis * e
        err_max = max(err_max, abs(e))
      end if
    end do
    call scene%destroy()
    call delete_file(dir // '/' // file)
    f11 = sxf / sxx
    write (line, '(es10.3)') channel_err
    call check(channel_err <= 1.0e-7_wp, 'alignment: output rail_offsets = (a, 0, a, 0) at the wheelset (' // &
               trim(line) // ' m)')
    fit = solve3(m, rhs)
    lam_e = lam * e0 / (e0 - r0 * lam)
    beta = k_psi / (2 * e0 * f11)
    y_pred = -cmplx(0.0_wp, amplitude, wp) * cmplx(e0 * k**2, -beta * k, wp) / &
             cmplx(lam_e / r0 - e0 * k**2, beta * k, wp)
    write (*, '(a, es12.5, a)') 'f11 from the run: ', f11, ' N'
    write (*, '(a, 2f9.4, a, 2f9.4, a, f9.4)') 'y - a: sin, cos part [um] ', fit(2) * 1e6, fit(3) * 1e6, &
      '; quasi-static model ', -aimag(y_pred) * 1e6, real(y_pred) * 1e6, '; mean ', fit(1) * 1e6
    call check(abs(cmplx(fit(3), -fit(2), wp) - y_pred) <= 0.03_wp * abs(y_pred), &
               'alignment: steady lag behind the rails = quasi-static steering model within 3 %')
    write (line, '(f0.3, a, f0.3, a)') err_max * 1e6, ' um <= ', (1.03_wp * abs(y_pred) + 1e-7_wp) * 1e6, ' um'
    call check(err_max <= 1.03_wp * abs(y_pred) + 1.0e-7_wp, 'alignment: max |y - a| on the last wavelength ' // &
               trim(line) // ' (' // trim(percent(err_max / amplitude)) // ' of A)')
  end subroutine test_alignment

  subroutine test_gauge()
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    character(len=:), allocatable :: file
    real(wp), parameter :: interval = 0.02_wp, t_end = 6.0_wp, widening = 2.0e-3_wp
    integer, parameter :: nsteps = nint(t_end / interval)
    real(wp) :: q(6), s(1), pl(23), pr(23), lat, z_before, z_after, rail_dev, offsets(4), channel_err
    integer :: i
    character(len=60) :: line
    file = 'raildyn_gauge_' // tag() // '.txt'
    call write_record(dir // '/' // file, 20.0_wp, 200.0_wp, 1.0_wp, 'gauge')
    call scene%load_string(deck_text(file, 10.0_wp, t_end, interval), dir, error)
    if (.not. allocated(error)) call scene%initialize(.false., error)
    call stop_on(error, 'gauge scene')
    lat = 0; z_before = 0; z_after = 0; rail_dev = 0; channel_err = 0
    do i = 1, nsteps
      call scene%advance(i * interval, error)
      call stop_on(error, 'gauge run')
      call scene%get_output('bodies/ws1/position_track', q, error)
      if (.not. allocated(error)) call scene%get_output('track/frames/1/sigma', s, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/left/patch1', pl, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/right/patch1', pr, error)
      if (.not. allocated(error)) call scene%get_output('wheelsets/w1/rail_offsets', offsets, error)
      call stop_on(error, 'gauge outputs')
      lat = max(lat, abs(q(2)), e0 * abs(q(4)), e0 * abs(q(5)))
      ! settled before the record (the initial vertical settling lasts ~0.5 s) and well after
      ! the fade (rail_point_y: channel 16)
      if (s(1) <= 20.0_wp) z_before = q(3)
      if (s(1) >= 50.0_wp) then
        z_after = q(3)
        rail_dev = max(rail_dev, abs(pl(16) - (e0 + 0.5_wp * widening)), abs(pr(16) + (e0 + 0.5_wp * widening)))
        channel_err = max(channel_err, maxval(abs(offsets - [0.5_wp * widening, 0.0_wp, -0.5_wp * widening, 0.0_wp])))
      else if (s(1) < 20.0_wp) then
        channel_err = max(channel_err, maxval(abs(offsets)))
      end if
    end do
    call scene%destroy()
    call delete_file(dir // '/' // file)
    write (line, '(es10.3)') lat
    call check(lat < 1.0e-7_wp, 'gauge widening: lateral displacement, e0 yaw, e0 roll < 1e-7 m (' // trim(line) // ')')
    write (line, '(es10.3)') rail_dev
    call check(rail_dev < 1.0e-12_wp, 'gauge widening: both contacts at +-(e0 + 1 mm) (' // trim(line) // ')')
    write (line, '(es10.3)') channel_err
    call check(channel_err == 0, 'gauge widening: output rail_offsets = (+1 mm, 0, -1 mm, 0), zeros before the record (' &
               // trim(line) // ')')
    write (line, '(es12.5, a, es12.5)') z_after - z_before, ' m vs ', -lam * 0.5_wp * widening
    call check(abs((z_after - z_before) + lam * 0.5_wp * widening) <= 1.0e-3_wp * lam * 0.5_wp * widening, &
               'gauge widening: wheelset lowered by lam * 1 mm (' // trim(line) // ')')
  end subroutine test_gauge

  !> A record from s0 to s1 every ds: 'alignment' = A sin(2 pi s / L), 'gauge' = 2 mm.
  subroutine write_record(path, s0, s1, ds, kind)
    character(len=*), intent(in) :: path, kind
    real(wp), intent(in) :: s0, s1, ds
    integer :: unit, i, n
    real(wp) :: s
    open (newunit=unit, file=path, status='replace', action='write')
    write (unit, '(a)') '# sigma_m alignment_m level_m cross_level_m gauge_m'
    n = nint((s1 - s0) / ds)
    do i = 0, n
      s = s0 + i * ds
      if (kind == 'alignment') then
        write (unit, '(f0.4, 4(1x, es24.16))') s, amplitude * sin(2 * pi * s / wavelength), 0.0_wp, 0.0_wp, 0.0_wp
      else
        write (unit, '(f0.4, 4(1x, es24.16))') s, 0.0_wp, 0.0_wp, 0.0_wp, 2.0e-3_wp
      end if
    end do
    close (unit)
  end subroutine write_record

  function solve3(a, b) result(x)
    real(wp), intent(in) :: a(3, 3), b(3)
    real(wp) :: x(3), d
    integer :: j
    real(wp) :: c(3, 3)
    d = det3(a)
    do j = 1, 3
      c = a
      c(:, j) = b
      x(j) = det3(c) / d
    end do
  end function solve3

  pure real(wp) function det3(a)
    real(wp), intent(in) :: a(3, 3)
    det3 = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
           a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
  end function det3

  function percent(x) result(s)
    real(wp), intent(in) :: x
    character(len=16) :: s
    write (s, '(f5.2, a)') 100 * x, ' %'
  end function percent

  !> A random tag: concurrent test runs (Release and Debug) must not share files.
  function tag() result(t)
    character(len=12) :: t
    real(wp) :: r
    call random_number(r)
    write (t, '(i12.12)') int(r * 1.0e12_wp, kind=8)
  end function tag

  function scratch_dir() result(d)
    character(len=:), allocatable :: d
    character(len=512) :: buf
    integer :: status, length
    call get_environment_variable('TMPDIR', buf, length, status)
    if (status /= 0 .or. length == 0) buf = '/tmp'
    d = trim(buf)
  end function scratch_dir

end program test_track_irregularity_scene
