!> Intersection of a straight line (an extruded rail point) with a conical wheel segment
!> (thesis 4.7.1.5, eqs. 4.64-4.71), and the deepest point of the line inside the cone.
!>
!> Everything is in the wheelset's intermediate frame (yaw and roll applied, no spin): the
!> axle is the y axis and the cone of segment j has radius r(y) = r1 + k (y - y1),
!> k = (r2 - r1)/(y2 - y1). The line is p(t) = p0 + t d with |d| = 1 (t = track x).
!>
!> The thesis parametrises the cone by the angle zeta and the segment parameter alpha and
!> obtains A cos(zeta) + B sin(zeta) + C = 0 (4.67) solved by a half-angle tangent (4.68),
!> which is singular for C = A and needs alpha from 4.69 or 4.70 depending on the segment's
!> orientation. The same intersection written in the line parameter is a quadratic,
!>   (p0x + t dx)^2 + (p0z + t dz)^2 = (R0 + k dy t)^2,  R0 = r1 + k (p0y - y1),
!> with alpha = (p_y(t) - y1)/(y2 - y1) and zeta = atan2(-p_x, -p_z) recovered from the
!> root; it has no singular orientation. Entry and exit points (the two roots) bound the
!> strip (4.72).
module rd_line_cone
  use rd_kinds, only: wp
  implicit none
  private
  public :: line_cone_roots, line_cone_max_depth, line_cone_max_depth_slope

contains

  !> Roots t of the line with the (unbounded, single-nappe) cone through the segment,
  !> sorted; alpha(i) tells whether the root lies on the segment (0 <= alpha <= 1).
  pure subroutine line_cone_roots(p0, d, y1, r1, y2, r2, nroot, t, alpha)
    real(wp), intent(in) :: p0(3), d(3), y1, r1, y2, r2
    integer, intent(out) :: nroot
    real(wp), intent(out) :: t(2), alpha(2)
    real(wp) :: k, r0, qa, qb, qc, disc, q, tt(2), rr
    integer :: i, m
    nroot = 0; t = 0; alpha = 0
    if (.not. (y2 > y1)) return
    k = (r2 - r1) / (y2 - y1)
    r0 = r1 + k * (p0(2) - y1)
    qa = d(1)**2 + d(3)**2 - (k * d(2))**2
    qb = 2 * (p0(1) * d(1) + p0(3) * d(3) - k * d(2) * r0)
    qc = p0(1)**2 + p0(3)**2 - r0**2
    m = 0
    if (abs(qa) <= 1.0e-14_wp * (abs(qb) + abs(qc))) then
      if (qb /= 0) then
        m = 1; tt(1) = -qc / qb
      end if
    else
      disc = qb**2 - 4 * qa * qc
      if (disc < 0) return
      ! numerically stable pair (Numerical Recipes 5.6)
      q = -0.5_wp * (qb + sign(sqrt(disc), qb))
      m = 2
      tt(1) = q / qa
      if (q /= 0) then
        tt(2) = qc / q
      else
        tt(2) = tt(1)
      end if
    end if
    do i = 1, m
      rr = r0 + k * d(2) * tt(i)        ! the radius must be positive: the wheel's nappe
      if (rr > 0) then
        nroot = nroot + 1
        t(nroot) = tt(i)
        alpha(nroot) = (p0(2) + tt(i) * d(2) - y1) / (y2 - y1)
      end if
    end do
    if (nroot == 2 .and. t(2) < t(1)) then
      t = t([2, 1]); alpha = alpha([2, 1])
    end if
  end subroutine line_cone_roots

  !> Largest radial depth r(p_y) - rho of the line inside the segment's cone, restricted
  !> to the part of the line whose p_y lies on the segment. With rho^2 = rho_min^2 +
  !> a^2 (t - t0)^2 (a^2 = dx^2 + dz^2, t0 the closest approach to the axle) the depth
  !> f(tau) = r(p_y(t0) + dy tau) - sqrt(rho_min^2 + a^2 tau^2) is concave; its stationary
  !> point is tau* = c rho_min / (a sqrt(a^2 - c^2)), c = k dy, clamped to the segment.
  !> Returns found = .false. if no part of the line lies over the segment.
  pure subroutine line_cone_max_depth(t0, rho_min, py0, a, dy, y1, r1, y2, r2, found, depth, tau)
    real(wp), intent(in) :: t0, rho_min, py0, a, dy, y1, r1, y2, r2
    logical, intent(out) :: found
    real(wp), intent(out) :: depth, tau
    found = .false.; depth = -huge(1.0_wp); tau = 0
    if (.not. (y2 > y1)) return
    call line_cone_max_depth_slope(t0, rho_min, py0, a, dy, y1, r1, y2, (r2 - r1) / (y2 - y1), &
                                   found, depth, tau)
  end subroutine line_cone_max_depth

  !> line_cone_max_depth with the cone's slope k = (r2 - r1)/(y2 - y1) given (y2 > y1 is
  !> the caller's to ensure). The strip search (rd_strip_contact, strip_depths) writes these
  !> operations out in its hot loop, with k from the wheel surface (wheel_surface_t%cone_slope),
  !> so that they are inlined: a change here must be made there too.
  pure subroutine line_cone_max_depth_slope(t0, rho_min, py0, a, dy, y1, r1, y2, k, found, depth, tau)
    real(wp), intent(in) :: t0, rho_min, py0, a, dy, y1, r1, y2, k
    logical, intent(out) :: found
    real(wp), intent(out) :: depth, tau
    !> lateral margin [m] inside which the clamp to the segment is skipped (see below)
    real(wp), parameter :: inside_margin = 1.0e-9_wp
    real(wp) :: c, ta, tb, tmp, py
    logical :: inside
    found = .false.; depth = -huge(1.0_wp); tau = 0
    c = k * dy
    ! Stationary point strictly inside the segment (the common case): the clamp to [ta, tb]
    ! is then the identity and its two divisions are skipped. Exact: with p_y 1 nm inside
    ! [y1, y2], ta and tb (rounding error below 1e-15 m / |dy| for |y - py0| < 1 km) cannot
    ! cross tau. Otherwise, and for a NaN, the general path.
    inside = .false.
    if (dy /= 0 .and. abs(c) < a) then
      tau = c * rho_min / (a * sqrt(a**2 - c**2))
      py = py0 + dy * tau
      inside = py > y1 + inside_margin .and. py < y2 - inside_margin
    end if
    if (.not. inside) then
      if (dy /= 0) then
        ta = (y1 - py0) / dy
        tb = (y2 - py0) / dy
        if (ta > tb) then
          tmp = ta; ta = tb; tb = tmp
        end if
      else
        if (py0 < y1 .or. py0 > y2) return
        ta = -huge(1.0_wp); tb = huge(1.0_wp)
      end if
      if (abs(c) < a) then
        tau = c * rho_min / (a * sqrt(a**2 - c**2))
      else if (c > 0) then
        tau = tb
      else
        tau = ta
      end if
      tau = min(max(tau, ta), tb)
    end if
    found = .true.
    depth = r1 + k * (py0 + dy * tau - y1) - sqrt(rho_min**2 + (a * tau)**2)
    if (t0 /= t0) depth = t0   ! propagate a NaN pose instead of hiding it
  end subroutine line_cone_max_depth_slope

end module rd_line_cone
