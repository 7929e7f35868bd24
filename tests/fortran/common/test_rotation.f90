!> Rotation helpers: orthonormality, composition and skew/cross consistency
!> checked against independent closed forms.
program test_rotation
  use rd_kinds, only: wp
  use rd_rotation
  implicit none
  real(wp) :: r(3, 3), a(3), b(3), eye(3, 3)
  integer :: i, nfail
  nfail = 0
  eye = 0; do i = 1, 3; eye(i, i) = 1; end do
  r = matmul(rot_z(0.3_wp), matmul(rot_y(-0.2_wp), rot_x(0.7_wp)))
  call check('orthonormal', maxval(abs(matmul(transpose(r), r) - eye)) < 1e-14_wp)
  ! rot_z(pi/2) maps local x to parent y
  call check('rot_z maps x to y', maxval(abs(matmul(rot_z(acos(-1.0_wp) / 2), [1.0_wp, 0.0_wp, 0.0_wp]) &
                                             - [0.0_wp, 1.0_wp, 0.0_wp])) < 1e-15_wp)
  call check('rot_x maps y to z', maxval(abs(matmul(rot_x(acos(-1.0_wp) / 2), [0.0_wp, 1.0_wp, 0.0_wp]) &
                                             - [0.0_wp, 0.0_wp, 1.0_wp])) < 1e-15_wp)
  call check('rot_y maps z to x', maxval(abs(matmul(rot_y(acos(-1.0_wp) / 2), [0.0_wp, 0.0_wp, 1.0_wp]) &
                                             - [1.0_wp, 0.0_wp, 0.0_wp])) < 1e-15_wp)
  a = [1.0_wp, -2.0_wp, 0.5_wp]; b = [0.3_wp, 0.1_wp, -4.0_wp]
  call check('skew is cross', maxval(abs(matmul(skew(a), b) - cross(a, b))) < 1e-14_wp)
  call check('unskew inverts skew', maxval(abs(unskew(skew(a)) - a)) < 1e-15_wp)
  call check('cross closed form', maxval(abs(cross(a, b) - [8.0_wp - 0.05_wp, 0.15_wp + 4.0_wp, 0.1_wp + 0.6_wp])) < 1e-14_wp)
  if (nfail > 0) error stop 1
  print '(a)', 'test_rotation: all checks passed'
contains
  subroutine check(name, ok)
    character(*), intent(in) :: name
    logical, intent(in) :: ok
    if (.not. ok) then
      nfail = nfail + 1
      print '(2a)', 'FAIL: ', name
    end if
  end subroutine check
end program test_rotation
