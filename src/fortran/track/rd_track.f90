!> Segment track: straights, clothoids and circular curves joined with continuous
!> position, heading and curvature (thesis 4.4.1-4.4.4), with cant ramps and a vertical
!> profile.
!>
!> sigma is the arc length of the HORIZONTAL projection of the centreline
!> (docs/conventions.md), so on a gradient g the centreline advances |dr/dsigma| =
!> sqrt(1 + g^2) metres per unit sigma; segment lengths are horizontal lengths.
!>
!> Per segment (local coordinate u = sigma - sigma_start, 0 <= u <= L):
!> - curvature kappa = k0 + c u, c = (k1 - k0)/L (zero for straights and curves), heading
!>   psi = psi0 + k0 u + c u^2/2, plane position from rd_clothoid (exact: Fresnel integrals,
!>   not the truncated series of thesis eqs. 4.13-4.14; the circle is written
!>   x = sin(k u)/k, y = 2 sin^2(k u/2)/k rather than thesis eqs. 4.23-4.24, which
!>   misplace R: it must multiply the sine and cosine terms, not only the start terms);
!> - superelevation h ramps from h0 to h1 on clothoids only: 'linear' (thesis eq. 4.16) or
!>   'cosine' (half-cosine ramp h0 + (h1-h0)(1 - cos(pi u/L))/2, zero cant rate at both
!>   ends); cant angle sin(phi) = h / cant_base (thesis eq. 3.1); the cant pivots on the
!>   centreline (the thesis' eq. 4.16 lifts the centreline z by h instead; here z is the
!>   vertical profile only);
!> - gradient g = dz/dsigma ramps linearly from g0 to g1 (parabolic vertical curve),
!>   z = z0 + g0 u + (g1 - g0) u^2 / (2 L).
!> Beyond both ends the track continues straight with the end heading, cant and gradient
!> (a track without segments is the straight through the start position).
module rd_track
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, pi
  use rd_text, only: int_text, real_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_track_point, only: track_point_t, track_geometry_t
  use rd_track_frame, only: set_track_frame
  use rd_clothoid, only: clothoid_t, build_clothoid, clothoid_offset, clothoid_turn
  implicit none
  private
  public :: track_t, track_settings_t, segment_spec_t, build_track, GRADIENT_UNCHANGED

  !> Default of segment_spec_t%gradient_end: keep the previous end gradient.
  real(wp), parameter :: GRADIENT_UNCHANGED = huge(1.0_wp)

  integer, parameter :: KIND_STRAIGHT = 1, KIND_CLOTHOID = 2, KIND_CURVE = 3
  integer, parameter :: RAMP_LINEAR = 1, RAMP_COSINE = 2

  type :: track_settings_t
    real(wp) :: gauge = 1.435_wp             !< track gauge [m]
    real(wp) :: cant_base = 1.5_wp           !< distance between rail contact points [m]
    real(wp) :: start_position(3) = 0        !< centreline at sigma = 0, fixed frame [m]
    real(wp) :: start_heading = 0            !< psi_t at sigma = 0 [rad]
    real(wp) :: start_superelevation = 0     !< left rail over right rail at sigma = 0 [m]
    real(wp) :: start_curvature = 0          !< kappa at sigma = 0 [1/m]
    real(wp) :: start_gradient = 0           !< dz/dsigma at sigma = 0 [-]
    character(len=256) :: origin = ''        !< e.g. "scene.nml:3: &track", for messages
  end type track_settings_t

  type :: segment_spec_t
    character(len=16) :: kind = ''           !< 'straight' | 'clothoid' | 'curve'
    real(wp) :: length = 0                   !< horizontal length [m] > 0
    real(wp) :: curvature_end = 0            !< signed, left positive [1/m]
    real(wp) :: superelevation_end = 0       !< left rail over right rail at the end [m]
    character(len=16) :: cant_ramp = 'linear' !< 'linear' | 'cosine' (clothoids)
    real(wp) :: gradient_end = GRADIENT_UNCHANGED !< dz/dsigma at the end [-]
    character(len=256) :: origin = ''        !< e.g. "scene.nml:12: &segment"
  end type segment_spec_t

  !> One segment, parameters fixed at build time.
  type :: segment_t
    integer :: kind = KIND_STRAIGHT
    real(wp) :: length = 0
    real(wp) :: r0(3) = 0, psi0 = 0, cos_psi0 = 1, sin_psi0 = 0
    type(clothoid_t) :: plan
    integer :: ramp = RAMP_LINEAR
    real(wp) :: h0 = 0, h1 = 0, g0 = 0, g1 = 0
  end type segment_t

  type, extends(track_geometry_t) :: track_t
    private   ! parameters fixed by the build routine; use evaluate() and length()
    type(segment_t), allocatable :: segments(:)
    real(wp), allocatable :: starts(:)       !< segment start sigmas, starts(n+1) = length
    real(wp) :: cant_base = 1.5_wp, gauge = 1.435_wp
    real(wp) :: start_r(3) = 0, start_psi = 0, start_h = 0, start_g = 0
    real(wp) :: end_r(3) = 0, end_psi = 0, end_h = 0, end_g = 0
  contains
    procedure :: evaluate => track_evaluate
    procedure :: length => track_length
  end type track_t

