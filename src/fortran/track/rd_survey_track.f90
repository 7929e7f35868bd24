!> Surveyed-points track (thesis 4.4, second approach: "cubic splines between control
!> points", with the cant given at each point).
!>
!> Construction:
!> 1. x(t), y(t): not-a-knot cubic splines against the accumulated horizontal chord
!>    length t (rd_cubic_spline);
!> 2. horizontal arc length at the knots, sigma_i = sum int |(x', y')| dt, by a 10-point
!>    Gauss-Legendre rule per interval (the integrand is the square root of a quartic close
!>    to 1, so the rule is exact to rounding for any sensible point spacing);
!> 3. z(sigma), h(sigma): not-a-knot cubic splines against those sigma_i, so the gradient
!>    g = dz/dsigma and the cant follow the same parameter as the dynamics.
!> Evaluation at sigma: bisection for the interval, Newton for t with
!>     sigma_i + int_{t_i}^{t} |v| dt = sigma   (derivative |v|, 2-3 iterations),
!> then heading psi = atan2(y', x') (unwrapped from the knot headings), curvature
!> kappa = (x'y'' - y'x'')/|v|^3 and dkappa/dsigma from the spline derivatives, and the
!> frame from rd_track_frame. sigma is the horizontal arc length, so |dr/dsigma| =
!> sqrt(1 + g^2). Beyond both ends the track runs on straight (end heading, cant, grade).
module rd_survey_track
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, pi
  use rd_text, only: int_text, real_text
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_IO
  use rd_track_point, only: track_point_t, track_geometry_t
  use rd_track_frame, only: set_track_frame
  use rd_cubic_spline, only: spline_not_a_knot, locate_interval
  use rd_gauss_legendre, only: gauss_legendre
  use rd_numeric_line, only: numeric_line_t, parse_numeric_line
  use rd_line_reader, only: read_line
  implicit none
  private
  public :: survey_track_t, build_survey_track, read_survey_file

  integer, parameter :: n_gauss = 10

  type, extends(track_geometry_t) :: survey_track_t
    private   ! parameters fixed by the build routine; use evaluate() and length()
    real(wp), allocatable :: chord(:)        !< spline parameter t at the points [m]
    real(wp), allocatable :: knot_sigma(:)   !< horizontal arc length at the points [m]
    real(wp), allocatable :: knot_heading(:) !< unwrapped heading at the points [rad]
    real(wp), allocatable :: knot_rate(:)    !< dt/dsigma = 1/|v| at the points [-]
    real(wp), allocatable :: plan(:, :, :)   !< x, y spline coefficients (0:3, n-1, 2) in t
    real(wp), allocatable :: profile(:, :, :) !< z, h spline coefficients (0:3, n-1, 2) in sigma
    real(wp) :: cant_base = 1.5_wp
    real(wp) :: xq(n_gauss) = 0, wq(n_gauss) = 0
    type(track_point_t) :: first, last      !< frames at sigma = 0 and at the end
  contains
    procedure :: evaluate => survey_evaluate
    procedure :: length => survey_length
  end type survey_track_t

contains

  !> Build from surveyed points x, y, z [m] and superelevation (left rail over right rail)
  !> [m]. cant_base (default 1.5 m) turns superelevation into the cant angle; gauge
  !> (default 1.435 m) bounds it; origin prefixes error messages.
  subroutine build_survey_track(track, x, y, z, superelevation, error, cant_base, gauge, origin)
    type(survey_track_t), intent(out) :: track
    real(wp), intent(in) :: x(:), y(:), z(:), superelevation(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: cant_base, gauge
    character(len=*), intent(in), optional :: origin
    character(len=:), allocatable :: where
    real(wp) :: base, gauge_, step, psi, dpsi, hmax, d
    real(wp), allocatable :: values(:, :)
    integer :: n, i, k

    where = 'survey track'
    if (present(origin)) where = origin
    base = 1.5_wp
    if (present(cant_base)) base = cant_base
    gauge_ = 1.435_wp
    if (present(gauge)) gauge_ = gauge
    n = size(x)
    if (size(y) /= n .or. size(z) /= n .or. size(superelevation) /= n) then
      call make_error(error, RD_ERR_INPUT, where // ': x, y, z and superelevation must have the same length')
      return
    end if
    if (n < 4) then
      call make_error(error, RD_ERR_INPUT, where // ': ' // trim(int_text(n)) // ' points given, at least 4 are needed')
      return
    end if
    if (.not. (all(ieee_is_finite(x)) .and. all(ieee_is_finite(y)) .and. all(ieee_is_finite(z)) .and. &
               all(ieee_is_finite(superelevation)) .and. ieee_is_finite(base) .and. ieee_is_finite(gauge_))) then
      call make_error(error, RD_ERR_INPUT, where // ': point coordinates and superelevations must be finite numbers')
      return
    end if
    if (base <= 0 .or. gauge_ <= 0) then
      call make_error(error, RD_ERR_INPUT, where // ': cant_base and gauge must be > 0 m')
      return
    end if
    allocate (track%chord(n), track%knot_sigma(n), track%knot_heading(n), track%knot_rate(n))
    track%chord(1) = 0
    do i = 2, n
      step = hypot(x(i) - x(i - 1), y(i) - y(i - 1))
      if (step <= 1.0e-9_wp * max(1.0_wp, abs(x(i)), abs(y(i)))) then
        call make_error(error, RD_ERR_INPUT, where // ': point ' // trim(int_text(i)) // ' repeats point ' // trim(int_text(i - 1)) // &
                        ' in plan (x, y); consecutive points must be distinct')
        return
      end if
      track%chord(i) = track%chord(i - 1) + step
    end do
    do i = 1, n
      if (abs(superelevation(i)) >= base .or. abs(superelevation(i)) > gauge_) then
        call make_error(error, RD_ERR_INPUT, where // ': point ' // trim(int_text(i)) // ': superelevation ' // &
                        trim(real_text(superelevation(i))) // ' m: cant larger than the gauge (need |h| < cant_base = ' // &
                        trim(real_text(base)) // ' m)')
        return
      end if
    end do
    track%cant_base = base
    call gauss_legendre(n_gauss, track%xq, track%wq)

    allocate (track%plan(0:3, n - 1, 2), track%profile(0:3, n - 1, 2))
    allocate (values(n, 2))
    values(:, 1) = x
    values(:, 2) = y
    call spline_not_a_knot(track%chord, values, track%plan, error)
    if (allocated(error)) then
      call error_context(error, where)
      return
    end if
    track%knot_sigma(1) = 0
    track%knot_heading(1) = atan2(track%plan(1, 1, 2), track%plan(1, 1, 1))
    do i = 1, n - 1
      d = track%chord(i + 1) - track%chord(i)
      track%knot_sigma(i + 1) = track%knot_sigma(i) + partial_length(track, i, d)
      psi = heading_at(track, i, d)
      dpsi = modulo(psi - track%knot_heading(i) + pi, 2 * pi) - pi
      if (abs(dpsi) > 0.5_wp * pi) then
        call make_error(error, RD_ERR_INPUT, where // ': the heading turns by more than 90 degrees between points ' // &
                        trim(int_text(i)) // ' and ' // trim(int_text(i + 1)) // ': points too sparse for this curvature')
        return
      end if
      track%knot_heading(i + 1) = track%knot_heading(i) + dpsi
      track%knot_rate(i) = 1 / speed(track, i, 0.0_wp)
    end do
    track%knot_rate(n) = 1 / speed(track, n - 1, track%chord(n) - track%chord(n - 1))
    values(:, 1) = z
    values(:, 2) = superelevation
    call spline_not_a_knot(track%knot_sigma, values, track%profile, error)
    if (allocated(error)) then
      call error_context(error, where)
      return
    end if
    ! the interpolated cant must stay possible between the points too, and the plan spline
    ! must not fold back (|v| ~ 1 with the chord parameter; a cusp would make kappa infinite)
    hmax = 0
    do i = 1, n - 1
      do k = 0, 16
        d = (track%knot_sigma(i + 1) - track%knot_sigma(i)) * k / 16
        hmax = max(hmax, abs(horner(track%profile(:, i, 2), d)))
        if (speed(track, i, (track%chord(i + 1) - track%chord(i)) * k / 16) < 0.1_wp) then
          call make_error(error, RD_ERR_INPUT, where // ': the spline through the points folds back between points ' // &
                          trim(int_text(i)) // ' and ' // trim(int_text(i + 1)) // ': check the point order and spacing')
          return
        end if
      end do
    end do
    if (hmax >= base) then
      call make_error(error, RD_ERR_INPUT, where // ': the interpolated superelevation reaches ' // trim(real_text(hmax)) // &
                      ' m between points: cant larger than the gauge (cant_base = ' // trim(real_text(base)) // ' m)')
      return
    end if
    track%first = interior_point(track, 1, 0.0_wp)
    track%last = interior_point(track, n - 1, track%knot_sigma(n))
  end subroutine build_survey_track

  pure real(wp) function horner(c, d)
    real(wp), intent(in) :: c(0:3), d
    horner = c(0) + d * (c(1) + d * (c(2) + d * c(3)))
  end function horner

  !> int_0^d |(x', y')| dt on interval i (10-point Gauss-Legendre).
  pure real(wp) function partial_length(track, i, d)
    type(survey_track_t), intent(in) :: track
    integer, intent(in) :: i
    real(wp), intent(in) :: d
    integer :: k
    real(wp) :: s
    partial_length = 0
    do k = 1, n_gauss
      s = 0.5_wp * d * (1 + track%xq(k))
      partial_length = partial_length + track%wq(k) * speed(track, i, s)
    end do
    partial_length = 0.5_wp * d * partial_length
  end function partial_length

  pure real(wp) function speed(track, i, d)
    type(survey_track_t), intent(in) :: track
    integer, intent(in) :: i
    real(wp), intent(in) :: d
    real(wp) :: dx, dy
    ! explicit copies: an associate name of a section would renumber 0:3 as 1:4
    real(wp) :: cx(0:3), cy(0:3)
    cx = track%plan(:, i, 1)
    cy = track%plan(:, i, 2)
    dx = cx(1) + d * (2 * cx(2) + 3 * d * cx(3))
    dy = cy(1) + d * (2 * cy(2) + 3 * d * cy(3))
    speed = hypot(dx, dy)
  end function speed

  pure real(wp) function heading_at(track, i, d)
    type(survey_track_t), intent(in) :: track
    integer, intent(in) :: i
    real(wp), intent(in) :: d
    real(wp) :: cx(0:3), cy(0:3)
    cx = track%plan(:, i, 1)
    cy = track%plan(:, i, 2)
    heading_at = atan2(cy(1) + d * (2 * cy(2) + 3 * d * cy(3)), cx(1) + d * (2 * cx(2) + 3 * d * cx(3)))
  end function heading_at

  !> Frame at sigma inside interval i (knot_sigma(i) <= sigma <= knot_sigma(i+1)).
  pure function interior_point(track, i, sigma) result(p)
    type(survey_track_t), intent(in) :: track
    integer, intent(in) :: i
    real(wp), intent(in) :: sigma
    type(track_point_t) :: p
    real(wp) :: target, span, d, correction, v, x1, y1, x2, y2, x3, y3, cross2, dot2, v3
    real(wp) :: psi, kappa, dkappa, ds, z0, z1, z2, z3, h0, h1, h2
    real(wp) :: cx(0:3), cy(0:3), cz(0:3), ch(0:3), width, s
    integer :: iteration

    target = sigma - track%knot_sigma(i)
    span = track%chord(i + 1) - track%chord(i)
    ! first guess: cubic Hermite of t(sigma) from the knot values and slopes 1/|v|; Newton
    ! then usually needs one or two steps
    width = track%knot_sigma(i + 1) - track%knot_sigma(i)
    s = target / width
    d = width * (s * (s - 1)**2 * track%knot_rate(i) + s * s * (s - 1) * track%knot_rate(i + 1)) &
        + span * s * s * (3 - 2 * s)
    do iteration = 1, 12
      v = speed(track, i, d)
      correction = (partial_length(track, i, d) - target) / v
      d = d - correction
      ! Newton converges quadratically (error after the step ~ |v|'/(2|v|) correction^2,
      ! and |v| ~ 1 varies slowly with the chord parameter): a step below sqrt(eps) span
      ! leaves an error at rounding level
      if (abs(correction) <= sqrt(epsilon(1.0_wp)) * span) exit
    end do
    cx = track%plan(:, i, 1)
    cy = track%plan(:, i, 2)
    cz = track%profile(:, i, 1)
    ch = track%profile(:, i, 2)
      p%r(1) = horner(cx, d)
      p%r(2) = horner(cy, d)
      x1 = cx(1) + d * (2 * cx(2) + 3 * d * cx(3))
      y1 = cy(1) + d * (2 * cy(2) + 3 * d * cy(3))
      x2 = 2 * cx(2) + 6 * d * cx(3)
      y2 = 2 * cy(2) + 6 * d * cy(3)
      x3 = 6 * cx(3)
      y3 = 6 * cy(3)
      ds = target
      z0 = horner(cz, ds)
      z1 = cz(1) + ds * (2 * cz(2) + 3 * ds * cz(3))
      z2 = 2 * cz(2) + 6 * ds * cz(3)
      z3 = 6 * cz(3)
      h0 = horner(ch, ds)
      h1 = ch(1) + ds * (2 * ch(2) + 3 * ds * ch(3))
      h2 = 2 * ch(2) + 6 * ds * ch(3)
    p%r(3) = z0
    p%sigma = sigma
    v = hypot(x1, y1)
    v3 = v**3
    cross2 = x1 * y2 - y1 * x2
    dot2 = x1 * x2 + y1 * y2
    psi = atan2(y1, x1)
    psi = track%knot_heading(i) + (modulo(psi - track%knot_heading(i) + pi, 2 * pi) - pi)
    kappa = cross2 / v3
    ! dkappa/dt = (x'y''' - y'x''')/v^3 - 3 (x'y'' - y'x'')(x'x'' + y'y'')/v^5; dsigma/dt = v
    dkappa = ((x1 * y3 - y1 * x3) / v3 - 3 * cross2 * dot2 / (v3 * v * v)) / v
    call set_track_frame(p, psi, kappa, dkappa, z1, z2, z3, h0, h1, h2, track%cant_base)
  end function interior_point

  pure function survey_evaluate(self, sigma) result(point)
    class(survey_track_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: point
    real(wp) :: total
    total = self%knot_sigma(size(self%knot_sigma))
    if (sigma < 0) then
      point = run_off(self%first, sigma, self%cant_base)
    else if (sigma > total) then
      point = run_off(self%last, sigma - total, self%cant_base)
    else
      point = interior_point(self, locate_interval(self%knot_sigma, sigma), sigma)
    end if
    point%sigma = sigma
  end function survey_evaluate

  !> Straight continuation of an end frame by u (negative before the start).
  pure function run_off(edge, u, cant_base) result(p)
    type(track_point_t), intent(in) :: edge
    real(wp), intent(in) :: u, cant_base
    type(track_point_t) :: p
    p%r = edge%r + u * [cos(edge%heading), sin(edge%heading), edge%dr(3)]
    call set_track_frame(p, edge%heading, 0.0_wp, 0.0_wp, edge%dr(3), 0.0_wp, 0.0_wp, &
                         edge%superelevation, 0.0_wp, 0.0_wp, cant_base)
  end function run_off

  pure function survey_length(self) result(total)
    class(survey_track_t), intent(in) :: self
    real(wp) :: total
    total = self%knot_sigma(size(self%knot_sigma))
  end function survey_length

  !> Read surveyed points from a plain text table: one point per line, columns
  !> x y z superelevation [m] separated by blanks, tabs or commas; '#' starts a comment;
  !> blank lines are skipped. Errors name path:line.
  subroutine read_survey_file(path, x, y, z, h, error)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: x(:), y(:), z(:), h(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=4096) :: line
    character(len=256) :: message
    real(wp), allocatable :: table(:, :)
    integer, allocatable :: line_of(:)
    real(wp) :: values(4)
    integer :: unit, ios, line_no, n
    type(numeric_line_t) :: info

    open (newunit=unit, file=path, status='old', action='read', iostat=ios, iomsg=message)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, path // ': cannot open survey file (' // trim(message) // ')')
      return
    end if
    allocate (table(4, 64), line_of(64))
    n = 0
    line_no = 0
    do
      call read_line(unit, path, line_no, line, ios, error)
      if (allocated(error)) then
        close (unit); return
      end if
      if (ios /= 0) exit
      call parse_numeric_line(line, values, info)
      if (info%blank) cycle
      ! exactly four numeric tokens
      if (info%n_tokens /= 4 .or. info%bad_column /= 0) then
        close (unit)
        call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(line_no)) // &
                        ': expected 4 numbers (x y z superelevation, metres), got "' // trim(adjustl(line)) // '"')
        return
      end if
      if (n > 0) then
        if (hypot(values(1) - table(1, n), values(2) - table(2, n)) <= &
            1.0e-9_wp * max(1.0_wp, abs(values(1)), abs(values(2)))) then
          close (unit)
          call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(line_no)) // ': point repeats the previous one (line ' // &
                          trim(int_text(line_of(n))) // '); consecutive points must be distinct')
          return
        end if
      end if
      if (n == size(line_of)) then
        table = reshape(table, [4, 2 * n], pad=[0.0_wp])
        line_of = [line_of, line_of]
      end if
      n = n + 1
      table(:, n) = values
      line_of(n) = line_no
    end do
    close (unit)
    if (n < 4) then
      call make_error(error, RD_ERR_INPUT, path // ': ' // trim(int_text(n)) // ' points found, at least 4 are needed ' // &
                      '(columns x y z superelevation, metres)')
      return
    end if
    x = table(1, 1:n)
    y = table(2, 1:n)
    z = table(3, 1:n)
    h = table(4, 1:n)
  end subroutine read_survey_file


end module rd_survey_track
