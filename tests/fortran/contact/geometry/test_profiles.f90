!> Profiles: analytic S1002 against the Manchester v3 file (independent data, 4e-6 mm),
!> the 60E1/54E1 arc construction against the EN 13674-1 numbers in the README, curvature
!> of circular arcs against 1/R, readers' error messages, writer round trips.
program test_profiles
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL, resample_profile
  use rd_profile_io, only: read_profile_file, write_profile_table, write_profile_simpack
  use rd_profile_analytic, only: s1002_radius_increase_mm, s1002_profile, rail_head_construction_t, &
    rail_head_construction, rail_head_profile, RAIL_60E1, RAIL_54E1
  use rd_test_support, only: check, test_summary
  use test_files, only: reference_path, scratch_name, write_file, delete_file
  implicit none
  type(profile_t) :: prof, p2, circ
  type(error_t), allocatable :: error
  type(rail_head_construction_t) :: c
  real(wp), allocatable :: ys(:), zs(:), ks(:)
  real(wp) :: dmax, s, f, fp, joint, x, h
  real(wp), parameter :: joints(7) = [-62.764705882_wp, -49.662510381_wp, -39.764473993_wp, &
    -38.426669071_wp, -35.0_wp, -26.0_wp, 32.15796_wp]
  integer :: i, n
  character(len=:), allocatable :: tmp   !< prefix of this run's scratch files

  tmp = scratch_name('test_profiles', '_')
  ! --- analytic S1002 vs the v3 file (distance normal to the curve)
  call read_profile_file(reference_path('profiles/MBench_S1002_v3.prw'), PROFILE_WHEEL, prof, error)
  call check(.not. allocated(error), 'read MBench_S1002_v3.prw')
  if (allocated(error)) error stop error%message
  n = size(prof%y)
  call check(n == 399, 'v3 wheel: 399 active points (a commented point is skipped)')
  call check(abs(prof%y(1) + 0.069612628_wp) < 1e-12_wp .and. prof%y(n) > prof%y(1), &
    'v3 wheel: mirrored to S (flange back side first) and in metres')
  dmax = 0
  do i = 1, n
    s = 1000 * prof%y(i)
    f = s1002_radius_increase_mm(s)
    fp = (s1002_radius_increase_mm(s + 1e-6_wp) - s1002_radius_increase_mm(s - 1e-6_wp)) / 2e-6_wp
    dmax = max(dmax, abs(1000 * prof%z(i) - f) / sqrt(1 + fp**2))
  end do
  write (*, '(a,es10.3,a)') 'analytic S1002 vs v3 file: max normal distance ', dmax, ' mm'
  call check(dmax < 4.0e-6_wp, 'analytic S1002 equals the v3 file within 4e-6 mm')
  joint = 0
  do i = 1, 7
    joint = max(joint, abs(s1002_radius_increase_mm(joints(i) - 1e-9_wp) - s1002_radius_increase_mm(joints(i) + 1e-9_wp)))
  end do
  write (*, '(a,es10.3,a)') 'S1002 joints: max step ', joint, ' mm'
  call check(joint < 1.2e-4_wp, 'S1002 sections join within 1.2e-4 mm (README)')
  ! flange height: max F over the flange minus F(0) = 28 mm
  f = -huge(1.0_wp)
  do i = 0, 20000
    f = max(f, s1002_radius_increase_mm(-70 + 40 * i / 20000.0_wp))
  end do
  call check(abs(f - s1002_radius_increase_mm(0.0_wp) - 28.0_wp) < 2e-3_wp, 'S1002 flange height 28.000 mm')
  ! flange thickness: from the flange back to the flange face at F = 10 mm
  x = -45; h = 1
  do i = 1, 60   ! bisection on the flange face (F decreasing with S)
    h = h / 2
    if (s1002_radius_increase_mm(x) > 10) then
      x = x + 20 * h
    else
      x = x - 20 * h
    end if
  end do
  call check(abs(x + 70 - 32.5_wp) < 2e-3_wp, 'S1002 flange thickness 32.500 mm at F = 10 mm')
  call s1002_profile(p2, 1.0e-4_wp, error)
  call check(.not. allocated(error) .and. abs(p2%y(1) + 0.070_wp) < 1e-12_wp .and. abs(p2%y(size(p2%y)) - 0.060_wp) < 1e-12_wp, &
    'generated S1002 spans S = -70 ... 60 mm')

  ! --- 60E1 / 54E1 construction
  c = rail_head_construction(10.228_wp, 26.0265_wp, 21.12524_wp)
  call check(norm2(c%c80 - [7.50053_wp, -80.12790_wp]) < 2e-3_wp, '60E1: R80 centre (7.50053, -80.12790) from tangency')
  call check(norm2(c%c13 - [23.01603_wp, -14.94915_wp]) < 2e-3_wp, '60E1: R13 centre (23.01603, -14.94915) from tangency')
  call check(norm2(c%t13 - [35.99981_wp, -14.29996_wp]) < 2e-3_wp, '60E1: flank tangent point (35.99981, -14.29996)')
  call check(norm2(c%c3 - [34.0523_wp, -35.4252_wp]) < 2e-3_wp, '60E1: R3 fillet centre (34.0523, -35.4252)')
  c = rail_head_construction(10.012_wp, 24.8635_wp, 21.12524_wp)
  write (*, '(a,f9.4,a)') '54E1 head width ', 2 * c%t13(1), ' mm'
  call check(abs(2 * c%t13(1) - 70.0_wp) < 0.05_wp, '54E1: head width 70.0 mm')
  call rail_head_profile(RAIL_60E1, p2, 5.0e-5_wp, error)
  call check(.not. allocated(error), '60E1 profile generated')
  call resample_profile(p2, 1.0e-4_wp, 2.0e-4_wp, ys, zs, ks, error)
  call check(abs(curv_at(0.0_wp) * 0.3_wp - 1) < 1e-3_wp, '60E1: curvature 1/0.3 on the crown')
  call check(abs(curv_at(0.018_wp) * 0.08_wp - 1) < 1e-3_wp, '60E1: curvature 1/0.08 on the R80 arc')
  call check(abs(curv_at(-0.032_wp) * 0.013_wp - 1) < 1e-3_wp, '60E1: curvature 1/0.013 on the R13 gauge corner')
  ! S1002 throat (section D, concave R13) and flange tip (section G, convex R12)
  call s1002_profile(p2, 5.0e-5_wp, error)
  call resample_profile(p2, 1.0e-4_wp, 2.0e-4_wp, ys, zs, ks, error)
  call check(abs(curv_at(-0.0367_wp) * 0.013_wp + 1) < 2e-3_wp, 'S1002: concave R13 in section D (curvature -1/0.013)')
  call check(abs(curv_at(-0.0560_wp) * 0.012_wp - 1) < 2e-3_wp, 'S1002: convex R12 flange tip (curvature 1/0.012)')
  ! an irregularly sampled circle of radius 50 mm (material inside): curvature 20 1/m
  circ%kind = PROFILE_RAIL; circ%source = 'circle'
  allocate (circ%y(200), circ%z(200))
  do i = 1, 200
    h = -1.0_wp + 2.0_wp * (real(i - 1, wp) / 199)**1.3_wp
    circ%y(i) = 0.05_wp * sin(h); circ%z(i) = 0.05_wp * cos(h) - 0.05_wp
  end do
  call resample_profile(circ, 1.0e-4_wp, 1.0e-3_wp, ys, zs, ks, error)
  call check(maxval(abs(ks - 20)) < 1e-6_wp * 20, 'circle R50: smoothed curvature exactly 1/R everywhere')

  ! --- readers: errors with file:line, units
  call write_file(tmp // 'bad_points.txt', [character(len=30) :: '# units: mm', '0 1', '1 x2', '2 3'])
  call read_profile_file(tmp // 'bad_points.txt', PROFILE_WHEEL, p2, error)
  call check(has(error, 'bad_points.txt:3:'), 'malformed line reported with file:line')
  call write_file(tmp // 'few_points.txt', ['0 0', '1 1', '2 2'])
  call read_profile_file(tmp // 'few_points.txt', PROFILE_RAIL, p2, error)
  call check(has(error, 'too few points'), 'too few points reported')
  call write_file(tmp // 'nonmono.txt', [character(len=30) :: '# units: mm', '0 0        ', '10 1       ', '20 2       ', '15 3       ', &
                                  '30 4       ', '40 5       '])
  call read_profile_file(tmp // 'nonmono.txt', PROFILE_RAIL, p2, error)
  call check(has(error, 'nonmono.txt:5: lateral coordinate 0.015 m does not increase from the point at line 4 (0.02 m)'), &
             'non-monotonic profile reported at its file line')
  call write_file(tmp // 'mm_units.txt', ['0 0  ', '20 1 ', '40 2 ', '60 3 ', '80 4 ', '100 5'])
  call read_profile_file(tmp // 'mm_units.txt', PROFILE_WHEEL, p2, error)
  call check(has(error, 'millimetres'), 'wheel of 100 "m" extent: suspected millimetres')
  call write_file(tmp // 'tiny.txt', ['0 0      ', '0.002 1  ', '0.004 2  ', '0.006 3  ', '0.008 4  ', '0.010 5  '])
  call read_profile_file(tmp // 'tiny.txt', PROFILE_WHEEL, p2, error)
  call check(has(error, 'implausible'), 'wheel of 10 mm extent: implausible')
  call write_file(tmp // 'nan.txt', [character(len=30) :: '0 0', '0.01 nan', '0.02 0', '0.03 0', '0.04 0', '0.05 0'])
  call read_profile_file(tmp // 'nan.txt', PROFILE_RAIL, p2, error)
  call check(has(error, 'nan.txt:2:') .or. has(error, 'non-finite'), 'NaN coordinate reported')
  call write_file(tmp // 'csv_mm.csv', [character(len=30) :: '# S1002 part; units: mm', '-60,20', '-30,5', '0,0', &
                                 '30,-1      ', '60, -3     '])
  call read_profile_file(tmp // 'csv_mm.csv', PROFILE_WHEEL, p2, error)
  call check(.not. allocated(error), 'comma table with "units: mm" reads')
  if (.not. allocated(error)) call check(abs(p2%y(5) - 0.060_wp) < 1e-15_wp .and. abs(p2%z(5) + 0.003_wp) < 1e-15_wp, &
    'table converted to metres')
  call read_profile_file(reference_path('profiles/MBench_UIC60_v3.prr'), PROFILE_WHEEL, p2, error)
  call check(has(error, 'type'), 'rail file read as wheel: header type mismatch reported')
  ! a number longer than 64 characters is read whole (cut at 64 it read 1000 times too large)
  call write_file(tmp // 'long_number.txt', [character(len=100) :: '-0.06 0', '-0.03 0', &
    '0 2.' // repeat('0', 70) // 'e-3', '0.03 0', '0.06 0'])
  call read_profile_file(tmp // 'long_number.txt', PROFILE_RAIL, p2, error)
  call check(.not. allocated(error), 'a 75-character number reads')
  if (.not. allocated(error)) call check(abs(p2%z(3) - 2.0e-3_wp) < 1e-18_wp, 'a 75-character number keeps its exponent')
  ! a line over 1024 characters is an error at its line, not cut or dropped
  call write_file(tmp // 'long_line.txt', [character(len=1100) :: '-0.06 0', '-0.03 0 ' // repeat(' ', 1030) // '# x', &
    '0 0', '0.03 0', '0.06 0'])
  call read_profile_file(tmp // 'long_line.txt', PROFILE_RAIL, p2, error)
  call check(has(error, 'long_line.txt:2: line longer than 1024 characters'), 'over-long line reported at its line')
  ! SIMPACK: a second point block is an error, not appended points
  call write_file(tmp // 'two_blocks.prr', [character(len=30) :: 'header.begin', 'type = 0', 'header.end', &
    'point.begin', '-60 0', '-30 0', '0 0', '30 0', '60 0', 'point.end', 'point.begin', '70 0', 'point.end'])
  call read_profile_file(tmp // 'two_blocks.prr', PROFILE_RAIL, p2, error)
  call check(has(error, 'two_blocks.prr:11: a second point.begin (the first at line 4)'), 'second point block reported')
  call read_profile_file(tmp // 'does_not_exist.prw', PROFILE_WHEEL, p2, error)
  call check(has(error, 'cannot open'), 'missing file reported')
  ! --- writers round trip
  call read_profile_file(reference_path('profiles/MBench_UIC60_v3.prr'), PROFILE_RAIL, prof, error)
  call check(.not. allocated(error) .and. size(prof%y) == 495, 'v3 rail: 495 points')
  call write_profile_simpack(tmp // 'roundtrip.prr', prof, ['round trip'], error)
  call read_profile_file(tmp // 'roundtrip.prr', PROFILE_RAIL, p2, error)
  call check(.not. allocated(error), 'SIMPACK writer output reads back')
  if (.not. allocated(error)) call check(maxval(abs(p2%y - prof%y)) + maxval(abs(p2%z - prof%z)) < 1e-12_wp, &
    'SIMPACK round trip exact')
  call write_profile_table(tmp // 'roundtrip.txt', prof, ['round trip'], error)
  call read_profile_file(tmp // 'roundtrip.txt', PROFILE_RAIL, p2, error)
  if (.not. allocated(error)) call check(maxval(abs(p2%y - prof%y)) + maxval(abs(p2%z - prof%z)) < 1e-15_wp, &
    'table round trip exact')
  call cleanup([character(len=16) :: 'bad_points.txt', 'few_points.txt', 'nonmono.txt   ', 'mm_units.txt  ', 'tiny.txt      ', &
                'csv_mm.csv    ', 'nan.txt       ', 'roundtrip.prr ', 'roundtrip.txt ', &
                'long_number.txt', 'long_line.txt  ', 'two_blocks.prr '])
  call test_summary('test_profiles')

contains

  real(wp) function curv_at(yq) result(k)
    real(wp), intent(in) :: yq
    k = ks(minloc(abs(ys - yq), dim=1))
  end function curv_at

  logical function has(e, text)
    type(error_t), allocatable, intent(in) :: e
    character(len=*), intent(in) :: text
    has = .false.
    if (allocated(e)) then
      has = index(e%message, text) > 0
      write (*, '(a)') '      message: ' // e%message
    end if
  end function has

  subroutine cleanup(paths)
    character(len=*), intent(in) :: paths(:)
    integer :: j
    do j = 1, size(paths)
      call delete_file(tmp // trim(paths(j)))
    end do
  end subroutine cleanup

end program test_profiles
