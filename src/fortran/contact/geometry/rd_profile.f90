!> Wheel and rail profiles as point lists in metres, and their pre-processing:
!> validation, resampling and smoothed curvature (thesis 5.2.1, figs. 5.2-5.4).
!>
!> Conventions (docs/conventions.md "Profiles"):
!> - wheel: `y` = lateral coordinate s from the tape circle, positive towards the field
!>   side; `z` = F(s), radius increase over the nominal rolling radius.
!> - rail: `y` = lateral coordinate from the rail's reference, positive towards the field
!>   side; `z` up; before inclination (unless the file is pre-canted, see rd_contact_surfaces).
!> In both cases the material lies on the side of smaller `z`, so one curvature formula
!> serves both: positive = convex (thesis 5.2.1, [28]), negative = concave (wheel throat).
module rd_profile
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: profile_t, PROFILE_WHEEL, PROFILE_RAIL, profile_kind_name
  public :: validate_profile, resample_profile, profile_arc_length

  integer, parameter :: PROFILE_WHEEL = 1
  integer, parameter :: PROFILE_RAIL = 2

  type :: profile_t
    integer :: kind = PROFILE_WHEEL
    character(len=:), allocatable :: source   !< file name or generator, for messages
    real(wp), allocatable :: y(:)             !< lateral coordinate [m], strictly increasing
    real(wp), allocatable :: z(:)             !< F (wheel) or height (rail) [m]
  end type profile_t

