!> The track frame from its three angles and their sigma-derivatives (thesis 4.3.1).
!>
!> Shared by every track parameterization: given heading psi(sigma), gradient
!> g(sigma) = dz/dsigma and superelevation h(sigma), each with two derivatives, it fills
!> the angles, A = R_z(psi) R_y(theta) R_x(phi) (thesis eq. 4.5), dA, d2A, omega, domega,
!> dr and d2r of a track_point_t (docs/conventions.md):
!>     theta = -atan(g)                 (positive gradient lifts X_T)
!>     phi   = asin(h / cant_base)      (thesis eq. 3.1 with D = cant_base)
!> sigma is the arc length of the horizontal projection, so dr = (cos psi, sin psi, g) and
!> |dr| = sqrt(1 + g^2).
!>
!> Derivatives. With the product rule, A^T dA = skew(w) where (track components)
!>     w = psi' R_x^T R_y^T e_z + theta' R_x^T e_y + phi' e_x
!>       = (phi' - psi' s_th,  psi' s_ph c_th + theta' c_ph,  psi' c_ph c_th - theta' s_ph),
!> hence dA = A skew(w) and d2A = dA skew(w) + A skew(w'), with w' differentiated
!> term by term below. (This is the product rule on R_z R_y R_x collected through
!> A^T dA; the thesis appendix A writes the nine entries out instead.)
module rd_track_frame
  use rd_kinds, only: wp
  use rd_track_point, only: track_point_t
  implicit none
  private
  public :: set_track_frame

contains

  !> Fill everything in `point` except sigma and r.
  !> psi, dpsi, d2psi: heading [rad] and its derivatives; g, dg, d2g: gradient [-] and
  !> derivatives; h, dh, d2h: superelevation [m] and derivatives; cant_base [m] > |h|.
  pure subroutine set_track_frame(point, psi, dpsi, d2psi, g, dg, d2g, h, dh, d2h, cant_base)
    type(track_point_t), intent(inout) :: point
    real(wp), intent(in) :: psi, dpsi, d2psi, g, dg, d2g, h, dh, d2h, cant_base
    real(wp) :: theta, dtheta, d2theta, phi, dphi, d2phi, one_g2, root
    real(wp) :: cps, sps, cth, sth, cph, sph
    real(wp) :: w(3), dw(3)

    ! grade angle (conventions.md): theta = -atan(g)
    one_g2 = 1 + g * g
    theta = -atan(g)
    dtheta = -dg / one_g2
    d2theta = -d2g / one_g2 + 2 * g * dg * dg / one_g2**2
    ! cant angle, thesis eq. 3.1: sin(phi) = h / cant_base
    root = sqrt((cant_base - h) * (cant_base + h))
    phi = asin(h / cant_base)
    dphi = dh / root
    d2phi = d2h / root + h * dh * dh / root**3

    cps = cos(psi); sps = sin(psi)
    cth = cos(theta); sth = sin(theta)
    cph = cos(phi); sph = sin(phi)

    point%heading = psi
    point%curvature = dpsi
    point%dcurvature = d2psi
    point%grade_angle = theta
    point%cant_angle = phi
    point%superelevation = h

    point%dr = [cps, sps, g]
    point%d2r = [-sps * dpsi, cps * dpsi, dg]

    w(1) = dphi - dpsi * sth
    w(2) = dpsi * sph * cth + dtheta * cph
    w(3) = dpsi * cph * cth - dtheta * sph
    dw(1) = d2phi - d2psi * sth - dpsi * cth * dtheta
    dw(2) = d2psi * sph * cth + dpsi * (cph * dphi * cth - sph * sth * dtheta) &
            + d2theta * cph - dtheta * sph * dphi
    dw(3) = d2psi * cph * cth - dpsi * (sph * dphi * cth + cph * sth * dtheta) &
            - d2theta * sph - dtheta * cph * dphi
    point%omega = w
    point%domega = dw

    ! A = R_z(psi) R_y(theta) R_x(phi) written out (thesis eq. 4.5; the product of
    ! rd_rotation's matrices, without temporaries: this runs in every RHS evaluation)
    point%a(:, 1) = [cps * cth, sps * cth, -sth]
    point%a(:, 2) = [cps * sth * sph - sps * cph, sps * sth * sph + cps * cph, cth * sph]
    point%a(:, 3) = [cps * sth * cph + sps * sph, sps * sth * cph - cps * sph, cth * cph]
    point%da = times_skew(point%a, w)
    point%d2a = times_skew(point%da, w) + times_skew(point%a, dw)
  end subroutine set_track_frame

  !> m skew(v), column by column: skew(v) e_j = v x e_j.
  pure function times_skew(m, v) result(r)
    real(wp), intent(in) :: m(3, 3), v(3)
    real(wp) :: r(3, 3)
    r(:, 1) = m(:, 2) * v(3) - m(:, 3) * v(2)
    r(:, 2) = m(:, 3) * v(1) - m(:, 1) * v(3)
    r(:, 3) = m(:, 1) * v(2) - m(:, 2) * v(1)
  end function times_skew
end module rd_track_frame
