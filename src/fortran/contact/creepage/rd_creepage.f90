!> Creepages of a wheel-rail contact patch (thesis 3.6.1, eqs. 3.34-3.38; 4.80-4.86):
!>   xi  = v_x / V_ref,  eta = v_y / V_ref,  phi = omega_n / V_ref  [-, -, 1/m]
!> v: velocity of the wheel's MATERIAL point at the contact relative to the rail, in
!> contact-frame components (x_c rolling, y_c lateral, n normal from rail into wheel;
!> docs/conventions.md); omega_n: wheel angular velocity relative to the rail along n.
!>
!> Regularised reference speed: V_ref = sqrt(V^2 + v0^2), V the rolling speed (mean of the
!> forward and circumferential speeds). For |V| >> v0 this is |V| (relative error
!> v0^2/(2V^2)); at standstill V_ref = v0, so creepages stay finite and continuous and the
!> creep forces become viscous-like (force ~ slip velocity / v0) below about v0.
module rd_creepage
  use rd_kinds, only: wp
  implicit none
  private
  public :: creepage_t, creepages_from_components, creepages_from_velocities, reference_speed

  !> Default regularisation speed v0 [m/s].
  real(wp), parameter, public :: default_creep_v0 = 0.05_wp

  type :: creepage_t
    real(wp) :: xi = 0.0_wp    !< longitudinal creepage [-]
    real(wp) :: eta = 0.0_wp   !< lateral creepage [-]
    real(wp) :: phi = 0.0_wp   !< spin creepage [1/m]
    real(wp) :: v_ref = 0.0_wp !< regularised reference speed used [m/s]
  end type creepage_t

contains

  !> Regularised reference speed sqrt(V^2 + v0^2) [m/s] (v0 > 0 keeps it positive).
  elemental function reference_speed(rolling_speed, v0) result(v_ref)
    real(wp), intent(in) :: rolling_speed, v0
    real(wp) :: v_ref
    v_ref = sqrt(rolling_speed**2 + v0**2)
  end function reference_speed

  !> Creepages from components already projected on the contact frame:
  !> slip_velocity(1:2) = (v_x, v_y) of the wheel material point relative to the rail [m/s],
  !> spin_rate = omega_n [rad/s], rolling_speed V [m/s] (sign irrelevant), v0 [m/s] > 0.
  pure subroutine creepages_from_components(slip_velocity, spin_rate, rolling_speed, v0, creep)
    real(wp), intent(in) :: slip_velocity(2), spin_rate, rolling_speed, v0
    type(creepage_t), intent(out) :: creep
    creep%v_ref = reference_speed(rolling_speed, v0)
    creep%xi = slip_velocity(1) / creep%v_ref
    creep%eta = slip_velocity(2) / creep%v_ref
    creep%phi = spin_rate / creep%v_ref
  end subroutine creepages_from_components

  !> Creepages from vectors, all in one common frame (e.g. track components):
  !> v_wheel_centre, v_wheel_point (the wheel material point at the contact), v_rail_point
  !> (rail material point at the contact, zero on a fixed track), omega_wheel, omega_rail
  !> [rad/s], contact_frame(:, 1:3) = unit vectors x_c, y_c, n as columns.
  !> The wheel point velocity is thesis eq. 4.80 = wheelset velocity (4.81) + circumferential
  !> velocity (4.82); projected on the contact frame as eqs. 3.34, 3.36, 3.38.
  !> Rolling speed V = ( |forward| + |circumferential| ) / 2 with
  !> forward = (v_wheel_centre - v_rail_point) . x_c and
  !> circumferential = (v_wheel_centre - v_wheel_point) . x_c (the omega x r part).
  pure subroutine creepages_from_velocities(v_wheel_centre, v_wheel_point, v_rail_point, &
                                            omega_wheel, omega_rail, contact_frame, v0, creep)
    real(wp), intent(in) :: v_wheel_centre(3), v_wheel_point(3), v_rail_point(3)
    real(wp), intent(in) :: omega_wheel(3), omega_rail(3), contact_frame(3, 3), v0
    type(creepage_t), intent(out) :: creep
    real(wp) :: v_rel(3), forward, circumferential, slip(2), spin_rate
    v_rel = v_wheel_point - v_rail_point
    slip(1) = dot_product(v_rel, contact_frame(:, 1))
    slip(2) = dot_product(v_rel, contact_frame(:, 2))
    spin_rate = dot_product(omega_wheel - omega_rail, contact_frame(:, 3))
    forward = dot_product(v_wheel_centre - v_rail_point, contact_frame(:, 1))
    circumferential = dot_product(v_wheel_centre - v_wheel_point, contact_frame(:, 1))
    call creepages_from_components(slip, spin_rate, 0.5_wp * (abs(forward) + abs(circumferential)), &
                                   v0, creep)
  end subroutine creepages_from_velocities
end module rd_creepage