contains

  !> Build the track from its settings and segment list (validated; RD_ERR_INPUT with the
  !> segment's origin on bad input).
  subroutine build_track(track, settings, specs, error)
    type(track_t), intent(out) :: track
    type(track_settings_t), intent(in) :: settings
    type(segment_spec_t), intent(in) :: specs(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, n
    real(wp) :: k_prev, h_prev, g_prev, r_prev(3), psi_prev, k1, h1, g1, s
    character(len=:), allocatable :: where
    type(track_point_t) :: p

    where = trim(settings%origin)
    if (len(where) == 0) where = 'track settings'
    if (.not. all(ieee_is_finite([settings%gauge, settings%cant_base, settings%start_position, &
                                  settings%start_heading, settings%start_superelevation, &
                                  settings%start_curvature, settings%start_gradient]))) then
      call make_error(error, RD_ERR_INPUT, where // ': gauge, cant_base and start values must be finite numbers')
      return
    end if
    if (settings%gauge <= 0 .or. settings%cant_base <= 0) then
      call make_error(error, RD_ERR_INPUT, where // ': gauge and cant_base must be > 0 m, got ' // &
                      trim(real_text(settings%gauge)) // ' and ' // trim(real_text(settings%cant_base)))
      return
    end if
    call check_cant(settings%start_superelevation, settings%gauge, settings%cant_base, where, &
                    'start_superelevation', error)
    if (allocated(error)) return
    ! no segments: a track of length 0, i.e. a straight through the start (run-off both ways)
    n = size(specs)

    track%gauge = settings%gauge
    track%cant_base = settings%cant_base
    allocate (track%segments(n), track%starts(n + 1))
    k_prev = settings%start_curvature
    h_prev = settings%start_superelevation
    g_prev = settings%start_gradient
    r_prev = settings%start_position
    psi_prev = settings%start_heading
    s = 0
    do i = 1, n
      where = trim(specs(i)%origin)
      if (len(where) == 0) where = 'segment ' // trim(int_text(i))
      where = where // ' (' // trim(specs(i)%kind) // ')'
      call validate_spec(specs(i), settings, k_prev, h_prev, g_prev, where, k1, h1, g1, error)
      if (allocated(error)) return
      associate (seg => track%segments(i))
        select case (trim(specs(i)%kind))
        case ('straight'); seg%kind = KIND_STRAIGHT
        case ('clothoid'); seg%kind = KIND_CLOTHOID
        case default; seg%kind = KIND_CURVE
        end select
        seg%length = specs(i)%length
        seg%r0 = r_prev
        seg%psi0 = psi_prev
        seg%cos_psi0 = cos(psi_prev)
        seg%sin_psi0 = sin(psi_prev)
        call build_clothoid(seg%plan, k_prev, (k1 - k_prev) / seg%length, seg%length)
        seg%ramp = merge(RAMP_COSINE, RAMP_LINEAR, trim(specs(i)%cant_ramp) == 'cosine')
        seg%h0 = h_prev
        seg%h1 = h1
        seg%g0 = g_prev
        seg%g1 = g1
        track%starts(i) = s
        ! the end state is evaluated with the same formulas, so joints are continuous
        call segment_point(seg, seg%length, track%cant_base, p)
        r_prev = p%r
        psi_prev = p%heading
        s = s + seg%length
      end associate
      k_prev = k1
      h_prev = h1
      g_prev = g1
    end do
    track%starts(n + 1) = s
    track%start_r = settings%start_position
    track%start_psi = settings%start_heading
    track%start_h = settings%start_superelevation
    track%start_g = settings%start_gradient
    track%end_r = r_prev
    track%end_psi = psi_prev
    track%end_h = h_prev
    track%end_g = g_prev
  end subroutine build_track

  !> Check one segment against its predecessor's end values; return its end values.
  subroutine validate_spec(spec, settings, k_prev, h_prev, g_prev, where, k1, h1, g1, error)
    type(segment_spec_t), intent(in) :: spec
    type(track_settings_t), intent(in) :: settings
    real(wp), intent(in) :: k_prev, h_prev, g_prev
    character(len=*), intent(in) :: where
    real(wp), intent(out) :: k1, h1, g1
    type(error_t), allocatable, intent(out) :: error

    k1 = 0; h1 = 0; g1 = 0
    if (.not. ieee_is_finite(spec%length) .or. .not. ieee_is_finite(spec%curvature_end) .or. &
        .not. ieee_is_finite(spec%superelevation_end) .or. .not. ieee_is_finite(spec%gradient_end)) then
      call make_error(error, RD_ERR_INPUT, where // ': length, curvature_end, superelevation_end and ' // &
                      'gradient_end must be finite numbers')
      return
    end if
    if (spec%length <= 0) then
      call make_error(error, RD_ERR_INPUT, where // ': length must be > 0 m, got ' // trim(real_text(spec%length)))
      return
    end if
    select case (trim(spec%cant_ramp))
    case ('linear', 'cosine')
    case default
      call make_error(error, RD_ERR_INPUT, where // ": cant_ramp must be 'linear' or 'cosine', got '" // &
                      trim(spec%cant_ramp) // "'")
      return
    end select

    select case (trim(spec%kind))
    case ('straight')
      if (spec%curvature_end /= 0) then
        call make_error(error, RD_ERR_INPUT, where // ': a straight has zero curvature, got curvature_end = ' // &
                        trim(real_text(spec%curvature_end)) // ' 1/m (use a curve or a clothoid)')
        return
      end if
      k1 = 0
      if (k_prev /= 0) then
        call curvature_jump_error(k_prev, k1, 'straight', where, error)
        return
      end if
    case ('curve')
      k1 = spec%curvature_end
      if (abs(k1 - k_prev) > 1.0e-12_wp * max(abs(k1), abs(k_prev))) then
        call curvature_jump_error(k_prev, k1, 'curve', where, error)
        return
      end if
      k1 = k_prev   ! bit-identical continuation
    case ('clothoid')
      k1 = spec%curvature_end
    case default
      call make_error(error, RD_ERR_INPUT, where // ": kind must be 'straight', 'clothoid' or 'curve', got '" // &
                      trim(spec%kind) // "'")
      return
    end select

    h1 = spec%superelevation_end
    if (trim(spec%kind) /= 'clothoid' .and. abs(h1 - h_prev) > 1.0e-12_wp) then
      call make_error(error, RD_ERR_INPUT, where // ': superelevation changes from ' // trim(real_text(h_prev)) // &
                      ' m to ' // trim(real_text(h1)) // ' m on a ' // trim(spec%kind) // &
                      ': only a clothoid can ramp the cant (set superelevation_end = ' // trim(real_text(h_prev)) // ')')
      return
    end if
    if (trim(spec%kind) /= 'clothoid') h1 = h_prev
    call check_cant(h1, settings%gauge, settings%cant_base, where, 'superelevation_end', error)
    if (allocated(error)) return

    if (spec%gradient_end == GRADIENT_UNCHANGED) then
      g1 = g_prev
    else
      g1 = spec%gradient_end
    end if
  end subroutine validate_spec

  subroutine check_cant(h, gauge, cant_base, where, name, error)
    real(wp), intent(in) :: h, gauge, cant_base
    character(len=*), intent(in) :: where, name
    type(error_t), allocatable, intent(out) :: error
    if (abs(h) >= cant_base .or. abs(h) > gauge) then
      call make_error(error, RD_ERR_INPUT, where // ': ' // name // ' = ' // trim(real_text(h)) // &
                      ' m: cant larger than the gauge (need |superelevation| < cant_base = ' // &
                      trim(real_text(cant_base)) // ' m and <= gauge = ' // trim(real_text(gauge)) // ' m)')
    end if
  end subroutine check_cant

  subroutine curvature_jump_error(k0, k1, kind, where, error)
    real(wp), intent(in) :: k0, k1
    character(len=*), intent(in) :: kind, where
    type(error_t), allocatable, intent(out) :: error
    call make_error(error, RD_ERR_INPUT, where // ': curvature jumps from ' // trim(curvature_text(k0)) // &
                    ' to ' // trim(curvature_text(k1)) // ' at the start of this ' // kind // &
                    ': a transition (clothoid) of non-zero length is needed')
  end subroutine curvature_jump_error

  !> "1/R1" text of a signed curvature: "1/150 m (left)", "0 (straight)".
  pure function curvature_text(k) result(text)
    real(wp), intent(in) :: k
    character(len=48) :: text
    if (k == 0) then
      text = '0 (straight)'
    else
      text = '1/' // trim(real_text(1 / abs(k))) // ' m (' // trim(merge('left ', 'right', k > 0)) // ')'
    end if
  end function curvature_text



  !> Track frame at local coordinate u of one segment.
  pure subroutine segment_point(seg, u, cant_base, p)
    type(segment_t), intent(in) :: seg
    real(wp), intent(in) :: u, cant_base
    type(track_point_t), intent(inout) :: p
    complex(wp) :: offset
    real(wp) :: psi, kappa, rate, g, dg, h, dh, d2h, dh_total, arg

    offset = clothoid_offset(seg%plan, u)
    psi = seg%psi0 + clothoid_turn(seg%plan, u)
    rate = seg%plan%rate
    kappa = seg%plan%k0 + rate * u
    dg = (seg%g1 - seg%g0) / seg%length
    g = seg%g0 + dg * u
    dh_total = seg%h1 - seg%h0
    if (seg%ramp == RAMP_COSINE) then
      arg = pi * u / seg%length
      h = seg%h0 + 0.5_wp * dh_total * (1 - cos(arg))
      dh = 0.5_wp * dh_total * pi / seg%length * sin(arg)
      d2h = 0.5_wp * dh_total * (pi / seg%length)**2 * cos(arg)
    else
      h = seg%h0 + dh_total * (u / seg%length)
      dh = dh_total / seg%length
      d2h = 0
    end if
    p%r(1) = seg%r0(1) + seg%cos_psi0 * real(offset, wp) - seg%sin_psi0 * aimag(offset)
    p%r(2) = seg%r0(2) + seg%sin_psi0 * real(offset, wp) + seg%cos_psi0 * aimag(offset)
    p%r(3) = seg%r0(3) + u * (seg%g0 + 0.5_wp * dg * u)
    call set_track_frame(p, psi, kappa, rate, g, dg, 0.0_wp, h, dh, d2h, cant_base)
  end subroutine segment_point

  !> Track frame at arc length sigma (binary search on the segment starts, no allocation).
  pure function track_evaluate(self, sigma) result(point)
    class(track_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: point
    integer :: lo, hi, mid, n
    real(wp) :: u
    n = size(self%segments)
    point%sigma = sigma
    if (sigma < 0) then
      point%r = self%start_r + sigma * [cos(self%start_psi), sin(self%start_psi), self%start_g]
      call set_track_frame(point, self%start_psi, 0.0_wp, 0.0_wp, self%start_g, 0.0_wp, 0.0_wp, &
                           self%start_h, 0.0_wp, 0.0_wp, self%cant_base)
      return
    end if
    if (sigma > self%starts(n + 1) .or. n == 0) then
      u = sigma - self%starts(n + 1)
      point%r = self%end_r + u * [cos(self%end_psi), sin(self%end_psi), self%end_g]
      call set_track_frame(point, self%end_psi, 0.0_wp, 0.0_wp, self%end_g, 0.0_wp, 0.0_wp, &
                           self%end_h, 0.0_wp, 0.0_wp, self%cant_base)
      return
    end if
    lo = 1
    hi = n
    do while (lo < hi)
      mid = (lo + hi + 1) / 2
      if (self%starts(mid) <= sigma) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    call segment_point(self%segments(lo), sigma - self%starts(lo), self%cant_base, point)
  end function track_evaluate

  pure function track_length(self) result(total)
    class(track_t), intent(in) :: self
    real(wp) :: total
    total = self%starts(size(self%starts))
  end function track_length
end module rd_track
