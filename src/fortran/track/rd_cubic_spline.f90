!> Not-a-knot cubic spline interpolation (de Boor, "A Practical Guide to Splines", ch. IV),
!> used by the surveyed-points track (thesis 4.4: "cubic splines between control points").
!>
!> On interval i (t_i <= t <= t_{i+1}, d = t - t_i) the spline is
!>     s(t) = c(0) + c(1) d + c(2) d^2 + c(3) d^3,
!> C2 everywhere and, with not-a-knot ends (s''' continuous at t_2 and t_{n-1}), exact for
!> cubics and free of the zero end curvature a natural spline would impose. The second
!> derivatives M solve a banded system (two super- and sub-diagonals because of the
!> not-a-knot rows), solved once at build time with LAPACK dgbsv (partial pivoting: the
!> not-a-knot rows are not diagonally dominant).
module rd_cubic_spline
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_INTERNAL
  use rd_lapack_interfaces, only: dgbsv, band_put
  implicit none
  private
  public :: spline_not_a_knot, locate_interval

contains

  !> Coefficients coef(0:3, i, j) of the not-a-knot spline through (t(k), y(k, j)) for
  !> each column j. t strictly increasing, n = size(t) >= 4.
  subroutine spline_not_a_knot(t, y, coef, error)
    real(wp), intent(in) :: t(:), y(:, :)
    real(wp), intent(out) :: coef(0:, :, :)
    type(error_t), allocatable, intent(out) :: error
    integer, parameter :: kl = 2, ku = 2, ldab = 2 * kl + ku + 1
    real(wp), allocatable :: ab(:, :), m(:, :)
    real(wp) :: h(size(t) - 1)
    integer, allocatable :: ipiv(:)
    integer :: n, i, j, info

    n = size(t)
    if (n < 4) then
      call make_error(error, RD_ERR_INPUT, 'spline_not_a_knot: at least 4 points are needed')
      return
    end if
    h = t(2:n) - t(1:n - 1)
    if (any(h <= 0)) then
      call make_error(error, RD_ERR_INPUT, 'spline_not_a_knot: knots must increase strictly')
      return
    end if
    allocate (ab(ldab, n), m(n, size(y, 2)), ipiv(n))
    ab = 0
    ! not-a-knot at t_2: h2 M1 - (h1 + h2) M2 + h1 M3 = 0
    call band_put(ab, kl, ku, 1, 1, h(2))
    call band_put(ab, kl, ku, 1, 2, -(h(1) + h(2)))
    call band_put(ab, kl, ku, 1, 3, h(1))
    m(1, :) = 0
    do i = 2, n - 1
      call band_put(ab, kl, ku, i, i - 1, h(i - 1))
      call band_put(ab, kl, ku, i, i, 2 * (h(i - 1) + h(i)))
      call band_put(ab, kl, ku, i, i + 1, h(i))
      m(i, :) = 6 * ((y(i + 1, :) - y(i, :)) / h(i) - (y(i, :) - y(i - 1, :)) / h(i - 1))
    end do
    ! not-a-knot at t_{n-1}
    call band_put(ab, kl, ku, n, n - 2, h(n - 1))
    call band_put(ab, kl, ku, n, n - 1, -(h(n - 2) + h(n - 1)))
    call band_put(ab, kl, ku, n, n, h(n - 2))
    m(n, :) = 0
    call dgbsv(n, kl, ku, size(y, 2), ab, ldab, ipiv, m, n, info)
    if (info /= 0) then
      call make_error(error, RD_ERR_INTERNAL, 'spline_not_a_knot: singular spline system (dgbsv info /= 0)')
      return
    end if
    do j = 1, size(y, 2)
      do i = 1, n - 1
        coef(0, i, j) = y(i, j)
        coef(1, i, j) = (y(i + 1, j) - y(i, j)) / h(i) - h(i) * (2 * m(i, j) + m(i + 1, j)) / 6
        coef(2, i, j) = 0.5_wp * m(i, j)
        coef(3, i, j) = (m(i + 1, j) - m(i, j)) / (6 * h(i))
      end do
    end do
  end subroutine spline_not_a_knot

  !> Largest i in 1..n-1 with knots(i) <= x (clamped), by bisection.
  pure function locate_interval(knots, x) result(i)
    real(wp), intent(in) :: knots(:), x
    integer :: i
    integer :: hi, mid
    i = 1
    hi = size(knots) - 1
    do while (i < hi)
      mid = (i + hi + 1) / 2
      if (knots(mid) <= x) then
        i = mid
      else
        hi = mid - 1
      end if
    end do
  end function locate_interval
end module rd_cubic_spline
