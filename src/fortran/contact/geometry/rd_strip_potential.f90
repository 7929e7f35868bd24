!> The strip geometry of the conservative strip normal forces: one strip's depth gradient
!> (its force direction), the shift of its deepest point, the wheel's curvatures and smooth
!> radius at it (used by the distributed force, the default: rd_strip_contact
!> distributed_force, docs/theory_flange_chatter.md section 14), and the effective
!> penetration of the patch force `strip_normal_force = 'potential'` (sections 6 and 13).
!>
!> The classic strip force (rd_strip_contact) takes the refined peak as the penetration and
!> applies the Hertz force along the rail normal at the centroid of the virtual-penetration
!> region. That field is not a gradient: around closed loops of poses at the flange root /
!> flange jump it returns work (docs/theory_flange_chatter.md sections 3 and 12; at
!> friction 0.6 the flange wheel's normal force is the only group with positive work per
!> cycle of the Manchester limit cycle). Here the penetration is a smooth function E of
!> the strip depths and the force direction on the wheel is the gradient of E with
!> respect to the wheel's displacement, so that at a fixed Hertz constant the force
!> N F = K E^(3/2) (-grad_u E) derives from U = (2/5) K E^(5/2).
module rd_strip_potential
  use rd_kinds, only: wp
  implicit none
  private
  !> order q of the Lehmer mean that stands in for the deepest strip (effective_penetration):
  !> larger follows the deepest bump more closely, with steeper changes between bumps
  integer, parameter :: lehmer_order = 8
  public :: effective_penetration, strip_force_direction, region_mean, wheel_point_curvatures, deepest_point_py_gradient
  public :: smooth_line_depth, smooth_wheel_radius, lehmer_order

