!> Rigid contact of a wheelset ("contact table" condition): for a lateral shift y and yaw
!> psi find the height z and roll phi at which both wheels just touch their rails, i.e.
!> the largest signed penetration of each wheel is zero. Newton's method on the two
!> equations with a finite-difference Jacobian (the functions are piecewise smooth; a kink
!> where the contact jumps between two points is crossed by the step limiter).
module rd_rigid_contact
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_RUNTIME
  use rd_contact_patch, only: wheel_contact_t
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT, SIDE_RIGHT
  implicit none
  private
  public :: rigid_contact

contains

  !> z [m] and phi [rad] of rigid contact for shift y [m] and yaw psi [rad]. The optional
  !> results are evaluated at that pose lowered by `lowering` [m] (default 0), so that the
  !> touching points appear as patches with penetration ~ lowering.
  subroutine rigid_contact(geo, y, psi, z, phi, error, left, right, lowering)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y, psi
    real(wp), intent(out) :: z, phi
    type(error_t), allocatable, intent(out) :: error
    type(wheel_contact_t), intent(out), optional :: left, right
    real(wp), intent(in), optional :: lowering
    real(wp), parameter :: tol = 1.0e-12_wp, hz = 1.0e-7_wp, hphi = 1.0e-7_wp, resolution = 1.0e-6_wp
    real(wp) :: g(2), gz(2), gp(2), jac(2, 2), det, dz, dphi, scale, z_reported
    integer :: it
    character(len=160) :: msg
    z = geo%placement%nominal_radius
    phi = 0
    do it = 1, 100
      g = residual(z, phi)
      if (maxval(abs(g)) < tol) exit
      gz = residual(z + hz, phi)
      gp = residual(z, phi + hphi)
      jac(:, 1) = (gz - g) / hz
      jac(:, 2) = (gp - g) / hphi
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      if (.not. (abs(det) > 0)) exit
      dz = -(jac(2, 2) * g(1) - jac(1, 2) * g(2)) / det
      dphi = -(-jac(2, 1) * g(1) + jac(1, 1) * g(2)) / det
      scale = min(1.0_wp, 2.0e-3_wp / max(abs(dz), tiny(1.0_wp)), 5.0e-3_wp / max(abs(dphi), tiny(1.0_wp)))
      z = z + scale * dz
      phi = phi + scale * dphi
      if (abs(scale * dz) < 1.0e-13_wp .and. abs(scale * dphi) < 1.0e-13_wp) exit
    end do
    g = residual(z, phi)
    if (.not. (maxval(abs(g)) < 1.0e-10_wp)) call nested_solve()
    g = residual(z, phi)
    ! accept within the geometric resolution of the polygonal profiles: a chord of length
    ! h on an arc of radius R deviates by h^2/(8R) (0.2 mm on the R12 flange tip: 0.4 um),
    ! and the maximum penetration may step by that much where the deepest point switches
    if (.not. (maxval(abs(g)) < resolution)) then
      write (msg, '(a,es10.3,a,es10.3,a,es10.3)') 'rigid_contact: no two-wheel contact found for y = ', y, &
        ' m, yaw = ', psi, ' rad; residual ', maxval(abs(g))
      call make_error(error, RD_ERR_RUNTIME, trim(msg))
      return
    end if
    z_reported = z
    if (present(lowering)) z_reported = z - lowering
    if (present(left)) call wheel_contact(geo, SIDE_LEFT, y, z_reported, phi, psi, left)
    if (present(right)) call wheel_contact(geo, SIDE_RIGHT, y, z_reported, phi, psi, right)
  contains
    !> Fallback across kinks (two-point contact): phi by bracketing on the right wheel's
    !> penetration, with z solved for each phi so that the left wheel just touches. Both
    !> functions are monotonic (raising z separates the left wheel; rolling with the left
    !> wheel kept in contact presses the right one), so regula falsi always converges.
    subroutine nested_solve()
      real(wp) :: pa, pb, ha, hb, pc, hc
      integer :: side_a, side_b, iter
      pa = phi; ha = h_of(pa)
      pb = pa + sign(1.0e-3_wp, -ha); hb = h_of(pb)
      do iter = 1, 60
        if (ha * hb <= 0) exit
        pa = pb; ha = hb
        pb = pb + sign(1.0e-3_wp, -hb); hb = h_of(pb)
      end do
      side_a = 0; side_b = 0
      do iter = 1, 200
        pc = (pa * hb - pb * ha) / (hb - ha)
        hc = h_of(pc)
        if (abs(hc) < 1.0e-13_wp .or. abs(pb - pa) < 1.0e-14_wp) exit
        if (hc * hb < 0) then
          pa = pb; ha = hb; pb = pc; hb = hc
          side_a = 0
        else
          pb = pc; hb = hc
          side_a = side_a + 1
          if (side_a >= 2) ha = 0.5_wp * ha       ! Illinois modification
        end if
      end do
      phi = pc
      z = z_of(phi)
    end subroutine nested_solve

    real(wp) function h_of(pp) result(h)
      real(wp), intent(in) :: pp
      type(wheel_contact_t) :: b
      real(wp) :: zz
      zz = z_of(pp)
      call wheel_contact(geo, SIDE_RIGHT, y, zz, pp, psi, b)
      h = b%max_penetration
    end function h_of

    !> z at which the left wheel just touches for roll pp (regula falsi, Illinois)
    real(wp) function z_of(pp) result(zc)
      real(wp), intent(in) :: pp
      real(wp) :: za, zb, ga, gb, gc
      integer :: iter, stuck
      za = z; ga = g_left(za, pp)
      zb = za + sign(1.0e-3_wp, ga); gb = g_left(zb, pp)
      do iter = 1, 100
        if (ga * gb <= 0) exit
        za = zb; ga = gb
        zb = zb + sign(1.0e-3_wp, gb); gb = g_left(zb, pp)
      end do
      zc = zb
      stuck = 0
      do iter = 1, 200
        zc = (za * gb - zb * ga) / (gb - ga)
        gc = g_left(zc, pp)
        if (abs(gc) < 1.0e-13_wp .or. abs(zb - za) < 1.0e-14_wp) exit
        if (gc * gb < 0) then
          za = zb; ga = gb; zb = zc; gb = gc
          stuck = 0
        else
          zb = zc; gb = gc
          stuck = stuck + 1
          if (stuck >= 2) ga = 0.5_wp * ga
        end if
      end do
    end function z_of

    real(wp) function g_left(zz, pp) result(gl)
      real(wp), intent(in) :: zz, pp
      type(wheel_contact_t) :: a
      call wheel_contact(geo, SIDE_LEFT, y, zz, pp, psi, a)
      gl = a%max_penetration
    end function g_left

    function residual(zz, pp) result(r)
      real(wp), intent(in) :: zz, pp
      real(wp) :: r(2)
      type(wheel_contact_t) :: a, b
      call wheel_contact(geo, SIDE_LEFT, y, zz, pp, psi, a)
      call wheel_contact(geo, SIDE_RIGHT, y, zz, pp, psi, b)
      r = [a%max_penetration, b%max_penetration]
    end function residual
  end subroutine rigid_contact

end module rd_rigid_contact
