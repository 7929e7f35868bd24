!> Equivalent conicity of a rolling-radius difference function Delta r(y) in the manner of
!> EN 15302 (docs/theory_contact_geometry.md, section 7a): the kinematic (pure rolling)
!> motion of a free wheelset,
!>   y'' = -Delta r(y) / (2 e0 r0)        (' = d/dx, distance along the track),
!> is periodic; its amplitude is half its peak-to-peak lateral motion about the zero of
!> Delta r. Two methods:
!>  - integration (Klingel): the wavelength L of that motion, by exact integration of the
!>    energy integral over the table's linear pieces, turned into a conicity by Klingel's
!>    formula L = 2 pi sqrt(e0 r0 / lambda_e);
!>  - regression (linearisation): the slope / 2 of the straight line fitted to Delta r over
!>    the lateral range of that motion, each position weighted by the time a harmonic
!>    motion spends there.
!> A motion that stays inside a zone where Delta r = 0 has conicity 0 (no restoring
!> force: the wavelength is infinite). Delta r is linear between the table's rows; amplitudes
!> whose motion would leave the table, or that no motion about the zero has (where Delta r
!> crosses zero again), are errors.
module rd_equivalent_conicity
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, pi
  use rd_text, only: real_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_INTERNAL
  use rd_delta_r_table, only: delta_r_table_t
  implicit none
  private
  public :: kinematic_motion_t, en15302_conicity, largest_amplitude, AMPLITUDE_ROUNDING

  !> Relative margin by which an amplitude may exceed the largest one the table supports and
  !> still be computed (as that one): a table that is odd up to rounding (1e-15 m in Delta r)
  !> reaches one end a few 1e-11 earlier than the other, and its end amplitude must not fail.
  real(wp), parameter :: AMPLITUDE_ROUNDING = 1.0e-9_wp

  !> The kinematic motion of one amplitude and its two equivalent conicities.
  type :: kinematic_motion_t
    real(wp) :: amplitude = 0            !< half the peak-to-peak lateral motion [m]
    real(wp) :: y_min = 0, y_max = 0     !< extreme lateral positions [m]
    logical :: oscillates = .false.      !< .false.: inside a zone with Delta r = 0
    real(wp) :: wavelength = 0           !< [m] (oscillates only)
    real(wp) :: conicity_integration = 0 !< Klingel's formula on the wavelength [-]
    real(wp) :: conicity_regression = 0  !< slope / 2 of the weighted regression [-]
  end type kinematic_motion_t

  !> The table as the motion sees it, on both sides of the centre. `right` runs from the
  !> centre zone to the right; `left` is the mirror image (y -> -y, Delta r -> -Delta r,
  !> rows reversed), so the same code walks out to either side. Potentials
  !> V(y) = integral of Delta r from the centre [m^2] at the rows.
  type :: side_t
    real(wp), allocatable :: y(:), dr(:), v(:)
    real(wp) :: start = 0   !< edge of the centre zone on this side (in this side's y)
  end type side_t

  type :: well_t
    type(side_t) :: side(2)        !< 1 left (mirrored), 2 right
    real(wp) :: zone(2) = 0        !< centre zone [za, zb] (za = zb: a plain zero crossing)
    real(wp) :: v_edge = 0         !< energy at which the motion first reaches a table end [m^2]
  end type well_t

contains

  !> Both conicities for amplitude `amplitude` [m], with the nominal rolling radius `r0` and
  !> half the distance between the contact points `e0` [m] (they set the wavelength only:
  !> the conicity by integration does not depend on them).
  subroutine en15302_conicity(table, amplitude, r0, e0, motion, error)
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: amplitude, r0, e0
    type(kinematic_motion_t), intent(out) :: motion
    type(error_t), allocatable, intent(out) :: error
    type(well_t) :: well
    real(wp) :: e_lo, e_hi, e_mid, a_max, w_lo, w_hi, ext(2), integral
    integer :: it
    if (.not. (ieee_is_finite(r0) .and. ieee_is_finite(e0) .and. r0 > 0 .and. e0 > 0)) then
      call make_error(error, RD_ERR_INPUT, 'equivalent conicity: r0 and e0 must be positive lengths [m]')
      return
    end if
    if (.not. (ieee_is_finite(amplitude) .and. amplitude > 0)) then
      call make_error(error, RD_ERR_INPUT, 'equivalent conicity: the amplitude must be a positive length [m]')
      return
    end if
    call find_well(table, well, error)
    if (allocated(error)) return
    motion%amplitude = amplitude
    if (2 * amplitude <= well%zone(2) - well%zone(1)) then
      ! inside the zone where Delta r = 0: no restoring force, no oscillation
      motion%y_min = 0.5_wp * sum(well%zone) - amplitude
      motion%y_max = 0.5_wp * sum(well%zone) + amplitude
      return
    end if
    a_max = 0.5_wp * width(well, well%v_edge)
    if (amplitude > a_max * (1 + AMPLITUDE_ROUNDING)) then
      call make_error(error, RD_ERR_INPUT, 'amplitude ' // trim(real_text(amplitude)) // ' m: the kinematic ' // &
        'motion would leave the table (y from ' // trim(real_text(table%y(1))) // ' to ' // &
        trim(real_text(table%y(size(table%y)))) // ' m); the largest amplitude it supports is ' // &
        trim(real_text(a_max)) // ' m')
      return
    end if
    ! width(E) is non-decreasing in the energy E: bisection for width = 2 A
    e_lo = 0
    e_hi = well%v_edge
    do it = 1, 200
      e_mid = 0.5_wp * (e_lo + e_hi)
      if (e_mid <= e_lo .or. e_mid >= e_hi) exit
      if (width(well, e_mid) >= 2 * amplitude) then
        e_hi = e_mid
      else
        e_lo = e_mid
      end if
    end do
    w_hi = width(well, e_hi)
    w_lo = 2 * amplitude
    if (e_lo > 0) w_lo = width(well, e_lo)
    if (w_hi - w_lo > 1.0e-6_wp * amplitude) then
      call make_error(error, RD_ERR_INPUT, 'amplitude ' // trim(real_text(amplitude)) // ' m: no kinematic ' // &
        'motion about the zero of Delta r has it (the motion jumps from amplitude ' // trim(real_text(0.5_wp * w_lo)) // &
        ' to ' // trim(real_text(0.5_wp * w_hi)) // ' m where Delta r crosses zero again)')
      return
    end if
    ext = extent(well, e_hi)
    motion%y_min = ext(1)
    motion%y_max = ext(2)
    integral = period_integral(table, e_hi, ext, well, error)
    if (allocated(error)) return
    motion%oscillates = .true.
    ! y'^2 / 2 = (E - V(y)) / (2 e0 r0): L = 2 integral dy / y' = 2 sqrt(e0 r0) * integral, and
    ! Klingel L = 2 pi sqrt(e0 r0 / lambda) gives lambda = (pi / integral)^2
    motion%wavelength = 2 * sqrt(e0 * r0) * integral
    motion%conicity_integration = (pi / integral)**2
    motion%conicity_regression = regression_slope(table, ext) / 2
  end subroutine en15302_conicity

  !> The largest amplitude whose kinematic motion stays inside the table [m].
  function largest_amplitude(table, error) result(a_max)
    type(delta_r_table_t), intent(in) :: table
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: a_max
    type(well_t) :: well
    a_max = 0
    call find_well(table, well, error)
    if (allocated(error)) return
    a_max = max(0.5_wp * width(well, well%v_edge), 0.5_wp * (well%zone(2) - well%zone(1)))
  end function largest_amplitude

  !> The centre of the motion: the zero of Delta r where it rises through 0 (a stable
  !> position, a potential minimum), or a zone where Delta r = 0 between a falling and a
  !> rising part; of several, the one nearest y = 0.
  subroutine find_well(table, well, error)
    type(delta_r_table_t), intent(in) :: table
    type(well_t), intent(out) :: well
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: best, za, zb, dist
    integer :: n, i, a, b
    logical :: found
    n = size(table%y)
    found = .false.
    best = huge(1.0_wp)
    associate (y => table%y, d => table%delta_r)
      i = 1
      do while (i <= n)
        if (d(i) == 0) then
          ! a run of zero rows a..b: stable when Delta r falls into it and rises out of it
          a = i
          b = i
          do while (b < n)
            if (d(b + 1) /= 0) exit
            b = b + 1
          end do
          if ((a == 1 .or. d(max(a - 1, 1)) < 0) .and. (b == n .or. d(min(b + 1, n)) > 0)) &
            call consider(y(a), y(b))
          i = b + 1
          cycle
        end if
        if (i < n) then
          if (d(i) < 0 .and. d(i + 1) > 0) then
            za = y(i) - d(i) * (y(i + 1) - y(i)) / (d(i + 1) - d(i))
            call consider(za, za)
          end if
        end if
        i = i + 1
      end do
    end associate
    if (.not. found) then
      call make_error(error, RD_ERR_INPUT, 'Delta r does not rise through zero inside the table (from ' // &
        trim(real_text(table%delta_r(1))) // ' m at y = ' // trim(real_text(table%y(1))) // ' m to ' // &
        trim(real_text(table%delta_r(n))) // ' m at y = ' // trim(real_text(table%y(n))) // &
        ' m): there is no centred position for the wheelset to oscillate about')
      return
    end if
    call build_side(table, well%zone(2), .false., well%side(2))
    call build_side(table, well%zone(1), .true., well%side(1))
    well%v_edge = min(max_potential(well%side(1)), max_potential(well%side(2)))
  contains
    subroutine consider(lo, hi)
      real(wp), intent(in) :: lo, hi
      dist = max(lo, min(hi, 0.0_wp))   ! the zone's point nearest y = 0
      if (abs(dist) < best) then
        best = abs(dist)
        well%zone = [lo, hi]
        found = .true.
      end if
    end subroutine consider
  end subroutine find_well

  !> One side of the well from `edge` outwards: rows beyond `edge`, with `edge` itself as the
  !> first row (Delta r interpolated there); mirrored for the left side.
  subroutine build_side(table, edge, mirror, side)
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: edge
    logical, intent(in) :: mirror
    type(side_t), intent(out) :: side
    real(wp), allocatable :: y(:), d(:)
    integer :: n, k, m
    n = size(table%y)
    if (mirror) then
      y = -table%y(n:1:-1)
      d = -table%delta_r(n:1:-1)
      side%start = -edge
    else
      y = table%y
      d = table%delta_r
      side%start = edge
    end if
    k = count(y <= side%start)          ! rows at or before the edge
    m = n - k + 1
    allocate (side%y(m), side%dr(m), side%v(m))
    side%y(1) = side%start
    side%dr(1) = interpolate(y, d, side%start)
    side%y(2:) = y(k + 1:)
    side%dr(2:) = d(k + 1:)
    side%v(1) = 0
    do k = 2, m
      side%v(k) = side%v(k - 1) + 0.5_wp * (side%y(k) - side%y(k - 1)) * (side%dr(k) + side%dr(k - 1))
    end do
  end subroutine build_side

  pure real(wp) function interpolate(y, d, x) result(v)
    real(wp), intent(in) :: y(:), d(:), x
    integer :: i
    i = max(1, min(size(y) - 1, count(y <= x)))
    v = d(i) + (d(i + 1) - d(i)) * (x - y(i)) / (y(i + 1) - y(i))
  end function interpolate

  !> Highest potential reached on a side (at a row, or inside a piece where Delta r falls
  !> through zero).
  pure real(wp) function max_potential(side) result(vmax)
    type(side_t), intent(in) :: side
    integer :: i
    real(wp) :: h, s, t
    vmax = maxval(side%v)
    do i = 1, size(side%y) - 1
      h = side%y(i + 1) - side%y(i)
      s = (side%dr(i + 1) - side%dr(i)) / h
      if (side%dr(i) > 0 .and. side%dr(i + 1) < 0) then
        t = -side%dr(i) / s
        vmax = max(vmax, side%v(i) + side%dr(i) * t + 0.5_wp * s * t * t)
      end if
    end do
  end function max_potential

  !> First position on a side where the potential reaches `energy` (the turning point); the
  !> side's last row when it never does (callers keep energy <= v_edge).
  pure real(wp) function turning_point(side, energy) result(yt)
    type(side_t), intent(in) :: side
    real(wp), intent(in) :: energy
    integer :: i
    real(wp) :: h, s, t
    do i = 1, size(side%y) - 1
      h = side%y(i + 1) - side%y(i)
      s = (side%dr(i + 1) - side%dr(i)) / h
      t = first_root(0.5_wp * s, side%dr(i), side%v(i) - energy, h)
      if (t >= 0) then
        yt = side%y(i) + t
        return
      end if
    end do
    yt = side%y(size(side%y))
  end function turning_point

  !> Smallest t in [0, h] with a t^2 + b t + c >= 0, given c < 0 at t = 0 (the potential
  !> below the energy); -1 when there is none. Roots in the cancellation-free form.
  pure real(wp) function first_root(a, b, c, h) result(t)
    real(wp), intent(in) :: a, b, c, h
    real(wp) :: disc, q, r(2)
    t = -1
    if (c >= 0) then
      t = 0
      return
    end if
    if (a * h * h + b * h + c < 0) then
      ! no crossing at the end: only a concave piece can rise above and fall back inside
      if (.not. (a < 0 .and. b > 0 .and. -b / (2 * a) < h)) return
    end if
    disc = b * b - 4 * a * c
    if (disc < 0) return
    q = -0.5_wp * (b + sign(sqrt(disc), b))
    r = -1
    if (a /= 0) r(1) = q / a
    if (q /= 0) r(2) = c / q
    if (r(1) >= 0 .and. r(1) <= h) t = r(1)
    if (r(2) >= 0 .and. r(2) <= h .and. (t < 0 .or. r(2) < t)) t = r(2)
    if (t < 0 .and. a * h * h + b * h + c >= 0) t = h   ! rounding at the row
  end function first_root

  !> [y_min, y_max] of the motion of energy E (> 0: above the centre's potential).
  pure function extent(well, energy) result(ext)
    type(well_t), intent(in) :: well
    real(wp), intent(in) :: energy
    real(wp) :: ext(2)
    ext(1) = -turning_point(well%side(1), energy)
    ext(2) = turning_point(well%side(2), energy)
  end function extent

  pure real(wp) function width(well, energy)
    type(well_t), intent(in) :: well
    real(wp), intent(in) :: energy
    real(wp) :: ext(2)
    ext = extent(well, energy)
    width = ext(2) - ext(1)
  end function width

  !> integral of dy / sqrt(E - V(y)) over the motion [y_min, y_max], exactly for the table's
  !> linear pieces: on each piece E - V is a quadratic in y; each piece is split at its middle
  !> (where E - V > 0) and integrated from there outwards by Euler's substitution, with
  !> E - V = 0 taken exactly at the turning points (its rounded value there would cost
  !> sqrt(epsilon) of accuracy). A row within rounding (1e-9 of the motion's width) of a
  !> turning point is moved onto it: the piece up to the row then ends at the turning point.
  function period_integral(table, energy, ext, well, error) result(total)
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: energy, ext(2)
    type(well_t), intent(in) :: well
    type(error_t), allocatable, intent(inout) :: error
    real(wp) :: total, h, s, t1, t2, m, qm, dq, c, v_row, len, snap
    integer :: i, n
    logical :: end_left, end_right
    n = size(table%y)
    total = 0
    snap = 1.0e-9_wp * (ext(2) - ext(1))
    do i = 1, n - 1
      t1 = max(table%y(i), ext(1))
      t2 = min(table%y(i + 1), ext(2))
      if (t1 - ext(1) <= snap) t1 = ext(1)
      if (ext(2) - t2 <= snap) t2 = ext(2)
      if (.not. (t2 - t1 > snap)) cycle
      end_left = t1 == ext(1)
      end_right = t2 == ext(2)
      h = table%y(i + 1) - table%y(i)
      s = (table%delta_r(i + 1) - table%delta_r(i)) / h
      len = t2 - t1
      v_row = potential_at(well, table%y(i))
      ! E - V(y(i) + t) = (E - v_row) - dr_i t - s t^2 / 2
      m = 0.5_wp * (t1 + t2) - table%y(i)
      qm = (energy - v_row) - table%delta_r(i) * m - 0.5_wp * s * m * m
      dq = -(table%delta_r(i) + s * m)
      c = -0.5_wp * s
      if (.not. (qm > 0)) then
        call make_error(error, RD_ERR_INTERNAL, 'equivalent conicity: the potential reaches the energy inside ' // &
                        'the motion at y = ' // trim(real_text(table%y(i) + m)) // ' m')
        return
      end if
      total = total + euler_piece(sqrt(qm), dq, c, 0.5_wp * len, end_right) + &
                      euler_piece(sqrt(qm), -dq, c, 0.5_wp * len, end_left)
    end do
  end function period_integral

  !> Potential (integral of Delta r from the centre zone) at a row y of the table.
  pure real(wp) function potential_at(well, y) result(v)
    type(well_t), intent(in) :: well
    real(wp), intent(in) :: y
    if (y >= well%zone(2)) then
      v = side_potential(well%side(2), y)
    else if (y <= well%zone(1)) then
      v = side_potential(well%side(1), -y)
    else
      v = 0
    end if
  end function potential_at

  pure real(wp) function side_potential(side, y) result(v)
    type(side_t), intent(in) :: side
    real(wp), intent(in) :: y
    integer :: i
    real(wp) :: h, s, t
    i = max(1, min(size(side%y) - 1, count(side%y <= y)))
    h = side%y(i + 1) - side%y(i)
    s = (side%dr(i + 1) - side%dr(i)) / h
    t = y - side%y(i)
    v = side%v(i) + side%dr(i) * t + 0.5_wp * s * t * t
  end function side_potential

  !> integral_0^len dsigma / sqrt(Q(sigma)), Q = P^2 + D sigma + c sigma^2 > 0 on [0, len)
  !> (it may reach 0 at len: a turning point). Euler's substitution sqrt(Q) = P + u sigma
  !> turns it into integral 2 du / (c - u^2) between u0 = D / (2P) and u1 = (sqrt(Q(len)) - P)
  !> / len, written with the difference formulas of atanh / atan so that it stays accurate
  !> as c -> 0 (where it tends to the linear case's 2 len / (P + sqrt(Q(len)))). `turning`:
  !> Q(len) = 0 exactly.
  pure real(wp) function euler_piece(p, d, c, len, turning) result(integral)
    real(wp), intent(in) :: p, d, c, len
    logical, intent(in) :: turning
    real(wp) :: s_end, u0, u1, w, nn, x
    integral = 0
    if (.not. (len > 0)) return
    if (c == 0 .and. d == 0) then
      integral = len / p
      return
    end if
    s_end = 0
    if (.not. turning) s_end = sqrt(max(p * p + d * len + c * len * len, 0.0_wp))
    u0 = d / (2 * p)
    u1 = (d + c * len) / (s_end + p)
    w = u1 - u0
    nn = c - u0 * u1
    if (c > 0) then
      x = sqrt(c) * w / nn
      integral = 2 * (w / nn) * atanh_ratio(x)
    else if (c < 0 .and. nn >= 0) then
      integral = 2 / sqrt(-c) * atan2(-w * sqrt(-c), -nn)
    else if (c < 0) then
      x = sqrt(-c) * w / nn
      integral = 2 * (w / nn) * atan_ratio(x)
    else
      integral = 2 * w / nn
    end if
  end function euler_piece

  !> atanh(x) / x and atan(x) / x, exact at x = 0.
  pure real(wp) function atanh_ratio(x) result(r)
    real(wp), intent(in) :: x
    if (abs(x) < 1.0e-8_wp) then
      r = 1 + x * x / 3
    else
      r = atanh(x) / x
    end if
  end function atanh_ratio

  pure real(wp) function atan_ratio(x) result(r)
    real(wp), intent(in) :: x
    if (abs(x) < 1.0e-8_wp) then
      r = 1 - x * x / 3
    else
      r = atan(x) / x
    end if
  end function atan_ratio

  !> Slope of the straight line fitted to Delta r over [y_min, y_max], each y weighted by the
  !> time the harmonic motion y = c + a sin(theta) spends there, 1 / (pi sqrt(a^2 - u^2)),
  !> u = y - c. The weighted mean of u is 0, so the slope is
  !>   integral Delta r u w du / integral u^2 w du = (2 / (pi a^2)) integral Delta r u / sqrt(a^2 - u^2) du,
  !> exact on each linear piece (Delta r = alpha + s u there).
  pure real(wp) function regression_slope(table, ext) result(slope)
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: ext(2)
    real(wp) :: centre, a, y1, y2, u1, u2, s, alpha, acc
    integer :: i
    centre = 0.5_wp * (ext(1) + ext(2))
    a = 0.5_wp * (ext(2) - ext(1))
    acc = 0
    do i = 1, size(table%y) - 1
      y1 = max(table%y(i), ext(1))
      y2 = min(table%y(i + 1), ext(2))
      if (.not. (y2 > y1)) cycle
      u1 = y1 - centre
      u2 = y2 - centre
      s = (table%delta_r(i + 1) - table%delta_r(i)) / (table%y(i + 1) - table%y(i))
      alpha = table%delta_r(i) + s * (centre - table%y(i))
      acc = acc + alpha * (root(y1) - root(y2)) + &
            s * (0.5_wp * a * a * (arc(y2) - arc(y1)) - 0.5_wp * (u2 * root(y2) - u1 * root(y1)))
    end do
    slope = 2 * acc / (pi * a * a)
  contains
    !> sqrt(a^2 - u^2) = sqrt((y_max - y) (y - y_min)): no cancellation at the ends
    pure real(wp) function root(y)
      real(wp), intent(in) :: y
      root = sqrt(max((ext(2) - y) * (y - ext(1)), 0.0_wp))
    end function root
    !> asin(u / a), from atan2 (accurate where asin's slope is infinite)
    pure real(wp) function arc(y)
      real(wp), intent(in) :: y
      arc = atan2(y - centre, root(y))
    end function arc
  end function regression_slope
end module rd_equivalent_conicity
