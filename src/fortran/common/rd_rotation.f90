!> Elementary rotation matrices and the small vector algebra shared by all modules.
!>
!> Convention (docs/conventions.md): a matrix R maps components in the rotated
!> (local) frame to components in the parent frame, v_parent = R v_local.
module rd_rotation
  use rd_kinds, only: wp
  implicit none
  private
  public :: rot_x, rot_y, rot_z, skew, cross, unskew

contains

  !> Rotation by angle a about the local x axis.
  pure function rot_x(a) result(r)
    real(wp), intent(in) :: a
    real(wp) :: r(3, 3)
    real(wp) :: c, s
    c = cos(a); s = sin(a)
    ! column by column: a reshape of an array constructor is a library call (gfortran -O2)
    r(:, 1) = [1.0_wp, 0.0_wp, 0.0_wp]
    r(:, 2) = [0.0_wp, c, s]
    r(:, 3) = [0.0_wp, -s, c]
  end function rot_x

  !> Rotation by angle a about the local y axis.
  pure function rot_y(a) result(r)
    real(wp), intent(in) :: a
    real(wp) :: r(3, 3)
    real(wp) :: c, s
    c = cos(a); s = sin(a)
    r(:, 1) = [c, 0.0_wp, -s]
    r(:, 2) = [0.0_wp, 1.0_wp, 0.0_wp]
    r(:, 3) = [s, 0.0_wp, c]
  end function rot_y

  !> Rotation by angle a about the local z axis.
  pure function rot_z(a) result(r)
    real(wp), intent(in) :: a
    real(wp) :: r(3, 3)
    real(wp) :: c, s
    c = cos(a); s = sin(a)
    r(:, 1) = [c, s, 0.0_wp]
    r(:, 2) = [-s, c, 0.0_wp]
    r(:, 3) = [0.0_wp, 0.0_wp, 1.0_wp]
  end function rot_z

  !> Skew-symmetric matrix with skew(a) b = a x b.
  pure function skew(a) result(s)
    real(wp), intent(in) :: a(3)
    real(wp) :: s(3, 3)
    s(:, 1) = [0.0_wp, a(3), -a(2)]
    s(:, 2) = [-a(3), 0.0_wp, a(1)]
    s(:, 3) = [a(2), -a(1), 0.0_wp]
  end function skew

  !> Axial vector of the skew-symmetric part of m (inverse of skew).
  pure function unskew(m) result(a)
    real(wp), intent(in) :: m(3, 3)
    real(wp) :: a(3)
    a = 0.5_wp * [m(3, 2) - m(2, 3), m(1, 3) - m(3, 1), m(2, 1) - m(1, 2)]
  end function unskew

  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: c(3)
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross
end module rd_rotation
