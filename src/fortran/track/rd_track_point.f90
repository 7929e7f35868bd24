!> The track seen from one arc length: what the equations of motion and the contact
!> need of the track frame (docs/conventions.md, thesis 4.3.1 and 4.4).
!>
!> `track_geometry_t` is the abstract interface the dynamics codes against; the
!> segment track (rd_track) and the surveyed-points track extend it, and tests may
!> supply their own simple tracks.
module rd_track_point
  use rd_kinds, only: wp
  implicit none
  private
  public :: track_point_t, track_geometry_t

  !> Everything about the track frame at arc length sigma. Derivatives are with
  !> respect to sigma (not time); vectors in fixed-frame components unless said.
  type :: track_point_t
    real(wp) :: sigma = 0          !< arc length of the horizontal projection [m]
    real(wp) :: r(3) = 0           !< centreline position p(sigma) [m]
    real(wp) :: dr(3) = 0          !< dp/dsigma [-]
    real(wp) :: d2r(3) = 0         !< d2p/dsigma2 [1/m]
    real(wp) :: a(3, 3) = 0        !< A(sigma): track -> fixed rotation (thesis eq. 4.5)
    real(wp) :: da(3, 3) = 0       !< dA/dsigma [1/m]
    real(wp) :: d2a(3, 3) = 0      !< d2A/dsigma2 [1/m^2]
    !> w with skew(w) = A^T dA/dsigma: angular velocity of the frame per unit sigma,
    !> track-frame components [rad/m]. The frame's angular velocity is V w.
    real(wp) :: omega(3) = 0
    real(wp) :: domega(3) = 0      !< dw/dsigma, track-frame components [rad/m^2]
    real(wp) :: heading = 0        !< psi_t [rad]
    real(wp) :: grade_angle = 0    !< theta_t = -atan(gradient) [rad]
    real(wp) :: cant_angle = 0     !< phi_t, positive lifts the left rail [rad]
    real(wp) :: curvature = 0      !< kappa = dpsi_t/dsigma, > 0 for a left-hand curve [1/m]
    real(wp) :: dcurvature = 0     !< dkappa/dsigma [1/m^2]
    real(wp) :: superelevation = 0 !< left rail over right rail [m]
  end type track_point_t

  type, abstract :: track_geometry_t
  contains
    procedure(evaluate_i), deferred :: evaluate
    procedure(length_i), deferred :: length
  end type track_geometry_t

  abstract interface
    !> Track frame at arc length sigma. Beyond the ends the track continues
    !> tangentially (straight, constant cant) so that a vehicle can run off.
    pure function evaluate_i(self, sigma) result(point)
      import :: track_geometry_t, track_point_t, wp
      class(track_geometry_t), intent(in) :: self
      real(wp), intent(in) :: sigma
      type(track_point_t) :: point
    end function evaluate_i
    pure function length_i(self) result(total)
      import :: track_geometry_t, wp
      class(track_geometry_t), intent(in) :: self
      real(wp) :: total
    end function length_i
  end interface
end module rd_track_point
