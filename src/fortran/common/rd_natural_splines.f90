!> Interpolating splines through (x_i, f_i) with natural ends, for the smooth wheel of the
!> distributed strip normal force and its tables (docs/theory_flange_chatter.md section 14):
!>
!> - natural_spline: the cubic spline (C2), its second derivatives M_i at the points;
!> - natural_quintic_spline: the quintic spline (C4), its second and fourth derivatives M_i,
!>   P_i at the points. On [x_i, x_(i+1)], h = x_(i+1) - x_i, t = (x - x_i) / h, u = 1 - t:
!>
!>     S   = u f_i + t f_(i+1) + h^2/6 ((u^3 - u) M_i + (t^3 - t) M_(i+1))
!>           + h^4 (e(u) P_i + e(t) P_(i+1)),     e(s) = s^5/120 - s^3/36 + 7 s/360,
!>     S'' = u M_i + t M_(i+1) + h^2/6 ((u^3 - u) P_i + (t^3 - t) P_(i+1)),
!>     S'''' = u P_i + t P_(i+1),
!>
!>   (S'' is the cubic-spline form one level up; e'' = (s^3 - s)/6, e(0) = e(1) = 0), so S,
!>   S'' and S'''' are continuous by construction, and S' and S''' continuous at the interior
!>   points give, with h0 = h_(i-1), h1 = h_i, D_i = (f_(i+1) - f_i) / h_i:
!>
!>     h0 M_(i-1) + 2 (h0 + h1) M_i + h1 M_(i+1)
!>        - (h0^3 (7 P_(i-1) + 8 P_i) + h1^3 (8 P_i + 7 P_(i+1))) / 60 = 6 (D_i - D_(i-1)),
!>     h0 P_(i-1) + 2 (h0 + h1) P_i + h1 P_(i+1)
!>        - 6 ((M_(i+1) - M_i) / h1 - (M_i - M_(i-1)) / h0) = 0,
!>
!>   with M = P = 0 at both ends; a banded system (the unknowns interleaved, three sub- and
!>   super-diagonals) solved once at build time with LAPACK dgbsv.
!>
!> Why C4 for the wheel: the distributed force's depth gradient holds the wheel's second
!> derivative through the deepest point's shift along its line, so the force is C1 along a
!> pose path only if r'' is C1, i.e. r''' continuous: with the cubic spline (r''' jumping at
!> every profile point) the flange force kinked wherever a strip's deepest point crossed one.
module rd_natural_splines
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_INTERNAL
  use rd_lapack_interfaces, only: dgbsv, band_put
  implicit none
  private
  public :: natural_spline, natural_quintic_spline

contains

  !> Second derivatives m of the natural cubic spline through (x, f) (m = 0 at both ends):
  !> h_(i-1) m_(i-1) + 2 (h_(i-1) + h_i) m_i + h_i m_(i+1) = 6 (f'_i - f'_(i-1)), solved by
  !> the Thomas algorithm (diagonally dominant: no pivoting needed).
  pure subroutine natural_spline(x, f, m)
    real(wp), intent(in) :: x(:), f(:)
    real(wp), allocatable, intent(out) :: m(:)
    real(wp) :: c(size(x)), rhs(size(x)), h0, h1, den
    integer :: n, i
    n = size(x)
    allocate (m(n))
    m = 0
    if (n < 3) return
    c = 0; rhs = 0
    do i = 2, n - 1
      h0 = x(i) - x(i - 1); h1 = x(i + 1) - x(i)
      den = 2 * (h0 + h1) - h0 * c(i - 1)
      c(i) = h1 / den
      rhs(i) = (6 * ((f(i + 1) - f(i)) / h1 - (f(i) - f(i - 1)) / h0) - h0 * rhs(i - 1)) / den
    end do
    do i = n - 1, 2, -1
      m(i) = rhs(i) - c(i) * m(i + 1)
    end do
  end subroutine natural_spline

  !> Second and fourth derivatives m, p of the natural quintic spline through (x, f) (the
  !> module's header has the equations). x strictly increasing, at least 3 points.
  subroutine natural_quintic_spline(x, f, m, p, error)
    real(wp), intent(in) :: x(:), f(:)
    real(wp), allocatable, intent(out) :: m(:), p(:)
    type(error_t), allocatable, intent(out) :: error
    integer, parameter :: kl = 3, ku = 3, ldab = 2 * kl + ku + 1
    real(wp), allocatable :: ab(:, :), b(:)
    real(wp) :: h0, h1
    integer, allocatable :: ipiv(:)
    integer :: n, i, info, rm, rp
    n = size(x)
    if (n < 3 .or. size(f) /= n) then
      call make_error(error, RD_ERR_INPUT, 'natural_quintic_spline: at least 3 points (x, f) are needed')
      return
    end if
    if (any(x(2:) <= x(:n - 1))) then
      call make_error(error, RD_ERR_INPUT, 'natural_quintic_spline: x must increase strictly')
      return
    end if
    allocate (ab(ldab, 2 * n), b(2 * n), ipiv(2 * n))
    ab = 0; b = 0
    ! unknowns: M_i at 2 i - 1, P_i at 2 i; the ends' rows M = 0, P = 0
    do i = 1, n, n - 1
      call put(2 * i - 1, 2 * i - 1, 1.0_wp)
      call put(2 * i, 2 * i, 1.0_wp)
    end do
    do i = 2, n - 1
      h0 = x(i) - x(i - 1); h1 = x(i + 1) - x(i)
      rm = 2 * i - 1; rp = 2 * i
      ! S' continuous
      call put(rm, 2 * i - 3, h0); call put(rm, 2 * i - 1, 2 * (h0 + h1)); call put(rm, 2 * i + 1, h1)
      call put(rm, 2 * i - 2, -7 * h0**3 / 60); call put(rm, 2 * i, -8 * (h0**3 + h1**3) / 60)
      call put(rm, 2 * i + 2, -7 * h1**3 / 60)
      b(rm) = 6 * ((f(i + 1) - f(i)) / h1 - (f(i) - f(i - 1)) / h0)
      ! S''' continuous
      call put(rp, 2 * i - 2, h0); call put(rp, 2 * i, 2 * (h0 + h1)); call put(rp, 2 * i + 2, h1)
      call put(rp, 2 * i - 3, -6 / h0); call put(rp, 2 * i - 1, 6 / h0 + 6 / h1); call put(rp, 2 * i + 1, -6 / h1)
    end do
    call dgbsv(2 * n, kl, ku, 1, ab, ldab, ipiv, b, 2 * n, info)
    if (info /= 0) then
      call make_error(error, RD_ERR_INTERNAL, 'natural_quintic_spline: singular spline system (dgbsv info /= 0)')
      return
    end if
    m = b(1::2)
    p = b(2::2)
  contains
    subroutine put(row, col, v)
      integer, intent(in) :: row, col
      real(wp), intent(in) :: v
      call band_put(ab, kl, ku, row, col, v)
    end subroutine put
  end subroutine natural_quintic_spline

end module rd_natural_splines