contains

  !> Effective penetration of a bump's strips and its gradient c_i = dE/d delta_i.
  !>
  !> Over the virtual-penetration region delta_i > t (Kik & Piotrowski's region):
  !>
  !>    E = G(t) / (1 - eps/7),   G(t) = sum (delta_i - t)^2 delta_i / sum (delta_i - t)^2,
  !>
  !> For a parabolic (Hertzian) gap delta = P (1 - s^2 / s0^2) with t = (1 - eps) P,
  !> G = P (1 - eps (16/105) / (16/15)) = P (1 - eps/7), so E = P, the peak depth of every
  !> Hertzian gap whatever its curvature. The threshold is a smooth stand-in for
  !> (1 - eps) max delta: the Lehmer mean L = sum delta_+^q / sum delta_+^(q-1), which for a
  !> parabolic gap is P 2q / (2q + 1) (the ratio of the integrals of (1 - s^2)^q and
  !> (1 - s^2)^(q-1)), so
  !>
  !>    t = (1 - eps) (2q + 1) / (2q) L,   q = lehmer_order.
  !>
  !> With the deepest strip itself (the first form) the force direction jumped where the
  !> deepest strip moved from one bump of a flat or two-bump gap to the other, and with t
  !> tied to E by a fixed point the fixed point was not unique on two-bump stretches (the
  !> solve picked one root or the other); L is one smooth function of all strips. Strips
  !> enter the region with zero weight and zero slope, so E and c are continuous. With
  !> G_i = [2 (delta_i - t)(delta_i - G) + (delta_i - t)^2] / W, G'(t) = -sum 2 (delta_i - t)(delta_i - G) / W
  !> and dL/d delta_i = delta_i^(q-2) (q delta_i - (q - 1) L) / sum delta_+^(q-1),
  !>
  !>    c_i = [G_i + G'(t) (1 - eps) (2q + 1) / (2q) dL/d delta_i] / (1 - eps/7).
  !>
  !> A stretch without penetration (max delta <= 0: a patch opened by its refined peak
  !> alone) has E = max delta, c = 0, t = 0.
  pure subroutine effective_penetration(delta, eps, e, c, t, dt)
    real(wp), intent(in) :: delta(:)
    real(wp), intent(in) :: eps        !< virtual penetration factor (Kik & Piotrowski 0.55)
    real(wp), intent(out) :: e
    real(wp), intent(out) :: c(:)      !< dE/d delta_i, size(delta)
    real(wp), intent(out) :: t         !< the region's threshold
    real(wp), intent(out) :: dt(:)     !< dt/d delta_i
    integer, parameter :: q = lehmer_order
    real(wp) :: dmax, sq, sq1, lm, tfac, w, g, dg, x
    integer :: i
    c = 0; dt = 0
    dmax = maxval(delta)
    t = 0
    if (.not. (dmax > 0)) then
      e = dmax
      return
    end if
    ! Lehmer mean on delta / dmax (scaled: no overflow or underflow of the powers)
    sq = 0; sq1 = 0
    do i = 1, size(delta)
      if (delta(i) > 0) then
        x = delta(i) / dmax
        sq1 = sq1 + x**(q - 1)
        sq = sq + x**q
      end if
    end do
    lm = dmax * sq / sq1
    tfac = (1 - eps) * (2 * q + 1) / real(2 * q, wp)
    t = tfac * lm
    w = 0; g = 0
    do i = 1, size(delta)
      if (delta(i) > t) then
        x = (delta(i) - t)**2
        w = w + x
        g = g + x * delta(i)
      end if
    end do
    g = g / w
    dg = 0
    do i = 1, size(delta)
      if (delta(i) > t) then
        c(i) = (2 * (delta(i) - t) * (delta(i) - g) + (delta(i) - t)**2) / w
        dg = dg - 2 * (delta(i) - t) * (delta(i) - g) / w
      end if
    end do
    ! the threshold's part: dt/d delta_i = tfac dL/d delta_i
    do i = 1, size(delta)
      if (delta(i) > 0) then
        x = delta(i) / dmax
        dt(i) = tfac * x**(q - 2) * (q * x - (q - 1) * lm / dmax) / sq1
        c(i) = c(i) + dg * dt(i)
      end if
    end do
    e = g / (1 - eps / 7)
    c = c / (1 - eps / 7)
  end subroutine effective_penetration

  !> The means of strip values v(i, q) over the region of effective_penetration (threshold
  !> t and its gradient dt) with E's weights, mean_q = sum (delta_i - t)^2 v_iq / sum (delta_i - t)^2,
  !> their derivatives dmean(i, q) = d mean_q / d delta_i at fixed v (the threshold moves
  !> with the strips: dt/d delta_i), and the normalised weights wn_i (for the
  !> derivatives through v). The Hertz curvatures of a potential patch are these means, so
  !> that the Hertz constant is a differentiable function of the pose (its gradient enters
  !> the force). Only strips inside the region (delta_i > t) are read.
  pure subroutine region_mean(delta, t, dt, v, mean, dmean, wn)
    real(wp), intent(in) :: delta(:), t, dt(:), v(:, :)
    real(wp), intent(out) :: mean(:), dmean(:, :), wn(:)
    real(wp) :: w, dmdt(size(mean))
    integer :: i, m
    dmean = 0; wn = 0
    if (.not. (maxval(delta) > 0)) then
      m = maxloc(delta, dim=1)
      mean = v(m, :); wn(m) = 1
      return
    end if
    w = 0
    do i = 1, size(delta)
      if (delta(i) > t) then
        wn(i) = (delta(i) - t)**2
        w = w + wn(i)
      end if
    end do
    wn = wn / w
    mean = 0
    do i = 1, size(delta)
      if (delta(i) > t) mean = mean + wn(i) * v(i, :)
    end do
    dmdt = 0
    do i = 1, size(delta)
      if (delta(i) > t) then
        dmean(i, :) = 2 * (delta(i) - t) * (v(i, :) - mean) / w
        dmdt = dmdt - dmean(i, :)
      end if
    end do
    do i = 1, size(delta)
      if (dt(i) /= 0) dmean(i, :) = dmean(i, :) + dmdt * dt(i)
    end do
  end subroutine region_mean

  !> The wheel's principal curvatures at lateral position py on segment j of the profile
  !> points y with the point values k_roll (rolling direction, cos(gamma)/r, thesis eq.
  !> 4.75) and kappa (smoothed profile curvature, lateral), and their derivatives with
  !> respect to py. With the splines' second derivatives k_roll_m, kappa_m (the distributed
  !> force) both are natural cubic splines through their point values (C2 in py): the Hertz
  !> constant's gradient term of the strip forces holds these derivatives, so it is
  !> continuous where a strip's deepest point crosses a profile point (with linear
  !> interpolation its slope jumped at every point, 0.2 mm apart, and the integrator's Newton
  !> iteration failed there) and, C1, does not kink the force there. Without them (the
  !> potential force, whose deepest points on the cones kink anyway) the cubic Hermite with
  !> central-difference slopes (C1; with the splines that level's quasi-static balance on
  !> straight track depended on its start by 2e-10 m in test_quasi_static_history, a balance
  !> near one of its kinks). Clamped (derivatives zero) beyond the profile's ends.
  pure subroutine wheel_point_curvatures(py, j, y, k_roll_pts, kappa, k_roll, k_lat, dk_roll, dk_lat, k_roll_m, kappa_m)
    real(wp), intent(in) :: py
    integer, intent(in) :: j
    real(wp), intent(in) :: y(:), k_roll_pts(:), kappa(:)
    !> second derivatives along y of the natural cubic splines through k_roll_pts and kappa
    !> (absent: the cubic Hermite)
    real(wp), intent(in), optional :: k_roll_m(:), kappa_m(:)
    real(wp), intent(out) :: k_roll, k_lat, dk_roll, dk_lat
    real(wp) :: h, x
    integer :: n
    n = size(y)
    h = y(j + 1) - y(j)
    x = (py - y(j)) / h
    if (x <= 0 .or. x >= 1) then
      x = min(max(x, 0.0_wp), 1.0_wp)
      k_roll = k_roll_pts(j + nint(x)); k_lat = kappa(j + nint(x))
      dk_roll = 0; dk_lat = 0
      return
    end if
    if (present(k_roll_m) .and. present(kappa_m)) then
      call spline(k_roll_pts, k_roll_m, k_roll, dk_roll)
      call spline(kappa, kappa_m, k_lat, dk_lat)
    else
      call hermite(k_roll_pts, k_roll, dk_roll)
      call hermite(kappa, k_lat, dk_lat)
    end if
  contains
    !> value and derivative of the cubic Hermite of point values v on segment j at x
    pure subroutine hermite(v, f, df)
      real(wp), intent(in) :: v(:)
      real(wp), intent(out) :: f, df
      real(wp) :: m0, m1, x2, x3
      m0 = (v(min(j + 1, n)) - v(max(j - 1, 1))) / (y(min(j + 1, n)) - y(max(j - 1, 1)))
      m1 = (v(min(j + 2, n)) - v(j)) / (y(min(j + 2, n)) - y(j))
      x2 = x * x; x3 = x2 * x
      f = (2 * x3 - 3 * x2 + 1) * v(j) + (x3 - 2 * x2 + x) * h * m0 + (-2 * x3 + 3 * x2) * v(j + 1) + (x3 - x2) * h * m1
      df = ((6 * x2 - 6 * x) * v(j) + (3 * x2 - 4 * x + 1) * h * m0 + (-6 * x2 + 6 * x) * v(j + 1) &
            + (3 * x2 - 2 * x) * h * m1) / h
    end subroutine hermite
    !> value and derivative of the natural cubic spline of point values v (second
    !> derivatives vm) on segment j at x
    pure subroutine spline(v, vm, f, df)
      real(wp), intent(in) :: v(:), vm(:)
      real(wp), intent(out) :: f, df
      real(wp) :: u
      u = 1 - x
      f = u * v(j) + x * v(j + 1) + h * h / 6 * ((u**3 - u) * vm(j) + (x**3 - x) * vm(j + 1))
      df = (v(j + 1) - v(j)) / h + h / 6 * (-(3 * u * u - 1) * vm(j) + (3 * x * x - 1) * vm(j + 1))
    end subroutine spline
  end subroutine wheel_point_curvatures

  !> Gradient of the lateral position p_y of a line's deepest point with respect to the
  !> wheel's translation (1:3) and rotation (4:6), intermediate frame. The point is the
  !> rail point p moving rigidly by -u (-theta e x p) relative to the wheel, plus its shift
  !> t along the line (direction d) where the deepest point is a stationary point inside a
  !> cone of slope s: D(t) = r(p_y(t)) - rho(t) with D_t = 0, so by the implicit function
  !> theorem dt = -(dD_t) / D_tt with (r'' = 0 on a cone, s_xz = p_x d_x + p_z d_z)
  !>    D_tt = -(a^2 rho^2 - s_xz^2) / rho^3,   a^2 = d_x^2 + d_z^2,
  !>    grad_p D_t = -(d_x / rho - s_xz p_x / rho^3, 0, d_z / rho - s_xz p_z / rho^3),
  !>    grad_d D_t = (-p_x / rho, s, -p_z / rho),
  !> dD_t = -grad_p D_t . u for a translation, -(p x grad_p D_t + d x grad_d D_t) . e theta
  !> for a rotation. On a yawed wheel the shift is as large as the rigid part (it doubled
  !> the yaw derivative of the flange curvatures). `inside`: the stationary point lies
  !> inside the cone (else it sits on the cone's edge, a circle of the wheel: p_y fixed).
  pure function deepest_point_py_gradient(p, d, s, inside, r2) result(gpy)
    real(wp), intent(in) :: p(3), d(3), s
    logical, intent(in) :: inside
    !> the wheel's d2r/dy2 at p (a smooth wheel; 0 on a cone): D_tt gains r2 d_y^2 and
    !> grad_p D_t its y component r2 d_y
    real(wp), intent(in), optional :: r2
    real(wp) :: gpy(6)
    real(wp) :: rho, sxz, a2, dtt, gp(3), gd(3), dt(6), ryy
    gpy = 0
    if (.not. inside) return
    ryy = 0
    if (present(r2)) ryy = r2
    rho = hypot(p(1), p(3))
    sxz = p(1) * d(1) + p(3) * d(3)
    a2 = d(1)**2 + d(3)**2
    dtt = ryy * d(2)**2 - (a2 * rho**2 - sxz**2) / rho**3
    gp = [-(d(1) / rho - sxz * p(1) / rho**3), ryy * d(2), -(d(3) / rho - sxz * p(3) / rho**3)]
    gd = [-p(1) / rho, s, -p(3) / rho]
    dt(1:3) = gp / dtt
    ! p x gp + d x gd and -p x e_y written out (a hot path of the distributed force; the
    ! module function is not inlined across modules)
    dt(4:6) = [p(2) * gp(3) - p(3) * gp(2) + d(2) * gd(3) - d(3) * gd(2), &
               p(3) * gp(1) - p(1) * gp(3) + d(3) * gd(1) - d(1) * gd(3), &
               p(1) * gp(2) - p(2) * gp(1) + d(1) * gd(2) - d(2) * gd(1)] / dtt
    gpy(1:3) = [0.0_wp, -1.0_wp, 0.0_wp]
    gpy(4:6) = [p(3), 0.0_wp, -p(1)]
    gpy = gpy + d(2) * dt
  end function deepest_point_py_gradient

  !> Direction in which a wheel displacement u (wheelset intermediate frame) DEcreases the
  !> normal depth of one strip, -d delta_i / d u: the direction of that strip's force on
  !> the wheel. The strip depth is delta_i = d_i / sqrt(1 + k^2) (rd_strip_contact:
  !> d_i the largest radial depth of the rail line into the wheel's cone j of slope s_j,
  !> k the profile slope interpolated at the deepest point p). By the envelope theorem
  !> only the explicit dependence on p counts; a wheel displacement u moves p by -u
  !> relative to the wheel (the shift of the deepest point along a yawed line is
  !> neglected), so with e_rho the radial unit vector at p and k_y = dk/dy on the segment
  !>
  !>    g = (-e_rho + s_j e_y) / sqrt(1 + k^2) - d_i k k_y / (1 + k^2)^(3/2) e_y.
  !>
  !> The cone slope s_j and the last term matter: with the unit surface normal instead the
  !> loop work at the flange jump stayed at 1e-2 (section 6 of the theory note).
  pure function strip_force_direction(p, depth, yj, yj1, slope_j, slope_j1, cone_slope) result(g)
    real(wp), intent(in) :: p(3)         !< deepest point of the line, intermediate frame [m]
    real(wp), intent(in) :: depth        !< normal depth delta_i [m]
    real(wp), intent(in) :: yj, yj1      !< the cone's end points' lateral positions [m]
    real(wp), intent(in) :: slope_j, slope_j1  !< profile slopes dr/dy at those points
    real(wp), intent(in) :: cone_slope   !< dr/dy of the cone
    real(wp) :: g(3)
    real(wp) :: x, k, ky, rho, root
    x = (p(2) - yj) / (yj1 - yj)
    ky = 0
    if (x > 0 .and. x < 1) ky = (slope_j1 - slope_j) / (yj1 - yj)
    x = min(max(x, 0.0_wp), 1.0_wp)
    k = slope_j + x * (slope_j1 - slope_j)
    root = sqrt(1 + k**2)
    rho = hypot(p(1), p(3))
    g = [-p(1) / rho, cone_slope, -p(3) / rho] / root
    ! d_i k k_y / (1 + k^2)^(3/2) with d_i = delta_i sqrt(1 + k^2)
    g(2) = g(2) - depth * k * ky / root**2
  end function strip_force_direction

  !> A strip's normal depth into the SMOOTH wheel, minus its gradient (the strip force's
  !> direction and moment) and the gradient of its deepest point's lateral position. The
  !> strip search's wheel is a chain of cones: a strip's depth kinks, and the direction's
  !> chord slope jumps, wherever its deepest point crosses a profile point (summed over a
  !> flange-root patch the distributed force jumped by 20-40 N every few micrometres, and BDF's
  !> steps collapsed in the TGV profile scene's curve), and on a yawed line the cones' deepest
  !> point sits on a profile point for a while, then leaves it (the force then jumped by ~26 N
  !> every micrometre on the flange face of a yawed wheelset). Here the wheel is the natural
  !> cubic spline r_h(y) through the profile points (C2: smooth_wheel_radius) and the deepest
  !> point of the line p + s d is found on it by Newton's method from the cones' point p:
  !>    D(s) = r_h(q_y) - rho(q),  q = p + s d,  D_s = r_h' d_y - s_xz / rho = 0,
  !>    D_ss = r_h'' d_y^2 - (a^2 rho^2 - s_xz^2) / rho^3   (s_xz = q_x d_x + q_z d_z, a^2 = d_x^2 + d_z^2)
  !> (stopping at the cones' point if D is not concave there). At q, with k = r_h'(q_y),
  !> k_y = r_h''(q_y): delta = D / sqrt(1 + k^2) and, the wheel displaced by u and turned by
  !> theta (q moves by -u - theta x q relative to it; by the envelope theorem D's own shift
  !> along the line does not count),
  !>    G = -grad delta = ((-e_rho + k e_y), q x (-e_rho + k e_y)) / sqrt(1 + k^2)
  !>                      + D k k_y / (1 + k^2)^(3/2) grad q_y,
  !> grad q_y from deepest_point_py_gradient (the point's shift along the line included).
  pure subroutine smooth_line_depth(p, d, j, y, r, m, p4, q, js, depth, g, gpy)
    real(wp), intent(in) :: p(3)            !< deepest point on the cones, intermediate frame [m]
    real(wp), intent(in) :: d(3)            !< the line's direction, intermediate frame
    integer, intent(in) :: j                !< the cone of p (segment j, j + 1)
    real(wp), intent(in) :: y(:), r(:)      !< profile points: lateral position, radius [m]
    real(wp), intent(in) :: m(:), p4(:)     !< the wheel spline's d2r/dy2 [1/m], d4r/dy4 [1/m^3] at the points
    real(wp), intent(out) :: q(3)           !< the deepest point on the smooth wheel [m]
    integer, intent(out) :: js              !< its segment
    real(wp), intent(out) :: depth          !< normal depth into the smooth wheel [m]
    real(wp), intent(out) :: g(6)           !< -d depth / d (translation, rotation), intermediate frame
    real(wp), intent(out) :: gpy(6)         !< d q_y / d (translation, rotation)
    !> Newton iterations on the line offset (to a step below 1e-11 m: the depth is then exact to
    !> ~1e-22 m, D being stationary there)
    integer, parameter :: max_iterations = 8
    real(wp) :: s, ds, rh, k, ky, rho, sxz, a2, dd, root, h, t, u, h2, h3, t2, u2
    integer :: it, n
    n = size(y)
    a2 = d(1)**2 + d(3)**2
    s = 0
    js = j
    do it = 1, max_iterations
      q = p + s * d
      js = hunt(q(2), js)
      ! the quintic spline at q_y (smooth_wheel_radius written out: the hot path of the distributed
      ! force, called per strip and iteration)
      h = y(js + 1) - y(js)
      t = min(max((q(2) - y(js)) / h, 0.0_wp), 1.0_wp)
      u = 1 - t
      t2 = t * t; u2 = u * u; h2 = h * h; h3 = h2 * h
      k = (r(js + 1) - r(js)) / h + h / 6 * (-(3 * u2 - 1) * m(js) + (3 * t2 - 1) * m(js + 1)) &
          + h3 * (-(u2 * (u2 / 24 - 1.0_wp / 12) + 7.0_wp / 360) * p4(js) &
                  + (t2 * (t2 / 24 - 1.0_wp / 12) + 7.0_wp / 360) * p4(js + 1))
      ky = u * m(js) + t * m(js + 1) + h2 / 6 * ((u2 - 1) * u * p4(js) + (t2 - 1) * t * p4(js + 1))
      rho = sqrt(q(1)**2 + q(3)**2)
      sxz = q(1) * d(1) + q(3) * d(3)
      dd = ky * d(2)**2 - (a2 * rho**2 - sxz**2) / rho**3
      if (.not. (dd < 0)) exit            ! not a maximum here: keep the point
      ds = -(k * d(2) - sxz / rho) / dd
      ! converged: keep the point just evaluated (D is stationary there to ~1e-11 m)
      if (abs(ds) < 1.0e-11_wp) exit
      s = s + ds
    end do
    rh = u * r(js) + t * r(js + 1) + h2 / 6 * ((u2 - 1) * u * m(js) + (t2 - 1) * t * m(js + 1)) &
         + h2 * h2 * (u * (u2 * (u2 / 120 - 1.0_wp / 36) + 7.0_wp / 360) * p4(js) &
                      + t * (t2 * (t2 / 120 - 1.0_wp / 36) + 7.0_wp / 360) * p4(js + 1))
    root = sqrt(1 + k**2)
    depth = (rh - rho) / root
    g(1:3) = [-q(1) / rho, k, -q(3) / rho] / root
    g(4:6) = [q(2) * g(3) - q(3) * g(2), q(3) * g(1) - q(1) * g(3), q(1) * g(2) - q(2) * g(1)]
    gpy = deepest_point_py_gradient(q, d, k, .true., ky)
    g = g + (rh - rho) * k * ky / root**3 * gpy
  contains
    !> the segment holding yq, hunted from j0 (clamped to the profile); rd_strip_contact's
    !> hunt_segment does the same in the strip search, but that module uses this one, and a
    !> function of another module is not inlined on this hot path
    pure integer function hunt(yq, j0) result(jj)
      real(wp), intent(in) :: yq
      integer, intent(in) :: j0
      jj = j0
      do while (jj < n - 1)
        if (.not. (yq > y(jj + 1))) exit
        jj = jj + 1
      end do
      do while (jj > 1)
        if (.not. (yq < y(jj))) exit
        jj = jj - 1
      end do
    end function hunt
  end subroutine smooth_line_depth

  !> The smooth wheel of smooth_line_depth at lateral position yq on segment j (clamped to
  !> it): the natural quintic spline r_h through the profile points (second and fourth
  !> derivatives m, p4 at the points; rd_natural_splines has the formulas), its slope r_h'
  !> and second derivative r_h''. C4 along the profile: the depth gradient holds r_h''
  !> (through the deepest point's shift along its line), so the distributed force is C1 only
  !> if r_h'' is; the natural cubic spline's r_h''' jumped at every profile point and the
  !> flange force kinked wherever a strip's deepest point crossed one. (A cubic Hermite with
  !> the points' slopes, C1, made the force jump there: bench/contact_smoothness.)
  pure subroutine smooth_wheel_radius(yq, j, y, r, m, p4, r_h, k, ky)
    real(wp), intent(in) :: yq              !< lateral position on the wheel [m]
    integer, intent(in) :: j                !< the segment (points j, j + 1)
    real(wp), intent(in) :: y(:), r(:), m(:), p4(:)  !< profile points: y, radius, spline d2r/dy2, d4r/dy4
    real(wp), intent(out) :: r_h, k, ky     !< radius [m], dr/dy, d2r/dy2 [1/m]
    real(wp) :: h, t, u
    h = y(j + 1) - y(j)
    t = min(max((yq - y(j)) / h, 0.0_wp), 1.0_wp)
    u = 1 - t
    r_h = u * r(j) + t * r(j + 1) + h * h / 6 * ((u**3 - u) * m(j) + (t**3 - t) * m(j + 1)) &
          + h**4 * (quintic_e(u) * p4(j) + quintic_e(t) * p4(j + 1))
    k = (r(j + 1) - r(j)) / h + h / 6 * (-(3 * u * u - 1) * m(j) + (3 * t * t - 1) * m(j + 1)) &
        + h**3 * (-quintic_de(u) * p4(j) + quintic_de(t) * p4(j + 1))
    ky = u * m(j) + t * m(j + 1) + h * h / 6 * ((u**3 - u) * p4(j) + (t**3 - t) * p4(j + 1))
  contains
    !> e(s) = s^5/120 - s^3/36 + 7 s/360 and its derivative (rd_natural_splines)
    pure real(wp) function quintic_e(x)
      real(wp), intent(in) :: x
      quintic_e = x * (x * x * (x * x / 120 - 1.0_wp / 36) + 7.0_wp / 360)
    end function quintic_e
    pure real(wp) function quintic_de(x)
      real(wp), intent(in) :: x
      quintic_de = x * x * (x * x / 24 - 1.0_wp / 12) + 7.0_wp / 360
    end function quintic_de
  end subroutine smooth_wheel_radius

end module rd_strip_potential
