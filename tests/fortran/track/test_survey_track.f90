!> Surveyed-points track (rd_survey_track) against independent oracles:
!> - points sampled every 5 m from an analytic circle R 500 (closed form position, heading,
!>   curvature, arc length), and from a segment track (rd_track, itself tested against
!>   closed forms and quadrature in test_track_segments);
!> - sigma is the horizontal arc length: |d(x, y)/dsigma| = 1 by finite differences;
!> - derivatives against central differences; the file reader on good and bad files.
program test_survey_track
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_kinds, only: wp
  use test_files, only: scratch_name, write_file, delete_file
  use rd_error, only: error_t, RD_ERR_INPUT, RD_ERR_IO
  use rd_track_point, only: track_point_t
  use rd_track, only: track_t, track_settings_t, segment_spec_t, build_track
  use rd_survey_track, only: survey_track_t, build_survey_track, read_survey_file
  use rd_test_support, only: check, fail, test_summary
  implicit none

  call test_circle()
  call test_against_segment_track('thesis-like track (R 1000, 200 m clothoid)', 1000.0_wp, 200.0_wp, 0.05_wp)
  call test_against_segment_track('Manchester track case 1 (R 150, 30 m clothoid)', 150.0_wp, 30.0_wp, 0.1_wp)
  call test_reader()
  call test_build_errors()

  call test_summary('test_survey_track')

