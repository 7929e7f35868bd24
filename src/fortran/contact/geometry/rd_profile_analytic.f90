!> Analytic profiles: S1002 wheel (EN 13715 / UIC 510-2 sections A-H) and the 60E1 (UIC60)
!> and 54E1 rail heads (EN 13674-1 arc construction). Definitions and coefficients:
!> validation/reference/profiles/README.md. Output in metres, our conventions (rd_profile).
module rd_profile_analytic
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  implicit none
  private
  public :: s1002_radius_increase_mm, s1002_profile
  public :: rail_head_construction_t, rail_head_construction, rail_head_profile
  public :: RAIL_60E1, RAIL_54E1

  integer, parameter :: RAIL_60E1 = 1
  integer, parameter :: RAIL_54E1 = 2

  !> Section limits of the S1002 [mm], from the flange back (H) to the field side (A).
  real(wp), parameter :: s_lim(9) = [-70.0_wp, -62.764705882_wp, -49.662510381_wp, &
    -39.764473993_wp, -38.426669071_wp, -35.0_wp, -26.0_wp, 32.15796_wp, 60.0_wp]

  !> Arc construction of a rail head (right half, x lateral from the rail centre line,
  !> z up, origin on top), all lengths in mm.
  type :: rail_head_construction_t
    real(wp) :: c300(2), c80(2), c13(2), c3(2)   !< arc centres
    real(wp) :: x_300_80, x_80_13                !< joint abscissae
    real(wp) :: t13(2)                           !< R13 / 1:20 flank tangent point
    real(wp) :: t3(2)                            !< flank / R3 fillet tangent point
  end type rail_head_construction_t

