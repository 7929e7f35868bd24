!> Kalker's creepage and spin coefficients C11, C22, C23, C33 (Kalker 1967/1990;
!> thesis table B.1, used in eqs. 3.39-3.43), interpolated linearly in the table variable g
!> with each row's corner rounded (C1 in the ellipse's shape) and linearly in Poisson's ratio.
!> Plain linear interpolation made every creep law's forces kink at each row (e.g. at
!> a/b = 3.33: bench/contact_smoothness's ellipse sweep). Within corner_width w rows of an
!> interior row k the two segments (slopes s_l, s_r) are joined by two cubic Hermite pieces
!> through the row's value v_k with the mean slope (s_l + s_r) / 2 there, each meeting its
!> segment with the segment's value and slope at d = pos - k = -w or w; elsewhere the
!> interpolation is the linear one, and at the rows it is the table. (A cubic through
!> the rows (Catmull-Rom, natural spline, PCHIP) gives C11 = 4.736 at a/b = 1.5, nu = 0.28,
!> 0.16 % below the linear 4.744 that reproduces CONTACT's exact Fx there: the table's values
!> are rounded to 0.01.)
!>
!> Transcription notes (checked against Kalker 1990, table E3 / Vollebregt's tables):
!> - the thesis' column header "c12" is C22 (C11 = C22 at nu = 0, as printed).
!> - the thesis' eq. 3.42 writes f22 = G a^2 b^2 C22; it must be C33.
!> Spot checks: C11(a/b = 1, nu = 0.25) = 4.12; with a = 6 mm, b = 4 mm, nu = 0.28 the
!> interpolated C11 gives Fx = -93.36 N at xi = 1e-5, CONTACT's exact value (oracles.md).
!> The table's first half is indexed by g = a/b (0.1 ... 1), the second by g = b/a
!> (1 ... 0.1); a/b outside [0.1, 10]: the end segment's slope eased to zero over a quarter
!> row beyond the end row, then held (a C1 clamp; Hertz flags such ellipses).
module rd_kalker_coefficients
  use rd_kinds, only: wp
  implicit none
  private
  public :: kalker_coefficients

  integer, parameter :: n_rows = 19
  !> half width w of the rounded corner at each row, in rows (the reference value at a/b = 1.5
  !> lies a third of a row from its nearest row)
  real(wp), parameter :: corner_width = 0.25_wp
  ! rows: a/b = 0.1, 0.2, ..., 0.9, 1.0, then b/a = 0.9, 0.8, ..., 0.1
  ! columns: nu = 0, 0.25, 0.5
  real(wp), parameter :: c11_table(3, n_rows) = reshape([ &
    2.51_wp, 3.31_wp, 4.85_wp, 2.59_wp, 3.37_wp, 4.81_wp, 2.68_wp, 3.44_wp, 4.80_wp, &
    2.78_wp, 3.53_wp, 4.82_wp, 2.88_wp, 3.62_wp, 4.83_wp, 2.98_wp, 3.72_wp, 4.91_wp, &
    3.09_wp, 3.81_wp, 4.97_wp, 3.19_wp, 3.91_wp, 5.05_wp, 3.29_wp, 4.01_wp, 5.12_wp, &
    3.40_wp, 4.12_wp, 5.20_wp, &
    3.51_wp, 4.22_wp, 5.30_wp, 3.65_wp, 4.36_wp, 5.42_wp, 3.82_wp, 4.54_wp, 5.58_wp, &
    4.06_wp, 4.78_wp, 5.80_wp, 4.37_wp, 5.10_wp, 6.11_wp, 4.84_wp, 5.57_wp, 6.57_wp, &
    5.57_wp, 6.34_wp, 7.34_wp, 6.96_wp, 7.78_wp, 8.82_wp, 10.7_wp, 11.7_wp, 12.9_wp], [3, n_rows])
  real(wp), parameter :: c22_table(3, n_rows) = reshape([ &
    2.51_wp, 2.52_wp, 2.53_wp, 2.59_wp, 2.63_wp, 2.66_wp, 2.68_wp, 2.75_wp, 2.81_wp, &
    2.78_wp, 2.88_wp, 2.98_wp, 2.88_wp, 3.01_wp, 3.14_wp, 2.98_wp, 3.14_wp, 3.31_wp, &
    3.09_wp, 3.28_wp, 3.48_wp, 3.19_wp, 3.41_wp, 3.65_wp, 3.29_wp, 3.54_wp, 3.82_wp, &
    3.40_wp, 3.67_wp, 3.98_wp, &
    3.51_wp, 3.81_wp, 4.16_wp, 3.65_wp, 3.99_wp, 4.39_wp, 3.82_wp, 4.21_wp, 4.67_wp, &
    4.06_wp, 4.50_wp, 5.04_wp, 4.37_wp, 4.90_wp, 5.56_wp, 4.84_wp, 5.48_wp, 6.31_wp, &
    5.57_wp, 6.40_wp, 7.51_wp, 6.96_wp, 8.14_wp, 9.79_wp, 10.7_wp, 12.8_wp, 16.0_wp], [3, n_rows])
  real(wp), parameter :: c23_table(3, n_rows) = reshape([ &
    0.334_wp, 0.473_wp, 0.731_wp, 0.483_wp, 0.603_wp, 0.809_wp, 0.607_wp, 0.715_wp, 0.889_wp, &
    0.720_wp, 0.823_wp, 0.977_wp, 0.827_wp, 0.929_wp, 1.07_wp, 0.930_wp, 1.03_wp, 1.18_wp, &
    1.03_wp, 1.14_wp, 1.29_wp, 1.13_wp, 1.25_wp, 1.40_wp, 1.23_wp, 1.36_wp, 1.51_wp, &
    1.33_wp, 1.47_wp, 1.63_wp, &
    1.44_wp, 1.59_wp, 1.77_wp, 1.58_wp, 1.75_wp, 1.94_wp, 1.76_wp, 1.95_wp, 2.18_wp, &
    2.01_wp, 2.23_wp, 2.50_wp, 2.35_wp, 2.62_wp, 2.96_wp, 2.88_wp, 3.24_wp, 3.70_wp, &
    3.79_wp, 4.32_wp, 5.01_wp, 5.72_wp, 6.63_wp, 7.89_wp, 12.2_wp, 14.6_wp, 18.0_wp], [3, n_rows])
  real(wp), parameter :: c33_table(3, n_rows) = reshape([ &
    6.42_wp, 8.28_wp, 11.7_wp, 3.46_wp, 4.27_wp, 5.66_wp, 2.49_wp, 2.96_wp, 3.72_wp, &
    2.02_wp, 2.32_wp, 2.77_wp, 1.74_wp, 1.93_wp, 2.22_wp, 1.56_wp, 1.68_wp, 1.86_wp, &
    1.43_wp, 1.50_wp, 1.60_wp, 1.34_wp, 1.37_wp, 1.42_wp, 1.27_wp, 1.27_wp, 1.27_wp, &
    1.21_wp, 1.19_wp, 1.16_wp, &
    1.16_wp, 1.11_wp, 1.06_wp, 1.10_wp, 1.04_wp, 0.954_wp, 1.05_wp, 0.965_wp, 0.852_wp, &
    1.01_wp, 0.892_wp, 0.751_wp, 0.958_wp, 0.819_wp, 0.650_wp, 0.912_wp, 0.747_wp, 0.549_wp, &
    0.868_wp, 0.674_wp, 0.446_wp, 0.828_wp, 0.601_wp, 0.341_wp, 0.795_wp, 0.526_wp, 0.228_wp], [3, n_rows])

contains

  !> C11, C22, C23, C33 for the semi-axis ratio a/b (a along the rolling direction) and
  !> the combined Poisson ratio nu (clamped to [0, 0.5]).
  pure subroutine kalker_coefficients(a_over_b, poisson, c11, c22, c23, c33)
    real(wp), intent(in) :: a_over_b, poisson
    real(wp), intent(out) :: c11, c22, c23, c33
    real(wp) :: pos, pos_raw, wg, wn, nu
    integer :: ig, jn
    ! position in the row list: 1 + (g - 0.1)/0.1 on the a/b half, 10 + (1 - b/a)/0.1 beyond
    if (a_over_b <= 1.0_wp) then
      pos = 1.0_wp + (a_over_b - 0.1_wp) / 0.1_wp
    else
      pos = 10.0_wp + (1.0_wp - 1.0_wp / a_over_b) / 0.1_wp
    end if
    pos_raw = pos
    pos = min(max(pos, 1.0_wp), real(n_rows, wp))
    ig = min(int(pos), n_rows - 1)
    wg = pos - ig
    nu = min(max(poisson, 0.0_wp), 0.5_wp)
    jn = min(int(nu / 0.25_wp) + 1, 2)
    wn = (nu - 0.25_wp * (jn - 1)) / 0.25_wp
    c11 = interpolate(c11_table)
    c22 = interpolate(c22_table)
    c23 = interpolate(c23_table)
    c33 = interpolate(c33_table)
  contains
    !> linear in the row position pos (rows ig, ig + 1) with the nearest interior row's corner
    !> rounded, linear in nu
    pure real(wp) function interpolate(t)
      real(wp), intent(in) :: t(3, n_rows)
      real(wp) :: v(n_rows), d, s_l, s_r, s_m, s_o, u
      integer :: k
      v = (1.0_wp - wn) * t(jn, :) + wn * t(jn + 1, :)
      interpolate = (1.0_wp - wg) * v(ig) + wg * v(ig + 1)
      k = nint(pos)
      d = pos - k
      if (k > 1 .and. k < n_rows .and. abs(d) < corner_width) then
        s_l = v(k) - v(k - 1); s_r = v(k + 1) - v(k)
        ! Hermite on [k, k + w] (d >= 0) or [k - w, k] (d < 0, mirrored: u = -d)
        u = abs(d) / corner_width
        s_o = merge(s_r, -s_l, d >= 0)          ! outer slope, in the direction of |d|
        s_m = merge(1.0_wp, -1.0_wp, d >= 0) * 0.5_wp * (s_l + s_r)
        interpolate = v(k) + corner_width * ((u**3 - 2 * u**2 + u) * s_m + (-2 * u**3 + 3 * u**2) * s_o &
                                             + (u**3 - u**2) * s_o)
      end if
      ! beyond the table's ends (a/b < 0.1 or > 10): the end segment's slope eased to zero
      ! over corner_width rows, then held (clamping at the end row kinked the coefficients
      ! there, e.g. the spin moment of a narrow flange patch at a/b = 10)
      if (pos_raw > n_rows) then
        d = min(pos_raw - n_rows, corner_width)
        interpolate = v(n_rows) + (v(n_rows) - v(n_rows - 1)) * (d - d * d / (2 * corner_width))
      else if (pos_raw < 1) then
        d = min(1 - pos_raw, corner_width)
        interpolate = v(1) - (v(2) - v(1)) * (d - d * d / (2 * corner_width))
      end if
    end function interpolate
  end subroutine kalker_coefficients
end module rd_kalker_coefficients
