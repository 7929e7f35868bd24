!> Wheel and rail surfaces ready for contact search: profiles resampled, curvature
!> smoothed, and placed in the wheelset / track frames from the track standards
!> (gauge measured 14 mm below the running surface, rail inclination, back-to-back
!> distance, flange back position, nominal radius).
!>
!> Surfaces are built for the LEFT side (wheel at +y of the wheelset frame, rail at +Y of
!> the track frame, lateral coordinates increasing towards the field side); the right side
!> is the mirror image of a surface built the same way, from the left profiles or from the
!> right ones when a side has its own (rd_contact_geometry, docs/conventions.md "Profiles").
module rd_contact_surfaces
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL, resample_profile
  use rd_natural_splines, only: natural_spline, natural_quintic_spline
  implicit none
  private
  public :: track_placement_t, surface_options_t, wheel_surface_t, rail_surface_t
  public :: build_wheel_surface, build_rail_surface, wheel_radius_at, locate

  !> Placement of wheels and rails (defaults: UIC 1435 mm track, S1002 wheels, 1:40).
  type :: track_placement_t
    real(wp) :: gauge = 1.435_wp           !< between the gauge points [m]
    real(wp) :: gauge_depth = 0.014_wp     !< gauge point below the top of the rail [m]
    real(wp) :: inclination = 0.025_wp     !< tan of the rail inclination (1:40; 1:20 = 0.05)
    real(wp) :: rail_precant = 0.0_wp      !< tan of an inclination already in the rail data
    real(wp) :: back_to_back = 1.360_wp    !< between the flange backs [m]
    real(wp) :: flange_back = -0.070_wp    !< wheel profile coordinate s of the flange back [m]
    real(wp) :: nominal_radius = 0.46_wp   !< rolling radius at the tape circle [m]
  end type track_placement_t

  !> Pre-processing parameters (see docs/theory_contact_geometry.md).
  type :: surface_options_t
    real(wp) :: wheel_spacing = 2.0e-4_wp     !< arc-length spacing of wheel points [m]
    real(wp) :: rail_spacing = 2.0e-4_wp      !< arc-length spacing of rail lines (strips) [m]
    real(wp) :: curvature_sigma = 1.0e-3_wp   !< Gaussian curvature filter width [m]
  end type surface_options_t

  !> Left wheel in the wheelset frame: a surface of revolution about the axle (y axis);
  !> segment j (points j, j+1) is a cone (thesis 4.7.1.4).
  type :: wheel_surface_t
    integer :: n = 0
    real(wp), allocatable :: s(:)       !< wheel profile coordinate [m]
    real(wp), allocatable :: y(:)       !< lateral position in the wheelset frame [m], increasing
    real(wp), allocatable :: r(:)       !< radius [m]
    real(wp), allocatable :: slope(:)   !< dr/dy at the points (central differences)
    !> dr/dy of cone j (points j, j+1), n-1 values: the k of rd_line_cone, computed once
    !> here instead of once per rail line and cone in the strip search (hot path)
    real(wp), allocatable :: cone_slope(:)
    real(wp), allocatable :: kappa(:)   !< smoothed profile curvature [1/m], + convex
    !> principal curvature in the rolling direction at the points, cos(gamma)/r =
    !> 1 / (r sqrt(1 + slope^2)) (thesis eq. 4.75) [1/m]
    real(wp), allocatable :: k_roll(:)
    !> second and fourth derivatives d2r/dy2, d4r/dy4 at the points of the natural quintic
    !> spline through (y, r) (rd_natural_splines): the smooth (C4) wheel of the distributed
    !> strip force (rd_strip_potential smooth_line_depth, smooth_wheel_radius)
    real(wp), allocatable :: r_spline(:), r_fourth(:)
    !> second derivatives along y of the natural cubic splines through k_roll and kappa: the
    !> curvatures C2 along the profile (rd_strip_potential wheel_point_curvatures), so that the
    !> strip stiffness's gradient term, which holds their derivatives, is C1
    real(wp), allocatable :: k_roll_spline(:), kappa_spline(:)
    real(wp) :: r_max = 0
    real(wp) :: nominal_radius = 0
    real(wp) :: y_tape = 0              !< lateral position of the tape circle [m]
  end type wheel_surface_t

  !> Left rail in the track frame: each point is a longitudinal line (thesis 4.7.1.4).
  type :: rail_surface_t
    integer :: n = 0
    real(wp), allocatable :: u(:)       !< rail profile coordinate (input frame) [m]
    real(wp), allocatable :: y(:), z(:) !< track frame [m], y increasing
    real(wp), allocatable :: ny(:), nz(:) !< unit normal out of the rail (track frame)
    real(wp), allocatable :: kappa(:)   !< smoothed profile curvature [1/m], + convex
    !> rail arc length each strip stands for: half its distances to its neighbours [m]
    real(wp), allocatable :: width(:)
    !> distance from strip i to strip i + 1 (n - 1 values) [m]
    real(wp), allocatable :: interval(:)
    real(wp) :: y_gauge_point = 0       !< Y of the gauge point (= gauge / 2)
    real(wp) :: u_gauge_point = 0       !< its rail profile coordinate
    integer :: coarse_stride = 1        !< strips per coarse step of the search (1.6 mm apart)
  end type rail_surface_t