contains

  !> S1002 radius increase F(S) [mm] at S [mm] (S = 0 tape circle, S > 0 field side).
  pure function s1002_radius_increase_mm(s) result(f)
    real(wp), intent(in) :: s
    real(wp) :: f
    if (s >= 32.15796_wp) then                          ! A
      f = 1.364323640_wp - 0.066666667_wp * s
    else if (s >= -26.0_wp) then                        ! B
      f = -3.358537058e-02_wp * s + 1.565681624e-03_wp * s**2 - 2.810427944e-05_wp * s**3 &
          + 5.844240864e-08_wp * s**4 - 1.562379023e-08_wp * s**5 + 5.309217349e-15_wp * s**6 &
          - 5.957839843e-12_wp * s**7 + 2.646656573e-13_wp * s**8
    else if (s >= -35.0_wp) then                        ! C
      f = -4.320221063e+03_wp - 1.038384026e+03_wp * s - 1.065501873e+02_wp * s**2 &
          - 6.051367875_wp * s**3 - 2.054332446e-01_wp * s**4 - 4.169739389e-03_wp * s**5 &
          - 4.687195829e-05_wp * s**6 - 2.252755540e-07_wp * s**7
    else if (s >= -38.426669071_wp) then                ! D
      f = 16.446_wp - sqrt(max(13.0_wp**2 - (s + 26.210665_wp)**2, 0.0_wp))
    else if (s >= -39.764473993_wp) then                ! E
      f = -93.576667419_wp - 2.747477419_wp * s
    else if (s >= -49.662510381_wp) then                ! F
      f = 8.834924130_wp + sqrt(max(20.0_wp**2 - (s + 58.558326413_wp)**2, 0.0_wp))
    else if (s >= -62.764705882_wp) then                ! G
      f = 16.0_wp + sqrt(max(12.0_wp**2 - (s + 55.0_wp)**2, 0.0_wp))
    else                                                ! H
      f = 9.519259302_wp + sqrt(max(20.5_wp**2 - (s + 49.5_wp)**2, 0.0_wp))
    end if
  end function s1002_radius_increase_mm

  !> S1002 from S = -70 to +60 mm, points about `h` [m] apart in arc length (the step in S
  !> shrinks with the slope, so the vertical flange back is resolved), joints included.
  subroutine s1002_profile(profile, h, error)
    type(profile_t), intent(out) :: profile
    real(wp), intent(in) :: h
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: sb(:), fb(:)
    real(wp) :: s, hmm, slope, step, sn
    integer :: n, k
    if (.not. (h > 0 .and. h < 0.005_wp)) then
      call make_error(error, RD_ERR_INPUT, 's1002_profile: point spacing must be in (0, 5 mm)')
      return
    end if
    hmm = h * 1000
    allocate (sb(1000), fb(1000))
    n = 0
    s = s_lim(1)
    k = 2
    do
      n = n + 1
      if (n > size(sb)) then
        sb = [sb, sb]; fb = [fb, fb]
      end if
      sb(n) = s; fb(n) = s1002_radius_increase_mm(s)
      if (s >= s_lim(9)) exit
      slope = (s1002_radius_increase_mm(min(s + 1.0e-6_wp, s_lim(9))) - s1002_radius_increase_mm(s)) / 1.0e-6_wp
      step = max(hmm / sqrt(1 + slope**2), 1.0e-4_wp)
      sn = s + step
      if (sn >= s_lim(k) - 1.0e-9_wp) then   ! land exactly on the next joint
        sn = s_lim(k)
        k = min(k + 1, 9)
      end if
      s = sn
    end do
    profile%kind = PROFILE_WHEEL
    profile%source = 'analytic S1002'
    profile%y = sb(1:n) * 1.0e-3_wp
    profile%z = fb(1:n) * 1.0e-3_wp
  end subroutine s1002_profile

  !> Arc centres of a rail head from the two joint abscissae (R300 -> R80 at x1,
  !> R80 -> R13 at x2), each arc internally tangent to the previous one; R13 ends where its
  !> tangent is 1:20 from the vertical; the R3 fillet sits 3 mm inside the flank.
  pure function rail_head_construction(x1, x2, fillet_depth) result(c)
    real(wp), intent(in) :: x1, x2          !< joints [mm]
    real(wp), intent(in) :: fillet_depth    !< depth of the R3 centre below the R13 tangent point [mm]
    type(rail_head_construction_t) :: c
    real(wp) :: p1(2), p2(2), nrm(2), dir(2), a
    c%x_300_80 = x1; c%x_80_13 = x2
    c%c300 = [0.0_wp, -300.0_wp]
    p1 = c%c300 + 300 * [x1 / 300, sqrt(1 - (x1 / 300)**2)]
    c%c80 = c%c300 + (220.0_wp / 300.0_wp) * (p1 - c%c300)
    a = (x2 - c%c80(1)) / 80
    p2 = c%c80 + 80 * [a, sqrt(1 - a**2)]
    c%c13 = c%c80 + (67.0_wp / 80.0_wp) * (p2 - c%c80)
    nrm = [1.0_wp, 0.05_wp] / sqrt(1.0025_wp)       ! outward normal of a 1:20 flank
    c%t13 = c%c13 + 13 * nrm
    dir = [0.05_wp, -1.0_wp] / sqrt(1.0025_wp)       ! down the flank, widening
    ! R3 centre 3 mm inside the flank at the given depth; tangent point = its projection
    c%c3(2) = c%t13(2) - fillet_depth
    c%c3(1) = c%t13(1) + (c%c3(2) - c%t13(2)) * dir(1) / dir(2) - 3 * sqrt(1.0025_wp)
    c%t3 = c%c3 + 3 * nrm
  end function rail_head_construction

  !> Rail head profile (uncanted, symmetric, field side positive) down to the widest point
  !> of the R3 fillet, points about `h` [m] apart. 60E1: joints 10.228 / 26.0265 mm;
  !> 54E1: 10.012 / 24.8635 mm (README); the 54E1 fillet depth is taken from the 60E1.
  subroutine rail_head_profile(which, profile, h, error)
    integer, intent(in) :: which
    type(profile_t), intent(out) :: profile
    real(wp), intent(in) :: h
    type(error_t), allocatable, intent(out) :: error
    type(rail_head_construction_t) :: c
    real(wp), allocatable :: xh(:), zh(:)
    real(wp) :: hmm, fillet_depth
    integer :: n
    if (.not. (h > 0 .and. h < 0.005_wp)) then
      call make_error(error, RD_ERR_INPUT, 'rail_head_profile: point spacing must be in (0, 5 mm)')
      return
    end if
    hmm = h * 1000
    fillet_depth = 35.4252_wp - 14.29996_wp           ! 60E1 (README: centre (34.0523, -35.4252))
    select case (which)
    case (RAIL_60E1)
      c = rail_head_construction(10.228_wp, 26.0265_wp, fillet_depth)
      profile%source = 'analytic 60E1 head'
    case (RAIL_54E1)
      c = rail_head_construction(10.012_wp, 24.8635_wp, fillet_depth)
      profile%source = 'analytic 54E1 head'
    case default
      call make_error(error, RD_ERR_INPUT, 'rail_head_profile: unknown rail (expected 60E1 or 54E1)')
      return
    end select
    allocate (xh(0), zh(0))
    call add_arc(c%c300, 300.0_wp, 0.0_wp, asin(c%x_300_80 / 300))
    call add_arc(c%c80, 80.0_wp, asin((c%x_300_80 - c%c80(1)) / 80), asin((c%x_80_13 - c%c80(1)) / 80))
    call add_arc(c%c13, 13.0_wp, asin((c%x_80_13 - c%c13(1)) / 13), atan2(1.0_wp, 0.05_wp))
    call add_line(c%t13, c%t3)
    call add_arc(c%c3, 3.0_wp, atan2(1.0_wp, 0.05_wp), 0.5_wp * acos(-1.0_wp))
    n = size(xh)
    profile%kind = PROFILE_RAIL
    profile%y = [-xh(n:2:-1), xh] * 1.0e-3_wp
    profile%z = [zh(n:2:-1), zh] * 1.0e-3_wp
  contains
    !> points c + R (sin t, cos t), t from t0 to t1 (angle from the upward vertical)
    subroutine add_arc(cen, r, t0, t1)
      real(wp), intent(in) :: cen(2), r, t0, t1
      integer :: m, i, i0
      real(wp) :: t
      m = max(2, ceiling(r * abs(t1 - t0) / hmm))
      i0 = merge(1, 0, size(xh) > 0)       ! skip the shared joint point
      do i = i0, m
        t = t0 + (t1 - t0) * real(i, wp) / m
        xh = [xh, cen(1) + r * sin(t)]
        zh = [zh, cen(2) + r * cos(t)]
      end do
    end subroutine add_arc
    subroutine add_line(a, b)
      real(wp), intent(in) :: a(2), b(2)
      integer :: m, i
      m = max(1, ceiling(hypot(b(1) - a(1), b(2) - a(2)) / hmm))
      do i = 1, m
        xh = [xh, a(1) + (b(1) - a(1)) * real(i, wp) / m]
        zh = [zh, a(2) + (b(2) - a(2)) * real(i, wp) / m]
      end do
    end subroutine add_line
  end subroutine rail_head_profile

end module rd_profile_analytic
