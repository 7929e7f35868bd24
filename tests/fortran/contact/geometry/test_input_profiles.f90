!> inputs/profiles must equal the analytic generators: the S1002 file against the S1002
!> definition, the canted 60E1 (with its precant) against the analytic 60E1 inclined 1:40
!> in the placement (same rigid-contact heights and rolls).
program test_input_profiles
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_io, only: read_profile_file
  use rd_profile_analytic, only: s1002_radius_increase_mm, s1002_profile, rail_head_profile, RAIL_60E1, RAIL_54E1
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact
  use rd_rigid_contact, only: rigid_contact
  use rd_test_support, only: check, test_summary
  implicit none
  type(profile_t) :: w, r, ra, w2
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl, pl2
  type(surface_options_t) :: opt
  type(contact_geometry_t) :: g1, g2
  character(len=1024) :: src
  character(len=:), allocatable :: dir
  real(wp) :: dmax, s, f, fp, z1, p1, z2, p2
  integer :: i, n, st
  call get_environment_variable('RAILDYN_SOURCE_DIR', src, n, st)
  if (st /= 0 .or. n == 0) src = '.'
  dir = trim(src) // '/inputs/profiles/'
  call read_profile_file(dir // 's1002.prw', PROFILE_WHEEL, w, error)
  if (allocated(error)) error stop error%message
  dmax = 0
  do i = 1, size(w%y)
    s = 1000 * w%y(i)
    f = s1002_radius_increase_mm(s)
    fp = (s1002_radius_increase_mm(s + 1e-6_wp) - s1002_radius_increase_mm(s - 1e-6_wp)) / 2e-6_wp
    dmax = max(dmax, abs(1000 * w%z(i) - f) / sqrt(1 + fp**2))
  end do
  write (*, '(a,es10.3,a)') 's1002.prw vs S1002 definition: ', dmax, ' mm'
  call check(dmax < 1e-9_wp, 'inputs/profiles/s1002.prw equals the S1002 definition')
  call read_profile_file(dir // 's1002.txt', PROFILE_WHEEL, w2, error)
  call check(.not. allocated(error), 's1002.txt reads')
  if (.not. allocated(error)) call check(maxval(abs(w2%y - w%y)) + maxval(abs(w2%z - w%z)) < 1e-15_wp, &
    's1002.txt equals s1002.prw')
  call read_profile_file(dir // '54e1.prr', PROFILE_RAIL, r, error)
  call check(.not. allocated(error), '54e1.prr reads')
  call read_profile_file(dir // '60e1.prr', PROFILE_RAIL, r, error)
  call rail_head_profile(RAIL_60E1, ra, 1.0e-4_wp, error)
  call check(size(r%y) == size(ra%y), '60e1.prr has the generator points')
  if (size(r%y) == size(ra%y)) call check(maxval(abs(r%y - ra%y)) + maxval(abs(r%z - ra%z)) < 1e-15_wp, &
    '60e1.prr equals the analytic 60E1')
  ! canted file + precant == analytic + inclination
  call read_profile_file(dir // '60e1_1in40.prr', PROFILE_RAIL, r, error)
  if (allocated(error)) error stop error%message
  pl2%rail_precant = 0.025_wp
  ! fine resampling: both rails are resampled from different first points, so they differ
  ! by the polygon sagitta h^2/(8R) (R13 corner: 0.4 um at 0.2 mm, 0.02 um at 0.05 mm)
  opt%rail_spacing = 5.0e-5_wp; opt%wheel_spacing = 5.0e-5_wp
  call build_strip_contact(g1, w, ra, pl, opt, error)
  call build_strip_contact(g2, w, r, pl2, opt, error)
  if (allocated(error)) error stop error%message
  dmax = 0
  do i = -2, 6
    call rigid_contact(g1, 1.0e-3_wp * i, 0.0_wp, z1, p1, error)
    call rigid_contact(g2, 1.0e-3_wp * i, 0.0_wp, z2, p2, error)
    dmax = max(dmax, abs(z1 - z2), abs(p1 - p2))
  end do
  write (*, '(a,es10.3)') '60e1_1in40.prr + precant vs analytic + 1:40: max |dz|, |droll| ', dmax
  call check(dmax < 1e-7_wp, '60e1_1in40.prr with rail_precant 0.025 places like the analytic 60E1 at 1:40')
  call test_summary('test_input_profiles')
end program test_input_profiles
