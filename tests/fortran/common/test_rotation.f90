!> Rotation helpers: orthonormality, composition and skew/cross consistency
!> checked against independent closed forms.
program test_rotation
  use rd_kinds, only: wp
  use rd_rotation
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp) :: r(3, 3), a(3), b(3), eye(3, 3)
  integer :: i
  eye = 0; do i = 1, 3; eye(i, i) = 1; end do
  r = matmul(rot_z(0.3_wp), matmul(rot_y(-0.2_wp), rot_x(0.7_wp)))
  call check(maxval(abs(matmul(transpose(r), r) - eye)) < 1e-14_wp, 'orthonormal')
  ! rot_z(pi/2) maps local x to parent y
  call check(maxval(abs(matmul(rot_z(acos(-1.0_wp) / 2), [1.0_wp, 0.0_wp, 0.0_wp]) &
                                             - [0.0_wp, 1.0_wp, 0.0_wp])) < 1e-15_wp, 'rot_z maps x to y')
  call check(maxval(abs(matmul(rot_x(acos(-1.0_wp) / 2), [0.0_wp, 1.0_wp, 0.0_wp]) &
                                             - [0.0_wp, 0.0_wp, 1.0_wp])) < 1e-15_wp, 'rot_x maps y to z')
  call check(maxval(abs(matmul(rot_y(acos(-1.0_wp) / 2), [0.0_wp, 0.0_wp, 1.0_wp]) &
                                             - [1.0_wp, 0.0_wp, 0.0_wp])) < 1e-15_wp, 'rot_y maps z to x')
  a = [1.0_wp, -2.0_wp, 0.5_wp]; b = [0.3_wp, 0.1_wp, -4.0_wp]
  call check(maxval(abs(matmul(skew(a), b) - cross(a, b))) < 1e-14_wp, 'skew is cross')
  call check(maxval(abs(unskew(skew(a)) - a)) < 1e-15_wp, 'unskew inverts skew')
  call check(maxval(abs(cross(a, b) - [8.0_wp - 0.05_wp, 0.15_wp + 4.0_wp, 0.1_wp + 0.6_wp])) < 1e-14_wp, 'cross closed form')
  call test_summary('test_rotation')
end program test_rotation
