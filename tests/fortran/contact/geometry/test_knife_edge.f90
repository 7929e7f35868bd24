!> Knife-edge conical contact against the thesis' closed form (eqs. 5.2-5.7, solved here
!> independently for e1, r1 / e2, r2, written in our frame: knife edges at Y = +-e0, Z = 0),
!> the flange stop, yawed edges against sampling, and rigid contact of a conical wheelset.
program test_knife_edge
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_knife_edge_contact, only: knife_edge_t
  use rd_contact_geometry, only: contact_geometry_t, build_knife_edge_contact, wheelset_contact
  use rd_contact_patch, only: wheel_contact_t, PATCH_TREAD, PATCH_FLANGE_SPRING
  use rd_rigid_contact, only: rigid_contact
  use rd_test_support, only: check, fail, test_summary
  implicit none
  type(knife_edge_t) :: k
  type(contact_geometry_t) :: geo
  type(wheel_contact_t) :: l, r
  type(error_t), allocatable :: error
  real(wp) :: y, z, phi, g, e0, r0, e1, r1, e2, r2, dl, dr, err_d, err_g, err_r, tg, ys(5), phis(3)
  real(wp) :: psi, best, tt, py, rad, zz, pp
  integer :: i, j, m

  k%cone_angle = 0.1_wp; k%e0 = 0.75_wp; k%r0 = 0.45_wp      ! thesis table 5.7
  call build_knife_edge_contact(geo, k, error)
  if (allocated(error)) error stop error%message
  g = k%cone_angle; e0 = k%e0; r0 = k%r0; tg = tan(g)
  ys = [-6e-3_wp, -2e-3_wp, 0.0_wp, 1.5e-3_wp, 5e-3_wp]
  phis = [-2e-3_wp, 0.0_wp, 3e-3_wp]
  err_d = 0; err_g = 0; err_r = 0; m = 0
  do i = 1, size(ys)
    do j = 1, size(phis)
      y = ys(i); phi = phis(j)
      ! left wheel, eqs. 5.2 + 5.4: e0 = y + e1 cos(phi) + r1 sin(phi), r1 = r0 + (e0 - e1) tan(gamma)
      e1 = (e0 - y - (r0 + e0 * tg) * sin(phi)) / (cos(phi) - tg * sin(phi))
      r1 = r0 + (e0 - e1) * tg
      ! right wheel, eqs. 5.5 + 5.7 in our frame (edge at -e0)
      e2 = (e0 + y + (r0 + e0 * tg) * sin(phi)) / (cos(phi) + tg * sin(phi))
      r2 = r0 + (e0 - e2) * tg
      ! a height giving some 10-60 um of approach on both
      z = min(r1 * cos(phi) - e1 * sin(phi), r2 * cos(phi) + e2 * sin(phi)) - 6.0e-5_wp
      ! eq. 5.3 / 5.6: vertical overlap = delta / cos(gamma +- phi)
      dl = -(z + e1 * sin(phi) - r1 * cos(phi)) * cos(g + phi)
      dr = -(z - e2 * sin(phi) - r2 * cos(phi)) * cos(g - phi)
      call wheelset_contact(geo, y, z, phi, 0.0_wp, l, r, error)
      if (allocated(error)) error stop error%message
      if (l%n_patches /= 1 .or. r%n_patches /= 1) then
        call fail()
        cycle
      end if
      m = m + 1
      err_d = max(err_d, abs(l%patch(1)%penetration - dl), abs(r%patch(1)%penetration - dr))
      err_g = max(err_g, abs(l%patch(1)%contact_angle + (g + phi)), abs(r%patch(1)%contact_angle - (g - phi)))
      ! the rolling radius at the approach point differs from r1 by delta sin(gamma) at most
      err_r = max(err_r, abs(l%patch(1)%rolling_radius - r1), abs(r%patch(1)%rolling_radius - r2))
    end do
  end do
  write (*, '(a,i0,a,es10.3,a,es10.3,a,es10.3)') 'poses ', m, ': max |delta - eq. 5.3/5.6| ', err_d, &
    ' m, |gamma| ', err_g, ' rad, |r - r1| ', err_r
  call check(m == 15, 'every pose touches both knife edges once')
  call check(err_d < 1e-12_wp, 'penetration equals the closed form of eqs. 5.2-5.7')
  call check(err_g < 1e-12_wp, 'contact angles -(gamma + phi) left, gamma - phi right')
  call check(err_r < 1e-5_wp, 'rolling radii r1, r2 of eqs. 5.4/5.7 (within delta sin(gamma))')

  ! yawed edge: deepest point against sampling along the edge
  psi = 0.02_wp; y = 1e-3_wp; z = 0.4502_wp; phi = 1e-3_wp
  call wheelset_contact(geo, y, z, phi, psi, l, r, error)
  best = -huge(1.0_wp)
  do i = -200000, 200000
    tt = i * 1.0e-6_wp
    ! edge point (tt, e0, 0) in the wheelset frame: B^T (p - w), B = Rz(psi) Rx(phi)
    call depth_at(tt, py, rad, zz)
    best = max(best, zz)
  end do
  write (*, '(a,es12.4,a,es12.4)') 'yawed edge: model ', l%max_penetration, ' sampling ', best * cos(g)
  call check(abs(l%max_penetration - best * cos(g)) < 1e-11_wp, 'yawed knife edge: deepest point equals sampling')

  ! rigid contact of the conical wheelset: both closed-form approaches vanish
  do i = 1, size(ys)
    call rigid_contact(geo, ys(i), 0.0_wp, zz, pp, error)
    if (allocated(error)) error stop error%message
    e1 = (e0 - ys(i) - (r0 + e0 * tg) * sin(pp)) / (cos(pp) - tg * sin(pp))
    r1 = r0 + (e0 - e1) * tg
    e2 = (e0 + ys(i) + (r0 + e0 * tg) * sin(pp)) / (cos(pp) + tg * sin(pp))
    r2 = r0 + (e0 - e2) * tg
    dl = -(zz + e1 * sin(pp) - r1 * cos(pp)) * cos(g + pp)
    dr = -(zz - e2 * sin(pp) - r2 * cos(pp)) * cos(g - pp)
    call check(abs(dl) < 1e-12_wp .and. abs(dr) < 1e-12_wp, 'rigid contact: both approaches vanish (eqs. 5.3, 5.6)')
  end do

  ! flange stop beyond the clearance
  k%flange_clearance = 6.0e-3_wp
  call build_knife_edge_contact(geo, k, error)
  call wheelset_contact(geo, 7.0e-3_wp, 0.4490_wp, 0.0_wp, 0.0_wp, l, r, error)
  call check(l%n_patches == 2 .and. r%n_patches == 1, 'flange stop: a second patch on the left wheel only')
  if (l%n_patches == 2) then
    call check(l%patch(2)%kind == PATCH_FLANGE_SPRING .and. abs(l%patch(2)%penetration - 1.0e-3_wp) < 1e-15_wp &
      .and. abs(l%patch(2)%contact_angle + 0.5_wp * pi) < 1e-15_wp, 'flange stop: lateral overlap 1 mm, normal towards -Y')
  end if
  call wheelset_contact(geo, -7.0e-3_wp, 0.4490_wp, 0.0_wp, 0.0_wp, l, r, error)
  call check(r%n_patches == 2 .and. l%n_patches == 1, 'flange stop mirrored on the right wheel')
  call wheelset_contact(geo, 0.0_wp, ieee_nan(), 0.0_wp, 0.0_wp, l, r, error)
  call check(allocated(error), 'NaN pose reported as an error')
  call test_summary('test_knife_edge')
contains
  subroutine depth_at(t, pyq, radq, dep)
    real(wp), intent(in) :: t
    real(wp), intent(out) :: pyq, radq, dep
    real(wp) :: v(3), q(3)
    v = [t, e0 - y, -z]
    ! B^T v with B = Rz(psi) Rx(phi)
    q(1) = cos(psi) * v(1) + sin(psi) * v(2)
    q(2) = -sin(psi) * cos(phi) * v(1) + cos(psi) * cos(phi) * v(2) + sin(phi) * v(3)
    q(3) = sin(psi) * sin(phi) * v(1) - cos(psi) * sin(phi) * v(2) + cos(phi) * v(3)
    pyq = q(2)
    radq = hypot(q(1), q(3))
    dep = (r0 - tg * (pyq - e0)) - radq
  end subroutine depth_at
  real(wp) function ieee_nan()
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    ieee_nan = ieee_value(1.0_wp, ieee_quiet_nan)
  end function ieee_nan
end program test_knife_edge
