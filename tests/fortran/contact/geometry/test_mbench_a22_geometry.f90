!> Manchester contact benchmark A-2.2 (validation/reference/mbench_a22): S1002 v3 wheels on UIC60 v3
!> rails 1:40, wheelset shifted 0..10 mm with yaw 2.4 mrad/mm. Independent oracle: CONTACT's
!> contact positions on the rails and contact angles (reference.csv).
!>
!> Pose mapping: CONTACT's track frame has y to the right and z down, ours y left, z up,
!> so our y = -y_ws and our yaw = -yaw_ref; roll (about the common x axis) keeps its sign.
!> The vertical position is not given (CONTACT prescribes 10 kN): we take the rigid-contact
!> height and roll for the given shift and yaw, and lower the wheelset by 20 um (about the
!> Hertz approach at 10 kN, validation/reference/oracles.md) to open the patches.
!> Rail coordinates: reference y_cp_rail is the rail file coordinate (field side +) for the
!> right rail and its mirror for the left rail; our u_rail is the file coordinate on both.
!> Contact angles: CONTACT measures them in its frame (y right), ours towards +Y: both
!> sides change sign.
program test_mbench_a22_geometry
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_io, only: read_profile_file
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact
  use rd_contact_patch, only: wheel_contact_t, PATCH_TREAD
  use rd_rigid_contact, only: rigid_contact
  use rd_strip_contact, only: strip_wheel_contact
  use rd_test_support, only: check, test_summary
  use test_files, only: reference_path
  implicit none
  type(profile_t) :: wp_prof, rp_prof
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  type(contact_geometry_t) :: geo
  type(wheel_contact_t) :: left, right, full_l, full_r
  real(wp) :: err_search = 0, err_search_u = 0
  character(len=512) :: line
  real(wp) :: v(25), yws(21), yaw(21), roll(21), ul_ref(21), gl_ref(21), ur_ref(21), gr_ref(21)
  real(wp) :: z, phi, ul(21), ur(21), gl(21), gr(21), err_u, err_u_case2, err_g, jump, phis(21), err_roll, err_gf
  real(wp) :: xl(21), xr(21), xl_ref(21), xr_ref(21), err_x
  integer :: unit, ios, n, i, nl(21), nr(21), ir, il
  logical :: flange_r(21)

  call read_profile_file(reference_path('profiles/MBench_S1002_v3.prw'), PROFILE_WHEEL, wp_prof, error)
  if (allocated(error)) error stop 'cannot read wheel: ' // error%message
  call read_profile_file(reference_path('profiles/MBench_UIC60_v3.prr'), PROFILE_RAIL, rp_prof, error)
  if (allocated(error)) error stop 'cannot read rail: ' // error%message
  pl%rail_precant = 0.025_wp      ! the v3 rail is already canted 1:40
  pl%inclination = 0.025_wp
  call build_strip_contact(geo, wp_prof, rp_prof, pl, opt, error)
  if (allocated(error)) error stop error%message

  open (newunit=unit, file=reference_path('mbench_a22/reference.csv'), status='old', action='read')
  read (unit, '(a)') line
  n = 0
  do
    read (unit, '(a)', iostat=ios) line
    if (ios /= 0) exit
    read (line, *) v
    n = n + 1
    yws(n) = v(2) * 1.0e-3_wp; yaw(n) = v(3) * 1.0e-3_wp; roll(n) = v(4)
    ul_ref(n) = v(8) * 1.0e-3_wp; gl_ref(n) = v(9)
    ur_ref(n) = v(13) * 1.0e-3_wp; gr_ref(n) = v(14)
  end do
  close (unit)
  call check(n == 21, 'reference.csv has 21 cases')
  ! longitudinal contact positions XCP(TR) [mm] from CONTACT's outputs (same x axis as ours)
  call read_xcp(reference_path('mbench_a22/mbench_a22_left.ref_out'), xl_ref)
  call read_xcp(reference_path('mbench_a22/mbench_a22_right.ref_out'), xr_ref)

  write (*, '(a)') ' case  y[mm]  roll_ref   roll_rigid | nL uL[mm] ref    gL[rad] ref     | nR uR[mm] ref     gR[rad] ref'
  do i = 1, n
    call rigid_contact(geo, -yws(i), -yaw(i), z, phi, error, left, right, lowering=2.0e-5_wp)
    if (allocated(error)) error stop error%message
    nl(i) = left%n_patches; nr(i) = right%n_patches
    phis(i) = phi
    il = deepest(left); ir = deepest(right)
    ul(i) = left%patch(il)%u_rail; gl(i) = left%patch(il)%contact_angle
    ur(i) = right%patch(ir)%u_rail; gr(i) = right%patch(ir)%contact_angle
    flange_r(i) = any(abs(right%patch(1:nr(i))%contact_angle) > 0.5_wp)
    xl(i) = left%patch(il)%point_rail(1); xr(i) = right%patch(ir)%point_rail(1)
    ! the hill-climbing search along each strip equals the exhaustive search over all cones
    call strip_wheel_contact(geo%wheel, geo%rail, -yws(i), z - 2.0e-5_wp, phi, -yaw(i), full_l, exhaustive=.true.)
    call strip_wheel_contact(geo%wheel, geo%rail, yws(i), z - 2.0e-5_wp, -phi, yaw(i), full_r, exhaustive=.true.)
    err_search = max(err_search, abs(full_l%max_penetration - left%max_penetration), &
      abs(full_r%max_penetration - right%max_penetration))
    err_search_u = max(err_search_u, abs(full_l%patch(1)%u_rail - left%patch(1)%u_rail), &
      abs(full_r%patch(1)%u_rail - right%patch(1)%u_rail))
    write (*, '(i4,f7.2,2es11.3," |",i2,2f8.3,2f9.4," |",i2,2f8.3,2f9.4)') i, 1000 * yws(i), roll(i), phi, &
      nl(i), 1000 * ul(i), -1000 * ul_ref(i), gl(i), -gl_ref(i), nr(i), 1000 * ur(i), 1000 * ur_ref(i), gr(i), -gr_ref(i)
  end do

  ! On the yawed flange the depth along one strip can have several local maxima at the
  ! vertices of the polygonal (concave) throat; the climb may stop on one of them. The
  ! difference is bounded by the polygon resolution h^2/(8R) (0.2 mm, R12: 0.4 um).
  write (*, '(a,es10.3,a,es10.3,a)') 'hill climb vs exhaustive search: max difference ', err_search, &
    ' m in penetration, ', err_search_u, ' m in contact position'
  call check(err_search < 5e-7_wp .and. err_search_u < 5e-6_wp, &
    'hill-climbing strip search equals the exhaustive search within the polygon resolution')
  ! positions and tread angles where each side has one patch, at a fixed rigid lowering of
  ! 20 um (a geometry-only stand-in for the benchmark's 10 kN per wheel). At 0.5 mm shift
  ! (case 2) CONTACT's right patch is a 14 mm wide near-conformal patch just after the
  ! contact jump, and its point moves with the approach (-18.4, -17.4, -13.9 mm at 10, 20,
  ! 40 um): here it lies 1.41 mm from CONTACT's location; loaded to 10 kN as the benchmark
  ! prescribes it lies 0.71 mm away, and that 1 mm check of every case is in
  ! test_wheelset_mbench_a22. Case 2 is reported here on its own (guarded against getting
  ! worse) and the rest must meet 1 mm at this lowering as well.
  err_u = 0; err_g = 0; err_u_case2 = 0
  do i = 1, n
    if (nl(i) == 1) then
      if (i == 2) then
        err_u_case2 = max(err_u_case2, abs(ul(i) + ul_ref(i)))
      else
        err_u = max(err_u, abs(ul(i) + ul_ref(i)))
      end if
      if (abs(gl(i)) < 0.3_wp) err_g = max(err_g, abs(gl(i) + gl_ref(i)))
    end if
    if (nr(i) == 1) then
      if (i == 2) then
        err_u_case2 = max(err_u_case2, abs(ur(i) - ur_ref(i)))
      else
        err_u = max(err_u, abs(ur(i) - ur_ref(i)))
      end if
      if (abs(gr(i)) < 0.3_wp) err_g = max(err_g, abs(gr(i) + gr_ref(i)))
    end if
  end do
  write (*, '(a,f7.3,a,f7.4,a)') 'max |u_rail - ref| (all one-patch cases but 2) = ', 1000 * err_u, &
    ' mm, max tread |gamma - ref| = ', err_g, ' rad'
  write (*, '(a,f7.3,a)') 'case 2 (0.5 mm, at the jump) at this 20 um lowering: |u_rail - ref| = ', &
    1000 * err_u_case2, ' mm (at the benchmark load of 10 kN: test_wheelset_mbench_a22)'
  call check(err_u < 1.0e-3_wp, 'contact positions on the rails within 1 mm of CONTACT (cases other than 2)')
  call check(err_u_case2 < 1.5e-3_wp, 'case 2 deviation does not grow beyond its measured 1.41 mm')
  call check(err_g < 0.02_wp, 'tread contact angles within 0.02 rad of CONTACT')
  ! flange contact angles and the roll angle (CONTACT solved roll for equal 10 kN loads;
  ! rigid contact must give nearly the same roll)
  err_gf = maxval(abs(gr(14:21) + gr_ref(14:21)))
  err_roll = maxval(abs(phis(2:21) - roll(2:21)) / abs(roll(2:21)))
  write (*, '(a,f7.4,a,f6.3)') 'max flange |gamma - ref| = ', err_gf, ' rad, max relative roll difference ', err_roll
  call check(err_gf < 0.02_wp, 'flange contact angles within 0.02 rad of CONTACT')
  call check(err_roll < 0.10_wp, 'rigid-contact roll within 10% of the roll CONTACT balanced for 10 kN per wheel')
  call check(abs(phis(1)) < 1e-12_wp, 'centred wheelset: zero roll')
  ! longitudinal position: the yawed wheel's centre plane (yaw x 0.745 m, about 0.9 mm per
  ! 1.2 mrad) plus the flange lead (5.8 mm at 6.5 mm shift)
  err_x = max(maxval(abs(xl(1:n) - xl_ref(1:n))), maxval(abs(xr(1:n) - xr_ref(1:n))))
  write (*, '(a)') ' case  xL ours  xL ref   xR ours  xR ref [mm]'
  do i = 1, n
    write (*, '(i4,4f9.3)') i, 1000 * xl(i), 1000 * xl_ref(i), 1000 * xr(i), 1000 * xr_ref(i)
  end do
  write (*, '(a,f7.3,a)') 'max |x_cp - ref| = ', 1000 * err_x, ' mm'
  call check(err_x < 0.5e-3_wp, 'longitudinal contact positions (yaw offset, flange lead) within 0.5 mm of CONTACT')
  ! jumps of the right contact where CONTACT jumps (> 4 mm between 0.5 mm steps), and only there
  do i = 1, n - 1
    jump = abs(ur(i + 1) - ur(i))
    if (i == 1 .or. i == 10 .or. i == 13) then
      call check(jump > 4.0e-3_wp, 'right contact jumps between cases ' // itoa(i) // ' and ' // itoa(i + 1))
    else
      call check(jump < 4.0e-3_wp, 'right contact moves continuously between cases ' // itoa(i) // ' and ' // itoa(i + 1))
    end if
  end do
  call check(.not. any(flange_r(1:13)), 'no right flange contact up to 6.0 mm')
  call check(flange_r(14), 'right flange contact at 6.5 mm')
  call test_summary('test_mbench_a22_geometry')

contains

  subroutine read_xcp(path, x)
    character(len=*), intent(in) :: path
    real(wp), intent(out) :: x(:)
    integer :: u, ios, m
    character(len=256) :: l
    x = 0; m = 0
    open (newunit=u, file=path, status='old', action='read')
    do
      read (u, '(a)', iostat=ios) l
      if (ios /= 0) exit
      if (index(l, 'XCP(TR)') > 0) then
        read (u, '(a)', iostat=ios) l
        m = m + 1
        if (m <= size(x)) read (l, *) x(m)
      end if
    end do
    close (u)
    x = x * 1.0e-3_wp
    call check(m == size(x), 'XCP(TR) read for every case of ' // path)
  end subroutine read_xcp

  integer function deepest(res) result(k)
    type(wheel_contact_t), intent(in) :: res
    k = 1
    if (res%n_patches > 0) k = maxloc(res%patch(1:res%n_patches)%penetration, dim=1)
  end function deepest

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=12) :: b
    write (b, '(i0)') i
    s = trim(b)
  end function itoa

end program test_mbench_a22_geometry
