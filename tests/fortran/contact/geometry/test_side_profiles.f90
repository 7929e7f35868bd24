!> Different wheel and rail profiles on the left and right side (docs/conventions.md
!> "Profiles", docs/theory_contact_geometry.md "Per-side profiles"). Oracles, none produced
!> by the per-side code itself:
!> (a) the single-profile model: the same profiles given explicitly share the surfaces and
!>     give bit-identical results; a side with its own profiles gives, bit for bit, what the
!>     single-profile model built from that side's profiles gives on that side;
!> (b) rigid-body equivalences: a right wheel whose profile is the left one raised by dr
!>     (radius + dr) is, at zero yaw, the single-profile right wheel with the wheelset moved
!>     by dr along its own -z axis (that side only); the rigid-contact roll then satisfies
!>     the single-profile model's contact conditions and is ~ -dr / (2 e0). A right rail
!>     file translated in its profile frame changes nothing but u (rails are placed by gauge
!>     point and top, rd_contact_surfaces);
!> (c) mirror: swapping the left and right profiles and mirroring the pose mirrors the
!>     results (exactly for one evaluation, to the solver tolerance for rigid contact);
!> (d) profile scan of conical wheels on two circular rail heads of different radii: the
!>     rolling-radius difference and roll at y = 0 from the tangency conditions solved here.
program test_side_profiles
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1, RAIL_54E1
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, wheelset_contact, wheel_contact, &
                                 SIDE_LEFT, SIDE_RIGHT
  use rd_contact_patch, only: wheel_contact_t, mirror_wheel_contact
  use rd_rigid_contact, only: rigid_contact
  use rd_profile_scan, only: profile_scan_t, run_profile_scan
  use geometry_test_support, only: cone_wheel_profile, circle_rail_profile, circle_rail_centre_y
  use rd_test_support, only: check, test_summary
  implicit none
  type(profile_t) :: ws, r60, r54, wsdr, r60s
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  type(contact_geometry_t) :: geo_t, geo_e, geo_a, geo_l, geo_w, geo_s, geo_m
  type(wheel_contact_t) :: l1, r1, l2, r2, ref
  real(wp), parameter :: dr = 5.0e-4_wp, dshift = 3.0e-3_wp, hshift = -2.0e-3_wp
  real(wp) :: ys(5), yaws(2), rolls(2), z, phi, phi0, roll, z2, phi2, dmax, dmax2, e0, phi_ref, pen_l, pen_r
  integer :: i, j, k, m, nbad, nposes
  ! the poses of (a) and (c): ys x yaws x rolls about today's rigid-contact pose lowered by 20 um
  integer, parameter :: npose = 20
  real(wp) :: pose_y(npose), pose_yaw(npose), pose_z(npose), pose_roll(npose)
  logical :: ok
  ! (d): conicity, rail head radii (left, right), and the oracle's geometry (two_circle_scan)
  real(wp), parameter :: lam = 0.05_wp, rl = 0.3_wp, rr = 0.2_wp
  real(wp) :: ytape, cl(2), cr(2), nw(2), pw(2)

  call s1002_profile(ws, 1.0e-4_wp, error)
  if (.not. allocated(error)) call rail_head_profile(RAIL_60E1, r60, 1.0e-4_wp, error)
  if (.not. allocated(error)) call rail_head_profile(RAIL_54E1, r54, 1.0e-4_wp, error)
  if (allocated(error)) error stop error%message
  ! a right wheel 0.5 mm larger in radius (F + dr), a right rail file translated in its frame
  wsdr = ws; wsdr%z = ws%z + dr; wsdr%source = 's1002 + 0.5 mm'
  r60s = r60; r60s%y = r60%y + dshift; r60s%z = r60%z + hshift; r60s%source = '60e1 translated'

  call build_strip_contact(geo_t, ws, r60, pl, opt, error)                    ! today's model
  if (allocated(error)) error stop error%message
  ys = [-6.0e-3_wp, -3.0e-3_wp, 0.0_wp, 2.0e-3_wp, 5.0e-3_wp]
  yaws = [0.0_wp, 2.0e-3_wp]
  rolls = [0.0_wp, 1.5e-5_wp]     ! about the rigid roll: both wheels stay in contact
  k = 0
  do i = 1, size(ys)
    do j = 1, size(yaws)
      do m = 1, size(rolls)
        k = k + 1
        call base_pose(geo_t, ys(i), yaws(j), pose_z(k), phi0)
        pose_y(k) = ys(i); pose_yaw(k) = yaws(j); pose_roll(k) = phi0 + rolls(m)
      end do
    end do
  end do

  ! ---- (a) same profiles given explicitly on both sides
  call build_strip_contact(geo_e, ws, r60, pl, opt, error, wheel_profile_right=ws, rail_profile_right=r60, &
                          rail_precant_right=pl%rail_precant)
  if (allocated(error)) error stop error%message
  call check(.not. (geo_e%own_wheel_right .or. geo_e%own_rail_right) .and. .not. allocated(geo_e%wheel_right%y) &
    .and. .not. allocated(geo_e%rail_right%y), '(a) equal right profiles share the left surfaces (no copy)')
  nbad = 0; nposes = 0
  do k = 1, npose
    call wheelset_contact(geo_t, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), l1, r1, error)
    call wheelset_contact(geo_e, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), l2, r2, error)
    if (allocated(error)) error stop error%message
    nposes = nposes + 1
    if (.not. (identical(l1, l2) .and. identical(r1, r2))) nbad = nbad + 1
  end do
  call check(nbad == 0 .and. nposes == 20, '(a) explicit equal right profiles: both wheels bit for bit as today (20 poses)')

  ! own surfaces: left S1002+0.5mm / 54E1, right S1002 / 60E1; each side bit for bit equal to
  ! the single-profile model of its own profiles
  call build_strip_contact(geo_a, wsdr, r54, pl, opt, error, wheel_profile_right=ws, rail_profile_right=r60)
  if (allocated(error)) error stop error%message
  call build_strip_contact(geo_l, wsdr, r54, pl, opt, error)
  if (allocated(error)) error stop error%message
  call check(geo_a%own_wheel_right .and. geo_a%own_rail_right, '(a) different right profiles get own surfaces')
  nbad = 0; nposes = 0
  do k = 1, npose
    call wheelset_contact(geo_a, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), l1, r1, error)
    call wheel_contact(geo_l, SIDE_LEFT, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), l2)
    call wheel_contact(geo_t, SIDE_RIGHT, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), r2)
    if (allocated(error)) error stop error%message
    if (.not. (identical(l1, l2) .and. identical(r1, r2))) nbad = nbad + 1
    if (l1%n_patches > 0 .and. r1%n_patches > 0) nposes = nposes + 1
  end do
  write (*, '(a,i0,a)') '(a) own right surfaces: ', nposes, ' of 20 poses with patches on both wheels'
  call check(nbad == 0 .and. nposes >= 10, '(a) own right surfaces: each side bit for bit its single-profile model (20 poses)')

  ! ---- (b) right wheel radius + dr = today's right wheel with the wheelset moved by
  ! -dr along its own z axis, (y, z) -> (y + dr sin(phi), z - dr cos(phi)), at zero yaw
  call build_strip_contact(geo_w, ws, r60, pl, opt, error, wheel_profile_right=wsdr)
  if (allocated(error)) error stop error%message
  call check(geo_w%own_wheel_right .and. .not. geo_w%own_rail_right, '(b) only the right wheel has its own surface')
  dmax = 0; nbad = 0
  do i = 1, size(ys)
    do k = 1, size(rolls)
      call base_pose(geo_t, ys(i), 0.0_wp, z, phi0)
      roll = phi0 + rolls(k)
      call wheelset_contact(geo_w, ys(i), z, roll, 0.0_wp, l1, r1, error)
      if (allocated(error)) error stop error%message
      call wheel_contact(geo_t, SIDE_LEFT, ys(i), z, roll, 0.0_wp, l2)
      call wheel_contact(geo_t, SIDE_RIGHT, ys(i) + dr * sin(roll), z - dr * cos(roll), roll, 0.0_wp, r2)
      if (.not. identical(l1, l2)) nbad = nbad + 1
      if (r1%n_patches /= r2%n_patches .or. r1%n_patches == 0) then
        nbad = nbad + 1
        cycle
      end if
      dmax = max(dmax, patch_difference(r1, r2, dr))
    end do
  end do
  write (*, '(a,es10.3)') '(b) right wheel + dr vs today''s right wheel moved by dr: max difference ', dmax
  call check(nbad == 0, '(b) left wheel unchanged bit for bit, same patch counts on the right')
  call check(dmax < 1.0e-10_wp, '(b) right contacts = today''s with the wheelset moved by dr on that side ' // &
    '(points, penetration, angle, s, u to 1e-10; rolling radius + dr)')
  ! rigid contact of the centred wheelset: the single-profile model's contact conditions at
  ! the equivalent poses hold, and the roll is -dr / (2 e0) to first order
  call rigid_contact(geo_w, 0.0_wp, 0.0_wp, z, phi, error)
  if (allocated(error)) error stop error%message
  call wheel_contact(geo_t, SIDE_LEFT, 0.0_wp, z, phi, 0.0_wp, l2)
  call wheel_contact(geo_t, SIDE_RIGHT, dr * sin(phi), z - dr * cos(phi), phi, 0.0_wp, r2)
  pen_l = l2%max_penetration; pen_r = r2%max_penetration
  call rigid_contact(geo_t, 0.0_wp, 0.0_wp, z2, phi2, error, ref, lowering=1.0e-6_wp)
  e0 = abs(ref%patch(1)%point_rail(2))
  phi_ref = -dr / (2 * e0)
  write (*, '(a,es11.4,a,es11.4,a,2es10.2)') '(b) rigid roll ', phi, ' rad, -dr/(2 e0) ', phi_ref, &
    '; today''s gaps at the equivalent poses ', pen_l, pen_r
  call check(abs(pen_l) < 1.0e-9_wp .and. abs(pen_r) < 1.0e-9_wp, &
    '(b) rigid contact with a larger right wheel: both wheels touch in the single-profile model''s terms')
  call check(abs(phi / phi_ref - 1) < 0.03_wp, '(b) rigid roll = -dr/(2 e0) within 3 % (first order, contact angles)')

  ! right rail translated by (3 mm, -2 mm) in its profile frame: same contacts, u shifted
  call build_strip_contact(geo_s, ws, r60, pl, opt, error, rail_profile_right=r60s)
  if (allocated(error)) error stop error%message
  dmax = 0; nbad = 0
  do i = 1, size(ys)
    do j = 1, size(yaws)
      call base_pose(geo_t, ys(i), yaws(j), z, phi0)
      call wheel_contact(geo_s, SIDE_RIGHT, ys(i), z, phi0, yaws(j), r1)
      call wheel_contact(geo_t, SIDE_RIGHT, ys(i), z, phi0, yaws(j), r2)
      if (r1%n_patches /= r2%n_patches .or. r1%n_patches == 0) then
        nbad = nbad + 1
        cycle
      end if
      do k = 1, r1%n_patches
        dmax = max(dmax, abs(r1%patch(k)%u_rail - dshift - r2%patch(k)%u_rail))
        r1%patch(k)%u_rail = r2%patch(k)%u_rail; r1%patch(k)%u_rail_min = r2%patch(k)%u_rail_min
        r1%patch(k)%u_rail_max = r2%patch(k)%u_rail_max
      end do
      dmax = max(dmax, patch_difference(r1, r2, 0.0_wp))
    end do
  end do
  write (*, '(a,es10.3)') '(b) right rail file translated in its profile frame: max difference ', dmax
  call check(nbad == 0 .and. dmax < 1.0e-10_wp, '(b) a translated rail file changes nothing but u (gauge-point placement)')

  ! ---- (c) mirror: left/right profiles swapped and the pose mirrored
  call build_strip_contact(geo_m, ws, r60, pl, opt, error, wheel_profile_right=wsdr, rail_profile_right=r54)
  if (allocated(error)) error stop error%message
  nbad = 0
  do k = 1, npose
    call wheelset_contact(geo_a, pose_y(k), pose_z(k), pose_roll(k), pose_yaw(k), l1, r1, error)
    call wheelset_contact(geo_m, -pose_y(k), pose_z(k), -pose_roll(k), -pose_yaw(k), l2, r2, error)
    if (allocated(error)) error stop error%message
    call mirror_wheel_contact(l2); call mirror_wheel_contact(r2)
    if (.not. (identical(l1, r2) .and. identical(r1, l2))) nbad = nbad + 1
  end do
  call check(nbad == 0, '(c) swapped profiles, mirrored pose: exactly mirrored contacts (20 poses)')
  dmax = 0
  do i = 1, size(ys)
    call rigid_contact(geo_a, ys(i), 1.0e-3_wp, z, phi, error)
    call rigid_contact(geo_m, -ys(i), -1.0e-3_wp, z2, phi2, error)
    if (allocated(error)) error stop error%message
    dmax = max(dmax, abs(z - z2), abs(phi + phi2))
  end do
  write (*, '(a,es10.3)') '(c) rigid contact, swapped and mirrored: max |dz|, |roll + roll''| ', dmax
  call check(dmax < 1.0e-9_wp, '(c) rigid contact: same height, opposite roll (solver tolerance)')
  call mirrored_scans(geo_a, geo_m, dmax2, ok)
  write (*, '(a,es10.3)') '(c) profile scans, swapped: max |delta_r(y) + delta_r''(-y)| ', dmax2
  call check(ok .and. dmax2 < 1.0e-9_wp, '(c) profile scans: delta_r and roll antisymmetric, patch counts mirrored')

  ! ---- (d) profile scan with two different rails
  call two_circle_scan()

  call test_summary('test_side_profiles')

