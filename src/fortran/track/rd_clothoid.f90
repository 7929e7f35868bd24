!> Exact plane curve with linearly varying curvature (clothoid / Euler spiral), arcs and
!> straights as its special cases, in the frame of its start tangent.
!>
!> Heading relative to the start: dpsi(u) = k0 u + c u^2 / 2 (curvature k0 + c u).
!> Offset of the point at arc length u, as a complex number x + i y in the start frame:
!>     I(u) = int_0^u exp(i (k0 v + c v^2 / 2)) dv.
!> This replaces the truncated series of thesis eqs. 4.13-4.14 (and 3.5), which drop the
!> s^9, s^11 terms and (4.13-4.14) carry a spurious 1/pi^2: they are neither exact nor
!> valid for a clothoid that does not start from zero curvature.
!>
!> Fresnel method (c /= 0). Completing the square about the inflection point u* = -k0/c,
!> with c > 0 (c < 0 by conjugation), s = sqrt(pi / c), t = (k0 + c v)/sqrt(pi c):
!>     I(u) = s exp(-i pi t0^2 / 2) [F(t1) - F(t0)],   F = C + i S.
!> Written with the auxiliary function G (rd_fresnel: F = (1+i)/2 - G e^{i pi t^2/2},
!> F(-t) = -F(t)) the large phases pi t^2 / 2 cancel analytically, leaving only the
!> relative heading dpsi(u), which is computed directly:
!>     t0, t1 >= 0:   I = s [G(t0) - G(t1) e^{i dpsi}]
!>     t0, t1 <= 0:   I = s [G(|t1|) e^{i dpsi} - G(|t0|)]
!>     t0 < 0 < t1:   I = s [(1+i) e^{-i pi t0^2/2} - G(t1) e^{i dpsi} - G(|t0|)]
!> (inflection inside the segment; then pi t0^2/2 <= |c| u^2/2 is a small angle).
!> The rounding error is about eps * max(length, radius).
!>
!> Quadrature method: when c is tiny (|c| < pi 1e-8 1/m^2, s > 1e4 m) and the heading
!> change along the segment is moderate, a 20-point Gauss-Legendre rule of the exact
!> integrand on [0, u] is used instead (exact to rounding: the phase varies by less than
!> 8 rad, where the 20-point rule's error is below 1e-20 relative). This is the "Taylor
!> fallback around the arc" of the task, done without truncation.
!> Arc method (c = 0): I = (sin(k u) + i 2 sin^2(k u/2)) / k, or u for k = 0.
module rd_clothoid
  use rd_kinds, only: wp, pi
  use rd_fresnel, only: fresnel_aux
  use rd_gauss_legendre, only: gauss_legendre
  implicit none
  private
  public :: clothoid_t, build_clothoid, clothoid_offset, clothoid_turn
  public :: CLOTHOID_ARC, CLOTHOID_FRESNEL, CLOTHOID_QUADRATURE

  integer, parameter :: CLOTHOID_ARC = 0, CLOTHOID_FRESNEL = 1, CLOTHOID_QUADRATURE = 2
  integer, parameter :: n_gauss = 20

  type :: clothoid_t
    real(wp) :: k0 = 0             !< start curvature [1/m]
    real(wp) :: rate = 0           !< dkappa/du [1/m^2]
    integer :: method = CLOTHOID_ARC
    ! Fresnel method, folded to rate > 0 (mirror flag says whether to conjugate):
    logical :: mirrored = .false.
    real(wp) :: scale = 0          !< sqrt(pi / |c|) [m]
    real(wp) :: k0_folded = 0      !< k0 after folding to c > 0 [1/m]
    real(wp) :: t0 = 0             !< (k0 / sqrt(pi |c|)) after folding [-]
    complex(wp) :: g0 = 0          !< G(|t0|)
    complex(wp) :: straddle = 0    !< (1+i) exp(-i pi t0^2/2), used if t0 < 0
    real(wp) :: xq(n_gauss) = 0, wq(n_gauss) = 0
  end type clothoid_t

contains

  !> Precompute everything that does not depend on u.
  pure subroutine build_clothoid(cl, k0, rate, length)
    type(clothoid_t), intent(out) :: cl
    real(wp), intent(in) :: k0, rate, length
    real(wp) :: phase
    cl%k0 = k0
    cl%rate = rate
    if (rate == 0) then
      cl%method = CLOTHOID_ARC
    else if (abs(rate) < pi * 1.0e-8_wp .and. max(abs(k0), abs(k0 + rate * length)) * length <= 8) then
      cl%method = CLOTHOID_QUADRATURE
      call gauss_legendre(n_gauss, cl%xq, cl%wq)
    else
      cl%method = CLOTHOID_FRESNEL
      cl%mirrored = rate < 0
      cl%k0_folded = merge(-k0, k0, cl%mirrored)
      cl%scale = sqrt(pi / abs(rate))
      cl%t0 = cl%k0_folded * cl%scale / pi
      cl%g0 = fresnel_aux(abs(cl%t0))
      phase = 0.5_wp * pi * cl%t0**2
      cl%straddle = cmplx(1.0_wp, 1.0_wp, wp) * cmplx(cos(phase), -sin(phase), wp)
    end if
  end subroutine build_clothoid

  !> Heading change from the start, k0 u + c u^2 / 2 [rad].
  elemental function clothoid_turn(cl, u) result(dpsi)
    type(clothoid_t), intent(in) :: cl
    real(wp), intent(in) :: u
    real(wp) :: dpsi
    dpsi = u * (cl%k0 + 0.5_wp * cl%rate * u)
  end function clothoid_turn

  !> Offset x + i y of the point at arc length u (0 <= u <= length) in the start frame.
  pure function clothoid_offset(cl, u) result(z)
    type(clothoid_t), intent(in) :: cl
    real(wp), intent(in) :: u
    complex(wp) :: z
    real(wp) :: dpsi, t1, half, phase, v
    complex(wp) :: e1
    integer :: i
    select case (cl%method)
    case (CLOTHOID_ARC)
      if (cl%k0 == 0) then
        z = cmplx(u, 0.0_wp, wp)
      else
        half = 0.5_wp * cl%k0 * u
        z = cmplx(sin(cl%k0 * u), 2 * sin(half)**2, wp) / cl%k0
      end if
    case (CLOTHOID_QUADRATURE)
      z = 0
      half = 0.5_wp * u
      do i = 1, n_gauss
        v = half * (1 + cl%xq(i))
        phase = v * (cl%k0 + 0.5_wp * cl%rate * v)
        z = z + cl%wq(i) * cmplx(cos(phase), sin(phase), wp)
      end do
      z = half * z
    case default
      dpsi = u * (cl%k0_folded + 0.5_wp * abs(cl%rate) * u)
      e1 = cmplx(cos(dpsi), sin(dpsi), wp)
      t1 = (cl%k0_folded + abs(cl%rate) * u) * cl%scale / pi
      if (cl%t0 >= 0) then
        z = cl%scale * (cl%g0 - fresnel_aux(t1) * e1)
      else if (t1 <= 0) then
        z = cl%scale * (fresnel_aux(-t1) * e1 - cl%g0)
      else
        z = cl%scale * (cl%straddle - fresnel_aux(t1) * e1 - cl%g0)
      end if
      if (cl%mirrored) z = conjg(z)
    end select
  end function clothoid_offset
end module rd_clothoid
