!> Knife-edge contact of conical wheels (thesis 5.3.3, eqs. 5.2-5.7, fig. 5.13): each wheel
!> is a cone of angle gamma and radius r0 at lateral distance e0 from the wheelset centre,
!> each rail a longitudinal line (knife edge) at Y = +-e0 in the plane of the rail tops.
!>
!> For the left wheel the cone is r(e) = r0 + (e0 - e) tan(gamma) (thesis 5.4). Eqs. 5.2-5.3
!> place the contact where the knife edge lies under the wheel and measure the approach
!> delta along the normal of the rolled cone: delta = (vertical overlap) cos(gamma + phi).
!> The same number is the radial overlap in the wheelset frame times cos(gamma) (distance
!> of a point from a line is invariant under the roll rotation); we evaluate that form with
!> the exact deepest point of the (possibly yawed) edge inside the cone (rd_line_cone),
!> which reduces to eqs. 5.2-5.4 at zero yaw. (The thesis writes 5.3 as
!> delta cos + delta tan sin = delta / cos(gamma + phi), i.e. vertical overlap = delta / cos.)
!>
!> Optional flange: beyond a lateral clearance the wheel meets a lateral stop; the model
!> returns a PATCH_FLANGE_SPRING patch whose "penetration" is the lateral overlap
!> |y| - clearance, normal horizontal, for a linear lateral stiffness in the normal model.
module rd_knife_edge_contact
  use rd_kinds, only: wp, pi
  use rd_contact_patch, only: patch_geometry_t, wheel_contact_t, PATCH_TREAD, PATCH_FLANGE_SPRING
  use rd_line_cone, only: line_cone_max_depth
  implicit none
  private
  public :: knife_edge_t, knife_wheel_contact

  type :: knife_edge_t
    real(wp) :: cone_angle = 0.1_wp        !< gamma [rad] (thesis table 5.7)
    real(wp) :: e0 = 0.75_wp               !< half distance between the contact points [m]
    real(wp) :: r0 = 0.45_wp               !< nominal rolling radius [m]
    real(wp) :: flange_clearance = -1.0_wp !< lateral clearance to the flange stop [m]; <= 0: none
    real(wp) :: rail_crown_radius = 0.3_wp !< rail head radius reported for Hertz [m]
  end type knife_edge_t

contains

  !> Left wheel on the left knife edge; pose as in rd_strip_contact.
  pure subroutine knife_wheel_contact(knife, y, z, phi, psi, res)
    type(knife_edge_t), intent(in) :: knife
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t), intent(out) :: res
    real(wp) :: bt(3, 3), d(3), a, cp, sp, cs, ss, p0(3), t0, rho, py0, tau, dep, k, pw(3), rr, nloc(3), n(3), er(3)
    logical :: found
    type(patch_geometry_t) :: p

    cp = cos(phi); sp = sin(phi); cs = cos(psi); ss = sin(psi)
    bt(1, :) = [cs, ss, 0.0_wp]
    bt(2, :) = [-ss * cp, cs * cp, sp]
    bt(3, :) = [ss * sp, -cs * sp, cp]
    d = bt(:, 1)
    a = hypot(d(1), d(3))
    p0 = matmul(bt, [0.0_wp, knife%e0 - y, -z])
    t0 = -(p0(1) * d(1) + p0(3) * d(3)) / a**2
    rho = hypot(p0(1) + t0 * d(1), p0(3) + t0 * d(3))
    py0 = p0(2) + t0 * d(2)
    k = -tan(knife%cone_angle)
    ! the cone is unbounded: one long segment around e0
    call line_cone_max_depth(t0, rho, py0, a, d(2), knife%e0 - 1, knife%r0 - k, knife%e0 + 1, knife%r0 + k, found, dep, tau)
    res%n_patches = 0
    res%max_penetration = dep * cos(knife%cone_angle)
    if (res%max_penetration > 0) then
      pw = p0 + (t0 + tau) * d
      rr = knife%r0 + k * (pw(2) - knife%e0)
      ! wheel normal at pw: outward n = (e_rho - k e_y)/sqrt(1 + k^2); contact normal = -n
      er = [pw(1), 0.0_wp, pw(3)] / hypot(pw(1), pw(3))
      nloc = -(er - [0.0_wp, k, 0.0_wp]) / sqrt(1 + k**2)
      n = matmul(nloc, bt)
      p%kind = PATCH_TREAD
      p%penetration = res%max_penetration
      p%point_rail = [t0 + tau, knife%e0, 0.0_wp]
      p%point_wheel = pw
      p%s_wheel = pw(2) - knife%e0
      p%u_rail = 0
      p%normal = n
      p%contact_angle = atan2(n(2), n(3))
      p%rolling_radius = rr
      p%curv_wheel_lat = 0
      p%curv_wheel_roll = cos(knife%cone_angle) / rr
      p%curv_rail_lat = 1 / knife%rail_crown_radius
      p%curv_rail_roll = 0
      p%u_rail_min = 0; p%u_rail_max = 0
      p%strip_length = 2 * sqrt(max(2 * rr * dep, 0.0_wp))
      res%n_patches = 1
      res%patch(1) = p
    end if
    if (knife%flange_clearance > 0 .and. y > knife%flange_clearance) then
      p = patch_geometry_t()
      p%kind = PATCH_FLANGE_SPRING
      p%penetration = y - knife%flange_clearance
      p%point_rail = [0.0_wp, knife%e0, 0.0_wp]
      p%point_wheel = matmul(bt, [0.0_wp, knife%e0 - y, -z])
      p%normal = [0.0_wp, -1.0_wp, 0.0_wp]
      p%contact_angle = -0.5_wp * pi
      p%rolling_radius = knife%r0
      res%n_patches = res%n_patches + 1
      res%patch(res%n_patches) = p   ! not in max_penetration: a lateral stop, not a vertical support
    end if
  end subroutine knife_wheel_contact

end module rd_knife_edge_contact
