!> Contact tables (rd_contact_table) against the online strip model they tabulate, on the
!> Manchester S1002 v3 / UIC60 v3 1:40 pair (validation/reference/profiles):
!>  1. at the table's nodes and between them (mid-cell shifts, a roll between roll nodes,
!>     approaches other than the tabulated one): the per-wheel "unit Hertz force"
!>     sum_p delta_p^1.5 n_p and the deepest patch's contact point and angle;
!>  2. patch identity and smoothness: through the onset of the flange patch the table's
!>     force has no jump or kink, and every patch lies on its slot's side of the cut;
!>  3. A-2.2 through the table (rigid contact, lowered 20 um): CONTACT's positions and
!>     angles, as test_mbench_a22_geometry checks them for the strip model;
!>  4. yaw: how much the angle of attack moves the contact (strips), and how well the
!>     table's yaw terms (exact wheel position, first-order flange lead) follow it.
!> The online model is the oracle: the table is built from it but at other poses.
program test_contact_table
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_io, only: read_profile_file
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, build_table_contact, wheel_contact, &
    SIDE_LEFT, SIDE_RIGHT
  use rd_contact_table, only: contact_table_options_t, contact_table_t, table_wheel_contact, node_probe, &
    PROBE_SHIFT_SHARES, TABLE_SLOTS, TABLE_SLOT_TREAD, TABLE_QUANTITIES
  use rd_contact_table_cache, only: obtain_contact_table
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  use rd_contact_patch, only: wheel_contact_t, PATCH_TREAD
  use rd_rigid_contact, only: rigid_contact
  use rd_test_support, only: check, test_summary
  use rd_sweep_smoothness, only: window_median, find_jumps_and_kinks, smoothness_feature_t
  use test_files, only: reference_path, scratch_name
  implicit none
  interface
    function c_setenv(name, value, overwrite) result(status) bind(C, name='setenv')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: status
    end function c_setenv
    function c_rmdir(path) result(status) bind(C, name='rmdir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function c_rmdir
  end interface
  type(profile_t) :: wprof, rprof
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  type(contact_table_options_t) :: topt
  type(contact_geometry_t) :: strip, table
  integer(8) :: c0, c1, rate
  real(wp) :: build_s
  character(len=:), allocatable :: cache_dir

  ! the table cache goes to a scratch directory of this test (removed at the end)
  cache_dir = scratch_name('contact_table_cache', '')
  if (c_setenv('RAILDYN_CACHE_DIR' // c_null_char, cache_dir // c_null_char, 1_c_int) /= 0) error stop 'setenv'
  call read_profile_file(reference_path('profiles/MBench_S1002_v3.prw'), PROFILE_WHEEL, wprof, error)
  if (allocated(error)) error stop error%message
  call read_profile_file(reference_path('profiles/MBench_UIC60_v3.prr'), PROFILE_RAIL, rprof, error)
  if (allocated(error)) error stop error%message
  pl%rail_precant = 0.025_wp
  pl%inclination = 0.025_wp
  call build_strip_contact(strip, wprof, rprof, pl, opt, error)
  if (allocated(error)) error stop error%message
  table = strip
  call system_clock(c0, rate)
  call build_table_contact(table, topt, error)
  call system_clock(c1)
  if (allocated(error)) error stop error%message
  build_s = real(c1 - c0, wp) / rate
  write (*, '(a,f6.2,a,i0,a,i0,a,es10.3,a)') 'table built in ', build_s, ' s: ', table%table%nu, ' shifts x ', &
    table%table%nphi, ' rolls, cut at s = ', table%table%s_cut, ' m'

  call cache_checks(cache_dir)
  if (c_rmdir(cache_dir // c_null_char) /= 0) call check(.false., 'cache directory empty at the end')
  call compare_with_strips()
  call flange_onset()
  call a22_through_table()
  call yaw_measurement()
  call skipped_slots_change_nothing()

  call test_summary('test_contact_table')

contains

  !> table_wheel_contact skips a flange slot whose interpolated touch height is certainly
  !> clear of the rail by more than the tread's approach (a bound from the node values):
  !> exact, so over poses across the table (shifts -12..12 mm, rolls inside and beyond the
  !> roll range, yaws inside and beyond the yaw range, the wheel lowered 5 and 60 um below
  !> the strips' touch and lifted 0.1 and 2 mm) every result equals, bit for bit, the
  !> evaluation of every slot; and the skip happens (poses where a flange slot is clear).
  subroutine skipped_slots_change_nothing()
    real(wp), parameter :: phis(4) = [-0.02_wp, 0.0_wp, 0.013_wp, 0.031_wp]
    real(wp), parameter :: psis(4) = [0.0_wp, 0.007_wp, -0.019_wp, 0.06_wp]
    real(wp), parameter :: dzs(4) = [-6.0e-5_wp, -5.0e-6_wp, 1.0e-4_wp, 2.0e-3_wp]
    type(wheel_contact_t) :: fast, every
    real(wp) :: y, z0
    integer :: i, ip, iy, iz, k, poses, differ, one_patch
    poses = 0; differ = 0; one_patch = 0
    do i = -32, 32
      y = i * 3.7e-4_wp
      do ip = 1, size(phis)
        z0 = touch_z(strip, y, phis(ip), 0.0_wp)
        do iy = 1, size(psis)
          do iz = 1, size(dzs)
            call table_wheel_contact(table%table, y, z0 + dzs(iz), phis(ip), psis(iy), fast)
            call table_wheel_contact(table%table, y, z0 + dzs(iz), phis(ip), psis(iy), every, every_slot=.true.)
            poses = poses + 1
            if (fast%n_patches == 1) one_patch = one_patch + 1
            if (fast%n_patches /= every%n_patches .or. fast%max_penetration /= every%max_penetration) then
              differ = differ + 1
              cycle
            end if
            do k = 1, fast%n_patches
              associate (a => fast%patch(k), b => every%patch(k))
                if (a%kind /= b%kind .or. a%penetration /= b%penetration .or. a%contact_angle /= b%contact_angle &
                    .or. any(a%point_rail /= b%point_rail) .or. any(a%point_wheel /= b%point_wheel) &
                    .or. a%rolling_radius /= b%rolling_radius .or. a%curv_wheel_lat /= b%curv_wheel_lat &
                    .or. a%curv_rail_lat /= b%curv_rail_lat) differ = differ + 1
              end associate
            end do
          end do
        end do
      end do
    end do
    write (*, '(a,i0,a,i0,a,i0)') 'skipped flange slots: ', poses, ' poses, ', one_patch, ' with one patch, differing: ', &
      differ
    call check(differ == 0, 'skipping the flange slots clear of the rail changes no result')
    call check(one_patch > poses / 4, 'the poses include many with the tread alone in contact (the skip is exercised)')
  end subroutine skipped_slots_change_nothing

  !> The cache (rd_contact_table_cache) in a scratch directory: a built table is stored and
  !> read back equal; a table with other inputs (another inclination) has another key and is
  !> built, not read; a file under the right name holding another key, or cut short, is
  !> not used (rebuilt, equal to the original build, and replaced).
  subroutine cache_checks(dir)
    character(len=*), intent(in) :: dir
    type(contact_table_t) :: t1, t2, t3
    type(contact_geometry_t) :: other
    type(track_placement_t) :: pl2
    logical :: hit
    character(len=:), allocatable :: file1, file2
    integer :: unit, ios
    integer(1), allocatable :: bytes(:)
    integer :: nbytes
    call obtain_contact_table(strip%wheel, strip%rail, topt, t1, error, from_cache=hit, path=file1)
    if (allocated(error)) error stop error%message
    call check(hit .and. index(file1, dir) == 1, 'cache: the table built at the start is read from the cache directory')
    call check(all(t1%values == table%table%values) .and. all(t1%slopes == table%table%slopes), &
               'cache: the table read back equals the one built')
    pl2 = pl
    pl2%inclination = 0.05_wp
    call build_strip_contact(other, wprof, rprof, pl2, opt, error)
    if (allocated(error)) error stop error%message
    call obtain_contact_table(other%wheel, other%rail, topt, t2, error, from_cache=hit, path=file2)
    if (allocated(error)) error stop error%message
    call check(.not. hit .and. file2 /= file1, 'cache: another inclination has another key and is built')
    call check(any(abs(t2%values - t1%values) > 1.0e-6_wp), 'cache: ... and gives another table')
    ! the other table's file under the first table's name: its key does not match
    open (newunit=unit, file=file2, access='stream', form='unformatted', status='old', action='read')
    inquire (unit=unit, size=nbytes)
    allocate (bytes(nbytes))
    read (unit) bytes
    close (unit)
    open (newunit=unit, file=file1, access='stream', form='unformatted', status='replace', action='write')
    write (unit) bytes
    close (unit)
    call obtain_contact_table(strip%wheel, strip%rail, topt, t3, error, from_cache=hit)
    if (allocated(error)) error stop error%message
    call check(.not. hit .and. all(t3%values == t1%values), 'cache: a file holding another key is not used (rebuilt)')
    ! cut short: header intact, data missing
    open (newunit=unit, file=file1, access='stream', form='unformatted', status='replace', action='write')
    write (unit) bytes(1:200)
    close (unit)
    call obtain_contact_table(strip%wheel, strip%rail, topt, t3, error, from_cache=hit)
    if (allocated(error)) error stop error%message
    call check(.not. hit .and. all(t3%values == t1%values), 'cache: a truncated file is not used (rebuilt)')
    call obtain_contact_table(strip%wheel, strip%rail, topt, t3, error, from_cache=hit)
    call check(hit, 'cache: the rebuilt table replaced the bad file')
    call probe_is_the_tables_nodes(t1)
    open (newunit=unit, file=file1, status='old', iostat=ios)
    if (ios == 0) close (unit, status='delete')
    open (newunit=unit, file=file2, status='old', iostat=ios)
    if (ios == 0) close (unit, status='delete')
  end subroutine cache_checks

  !> The key hashes node_probe (rd_contact_table_cache): the node evaluation at fixed poses,
  !> so that a table built by a runner whose strip geometry gives other nodes is not read.
  !> That holds when the probe is what the table holds there: at zero roll and yaw its rows
  !> are the table's nodes at those shifts, value for value, for every slot with a rail under
  !> it; and the tread (always on the rail) is among them.
  subroutine probe_is_the_tables_nodes(t)
    type(contact_table_t), intent(in) :: t
    real(wp), allocatable :: probe(:)
    integer :: i, slot, k, iu, j0, n_found
    logical :: same
    call node_probe(strip%wheel, strip%rail, topt, probe, error)
    if (allocated(error)) error stop error%message
    call check(size(probe) == 3 + (size(PROBE_SHIFT_SHARES) + 2) * TABLE_SLOTS * (1 + TABLE_QUANTITIES), &
               'cache key probe: its fixed layout')
    j0 = nint(-t%phi0 / t%dphi) + 1          ! the zero-roll node
    same = abs(t%phi0 + (j0 - 1) * t%dphi) < 1.0e-15_wp
    n_found = 0
    k = 3
    do i = 1, size(PROBE_SHIFT_SHARES)
      iu = nint((PROBE_SHIFT_SHARES(i) * topt%shift_max - t%u0) / t%du) + 1
      do slot = 1, TABLE_SLOTS
        if (probe(k + 1) == 1) then
          n_found = n_found + 1
          same = same .and. all(probe(k + 2:k + 1 + TABLE_QUANTITIES) == t%values(:, iu, j0, slot))
        end if
        if (slot == TABLE_SLOT_TREAD) same = same .and. probe(k + 1) == 1
        k = k + 1 + TABLE_QUANTITIES
      end do
    end do
    call check(same .and. n_found >= size(PROBE_SHIFT_SHARES), 'cache key probe: its rows at zero roll and ' // &
               'yaw are the table''s nodes at those shifts (every slot found there; the tread at every shift)')
  end subroutine probe_is_the_tables_nodes

  !> Wheelset height at which the left wheel of `geo` touches (signed max penetration 0).
  real(wp) function touch_z(geo, y, phi, psi) result(z)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y, phi, psi
    real(wp) :: za, zb, ga, gb, zc, gc
    integer :: it
    za = 0.40_wp; zb = 0.52_wp
    ga = left_depth(geo, y, za, phi, psi); gb = left_depth(geo, y, zb, phi, psi)
    do it = 1, 200
      zc = 0.5_wp * (za + zb)
      gc = left_depth(geo, y, zc, phi, psi)
      if (gc > 0) then
        za = zc; ga = gc
      else
        zb = zc; gb = gc
      end if
      if (zb - za < 1.0e-13_wp) exit
    end do
    z = 0.5_wp * (za + zb)
  end function touch_z

  real(wp) function left_depth(geo, y, z, phi, psi)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t) :: r
    call wheel_contact(geo, SIDE_LEFT, y, z, phi, psi, r)
    left_depth = r%max_penetration
  end function left_depth

  !> sum over patches of delta^1.5 n (Y, Z): the normal force of unit Hertz constant.
  function unit_force(r) result(f)
    type(wheel_contact_t), intent(in) :: r
    real(wp) :: f(2)
    integer :: k
    f = 0
    do k = 1, r%n_patches
      f = f + r%patch(k)%penetration**1.5_wp * r%patch(k)%normal(2:3)
    end do
  end function unit_force

  integer function deepest(r) result(k)
    type(wheel_contact_t), intent(in) :: r
    k = maxloc(r%patch(1:max(r%n_patches, 1))%penetration, dim=1)
  end function deepest

  !> Sweeps of the left wheel over shifts -12..12 mm every 0.05 mm (every other one a
  !> node), roll 0 (a node), 0.0041 and -0.0117 rad (between roll nodes), lowered 5, 20
  !> and 60 um below the online touch height. Error measure: the largest component of
  !> the unit-Hertz force difference over lowering^1.5 (the force of that lowering on a
  !> flat tread), at 20 um; contact point and angle where both have one patch.
  subroutine compare_with_strips()
    real(wp), parameter :: phis(3) = [0.0_wp, 0.0041_wp, -0.0117_wp]
    real(wp), parameter :: lowerings(3) = [5.0e-6_wp, 2.0e-5_wp, 6.0e-5_wp]
    type(wheel_contact_t) :: rs, rt
    real(wp) :: y, z0, fs(2), ft(2), err_y(2), err_g(2), e, err_other(2), med(2), above(2)
    real(wp), allocatable :: errs(:, :)
    integer :: i, ip, il, mid, n(2)
    allocate (errs(3 * 481, 2))
    n = 0; err_y = 0; err_g = 0; err_other = 0
    do ip = 1, size(phis)
      do i = -240, 240
        y = i * 5.0e-5_wp
        mid = merge(1, 2, mod(i, 2) == 0 .and. ip == 1)
        z0 = touch_z(strip, y, phis(ip), 0.0_wp)
        do il = 1, size(lowerings)
          call wheel_contact(strip, SIDE_LEFT, y, z0 - lowerings(il), phis(ip), 0.0_wp, rs)
          call wheel_contact(table, SIDE_LEFT, y, z0 - lowerings(il), phis(ip), 0.0_wp, rt)
          fs = unit_force(rs); ft = unit_force(rt)
          e = maxval(abs(ft - fs)) / lowerings(il)**1.5_wp
          if (il == 2) then
            n(mid) = n(mid) + 1
            errs(n(mid), mid) = e
          else
            err_other(mid) = max(err_other(mid), e)
          end if
          if (il == 2 .and. rs%n_patches == 1 .and. rt%n_patches == 1) then
            err_y(mid) = max(err_y(mid), abs(rt%patch(1)%point_rail(2) - rs%patch(1)%point_rail(2)))
            err_g(mid) = max(err_g(mid), abs(rt%patch(1)%contact_angle - rs%patch(1)%contact_angle))
          end if
        end do
      end do
    end do
    do i = 1, 2
      med(i) = window_median(errs(1:n(i), i), 1, n(i), 0, -1)
      above(i) = real(count(errs(1:n(i), i) > 0.05_wp), wp) / n(i)
    end do
    write (*, '(a)') 'table vs strips, left wheel, shifts -12..12 mm; unit-force error / tread force at 20 um:'
    write (*, '(a,i4,a,2es10.3,f7.3,a,es10.3)') '  at nodes      (', n(1), ' poses) median, max, share > 5 %: ', &
      med(1), maxval(errs(1:n(1), 1)), above(1), '   max at 5 and 60 um ', err_other(1)
    write (*, '(a,i4,a,2es10.3,f7.3,a,es10.3)') '  between nodes (', n(2), ' poses) median, max, share > 5 %: ', &
      med(2), maxval(errs(1:n(2), 2)), above(2), '   max at 5 and 60 um ', err_other(2)
    write (*, '(a,2es10.3,a,2es10.3)') '  one-patch poses: contact point Y error [m] nodes, between ', err_y, &
      '   contact angle error [rad] ', err_g
    ! bounds: the measured values (docs/theory_contact_geometry.md "Contact tables"),
    ! rounded up: at the nodes 0.033 (next to the root -> face jump, 6.6 mm), between them
    ! 0.446 (the flange face at a roll between roll nodes, 8.9 mm). With one slot for flange
    ! root and face between them it was 0.60: the contact jump from root to face near 6.5 mm
    ! inside the slot, spread by the cubic over one shift step
    call check(maxval(errs(1:n(1), 1)) < 0.04_wp, 'at the nodes the table force is within 4 % of the strips'' (20 um)')
    call check(err_y(1) < 3.0e-5_wp .and. err_g(1) < 5.0e-3_wp, &
               'at the nodes the contact point is within 0.03 mm and 5 mrad of the strips''')
    call check(med(2) < 0.01_wp, 'between the nodes the median force error is below 1 %')
    call check(above(2) < 0.08_wp, 'between the nodes fewer than 8 % of the poses are more than 5 % off')
    call check(maxval(errs(1:n(2), 2)) < 0.5_wp, 'between the nodes no force error beyond 0.5 tread forces')
  end subroutine compare_with_strips

  !> Patch identity and smoothness through the onset of the flange patch: along a path
  !> from 4.5 to 6.5 mm shift (z linear between the table's touch heights there, lowered
  !> 0.1 mm) the unit-Hertz force of the table has no jump or kink (rd_sweep_smoothness),
  !> and every patch lies on its slot's side of the cut.
  subroutine flange_onset()
    integer, parameter :: n = 2001
    type(wheel_contact_t) :: rt
    type(smoothness_feature_t), allocatable :: features(:)
    real(wp) :: ys(n), f(n, 2), za, zb
    integer :: i, k, c, nfeat
    logical :: sides_ok, both_seen
    sides_ok = .true.
    both_seen = .false.
    za = touch_z(table, 4.5e-3_wp, 0.0_wp, 0.0_wp) - 1.0e-4_wp
    zb = touch_z(table, 6.5e-3_wp, 0.0_wp, 0.0_wp) - 1.0e-4_wp
    do i = 1, n
      ys(i) = 4.5e-3_wp + 2.0e-3_wp * (i - 1) / (n - 1)
      call wheel_contact(table, SIDE_LEFT, ys(i), za + (zb - za) * (i - 1) / (n - 1), 0.0_wp, 0.0_wp, rt)
      f(i, :) = unit_force(rt)
      both_seen = both_seen .or. rt%n_patches == 2
      do k = 1, rt%n_patches
        if (rt%patch(k)%kind == PATCH_TREAD) then
          sides_ok = sides_ok .and. rt%patch(k)%s_wheel >= table%table%s_cut - 1.0e-9_wp
        else
          sides_ok = sides_ok .and. rt%patch(k)%s_wheel <= table%table%s_cut + 1.0e-9_wp
        end if
      end do
    end do
    nfeat = 0
    do c = 1, 2
      call find_jumps_and_kinks(ys, f(:, c), maxval(abs(f(:, c))), features, error)
      if (allocated(error)) error stop error%message
      nfeat = nfeat + size(features)
    end do
    call check(both_seen, 'flange onset: tread and flange patches carry load together on the path')
    call check(nfeat == 0, 'flange onset: the table''s force has no jump or kink through the onset')
    call check(sides_ok, 'every table patch lies on its slot''s side of the tread/flange cut')
  end subroutine flange_onset

  !> A-2.2 through the table: rigid contact of the table geometry at the benchmark's
  !> shifts and yaws (2.4 mrad per mm, through the table's yaw terms), lowered 20 um;
  !> CONTACT's rail positions and contact angles of the deepest patch per wheel, as
  !> test_mbench_a22_geometry checks the strips (1 mm except the near-conformal case 2,
  !> angles 0.02 rad); the strips at the same poses printed next to them.
  subroutine a22_through_table()
    character(len=512) :: line
    real(wp) :: v(25), z, phi, u_t(2), g_t(2), u_s(2), g_s(2), u_ref(2), g_ref(2), err_u, err_g, err_ts
    type(wheel_contact_t) :: left, right
    integer :: unit, ios, n
    err_u = 0; err_g = 0; err_ts = 0
    open (newunit=unit, file=reference_path('mbench_a22/reference.csv'), status='old', action='read')
    read (unit, '(a)') line
    n = 0
    write (*, '(a)') 'A-2.2 through the table: case, y [mm], u_L table strips ref [mm], u_R ..., gamma_R ...'
    do
      read (unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      read (line, *) v
      n = n + 1
      u_ref = [-v(8), v(13)] * 1.0e-3_wp
      g_ref = [-v(9), -v(14)]
      call rigid_contact(table, -v(2) * 1.0e-3_wp, -v(3) * 1.0e-3_wp, z, phi, error, left, right, lowering=2.0e-5_wp)
      if (allocated(error)) error stop error%message
      u_t = [left%patch(deepest(left))%u_rail, right%patch(deepest(right))%u_rail]
      g_t = [left%patch(deepest(left))%contact_angle, right%patch(deepest(right))%contact_angle]
      call rigid_contact(strip, -v(2) * 1.0e-3_wp, -v(3) * 1.0e-3_wp, z, phi, error, left, right, lowering=2.0e-5_wp)
      if (allocated(error)) error stop error%message
      u_s = [left%patch(deepest(left))%u_rail, right%patch(deepest(right))%u_rail]
      g_s = [left%patch(deepest(left))%contact_angle, right%patch(deepest(right))%contact_angle]
      write (*, '(i4,f6.2,3(2x,3f8.3),2x,3f8.4)') n, v(2), 1e3 * [u_t(1), u_s(1), u_ref(1)], &
        1e3 * [u_t(2), u_s(2), u_ref(2)], g_t(2), g_s(2), g_ref(2)
      if (n /= 2) err_u = max(err_u, maxval(abs(u_t - u_ref)))
      err_g = max(err_g, maxval(abs(g_t - g_ref)))
      err_ts = max(err_ts, maxval(abs(u_t - u_s)))
    end do
    close (unit)
    write (*, '(a,f7.3,a,f7.4,a,f7.3,a)') 'A-2.2 table: max |u - ref| (cases but 2) ', 1e3 * err_u, ' mm, max |gamma - ref| ', &
      err_g, ' rad; max |u_table - u_strips| ', 1e3 * err_ts, ' mm'
    call check(n == 21, 'A-2.2: 21 cases')
    call check(err_u < 1.0e-3_wp, 'A-2.2 through the table: rail contact positions within 1 mm of CONTACT (cases but 2)')
    call check(err_g < 0.02_wp, 'A-2.2 through the table: contact angles within 0.02 rad of CONTACT')
  end subroutine a22_through_table

  !> How much the angle of attack moves the contact (online strips) and what the table's
  !> yaw table makes of it: per shift, yaw and roll, the change of the touch height from zero
  !> yaw (strips, table), the wheel point's x (strips, table) and the unit-force error at 20 um.
  !> The yaw table is built at zero roll: at a roll the table adds the change at zero roll.
  subroutine yaw_measurement()
    real(wp), parameter :: shifts(7) = [0.0_wp, 2.0e-3_wp, 4.0e-3_wp, 5.5e-3_wp, 7.0e-3_wp, 9.0e-3_wp, 1.1e-2_wp]
    real(wp), parameter :: yaws(6) = [5.0e-3_wp, 1.0e-2_wp, -1.5e-2_wp, 2.07e-2_wp, -3.0e-2_wp, 4.2e-2_wp]
    real(wp), parameter :: rolls(2) = [0.0_wp, 1.2e-2_wp]
    type(wheel_contact_t) :: r1, rt
    real(wp) :: z0, z1, zt0, zt1, e, err_h(2), err_x(2), err_f(2), dh_max
    integer :: i, j, l, ks, kt
    err_h = 0; err_x = 0; err_f = 0; dh_max = 0
    write (*, '(a)') 'yaw (left wheel): roll [mrad], shift [mm], yaw [mrad], d(touch height) strips, table [um], ' // &
      'wheel point x strips, table [mm], force error at 20 um'
    do l = 1, size(rolls)
      do i = 1, size(shifts)
        z0 = touch_z(strip, shifts(i), rolls(l), 0.0_wp)
        zt0 = touch_z(table, shifts(i), rolls(l), 0.0_wp)
        do j = 1, size(yaws)
          z1 = touch_z(strip, shifts(i), rolls(l), yaws(j))
          zt1 = touch_z(table, shifts(i), rolls(l), yaws(j))
          call wheel_contact(strip, SIDE_LEFT, shifts(i), z1 - 2.0e-5_wp, rolls(l), yaws(j), r1)
          call wheel_contact(table, SIDE_LEFT, shifts(i), z1 - 2.0e-5_wp, rolls(l), yaws(j), rt)
          ks = deepest(r1); kt = deepest(rt)
          e = maxval(abs(unit_force(rt) - unit_force(r1))) / 2.0e-5_wp**1.5_wp
          write (*, '(f6.1,f6.1,f7.1,2f10.3,2f9.3,f9.4)') 1e3 * rolls(l), 1e3 * shifts(i), 1e3 * yaws(j), &
            1e6 * (z1 - z0), 1e6 * (zt1 - zt0), 1e3 * r1%patch(ks)%point_wheel(1), 1e3 * rt%patch(kt)%point_wheel(1), e
          dh_max = max(dh_max, abs(z1 - z0))
          err_h(l) = max(err_h(l), abs((zt1 - zt0) - (z1 - z0)))
          err_x(l) = max(err_x(l), abs(r1%patch(ks)%point_wheel(1) - rt%patch(kt)%point_wheel(1)))
          err_f(l) = max(err_f(l), e)
        end do
      end do
      write (*, '(a,f5.1,a,f8.3,a,f7.3,a,f7.4)') 'roll ', 1e3 * rolls(l), ' mrad: the yaw table follows the strips'' ' // &
        'touch height within ', 1e6 * err_h(l), ' um, the wheel point x within ', 1e3 * err_x(l), ' mm, force error ', &
        err_f(l)
    end do
    write (*, '(a,f9.3,a)') 'yaw moves the touch height by up to ', 1e6 * dh_max, ' um'
    ! bounds, up to 42 mrad: at zero roll the measured 1.68 um, 0.198 mm, 0.0236 (7 mm shift,
    ! -30 mrad: the flange contact 39 mm ahead of the axle), rounded up; the first-order
    ! yaw terms the yaw table replaced gave 11.7 um, 0.71 mm and 0.138 up to 15 mrad and put
    ! the flange's touch up to 290 um low at 20.7 mrad
    call check(err_h(1) < 2.5e-6_wp, 'yaw: the table''s touch height follows the strips'' within 2.5 um (to 42 mrad)')
    call check(err_x(1) < 3.0e-4_wp, 'yaw: the table''s contact lead follows the strips'' within 0.3 mm')
    call check(err_f(1) < 0.035_wp, 'yaw: force error within 0.035 tread forces at 20 um (to 42 mrad)')
    ! at 12 mrad of roll the table adds the yaw's change at zero roll: measured 79.2 um and
    ! 3.09 (4 mm shift, 42 mrad; up to 20.7 mrad 25 um and 0.59), rounded up; the first-order
    ! yaw terms it replaced gave 442 um and 26.4. (A first-order roll coupling of the change
    ! measured 31 um and 0.68 here but made the flange-climb scene's quasi-static balance fail
    ! at 0.50 s: not used. The wheel point x is not compared at this roll: at some of these
    ! poses the table's deepest patch is another slot's.)
    call check(err_h(2) < 90.0e-6_wp, 'yaw at 12 mrad of roll: touch height within 90 um (to 42 mrad)')
    call check(err_f(2) < 3.5_wp, 'yaw at 12 mrad of roll: force error within 3.5 tread forces at 20 um (to 42 mrad)to 42 mrad)')
  end subroutine yaw_measurement
end program test_contact_table