contains

  !> The error exists, has the code and contains each fragment (up to three; separate
  !> arguments because gfortran 12 miscompiles typed array constructors of
  !> variable-length strings).
  subroutine check_message(error, code, what, f1, f2, f3)
    type(error_t), allocatable, intent(in) :: error
    integer, intent(in) :: code
    character(len=*), intent(in) :: what, f1
    character(len=*), intent(in), optional :: f2, f3
    if (.not. allocated(error)) then
      call fail()
      print '(a)', 'FAIL: no error for ' // what
      return
    end if
    print '(a)', '  ' // what // ' -> ' // error%message
    if (error%code /= code) then
      call fail()
      print '(a)', 'FAIL: wrong error code for ' // what
    end if
    call check_fragment(error, what, f1)
    if (present(f2)) call check_fragment(error, what, f2)
    if (present(f3)) call check_fragment(error, what, f3)
  end subroutine check_message

  subroutine check_fragment(error, what, fragment)
    type(error_t), intent(in) :: error
    character(len=*), intent(in) :: what, fragment
    if (index(error%message, fragment) == 0) then
      call fail()
      print '(a)', 'FAIL: message for ' // what // ' lacks "' // fragment // '"'
    end if
  end subroutine check_fragment

  subroutine test_circle()
    integer, parameter :: n = 81
    real(wp), parameter :: radius = 500.0_wp, spacing = 5.0_wp
    real(wp) :: x(n), y(n), z(n), h(n), s, angle, worst_pos, worst_along, worst_kappa, worst_other
    type(survey_track_t) :: track
    type(error_t), allocatable :: error
    type(track_point_t) :: p
    integer :: i
    do i = 1, n
      s = spacing * (i - 1)
      x(i) = radius * sin(s / radius)
      y(i) = radius * (1 - cos(s / radius))
      z(i) = 2 + 0.001_wp * s
      h(i) = -0.1_wp
    end do
    call build_survey_track(track, x, y, z, h, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // error%message
      error stop 1
    end if
    worst_pos = 0; worst_along = 0; worst_kappa = 0; worst_other = 0
    do i = 0, 4 * (n - 1)
      s = 1.25_wp * i + 0.3_wp * modulo(i, 2)
      if (s > track%length()) exit
      p = track%evaluate(s)
      angle = atan2(p%r(1), radius - p%r(2))
      worst_pos = max(worst_pos, abs(hypot(p%r(1), p%r(2) - radius) - radius))
      worst_along = max(worst_along, abs(radius * angle - s))
      worst_kappa = max(worst_kappa, abs(p%curvature * radius - 1))
      worst_other = max(worst_other, abs(p%heading - angle), abs(p%r(3) - (2 + 0.001_wp * s)), &
                        abs(p%cant_angle + asin(0.1_wp / 1.5_wp)))
    end do
    print '(a,4es9.2)', 'survey of circle R 500 (5 m): radial, along-track [m], curvature [rel], other: ', &
      worst_pos, worst_along, worst_kappa, worst_other
    call check(worst_pos < 1.0e-4_wp, 'circle: radial position error', worst_pos)
    call check(worst_along < 1.0e-4_wp, 'circle: along-track position error', worst_along)
    call check(worst_kappa < 0.01_wp, 'circle: curvature relative error', worst_kappa)
    call check(worst_other < 1.0e-6_wp, 'circle: heading, z, cant', worst_other)
    call check(abs(track%length() - 400) < 1.0e-4_wp, 'circle: length', track%length() - 400)
    call check_derivatives(track)
  end subroutine test_circle

  subroutine check_derivatives(track)
    type(survey_track_t), intent(in) :: track
    real(wp), parameter :: dh = 1.0e-4_wp
    type(track_point_t) :: p, pp, pm
    real(wp) :: sigma, e(7), worst(7)
    integer :: i
    worst = 0
    do i = 0, 38
      sigma = 10.0_wp * i + 3.3_wp
      p = track%evaluate(sigma)
      pp = track%evaluate(sigma + dh)
      pm = track%evaluate(sigma - dh)
      e(1) = maxval(abs((pp%r - pm%r) / (2 * dh) - p%dr))
      e(2) = abs(hypot(pp%r(1) - pm%r(1), pp%r(2) - pm%r(2)) / (2 * dh) - 1)
      e(3) = maxval(abs((pp%dr - pm%dr) / (2 * dh) - p%d2r))
      e(4) = maxval(abs((pp%a - pm%a) / (2 * dh) - p%da))
      e(5) = maxval(abs((pp%da - pm%da) / (2 * dh) - p%d2a))
      e(6) = maxval(abs((pp%omega - pm%omega) / (2 * dh) - p%domega))
      e(7) = abs((pp%curvature - pm%curvature) / (2 * dh) - p%dcurvature)
      worst = max(worst, e)
    end do
    print '(a,7es9.2)', 'survey derivatives vs FD (dr, |dxy/dsigma|-1, d2r, dA, d2A, domega, dkappa): ', worst
    call check(worst(1) < 1.0e-9_wp, 'survey dr vs FD', worst(1))
    call check(worst(2) < 1.0e-9_wp, 'survey: sigma is the horizontal arc length', worst(2))
    call check(all(worst(3:7) < 1.0e-9_wp), 'survey second derivatives vs FD', maxval(worst(3:7)))
  end subroutine check_derivatives

  !> Sample a segment track every 5 m (with a gradient change and a cant ramp) and compare.
  subroutine test_against_segment_track(name, radius, transition, cant)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: radius, transition, cant
    type(track_t) :: reference
    type(track_settings_t) :: settings
    type(segment_spec_t) :: specs(3)
    type(survey_track_t) :: track
    type(error_t), allocatable :: error
    type(track_point_t) :: p, q
    real(wp), allocatable :: x(:), y(:), z(:), h(:)
    real(wp) :: s, worst_pos, worst_kappa, worst_kappa_joint, worst_cant, joint1, joint2
    integer :: i, n
    specs(1)%kind = 'straight'; specs(1)%length = 100
    specs(1)%gradient_end = 0.01_wp
    specs(2)%kind = 'clothoid'; specs(2)%length = transition
    specs(2)%curvature_end = 1 / radius; specs(2)%superelevation_end = -cant
    specs(3)%kind = 'curve'; specs(3)%length = 200
    specs(3)%curvature_end = 1 / radius; specs(3)%superelevation_end = -cant
    call build_track(reference, settings, specs, error)
    if (allocated(error)) error stop 1
    n = nint(reference%length() / 5) + 1
    allocate (x(n), y(n), z(n), h(n))
    do i = 1, n
      p = reference%evaluate(5.0_wp * (i - 1))
      x(i) = p%r(1); y(i) = p%r(2); z(i) = p%r(3); h(i) = p%superelevation
    end do
    call build_survey_track(track, x, y, z, h, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // error%message
      error stop 1
    end if
    joint1 = 100
    joint2 = 100 + transition
    worst_pos = 0; worst_kappa = 0; worst_kappa_joint = 0; worst_cant = 0
    do i = 0, 4 * (n - 1)
      ! up to the survey's own end (its length differs from the reference by ~1e-6 m)
      s = min(1.25_wp * i, track%length())
      p = track%evaluate(s)
      q = reference%evaluate(s)
      worst_pos = max(worst_pos, maxval(abs(p%r - q%r)))
      worst_cant = max(worst_cant, abs(p%cant_angle - q%cant_angle))
      ! the reference curvature has kinks at the joints (piecewise linear); the C2
      ! spline smooths them, the error is largest next to them
      if (min(abs(s - joint1), abs(s - joint2)) > 15) then
        worst_kappa = max(worst_kappa, abs(p%curvature - q%curvature) * radius)
      else
        worst_kappa_joint = max(worst_kappa_joint, abs(p%curvature - q%curvature) * radius)
      end if
    end do
    print '(a,a,/,a,4es9.2)', 'survey of the ', name, &
      '   position [m], curvature/(1/R) away from / within 15 m of joints, cant angle: ', &
      worst_pos, worst_kappa, worst_kappa_joint, worst_cant
    call check(worst_pos < 1.0e-4_wp, name // ': position', worst_pos)
    call check(max(worst_kappa, worst_kappa_joint) < 0.01_wp, name // ': curvature within 1% of 1/R', &
               max(worst_kappa, worst_kappa_joint))
    call check(worst_cant < 2.0e-3_wp, name // ': cant angle', worst_cant)
    call check(abs(track%length() - reference%length()) < 1.0e-4_wp, name // ': length', &
               track%length() - reference%length())
  end subroutine test_against_segment_track

  subroutine test_reader()
    character(len=256) :: path
    real(wp), allocatable :: x(:), y(:), z(:), h(:)
    type(error_t), allocatable :: error
    path = scratch_name('survey')
    call write_file(trim(path), [character(len=60) :: '# surveyed points: x y z superelevation', &
                    '0, 0, 1.5, 0   # first', '', '5.0 0.01 1.5 -0.01', &
                    '  10.0	0.05  1.51  -0.02', '15 0.11 1.52 -0.03'])
    call read_survey_file(trim(path), x, y, z, h, error)
    if (allocated(error)) then
      call fail()
      print '(a)', 'FAIL: reader: ' // error%message
    else
      call check(size(x) == 4, 'reader: number of points', real(size(x), wp))
      call check(maxval(abs(x - [0.0_wp, 5.0_wp, 10.0_wp, 15.0_wp])) + maxval(abs(h - [0.0_wp, -0.01_wp, &
                 -0.02_wp, -0.03_wp])) + abs(y(4) - 0.11_wp) + abs(z(3) - 1.51_wp) == 0, 'reader: values', 0.0_wp)
    end if
    call write_file(trim(path), [character(len=60) :: '# header', '0 0 0 0', '5 0 0', '10 0 0 0', '15 0 0 0'])
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_INPUT, 'row with 3 columns', trim(path) // ':3:', 'expected 4 numbers', '5 0 0')
    call write_file(trim(path), [character(len=60) :: '0 0 0 0', '5 0 0 0 7', '10 0 0 0', '15 0 0 0'])
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_INPUT, 'row with 5 columns', trim(path) // ':2:', 'expected 4 numbers')
    call write_file(trim(path), [character(len=60) :: '0 0 0 0', '5 0 abc 0', '10 0 0 0', '15 0 0 0'])
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_INPUT, 'non-numeric row', trim(path) // ':2:', 'abc')
    call write_file(trim(path), [character(len=60) :: '0 0 0 0', '5 0 0 0', '# comment', '5 0 0.1 0', '15 0 0 0'])
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_INPUT, 'repeated point', trim(path) // ':4:', 'repeats', 'line 2')
    call write_file(trim(path), [character(len=60) :: '0 0 0 0', '5 0 0 0', '10 0 0 0'])
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_INPUT, 'three points', trim(path), '3 points', 'at least 4')
    call delete_file(trim(path))
    call read_survey_file(trim(path), x, y, z, h, error)
    call check_message(error, RD_ERR_IO, 'missing file', trim(path), 'cannot open')
  end subroutine test_reader

  subroutine test_build_errors()
    type(survey_track_t) :: track
    type(error_t), allocatable :: error
    real(wp) :: nan
    call build_survey_track(track, [0.0_wp, 5.0_wp, 10.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], &
                            [0.0_wp, 0.0_wp, 0.0_wp], error, origin='survey.txt')
    call check_message(error, RD_ERR_INPUT, 'build: 3 points', 'survey.txt', 'at least 4')
    call build_survey_track(track, [0.0_wp, 5.0_wp, 5.0_wp, 10.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                            [0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], error, origin='survey.txt')
    call check_message(error, RD_ERR_INPUT, 'build: repeated point', 'survey.txt', 'point 3 repeats point 2')
    call build_survey_track(track, [0.0_wp, 5.0_wp, 10.0_wp, 15.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                            [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 1.6_wp, 0.0_wp], error, origin='survey.txt')
    call check_message(error, RD_ERR_INPUT, 'build: cant too large', 'survey.txt', 'point 3', 'cant larger than the gauge')
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    call build_survey_track(track, [0.0_wp, 5.0_wp, 10.0_wp, 15.0_wp], [0.0_wp, nan, 0.0_wp, 0.0_wp], &
                            [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], error, origin='survey.txt')
    call check_message(error, RD_ERR_INPUT, 'build: NaN', 'survey.txt', 'finite')
    ! points out of order: the track would reverse between points 2 and 3
    call build_survey_track(track, [0.0_wp, 5.0_wp, 0.0_wp, 5.0_wp, 10.0_wp], [0.0_wp, 0.0_wp, 0.5_wp, 1.0_wp, 1.0_wp], &
                            [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], error, &
                            origin='survey.txt')
    call check_message(error, RD_ERR_INPUT, 'build: zig-zag points', 'survey.txt', 'between points')
  end subroutine test_build_errors
end program test_survey_track