contains

  subroutine build_wheel_surface(profile, placement, options, wheel, error)
    type(profile_t), intent(in) :: profile
    type(track_placement_t), intent(in) :: placement
    type(surface_options_t), intent(in) :: options
    type(wheel_surface_t), intent(out) :: wheel
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: ys(:), zs(:), ks(:)
    integer :: n, i
    if (profile%kind /= PROFILE_WHEEL) then
      call make_error(error, RD_ERR_INPUT, 'build_wheel_surface: a wheel profile is expected')
      return
    end if
    if (.not. (placement%nominal_radius > 0.1_wp .and. placement%nominal_radius < 2.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_wheel_surface: nominal radius must be in (0.1, 2) m')
      return
    end if
    if (.not. (placement%back_to_back > 0.5_wp .and. placement%back_to_back < 2.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_wheel_surface: back-to-back distance must be in (0.5, 2) m')
      return
    end if
    call resample_profile(profile, options%wheel_spacing, options%curvature_sigma, ys, zs, ks, error)
    if (allocated(error)) then
      call error_context(error, 'build_wheel_surface')
      return
    end if
    n = size(ys)
    wheel%n = n
    wheel%s = ys
    wheel%y_tape = 0.5_wp * placement%back_to_back - placement%flange_back
    wheel%y = wheel%y_tape + ys
    wheel%r = placement%nominal_radius + zs
    wheel%kappa = ks
    allocate (wheel%slope(n))
    do i = 1, n
      wheel%slope(i) = (wheel%r(min(i + 1, n)) - wheel%r(max(i - 1, 1))) / &
                       (wheel%y(min(i + 1, n)) - wheel%y(max(i - 1, 1)))
    end do
    wheel%k_roll = 1 / (wheel%r * sqrt(1 + wheel%slope**2))
    call natural_quintic_spline(wheel%y, wheel%r, wheel%r_spline, wheel%r_fourth, error)
    if (allocated(error)) then
      call error_context(error, 'build_wheel_surface')
      return
    end if
    call natural_spline(wheel%y, wheel%k_roll, wheel%k_roll_spline)
    call natural_spline(wheel%y, wheel%kappa, wheel%kappa_spline)
    allocate (wheel%cone_slope(n - 1))
    do i = 1, n - 1
      wheel%cone_slope(i) = (wheel%r(i + 1) - wheel%r(i)) / (wheel%y(i + 1) - wheel%y(i))
    end do
    wheel%r_max = maxval(wheel%r)
    wheel%nominal_radius = placement%nominal_radius
  end subroutine build_wheel_surface

  subroutine build_rail_surface(profile, placement, options, rail, error)
    type(profile_t), intent(in) :: profile
    type(track_placement_t), intent(in) :: placement
    type(surface_options_t), intent(in) :: options
    type(rail_surface_t), intent(out) :: rail
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: us(:), zs(:), ks(:), yr(:), zr(:)
    real(wp) :: beta, cb, sb, ztop, level, ygp, ugp, w, t1, t2, tn
    integer :: n, i, itop, ilo, ihi, m
    if (profile%kind /= PROFILE_RAIL) then
      call make_error(error, RD_ERR_INPUT, 'build_rail_surface: a rail profile is expected')
      return
    end if
    if (.not. (placement%gauge > 0.5_wp .and. placement%gauge < 2.5_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_rail_surface: gauge must be in (0.5, 2.5) m')
      return
    end if
    if (.not. (abs(placement%inclination) <= 0.1_wp .and. abs(placement%rail_precant) <= 0.1_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_rail_surface: rail inclination must be a slope in [-0.1, 0.1] (1:40 = 0.025)')
      return
    end if
    call resample_profile(profile, options%rail_spacing, options%curvature_sigma, us, zs, ks, error)
    if (allocated(error)) then
      call error_context(error, 'build_rail_surface')
      return
    end if
    n = size(us)
    ! Inclination turns the head towards the track centre: for the left rail (field side
    ! +Y) that is a positive rotation in the (Y, Z) plane (the top normal tilts to -Y).
    beta = atan(placement%inclination) - atan(placement%rail_precant)
    cb = cos(beta); sb = sin(beta)
    allocate (yr(n), zr(n))
    yr = cb * us - sb * zs
    zr = sb * us + cb * zs
    ! keep the part visible from above: the run around the top where Y increases
    itop = maxloc(zr, dim=1)
    ztop = zr(itop)
    ilo = itop
    do while (ilo > 1)
      if (.not. (yr(ilo - 1) < yr(ilo))) exit
      ilo = ilo - 1
    end do
    ihi = itop
    do while (ihi < n)
      if (.not. (yr(ihi + 1) > yr(ihi))) exit
      ihi = ihi + 1
    end do
    ! gauge point: gauge_depth below the top, on the gauge side (thesis 5.3.1; EN 13848-1)
    level = ztop - placement%gauge_depth
    ygp = huge(1.0_wp)
    do i = itop, ilo + 1, -1
      if (zr(i - 1) <= level .and. zr(i) > level) then
        w = (level - zr(i - 1)) / (zr(i) - zr(i - 1))
        ygp = yr(i - 1) + w * (yr(i) - yr(i - 1))
        ugp = us(i - 1) + w * (us(i) - us(i - 1))
        exit
      end if
    end do
    if (ygp == huge(1.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_rail_surface: rail profile ' // profile%source // &
        ' does not reach the gauge depth below its top on the gauge side (lateral coordinate must grow towards the field side)')
      return
    end if
    m = ihi - ilo + 1
    rail%n = m
    rail%u = us(ilo:ihi)
    rail%y = yr(ilo:ihi) + (0.5_wp * placement%gauge - ygp)
    rail%z = zr(ilo:ihi) - ztop
    rail%kappa = ks(ilo:ihi)
    rail%y_gauge_point = 0.5_wp * placement%gauge
    rail%coarse_stride = max(1, min(8, int(1.6e-3_wp / options%rail_spacing + 1.0e-9_wp)))
    rail%u_gauge_point = ugp
    allocate (rail%ny(m), rail%nz(m), rail%width(m), rail%interval(max(m - 1, 0)))
    rail%width = 0
    do i = 1, m - 1
      rail%interval(i) = hypot(rail%y(i + 1) - rail%y(i), rail%z(i + 1) - rail%z(i))
      tn = 0.5_wp * rail%interval(i)
      rail%width(i) = rail%width(i) + tn
      rail%width(i + 1) = rail%width(i + 1) + tn
    end do
    do i = 1, m
      t1 = rail%y(min(i + 1, m)) - rail%y(max(i - 1, 1))
      t2 = rail%z(min(i + 1, m)) - rail%z(max(i - 1, 1))
      tn = hypot(t1, t2)
      rail%ny(i) = -t2 / tn
      rail%nz(i) = t1 / tn
    end do
  end subroutine build_rail_surface

  !> Index j with y(j) <= x < y(j+1), clamped to [1, n-1] (bisection).
  pure integer function locate(y, x) result(j)
    real(wp), contiguous, intent(in) :: y(:)   ! (contiguous: unit stride known, hot path)
    real(wp), intent(in) :: x
    integer :: lo, hi, mid
    lo = 1; hi = size(y)
    if (x <= y(1)) then
      j = 1; return
    end if
    if (x >= y(hi)) then
      j = hi - 1; return
    end if
    do while (hi - lo > 1)
      mid = (lo + hi) / 2
      if (y(mid) <= x) then
        lo = mid
      else
        hi = mid
      end if
    end do
    j = lo
  end function locate

  !> Radius of the (piecewise-conical) wheel at lateral position y (clamped at the ends).
  pure real(wp) function wheel_radius_at(wheel, y) result(r)
    type(wheel_surface_t), intent(in) :: wheel
    real(wp), intent(in) :: y
    integer :: j
    real(wp) :: w
    j = locate(wheel%y, y)
    w = (y - wheel%y(j)) / (wheel%y(j + 1) - wheel%y(j))
    w = min(max(w, 0.0_wp), 1.0_wp)
    r = wheel%r(j) + w * (wheel%r(j + 1) - wheel%r(j))
  end function wheel_radius_at

end module rd_contact_surfaces
