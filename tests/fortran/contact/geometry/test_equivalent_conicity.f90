!> EN 15302 equivalent conicity (rd_equivalent_conicity) against closed forms derived here:
!>  - a pure cone, Delta r = 2 gamma y, on unevenly spaced rows: gamma at every amplitude by
!>    both methods, and Klingel's wavelength 2 pi sqrt(e0 r0 / gamma);
!>  - a dead zone, Delta r = 0 for |y| < d and 2 lam (|y| - d) sign(y) outside: 0 while the
!>    motion stays inside; outside, the integration method's wavelength is a free flight
!>    across the zone plus half a harmonic oscillation on each side,
!>    lambda_e = lam pi^2 / (pi + 2 d / (A - d))^2, and the regression weighted by a harmonic
!>    motion is the describing function of a dead zone,
!>    lam (1 - (2/pi) (asin(d/A) + (d/A) sqrt(1 - (d/A)^2))) (Slotine & Li, Applied Nonlinear
!>    Control, 1991, section 5.2);
!>  - an asymmetric bilinear Delta r through zero at y0 /= 0 with slopes 2 lam1 (left) and
!>    2 lam2 (right): two half-oscillations, lambda_e = 4 / (lam1^-1/2 + lam2^-1/2)^2 at every
!>    amplitude, extremes where lam1 A_L^2 = lam2 A_R^2, A_L + A_R = 2 A; its regression
!>    against a least-squares fit to Delta r sampled along y = c + A sin(theta) written here;
!>  - errors: amplitude beyond the table, no zero crossing, a second zero crossing (gap),
!>    table checks.
program test_equivalent_conicity
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_delta_r_table, only: delta_r_table_t, build_delta_r_table
  use rd_equivalent_conicity, only: kinematic_motion_t, en15302_conicity, largest_amplitude
  use rd_test_support, only: check, fail, failure_count, test_summary
  implicit none
  type(delta_r_table_t) :: table
  type(kinematic_motion_t) :: m
  type(error_t), allocatable :: error
  real(wp), allocatable :: y(:), dr(:)
  real(wp) :: gamma, lam, lam1, lam2, d, y0, a, worst_int, worst_reg, worst_wl, expect, dz, al, ar
  integer :: i, k, n

  ! 1. pure cone on uneven rows (spacing 0.2 .. 0.45 mm), not symmetric about 0
  gamma = 0.0734_wp
  n = 0
  allocate (y(0))
  y = [-0.0121_wp]
  do while (y(size(y)) < 0.0113_wp)
    y = [y, y(size(y)) + 0.0002_wp + 0.00025_wp * abs(sin(7.3_wp * size(y)))]
  end do
  dr = 2 * gamma * y
  call build_delta_r_table(table, y, dr, error)
  call require_no_error('cone table')
  worst_int = 0; worst_reg = 0; worst_wl = 0
  do k = 1, 22
    a = 0.0005_wp * k
    call en15302_conicity(table, a, 0.46_wp, 0.75_wp, m, error)
    call require_no_error('cone')
    worst_int = max(worst_int, abs(m%conicity_integration / gamma - 1))
    worst_reg = max(worst_reg, abs(m%conicity_regression / gamma - 1))
    worst_wl = max(worst_wl, abs(m%wavelength / (2 * pi * sqrt(0.75_wp * 0.46_wp / gamma)) - 1))
    if (abs(m%y_min + a) > 1e-12_wp .or. abs(m%y_max - a) > 1e-12_wp) call fail()
  end do
  write (*, '(a,3es10.2)') 'cone: worst relative error integration, regression, wavelength', worst_int, worst_reg, worst_wl
  call check(worst_int < 1e-10_wp, 'cone: conicity by integration = gamma at 0.5 .. 11 mm')
  call check(worst_reg < 1e-12_wp, 'cone: conicity by regression = gamma at 0.5 .. 11 mm')
  call check(worst_wl < 1e-10_wp, 'cone: wavelength = Klingel 2 pi sqrt(e0 r0 / gamma)')
  call en15302_conicity(table, 0.003_wp, 0.9_wp, 0.6_wp, m, error)
  call check(abs(m%conicity_integration / gamma - 1) < 1e-8_wp, 'cone: the conicity does not depend on r0, e0')
  a = largest_amplitude(table, error)
  call check(abs(a - 0.0113_wp) < 0.0005_wp .and. a <= y(size(y)), 'cone: largest amplitude = nearer table end')
  call en15302_conicity(table, a * 1.001_wp, 0.46_wp, 0.75_wp, m, error)
  call check(allocated(error), 'amplitude beyond the table refused')
  if (allocated(error)) then
    write (*, '(a)') '  ' // error%message
    call check(index(error%message, 'largest amplitude') > 0, 'the message names the largest amplitude')
  end if

  ! 2. dead zone d = 2 mm, lam = 0.12, rows every 0.1 mm
  d = 0.002_wp; lam = 0.12_wp
  y = [(-0.012_wp + 0.0001_wp * i, i=0, 240)]
  dr = 2 * lam * sign(max(abs(y) - d, 0.0_wp), y)
  call build_delta_r_table(table, y, dr, error)
  call require_no_error('dead-zone table')
  do k = 1, 3
    call en15302_conicity(table, 0.0006_wp * k, 0.46_wp, 0.75_wp, m, error)
    call require_no_error('dead zone inside')
    if (m%oscillates .or. m%conicity_integration /= 0 .or. m%conicity_regression /= 0) call fail()
  end do
  call check(failure_count() == 0, 'dead zone: conicity 0 while the motion stays inside (0.6, 1.2, 1.8 mm)')
  worst_int = 0; worst_reg = 0
  do k = 1, 9
    a = 0.0021_wp + 0.001_wp * k
    call en15302_conicity(table, a, 0.46_wp, 0.75_wp, m, error)
    call require_no_error('dead zone outside')
    expect = lam * pi**2 / (pi + 2 * d / (a - d))**2
    worst_int = max(worst_int, abs(m%conicity_integration / expect - 1))
    expect = lam * (1 - (2 / pi) * (asin(d / a) + (d / a) * sqrt(1 - (d / a)**2)))
    worst_reg = max(worst_reg, abs(m%conicity_regression / expect - 1))
    if (k == 1) write (*, '(a,f8.5,a,f8.5)') 'dead zone A = 3.1 mm: integration ', m%conicity_integration, &
      ', regression ', m%conicity_regression
  end do
  write (*, '(a,2es10.2)') 'dead zone: worst relative error integration, regression', worst_int, worst_reg
  call check(worst_int < 1e-10_wp, 'dead zone: integration = free flight + harmonic halves (3.1 .. 11.1 mm)')
  call check(worst_reg < 1e-10_wp, 'dead zone: regression = describing function of a dead zone')

  ! 3. asymmetric: zero at y0 = 0.75 mm (a row: the kink is in the table), slopes 2 lam1 left, 2 lam2 right, Delta r(0) /= 0
  y0 = 0.00075_wp; lam1 = 0.04_wp; lam2 = 0.15_wp
  y = [(-0.015_wp + 0.00025_wp * i, i=0, 120)]
  dr = merge(2 * lam1 * (y - y0), 2 * lam2 * (y - y0), y < y0)
  call build_delta_r_table(table, [y, y0], [dr, 0.0_wp], error)   ! y0 appended: not ascending
  call check(allocated(error), 'table with y not ascending refused')
  call build_delta_r_table(table, y, dr, error)
  call require_no_error('asymmetric table')
  worst_int = 0; worst_reg = 0; dz = 0
  do k = 1, 8
    a = 0.001_wp * k
    call en15302_conicity(table, a, 0.46_wp, 0.75_wp, m, error)
    call require_no_error('asymmetric')
    expect = 4 / (1 / sqrt(lam1) + 1 / sqrt(lam2))**2
    worst_int = max(worst_int, abs(m%conicity_integration / expect - 1))
    al = 2 * a * sqrt(lam2) / (sqrt(lam1) + sqrt(lam2))
    ar = 2 * a - al
    dz = max(dz, abs(m%y_min - (y0 - al)), abs(m%y_max - (y0 + ar)))
    expect = sampled_regression(y0 + 0.5_wp * (ar - al), a) / 2
    worst_reg = max(worst_reg, abs(m%conicity_regression / expect - 1))
  end do
  write (*, '(a,3es10.2)') 'asymmetric: worst relative error integration, regression; extremes [m]', worst_int, &
    worst_reg, dz
  call check(worst_int < 1e-10_wp, 'asymmetric: integration = 4 / (lam1^-1/2 + lam2^-1/2)^2 (1 .. 8 mm)')
  call check(dz < 1e-10_wp, 'asymmetric: extremes of the motion about the zero at y0')
  call check(worst_reg < 1e-8_wp, 'asymmetric: regression = least squares on a sampled harmonic motion')

  ! 4. errors
  call build_delta_r_table(table, [0.001_wp, 0.002_wp], [0.001_wp, 0.002_wp], error)
  call require_no_error('positive table')
  call en15302_conicity(table, 0.0005_wp, 0.46_wp, 0.75_wp, m, error)
  call check(allocated(error), 'Delta r without a zero crossing refused')
  if (allocated(error)) write (*, '(a)') '  ' // error%message
  ! Delta r rises through 0 at 0, falls back below 0 at 4 mm, rises again at 6 mm: the motion
  ! about 0 opens into the second well once its energy passes the bump at 4 mm
  y = [-0.01_wp, 0.002_wp, 0.004_wp, 0.005_wp, 0.006_wp, 0.012_wp]
  dr = [-0.001_wp, 0.0002_wp, 0.0_wp, -0.0001_wp, 0.0_wp, 0.0012_wp]
  call build_delta_r_table(table, y, dr, error)
  call require_no_error('two-well table')
  call en15302_conicity(table, 0.001_wp, 0.46_wp, 0.75_wp, m, error)
  call require_no_error('inside the first well')
  call check(m%oscillates .and. m%y_max < 0.004_wp, 'two wells: small amplitude stays in the well about 0')
  call en15302_conicity(table, 0.004_wp, 0.46_wp, 0.75_wp, m, error)
  call check(allocated(error), 'an amplitude no motion about the zero has is refused')
  if (allocated(error)) write (*, '(a)') '  ' // error%message
  call build_delta_r_table(table, [0.0_wp], [0.0_wp], error)
  call check(allocated(error), 'one row refused')
  call build_delta_r_table(table, [0.0_wp, 0.001_wp], [0.0_wp, 2.0_wp], error)
  call check(allocated(error), 'millimetres refused')
  call en15302_conicity(table, 0.001_wp, -1.0_wp, 0.75_wp, m, error)
  call check(allocated(error), 'negative r0 refused')
  call test_summary('test_equivalent_conicity')
