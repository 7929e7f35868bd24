!> Fresnel integrals C(x), S(x) and their auxiliary function, to ~1e-15 relative.
!>
!> Normalised convention (Abramowitz & Stegun 7.3.1-7.3.2):
!>     C(x) = int_0^x cos(pi t^2 / 2) dt,   S(x) = int_0^x sin(pi t^2 / 2) dt.
!> With F(x) = C(x) + i S(x) the auxiliary function G(x) = g(x) + i f(x) (A&S 7.3.5-7.3.6)
!> is defined for x >= 0 by
!>     F(x) = (1 + i)/2 - G(x) exp(i pi x^2 / 2).
!> G is what the clothoid needs (rd_clothoid): it keeps the large phases pi x^2/2 out of
!> the difference of two Fresnel integrals.
!>
!> Method (as Numerical Recipes 3rd ed. section 6.8, "frenel", with double-precision
!> tolerances): power series for |x| <= 1.5, where the largest term is below
!> exp(pi x^2/2) ~ 34 so at most ~1.5 digits are lost; for x > 1.5 the continued fraction
!> of erfc (A&S 7.1.14, even form) evaluated with the modified Lentz method,
!> F = (1+i)/2 erf(z), z = sqrt(pi)/2 (1 - i) x, which gives G = x * CF directly.
!> The phase pi x^2 / 2 is reduced modulo 2 pi exactly (x^2 split into two doubles), so the
!> only error at large x is the one inherent in the argument itself.
module rd_fresnel
  use rd_kinds, only: wp, pi
  implicit none
  private
  public :: fresnel_integrals, fresnel_aux, fresnel_phase

  real(wp), parameter :: series_limit = 1.5_wp
  real(wp), parameter :: tolerance = epsilon(1.0_wp)
  !> Beyond this the asymptotic series of f and g (A&S 7.3.27-7.3.28) is exact to
  !> rounding after its first term: the next relative term is 3/(pi x^2)^2 < 1e-28.
  real(wp), parameter :: asymptotic_limit = 1.0e7_wp
  integer, parameter :: max_terms = 300

contains

  !> C(x) and S(x) for any real x (odd functions).
  elemental subroutine fresnel_integrals(x, c, s)
    real(wp), intent(in) :: x
    real(wp), intent(out) :: c, s
    real(wp) :: ax
    complex(wp) :: f
    ax = abs(x)
    if (ax <= series_limit) then
      call fresnel_series(ax, c, s)
    else
      f = cmplx(0.5_wp, 0.5_wp, wp) - fresnel_aux(ax) * fresnel_phase(ax)
      c = real(f, wp)
      s = aimag(f)
    end if
    if (x < 0) then
      c = -c
      s = -s
    end if
  end subroutine fresnel_integrals

  !> G(x) = g + i f for x >= 0, with C + i S = (1+i)/2 - G exp(i pi x^2/2).
  elemental function fresnel_aux(x) result(g)
    real(wp), intent(in) :: x
    complex(wp) :: g
    real(wp) :: c, s
    if (x <= series_limit) then
      call fresnel_series(x, c, s)
      g = (cmplx(0.5_wp, 0.5_wp, wp) - cmplx(c, s, wp)) * conjg(fresnel_phase(x))
    else if (x < asymptotic_limit) then
      g = x * erfc_continued_fraction(x)
    else
      ! A&S 7.3.27-7.3.28 leading terms: f = 1/(pi x), g = 1/(pi^2 x^3).
      g = cmplx(1.0_wp / (pi**2 * x**3), 1.0_wp / (pi * x), wp)
    end if
  end function fresnel_aux

  !> exp(i pi x^2 / 2) with the phase reduced modulo 2 pi without losing digits:
  !> x^2 = hi + lo exactly (Dekker's product), and pi x^2/2 mod 2 pi = pi/2 (x^2 mod 4).
  elemental function fresnel_phase(x) result(e)
    real(wp), intent(in) :: x
    complex(wp) :: e
    real(wp), parameter :: splitter = 134217729.0_wp  ! 2^27 + 1
    real(wp) :: hi, lo, xh, xl, tmp, reduced
    hi = x * x
    if (hi < 4.0_wp) then
      reduced = hi
    else if (hi < 1.0e300_wp) then
      tmp = splitter * x
      xh = tmp - (tmp - x)
      xl = x - xh
      lo = ((xh * xh - hi) + 2.0_wp * xh * xl) + xl * xl
      reduced = modulo(hi, 4.0_wp) + lo
    else
      reduced = 0   ! x beyond 1e150: the phase is meaningless in double precision
    end if
    e = cmplx(cos(0.5_wp * pi * reduced), sin(0.5_wp * pi * reduced), wp)
  end function fresnel_phase

  !> A&S 7.3.11/7.3.13: C = sum (-1)^n (pi/2)^(2n) x^(4n+1) / ((2n)! (4n+1)),
  !> S = sum (-1)^n (pi/2)^(2n+1) x^(4n+3) / ((2n+1)! (4n+3)); term_k = x (pi x^2/2)^k / k!.
  pure subroutine fresnel_series(x, c, s)
    real(wp), intent(in) :: x
    real(wp), intent(out) :: c, s
    real(wp) :: term, factor, contribution
    integer :: k
    c = x
    s = 0
    term = x
    factor = 0.5_wp * pi * x * x
    do k = 1, max_terms
      term = term * factor / k
      contribution = term / (2 * k + 1)
      select case (modulo(k, 4))
      case (0); c = c + contribution
      case (1); s = s + contribution
      case (2); c = c - contribution
      case (3); s = s - contribution
      end select
      if (contribution < tolerance * max(abs(c), abs(s))) exit
    end do
  end subroutine fresnel_series

  !> Continued fraction for erfc (A&S 7.1.14) with 2z^2 = -i pi x^2: returns CF such that
  !> erfc(z) = (2 z / sqrt(pi)) exp(-z^2) CF, i.e. G = x CF (modified Lentz, NR 5.2).
  pure function erfc_continued_fraction(x) result(h)
    real(wp), intent(in) :: x
    complex(wp) :: h
    real(wp), parameter :: tiny = 1.0e-300_wp
    complex(wp) :: b, c, d, delta
    real(wp) :: a
    integer :: k, n
    b = cmplx(1.0_wp, -pi * x * x, wp)
    c = cmplx(1.0_wp / tiny, 0.0_wp, wp)
    d = 1.0_wp / b
    h = d
    n = -1
    do k = 2, max_terms
      n = n + 2
      a = -real(n * (n + 1), wp)
      b = b + 4.0_wp
      d = 1.0_wp / (a * d + b)
      c = b + a / c
      delta = c * d
      h = h * delta
      if (abs(real(delta, wp) - 1.0_wp) + abs(aimag(delta)) < tolerance) exit
    end do
  end function erfc_continued_fraction
end module rd_fresnel
