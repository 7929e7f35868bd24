!> Profile scan: equivalent conicity of a conical wheelset equals tan(gamma) (the textbook
!> definition), antisymmetry of the rolling-radius difference for S1002/60E1, and the
!> `raildyn profile-scan` command (CSV rows and columns, usage errors).
program test_profile_scan
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_knife_edge_contact, only: knife_edge_t
  use rd_contact_geometry, only: contact_geometry_t, build_knife_edge_contact, build_strip_contact
  use rd_profile, only: profile_t
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_profile_scan, only: profile_scan_t, run_profile_scan, equivalent_conicity
  use rd_cmd_profile_scan, only: run_profile_scan_command
  use rd_test_support, only: check, fail, test_summary
  use test_files, only: scratch_name
  implicit none
  type(knife_edge_t) :: k
  type(contact_geometry_t) :: geo
  type(profile_scan_t) :: scan
  type(error_t), allocatable :: error
  type(profile_t) :: wpf, rpf
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  real(wp) :: lam, amax, asym
  integer :: i, status, u, nlines, ncomma, ios
  character(len=4000) :: line
  character(len=:), allocatable :: csv

  k%cone_angle = 0.05_wp; k%e0 = 0.75_wp; k%r0 = 0.46_wp
  call build_knife_edge_contact(geo, k, error)
  call run_profile_scan(geo, 0.008_wp, 0.0005_wp, 0.0_wp, 5.0e-6_wp, scan, error)
  if (allocated(error)) error stop error%message
  ! Oracle: rigid contact of eqs. 5.2-5.7 solved here for roll phi (both approaches zero,
  ! z eliminated), giving the exact delta_r(A); for a (nearly) linear delta_r the harmonic
  ! linearisation is delta_r(A)/(2A). Because the wheelset rolls, the knife edges meet the
  ! cones off the nominal circles and delta_r = 2 y tan(gamma) / (1 - r0 tan(gamma)/e0) to
  ! first order (3 % above tan(gamma) here), not 2 y tan(gamma).
  amax = 0
  do i = 1, 4
    lam = equivalent_conicity(scan, 0.002_wp * i, error)
    amax = max(amax, abs(lam / (exact_delta_r(0.002_wp * i) / (0.004_wp * i)) - 1))
    if (i == 2) write (*, '(a,f9.6,a,f9.6,a,f9.6)') 'A = 4 mm: lambda_e ', lam, ', delta_r/2A (eqs. 5.2-5.7) ', &
      exact_delta_r(0.004_wp) / 0.008_wp, ', first order ', tan(k%cone_angle) / (1 - k%r0 * tan(k%cone_angle) / k%e0)
  end do
  write (*, '(a,es10.3)') 'conical wheelset: max relative |lambda_e - delta_r/2A| = ', amax
  call check(amax < 1e-4_wp, 'equivalent conicity of a conical wheelset = delta_r/(2A) of eqs. 5.2-5.7 (2-8 mm)')
  lam = equivalent_conicity(scan, 0.009_wp, error)
  call check(allocated(error), 'amplitude beyond the scan refused')

  call s1002_profile(wpf, 1.0e-4_wp, error)
  call rail_head_profile(RAIL_60E1, rpf, 1.0e-4_wp, error)
  call build_strip_contact(geo, wpf, rpf, pl, opt, error)
  call run_profile_scan(geo, 0.006_wp, 0.001_wp, 0.0_wp, 5.0e-6_wp, scan, error)
  if (allocated(error)) error stop error%message
  asym = 0
  do i = 1, scan%n
    asym = max(asym, abs(scan%delta_r(i) + scan%delta_r(scan%n + 1 - i)), abs(scan%roll(i) + scan%roll(scan%n + 1 - i)))
    if (any(scan%n_patches(:, i) /= scan%n_patches([2, 1], scan%n + 1 - i))) call fail()
  end do
  write (*, '(a,es10.3)') 'S1002/60E1: max antisymmetry defect ', asym
  call check(asym < 1e-9_wp, 'delta_r and roll antisymmetric in the shift, patch counts mirrored')
  call check(all(scan%delta_r(scan%n / 2 + 2:) > 0), 'positive shift (left): left rolling radius larger')

  csv = scratch_name('test_profile_scan', '.csv')
  call run_profile_scan_command([character(len=512) :: '--ymax', '0.004', '--step', '0.001', '--csv', csv], status)
  call check(status == 0, 'profile-scan command succeeds')
  open (newunit=u, file=csv, status='old', action='read', iostat=ios)
  call check(ios == 0, 'CSV written')
  nlines = 0
  if (ios == 0) then
    do
      read (u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      nlines = nlines + 1
      ncomma = count([(line(i:i) == ',', i=1, len_trim(line))])
      if (ncomma /= 4 + 2 * (1 + 4 * 5)) call fail()
    end do
    close (u, status='delete')
  end if
  call check(nlines == 1 + 9, 'CSV: header + 9 shifts, 47 columns each')
  call run_profile_scan_command([character(len=20) :: '--step'], status)
  call check(status == 2, 'missing value: usage error')
  call run_profile_scan_command([character(len=20) :: '--gauge', 'wide'], status)
  call check(status == 2, 'non-numeric value: usage error')
  call run_profile_scan_command([character(len=20) :: '--gauge', 'nan'], status)
  call check(status == 2, 'NaN value: usage error')
  call run_profile_scan_command([character(len=20) :: '--wheel', '/nonexistent.prw'], status)
  call check(status == 1, 'missing profile file: failure status')
  call test_summary('test_profile_scan')
contains
  real(wp) function exact_delta_r(y) result(dr)
    real(wp), intent(in) :: y
    real(wp) :: pa, pb, pm, fa, fm, r1, r2, e1, e2
    integer :: it
    pa = -0.01_wp; pb = 0.01_wp
    fa = f(y, pa)
    do it = 1, 200
      pm = 0.5_wp * (pa + pb)
      fm = f(y, pm)
      if (fa * fm <= 0) then
        pb = pm
      else
        pa = pm; fa = fm
      end if
    end do
    call radii(y, 0.5_wp * (pa + pb), r1, r2, e1, e2)
    dr = r1 - r2
  end function exact_delta_r

  !> eqs. 5.2 + 5.4 (left) and 5.5 + 5.7 (right, our frame): contact abscissae and radii
  subroutine radii(y, phi, r1, r2, e1, e2)
    real(wp), intent(in) :: y, phi
    real(wp), intent(out) :: r1, r2, e1, e2
    real(wp) :: tg
    tg = tan(k%cone_angle)
    e1 = (k%e0 - y - (k%r0 + k%e0 * tg) * sin(phi)) / (cos(phi) - tg * sin(phi))
    e2 = (k%e0 + y + (k%r0 + k%e0 * tg) * sin(phi)) / (cos(phi) + tg * sin(phi))
    r1 = k%r0 + (k%e0 - e1) * tg
    r2 = k%r0 + (k%e0 - e2) * tg
  end subroutine radii

  !> heights at which each wheel just touches (eqs. 5.3, 5.6 with delta = 0) must agree
  real(wp) function f(y, phi)
    real(wp), intent(in) :: y, phi
    real(wp) :: r1, r2, e1, e2
    call radii(y, phi, r1, r2, e1, e2)
    f = (r1 * cos(phi) - e1 * sin(phi)) - (r2 * cos(phi) + e2 * sin(phi))
  end function f
end program test_profile_scan