contains
  subroutine require_no_error(what)
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      write (*, '(a)') 'FAIL ' // what // ': ' // error%message
      error stop 1
    end if
  end subroutine require_no_error

  !> Slope of the ordinary least-squares line through Delta r at y = c + A sin(theta_j),
  !> theta_j equidistant (the residence-time weighting of a harmonic motion), Delta r
  !> interpolated linearly in the table.
  real(wp) function sampled_regression(c, amp) result(slope)
    real(wp), intent(in) :: c, amp
    integer, parameter :: ns = 200000
    real(wp) :: yy, ff, sy, sf, syy, syf
    integer :: j, i
    sy = 0; sf = 0; syy = 0; syf = 0
    do j = 1, ns
      yy = c + amp * sin(2 * pi * (j - 0.5_wp) / ns)
      i = max(1, min(size(table%y) - 1, count(table%y <= yy)))
      ff = table%delta_r(i) + (table%delta_r(i + 1) - table%delta_r(i)) * (yy - table%y(i)) / (table%y(i + 1) - table%y(i))
      sy = sy + yy; sf = sf + ff; syy = syy + yy * yy; syf = syf + yy * ff
    end do
    slope = (syf - sy * sf / ns) / (syy - sy * sy / ns)
  end function sampled_regression
end program test_equivalent_conicity
