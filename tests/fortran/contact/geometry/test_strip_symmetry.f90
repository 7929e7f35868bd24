!> Strip contact with real profiles: invariance tests (a centred wheelset is mirror
!> symmetric with zero rolling-radius difference; mirrored shifts give mirrored results),
!> an analytic case (conical wheel on a circular rail head: closed-form rigid height,
!> contact point, angle, radius), and continuity when a patch appears.
program test_strip_symmetry
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, wheelset_contact
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use geometry_test_support, only: cone_wheel_profile, circle_rail_profile, circle_rail_centre_y
  use rd_test_support, only: check, fail, test_summary
  implicit none
  type(profile_t) :: wpf, rpf
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  type(contact_geometry_t) :: geo
  type(wheel_contact_t) :: l, r, l2, r2
  real(wp) :: z, phi, z2, phi2, lam, rr, yc, zref, uref, alpha, d, dmax, prev, ytape, s
  integer :: i, n

  call s1002_profile(wpf, 1.0e-4_wp, error)
  call rail_head_profile(RAIL_60E1, rpf, 1.0e-4_wp, error)
  call build_strip_contact(geo, wpf, rpf, pl, opt, error)
  if (allocated(error)) error stop error%message

  ! centred: exact mirror symmetry
  call rigid_contact(geo, 0.0_wp, 0.0_wp, z, phi, error, l, r, lowering=1.0e-5_wp)
  if (allocated(error)) error stop error%message
  call check(phi == 0, 'centred wheelset: roll exactly zero')
  call check(l%n_patches == r%n_patches .and. l%n_patches >= 1, 'centred: same number of patches each side')
  call check(abs(l%patch(1)%rolling_radius - r%patch(1)%rolling_radius) == 0, 'centred: rolling-radius difference zero')
  call check(l%patch(1)%contact_angle == -r%patch(1)%contact_angle .and. l%patch(1)%u_rail == r%patch(1)%u_rail &
    .and. l%patch(1)%point_rail(2) == -r%patch(1)%point_rail(2), 'centred: mirrored contact points and angles')
  write (*, '(a,f9.4,a,f9.4,a,f8.4)') 'centred S1002/60E1 1:40: contact on rail u = ', 1000 * l%patch(1)%u_rail, &
    ' mm, wheel s = ', 1000 * l%patch(1)%s_wheel, ' mm, gamma = ', l%patch(1)%contact_angle

  ! mirrored shifts (with yaw) give mirrored results
  dmax = 0
  do i = 1, 8
    call rigid_contact(geo, 1.0e-3_wp * i, 1.0e-3_wp * i, z, phi, error, l, r, lowering=1.0e-5_wp)
    call rigid_contact(geo, -1.0e-3_wp * i, -1.0e-3_wp * i, z2, phi2, error, l2, r2, lowering=1.0e-5_wp)
    if (allocated(error)) error stop error%message
    if (l%n_patches /= r2%n_patches .or. r%n_patches /= l2%n_patches) then
      call fail()
      cycle
    end if
    dmax = max(dmax, abs(z - z2), abs(phi + phi2), abs(l%patch(1)%u_rail - r2%patch(1)%u_rail), &
      abs(l%patch(1)%contact_angle + r2%patch(1)%contact_angle), abs(r%patch(1)%rolling_radius - l2%patch(1)%rolling_radius))
    if (i == 3) call check(l%patch(1)%rolling_radius > r%patch(1)%rolling_radius, &
      'shift to the left: left rolling radius larger')
  end do
  write (*, '(a,es10.3)') 'mirrored shifts (rigid contact): max difference ', dmax
  call check(dmax < 1e-9_wp, 'mirrored shifts give mirrored heights, rolls, contacts (solver tolerance)')
  ! the evaluation itself is exactly mirror symmetric
  call wheelset_contact(geo, 4.0e-3_wp, z, 1.0e-4_wp, 3.0e-3_wp, l, r, error)
  call wheelset_contact(geo, -4.0e-3_wp, z, -1.0e-4_wp, -3.0e-3_wp, l2, r2, error)
  call check(l%n_patches == r2%n_patches .and. l%patch(1)%penetration == r2%patch(1)%penetration .and. &
    l%patch(1)%point_rail(2) == -r2%patch(1)%point_rail(2) .and. l%patch(1)%contact_angle == -r2%patch(1)%contact_angle, &
    'mirrored pose: exactly mirrored patches')

  ! continuity: lowering the wheelset through first touch, the penetration grows from 0
  call rigid_contact(geo, 2.0e-3_wp, 0.0_wp, z, phi, error)
  prev = -1
  n = 0
  do i = -5, 40
    call wheelset_contact(geo, 2.0e-3_wp, z - i * 1.0e-8_wp, phi, 0.0_wp, l, r, error)
    if (l%n_patches > 0) then
      n = n + 1
      if (n == 1) call check(l%patch(1)%penetration < 1.2e-8_wp, 'a new patch appears with penetration ~ 0')
      if (prev >= 0) then
        d = l%patch(1)%penetration - prev
        if (.not. (d > 0 .and. d < 1.0e-8_wp * 1.01_wp)) call fail()
      end if
      prev = l%patch(1)%penetration
    end if
  end do
  call check(n > 30, 'the patch persists while lowering')

  ! analytic: conical wheel (conicity lam) on a circular rail head R = 0.3 m, no inclination
  lam = 0.05_wp; rr = 0.3_wp
  call cone_wheel_profile(lam, wpf)
  call circle_rail_profile(rr, rpf)
  pl%inclination = 0
  call build_strip_contact(geo, wpf, rpf, pl, opt, error)
  if (allocated(error)) error stop error%message
  call rigid_contact(geo, 0.0_wp, 0.0_wp, z, phi, error, l, r, lowering=1.0e-6_wp)
  ! rail centre: gauge point 14 mm below the top at u = -sqrt(R^2 - (R - 0.014)^2)
  yc = circle_rail_centre_y(pl%gauge, rr)
  ytape = 0.5_wp * pl%back_to_back + 0.070_wp
  ! cone line Z = z - r0 + lam (Y - ytape) tangent to the circle centred (yc, -R)
  zref = pl%nominal_radius + lam * ytape - lam * yc - rr + rr * sqrt(1 + lam**2)
  alpha = atan(lam)
  uref = -rr * sin(alpha)
  s = yc + uref - ytape
  write (*, '(a,es11.3,a,f9.5,a,f9.5,a,es11.3)') 'cone on circle: z - zref ', z - zref, ' m, u ', 1000 * l%patch(1)%u_rail, &
    ' mm (ref ', 1000 * uref, '), r - ref ', l%patch(1)%rolling_radius - (pl%nominal_radius - lam * s)
  call check(abs(z - zref) < 1e-8_wp, 'cone on circle: rigid height equals the tangency condition')
  call check(abs(l%patch(1)%u_rail - uref) < 2e-5_wp, 'cone on circle: contact point where the slopes match (20 um)')
  call check(abs(l%patch(1)%contact_angle + alpha) < 1e-4_wp, 'cone on circle: contact angle -atan(conicity)')
  call check(abs(l%patch(1)%rolling_radius - (pl%nominal_radius - lam * s)) < 2e-6_wp, 'cone on circle: rolling radius')
  call check(abs(l%patch(1)%curv_rail_lat - 1 / rr) < 1e-6_wp / rr .and. abs(l%patch(1)%curv_wheel_lat) < 1e-6_wp, &
    'cone on circle: curvatures 1/R (rail) and 0 (cone)')
  call check(abs(l%patch(1)%curv_wheel_roll - 1 / (l%patch(1)%rolling_radius * sqrt(1 + lam**2))) < 1e-9_wp, &
    'cone on circle: rolling-direction wheel curvature cos(gamma)/r (eq. 4.75)')
  call test_summary('test_strip_symmetry')
end program test_strip_symmetry