contains

  !> Rigid-contact pose of today's model lowered by 20 um, so that patches exist.
  subroutine base_pose(geo, y, psi, z, phi)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y, psi
    real(wp), intent(out) :: z, phi
    type(error_t), allocatable :: err
    call rigid_contact(geo, y, psi, z, phi, err)
    if (allocated(err)) error stop err%message
    z = z - 2.0e-5_wp
  end subroutine base_pose

  !> Every field of every patch bitwise equal.
  logical function identical(a, b)
    type(wheel_contact_t), intent(in) :: a, b
    integer :: p
    identical = a%n_patches == b%n_patches .and. a%max_penetration == b%max_penetration
    if (.not. identical) return
    do p = 1, a%n_patches
      associate (x => a%patch(p), y => b%patch(p))
        identical = identical .and. x%kind == y%kind .and. x%penetration == y%penetration .and. &
          all(x%point_rail == y%point_rail) .and. all(x%point_wheel == y%point_wheel) .and. &
          x%s_wheel == y%s_wheel .and. x%u_rail == y%u_rail .and. all(x%normal == y%normal) .and. &
          x%contact_angle == y%contact_angle .and. x%rolling_radius == y%rolling_radius .and. &
          x%curv_wheel_roll == y%curv_wheel_roll .and. x%curv_wheel_lat == y%curv_wheel_lat .and. &
          x%curv_rail_roll == y%curv_rail_roll .and. x%curv_rail_lat == y%curv_rail_lat .and. &
          x%u_rail_min == y%u_rail_min .and. x%u_rail_max == y%u_rail_max .and. x%strip_length == y%strip_length
      end associate
    end do
  end function identical

  !> Largest difference of the quantities that a rigid translation of the wheel leaves
  !> unchanged (rail point, penetration, normal, profile coordinates), rolling radius of `a`
  !> taken minus `dr_a`.
  real(wp) function patch_difference(a, b, dr_a) result(d)
    type(wheel_contact_t), intent(in) :: a, b
    real(wp), intent(in) :: dr_a
    integer :: p
    d = 0
    do p = 1, a%n_patches
      associate (x => a%patch(p), y => b%patch(p))
        d = max(d, maxval(abs(x%point_rail - y%point_rail)), abs(x%penetration - y%penetration), &
                maxval(abs(x%normal - y%normal)), abs(x%contact_angle - y%contact_angle), &
                abs(x%s_wheel - y%s_wheel), abs(x%u_rail - y%u_rail), abs(x%rolling_radius - dr_a - y%rolling_radius))
      end associate
    end do
  end function patch_difference

  subroutine mirrored_scans(ga, gm, d, ok)
    type(contact_geometry_t), intent(in) :: ga, gm
    real(wp), intent(out) :: d
    logical, intent(out) :: ok
    type(profile_scan_t) :: sa, sm
    integer :: q, n
    call run_profile_scan(ga, 0.006_wp, 0.001_wp, 0.0_wp, 5.0e-6_wp, sa, error)
    if (.not. allocated(error)) call run_profile_scan(gm, 0.006_wp, 0.001_wp, 0.0_wp, 5.0e-6_wp, sm, error)
    if (allocated(error)) error stop error%message
    n = sa%n
    d = 0; ok = .true.
    do q = 1, n
      d = max(d, abs(sa%delta_r(q) + sm%delta_r(n + 1 - q)), abs(sa%roll(q) + sm%roll(n + 1 - q)), &
              abs(sa%z(q) - sm%z(n + 1 - q)))
      ok = ok .and. all(sa%n_patches(:, q) == sm%n_patches([2, 1], n + 1 - q))
    end do
    ok = ok .and. abs(sa%delta_r((n + 1) / 2)) > 1.0e-5_wp
  end subroutine mirrored_scans

  !> Conical wheels (conicity lam, no flange) on circular rail heads of radius RL (left)
  !> and RR (right), no rail inclination. Oracle in the track (Y, Z) plane at zero yaw: the
  !> cone generator of each wheel is a straight line through the tape-circle point
  !> (ytape, -r0) with upward normal n_w = (-lam, 1)/sqrt(1 + lam^2) in the wheelset frame;
  !> rolled by phi about the centre (0, z) it touches the circle centred at C (rail top 0,
  !> gauge point 14 mm below it at gauge/2) when  R(phi) n_w . (C - (0, z)) - n_w . p_w = -R.
  !> The right wheel is the same condition in the mirrored frame (roll -phi). z is
  !> eliminated with the left condition and phi found by bisection; the contact point is
  !> C + R n, its wheel coordinate s and radius r0 - lam s.
  subroutine two_circle_scan()
    type(profile_t) :: cone, circ_l, circ_r
    type(contact_geometry_t) :: geo
    type(profile_scan_t) :: scan
    real(wp) :: a, b, fa, fm, m, zc, s_l, s_r, dr_ref, phi_ref
    integer :: q, k0
    call cone_wheel_profile(lam, cone)
    call circle_rail_profile(rl, circ_l)
    call circle_rail_profile(rr, circ_r)
    pl%inclination = 0
    call build_strip_contact(geo, cone, circ_l, pl, opt, error, rail_profile_right=circ_r)
    if (allocated(error)) error stop error%message
    call run_profile_scan(geo, 0.002_wp, 0.001_wp, 0.0_wp, 5.0e-6_wp, scan, error)
    if (allocated(error)) error stop error%message
    k0 = (scan%n + 1) / 2

    ytape = 0.5_wp * pl%back_to_back + 0.070_wp
    cl = [circle_rail_centre_y(pl%gauge, rl), -rl]
    cr = [circle_rail_centre_y(pl%gauge, rr), -rr]
    nw = [-lam, 1.0_wp] / sqrt(1 + lam**2)
    pw = [ytape, -pl%nominal_radius]
    a = -0.01_wp; b = 0.01_wp
    fa = right_condition(a)
    do q = 1, 200
      m = 0.5_wp * (a + b)
      fm = right_condition(m)
      if (sign(1.0_wp, fm) == sign(1.0_wp, fa)) then
        a = m; fa = fm
      else
        b = m
      end if
    end do
    phi_ref = 0.5_wp * (a + b)
    zc = left_height(phi_ref)
    s_l = contact_s(cl, rl, phi_ref, zc)
    s_r = contact_s(cr, rr, -phi_ref, zc)
    dr_ref = (pl%nominal_radius - lam * s_l) - (pl%nominal_radius - lam * s_r)
    write (*, '(a,f10.6,a,f10.6,a,es10.3,a,es10.3)') '(d) two rails (R 0.3 / 0.2 m), y = 0: delta_r ', &
      1000 * scan%delta_r(k0), ' mm, tangency ', 1000 * dr_ref, ' mm; roll ', scan%roll(k0), ' ref ', phi_ref
    call check(abs(scan%delta_r(k0)) > 1.0e-4_wp, '(d) different rails: rolling-radius difference at y = 0 not zero')
    call check(abs(scan%delta_r(k0) - dr_ref) < 4.0e-6_wp, '(d) delta_r(0) = tangency solution (4 um, profile spacing)')
    call check(abs(scan%roll(k0) - phi_ref) < 1.0e-7_wp, '(d) roll at y = 0 = tangency solution')
    call check(abs(scan%z(k0) - zc) < 1.0e-7_wp, '(d) height at y = 0 = tangency solution')
    pl%inclination = track_placement_default_inclination()
  end subroutine two_circle_scan

  pure function normal_at(phi) result(n)
    real(wp), intent(in) :: phi
    real(wp) :: n(2)
    n = [nw(1) * cos(phi) - nw(2) * sin(phi), nw(1) * sin(phi) + nw(2) * cos(phi)]
  end function normal_at
  !> z at which the left cone (roll phi) touches the left circle
  real(wp) function left_height(phi) result(z)
    real(wp), intent(in) :: phi
    real(wp) :: n(2)
    n = normal_at(phi)
    z = (dot_product(n, cl) - dot_product(nw, pw) + rl) / n(2)
  end function left_height
  real(wp) function right_condition(phi) result(f)
    real(wp), intent(in) :: phi
    real(wp) :: n(2)
    n = normal_at(-phi)
    f = dot_product(n, cr) - n(2) * left_height(phi) - dot_product(nw, pw) + rr
  end function right_condition
  !> wheel coordinate of the tangency point C + R n (n the rolled upward normal)
  real(wp) function contact_s(c, r, phi, z) result(s)
    real(wp), intent(in) :: c(2), r, phi, z
    real(wp) :: p(2), n(2), yw
    n = normal_at(phi)
    p = c + r * n - [0.0_wp, z]
    yw = p(1) * cos(phi) + p(2) * sin(phi)       ! back to the wheelset frame: R(-phi) p
    s = yw - ytape
  end function contact_s

  real(wp) function track_placement_default_inclination() result(incl)
    type(track_placement_t) :: d
    incl = d%inclination
  end function track_placement_default_inclination

end program test_side_profiles
