!> Straight level track along X (A = I, docs/conventions.md): the frames a vehicle is built
!> in (its elements' free lengths and preloads, rd_static_preload), whatever the track where
!> a scene starts.
module rd_level_straight_track
  use rd_kinds, only: wp
  use rd_track_point, only: track_point_t, track_geometry_t
  implicit none
  private
  public :: level_straight_track_t

  type, extends(track_geometry_t) :: level_straight_track_t
  contains
    procedure :: evaluate => level_evaluate
    procedure :: length => level_length
  end type level_straight_track_t

contains

  pure function level_evaluate(self, sigma) result(point)
    class(level_straight_track_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: point
    point%sigma = sigma
    point%r = [sigma, 0.0_wp, 0.0_wp]
    point%dr = [1.0_wp, 0.0_wp, 0.0_wp]
    point%a = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
  end function level_evaluate

  !> Unbounded: a vehicle can be built at any sigma.
  pure function level_length(self) result(total)
    class(level_straight_track_t), intent(in) :: self
    real(wp) :: total
    total = huge(1.0_wp)
  end function level_length
end module rd_level_straight_track