contains

  pure function profile_kind_name(kind) result(name)
    integer, intent(in) :: kind
    character(len=:), allocatable :: name
    if (kind == PROFILE_WHEEL) then
      name = 'wheel'
    else
      name = 'rail'
    end if
  end function profile_kind_name

  !> Check a profile in metres: enough points, finite, strictly monotonic lateral
  !> coordinate (a monotonic polyline cannot self-intersect), plausible extent.
  !> A decreasing profile is reversed in place (file point order is not meaningful).
  subroutine validate_profile(profile, error)
    type(profile_t), intent(inout) :: profile
    type(error_t), allocatable, intent(out) :: error
    integer :: n, i
    real(wp) :: width, lo, hi
    character(len=200) :: msg
    character(len=:), allocatable :: what

    what = profile_kind_name(profile%kind) // ' profile ' // profile%source
    if (.not. allocated(profile%y) .or. .not. allocated(profile%z)) then
      call make_error(error, RD_ERR_INPUT, what // ': no points')
      return
    end if
    n = size(profile%y)
    if (n < 5) then
      write (msg, '(a,i0,a)') ': too few points (', n, '); at least 5 are needed'
      call make_error(error, RD_ERR_INPUT, what // trim(msg))
      return
    end if
    if (.not. (all(ieee_is_finite(profile%y)) .and. all(ieee_is_finite(profile%z)))) then
      call make_error(error, RD_ERR_INPUT, what // ': non-finite coordinates')
      return
    end if
    if (profile%y(n) < profile%y(1)) then
      profile%y = profile%y(n:1:-1)
      profile%z = profile%z(n:1:-1)
    end if
    do i = 2, n
      if (.not. (profile%y(i) > profile%y(i - 1))) then
        write (msg, '(a,i0,a,i0,a,es12.5,a)') ': lateral coordinate not strictly monotonic at points ', &
          i - 1, ' and ', i, ' (y = ', profile%y(i), ' m); the profile must be a graph z(y) '// &
          '(no overhangs, no self-intersection)'
        call make_error(error, RD_ERR_INPUT, what // trim(msg))
        return
      end if
    end do
    width = profile%y(n) - profile%y(1)
    if (profile%kind == PROFILE_WHEEL) then
      lo = 0.03_wp; hi = 0.25_wp
    else
      lo = 0.02_wp; hi = 0.25_wp
    end if
    if (width > 1000 * lo .and. width < 1000 * hi) then
      write (msg, '(a,es10.3,a)') ': lateral extent ', width, &
        ' m looks like millimetres; state the unit (units.len.f = 1000 or "# units: mm")'
      call make_error(error, RD_ERR_INPUT, what // trim(msg))
      return
    end if
    if (width < lo .or. width > hi) then
      write (msg, '(a,es10.3,a,f5.2,a,f5.2,a)') ': lateral extent ', width, ' m is implausible (expected ', &
        lo, ' to ', hi, ' m); check the units'
      call make_error(error, RD_ERR_INPUT, what // trim(msg))
      return
    end if
  end subroutine validate_profile

  !> Cumulative arc length along the polyline.
  pure function profile_arc_length(y, z) result(s)
    real(wp), intent(in) :: y(:), z(:)
    real(wp) :: s(size(y))
    integer :: i
    s(1) = 0
    do i = 2, size(y)
      s(i) = s(i - 1) + hypot(y(i) - y(i - 1), z(i) - z(i - 1))
    end do
  end function profile_arc_length

  !> Resample a validated profile at uniform arc-length spacing `ds` and return the
  !> smoothed curvature at the new points (positive convex).
  !>
  !> Curvature filter (thesis 5.2.1, figs. 5.3-5.4: the raw curvature of a rail head jumps
  !> where arcs of different radius meet, and Hertz would jump with it): the raw curvature
  !> is the signed curvature of the circle through three consecutive input points (exact on
  !> a circular arc), and the value at arc length s is its Gaussian-weighted mean
  !>   kappa(s) = sum_i w_i kappa_i / sum_i w_i,  w_i = exp(-(s - s_i)^2 / (2 sigma^2)) ds_i
  !> (ds_i = the arc length the input point represents). A constant curvature passes
  !> unchanged, a jump becomes an erf ramp of width ~ 4 sigma. sigma <= 0: no smoothing
  !> (the raw value of the nearest input point).
  subroutine resample_profile(profile, ds, sigma, y, z, kappa, error)
    type(profile_t), intent(in) :: profile
    real(wp), intent(in) :: ds, sigma
    real(wp), allocatable, intent(out) :: y(:), z(:), kappa(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: s(:), kraw(:), wlen(:)
    real(wp) :: total, sq, w, wsum, ksum, ax, az, bx, bz, cross2, la, lb, lc
    integer :: n, m, i, k, j, j0
    n = size(profile%y)
    if (.not. (ds > 0)) then
      call make_error(error, RD_ERR_INPUT, 'resample_profile: spacing must be > 0')
      return
    end if
    s = profile_arc_length(profile%y, profile%z)
    total = s(n)
    m = max(5, nint(total / ds) + 1)
    allocate (y(m), z(m), kappa(m), kraw(n), wlen(n))
    ! raw Menger curvature, sign: convex (material on the low-z side) positive
    do i = 2, n - 1
      ax = profile%y(i) - profile%y(i - 1); az = profile%z(i) - profile%z(i - 1)
      bx = profile%y(i + 1) - profile%y(i); bz = profile%z(i + 1) - profile%z(i)
      cross2 = ax * bz - az * bx            ! > 0: turning left (concave up)
      la = hypot(ax, az); lb = hypot(bx, bz)
      lc = hypot(ax + bx, az + bz)
      kraw(i) = -2 * cross2 / max(la * lb * lc, tiny(1.0_wp))
    end do
    kraw(1) = kraw(2); kraw(n) = kraw(n - 1)
    wlen(1) = 0.5_wp * (s(2) - s(1)); wlen(n) = 0.5_wp * (s(n) - s(n - 1))
    wlen(2:n - 1) = 0.5_wp * (s(3:n) - s(1:n - 2))
    j = 1
    do k = 1, m
      sq = total * real(k - 1, wp) / real(m - 1, wp)
      do while (j < n - 1 .and. s(j + 1) < sq)
        j = j + 1
      end do
      w = (sq - s(j)) / max(s(j + 1) - s(j), tiny(1.0_wp))
      w = min(max(w, 0.0_wp), 1.0_wp)
      y(k) = profile%y(j) + w * (profile%y(j + 1) - profile%y(j))
      z(k) = profile%z(j) + w * (profile%z(j + 1) - profile%z(j))
      if (sigma > 0) then
        wsum = 0; ksum = 0
        j0 = j
        do while (j0 > 1 .and. s(j0) > sq - 5 * sigma)
          j0 = j0 - 1
        end do
        do i = j0, n
          if (s(i) > sq + 5 * sigma) exit
          w = exp(-0.5_wp * ((s(i) - sq) / sigma)**2) * wlen(i)
          wsum = wsum + w
          ksum = ksum + w * kraw(i)
        end do
        kappa(k) = ksum / max(wsum, tiny(1.0_wp))
      else
        if (w < 0.5_wp) then
          kappa(k) = kraw(j)
        else
          kappa(k) = kraw(j + 1)
        end if
      end if
    end do
    ! the last point lands exactly on the input end
    y(m) = profile%y(n); z(m) = profile%z(n)
    do k = 2, m
      if (.not. (y(k) > y(k - 1))) then
        ! uniform arc length on a near-vertical part can repeat y within rounding: nudge
        y(k) = y(k - 1) + 1.0e-12_wp
      end if
    end do
  end subroutine resample_profile

end module rd_profile
