!> Helpers shared by the contact-geometry tests: a check that stops the test program with a message, and closed-form test profiles
!> (a conical wheel, a circular rail head) with the rail-head centre of their placement; the poses of the strip forces'
!> gradient checks.
module geometry_test_support
  use rd_kinds, only: wp
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  implicit none
  private
  public :: cone_wheel_profile, circle_rail_profile, circle_rail_centre_y
  public :: gradient_pose_y, gradient_pose_yaw, gradient_pose_name, gradient_pose_side

  !> Single-patch poses of the Manchester wheelset (S1002 / 60E1 1:40) where the strip
  !> forces' gradients are checked: tread, flange root, the flange root / flange jump and the
  !> flange of the left wheel, yawed, and the right wheel on its tread and its flange (lateral
  !> shift [m], yaw [rad], label, side: 1 left, 2 right as rd_contact_geometry's SIDE_*)
  real(wp), parameter :: gradient_pose_y(6) = [3.0e-3_wp, 6.0e-3_wp, 6.25e-3_wp, 7.0e-3_wp, 6.25e-3_wp, -6.25e-3_wp]
  real(wp), parameter :: gradient_pose_yaw(6) = [8.5e-3_wp, 8.5e-3_wp, 1.4e-2_wp, 8.5e-3_wp, 1.4e-2_wp, -1.4e-2_wp]
  character(len=*), parameter :: gradient_pose_name(6) = [character(len=32) :: 'tread 3.0 mm', 'flange root 6.0 mm', &
    'flange root / flange 6.25 mm', 'flange 7.0 mm', 'right wheel, tread at 6.25 mm', 'right wheel, flange at -6.25 mm']
  integer, parameter :: gradient_pose_side(6) = [1, 1, 1, 1, 2, 2]

contains

  !> Conical wheel of conicity lam: F(S) = -lam S for S in [-70, 60] mm, 0.1 mm apart.
  subroutine cone_wheel_profile(lam, prof)
    real(wp), intent(in) :: lam
    type(profile_t), intent(out) :: prof
    integer :: q
    allocate (prof%y(1301), prof%z(1301))
    do q = 1, 1301
      prof%y(q) = -0.070_wp + 1.0e-4_wp * (q - 1)
      prof%z(q) = -lam * prof%y(q)
    end do
    prof%kind = PROFILE_WHEEL
    prof%source = 'cone'
  end subroutine cone_wheel_profile

  !> Circular rail head of radius r, top at the origin, for |u| <= 0.1 m, 0.1 mm apart.
  subroutine circle_rail_profile(r, prof)
    real(wp), intent(in) :: r
    type(profile_t), intent(out) :: prof
    integer :: q
    character(len=16) :: text
    allocate (prof%y(2001), prof%z(2001))
    do q = 1, 2001
      prof%y(q) = -0.1_wp + 1.0e-4_wp * (q - 1)
      prof%z(q) = sqrt(r**2 - prof%y(q)**2) - r
    end do
    write (text, '(f0.3)') r
    prof%kind = PROFILE_RAIL
    prof%source = 'circle R ' // trim(text)
  end subroutine circle_rail_profile

  !> Track Y of the centre of a circular rail head of radius r placed (uninclined) with its
  !> gauge point 14 mm below the top at gauge / 2: the head centre lies sqrt(r^2 - (r - 0.014)^2)
  !> further out.
  pure real(wp) function circle_rail_centre_y(gauge, r) result(y)
    real(wp), intent(in) :: gauge, r
    y = 0.5_wp * gauge + sqrt(r**2 - (r - 0.014_wp)**2)
  end function circle_rail_centre_y

end module geometry_test_support
