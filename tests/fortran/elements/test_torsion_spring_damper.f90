!> Torsional spring-damper against closed forms:
!>  1. rotation vector of a Rodrigues rotation exp(skew(v)) returns v (general axis);
!>  2. body 2 rolled by alpha relative to body 1 (both yawed and pitched together in the
!>     frame, element axes = body 1 axes): moment on body 2 = -k_x alpha about body 1's x,
!>     body 1 gets the opposite (anti-roll bar);
!>  3. relative roll rate: damping moment -c_x rate; a common rotation of both bodies gives
!>     no moment.
program test_torsion_spring_damper
  use rd_kinds, only: wp
  use rd_rotation, only: skew
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_force_element, only: element_result_t
  use rd_torsion_spring_damper, only: torsion_spring_damper_t, rotation_vector
  use rd_dynamics_test_support, only: canted_circle_t
  use rd_test_support, only: check, test_summary
  implicit none
  type(torsion_spring_damper_t) :: ts
  type(body_kinematics_t) :: k1, k2
  type(element_result_t) :: res
  type(track_point_t) :: tp
  type(canted_circle_t) :: circle
  real(wp) :: xd(0), v(3), r(3, 3), ang, ax(3), eye(3, 3), expect(3)
  integer :: i

  ! 1. Rodrigues: R = I + sin(a) K + (1 - cos(a)) K^2, K = skew(axis)
  v = [0.3_wp, -0.5_wp, 0.8_wp]
  ang = norm2(v); ax = v / ang
  eye = 0; do i = 1, 3; eye(i, i) = 1; end do
  r = eye + sin(ang) * skew(ax) + (1 - cos(ang)) * matmul(skew(ax), skew(ax))
  call check(maxval(abs(rotation_vector(r) - v)) < 1e-14_wp, 'rotation vector of exp(skew(v)) = v')
  call check(maxval(abs(rotation_vector(eye))) == 0, 'rotation vector of I = 0')

  ! 2. relative roll 0.05 rad; bodies in a canted curve frame, both yawed 0.2 and pitched 0.1
  circle%kappa = 1.0_wp / 300; circle%cant = -0.1_wp
  tp = circle%evaluate(12.0_wp)
  ts%body1 = 1; ts%body2 = 2
  ts%stiffness = [2.0e6_wp, 3.0e6_wp, 4.0e6_wp]
  ts%damping = [1.0e4_wp, 0.0_wp, 0.0_wp]
  call compute_body_kinematics(k1, tp, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.5_wp, 0.2_wp, 0.0_wp, 0.1_wp], &
                               [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
  ! body 2 = body 1 followed by a roll about body 1's x: B2 = B1 Rx(0.05) (Z-X-Y angles of
  ! that product computed from the matrix)
  block
    real(wp) :: b2(3, 3), q2(6)
    real(wp) :: cx, sx
    cx = cos(0.05_wp); sx = sin(0.05_wp)
    b2 = matmul(k1%b, reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, cx, sx, 0.0_wp, -sx, cx], [3, 3]))
    q2 = 0
    q2(3) = 1.5_wp
    q2(4) = atan2(-b2(1, 2), b2(2, 2)); q2(5) = asin(b2(3, 2)); q2(6) = atan2(-b2(3, 1), b2(3, 3))
    call compute_body_kinematics(k2, tp, 0.0_wp, 0.0_wp, q2, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
  end block
  call ts%evaluate(0.0_wp, k1, k2, xd, res, xd)
  call check(maxval(abs(res%deflection - [0.05_wp, 0.0_wp, 0.0_wp])) < 1e-13_wp, 'deflection = relative roll')
  expect = -2.0e6_wp * 0.05_wp * k1%rot(:, 1)
  call check(maxval(abs(res%moment - expect)) < 1e-8_wp, 'moment on body 2 = -k alpha about body 1 x')
  call check(all(res%force == 0), 'pure couple (no force)')

  ! 3. rates: body 2 rolls at 0.4 rad/s relative to body 1 (same angles): -c * 0.4
  call compute_body_kinematics(k2, tp, 0.0_wp, 0.0_wp, k1%q, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
  block
    type(body_kinematics_t) :: k2b
    k2b = k2
    k2b%omega = k2%omega + 0.4_wp * k1%rot(:, 1)
    k2b%omega_attach = k2b%omega
    call ts%evaluate(0.0_wp, k1, k2b, xd, res, xd)
    call check(maxval(abs(res%moment + 1.0e4_wp * 0.4_wp * k1%rot(:, 1))) < 1e-9_wp, 'damping moment -c rate')
  end block
  call compute_body_kinematics(k1, tp, 30.0_wp, 0.0_wp, k1%q, [0.1_wp, 0.0_wp, 0.0_wp, 0.3_wp, -0.2_wp, 0.5_wp], .false.)
  call compute_body_kinematics(k2, tp, 30.0_wp, 0.0_wp, k1%q, [0.0_wp, 0.0_wp, 0.0_wp, 0.3_wp, -0.2_wp, 0.5_wp], .false.)
  call ts%evaluate(0.0_wp, k1, k2, xd, res, xd)
  call check(maxval(abs(res%moment)) < 1e-9_wp, 'common rotation: no moment')

  call test_summary('test_torsion_spring_damper')
end program test_torsion_spring_damper
