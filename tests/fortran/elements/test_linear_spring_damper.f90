!> Linear three-axis spring-damper against closed forms and energy:
!>  1. hand-derived force: body 1 yawed 90 deg, body 2 displaced along fixed Y, element
!>     axes along body 1 -> the force acts along body 1's x axis (fixed Y), -k_x d;
!>     free length, preload and actuator add per axis;
!>  2. conservative: for arbitrary rates of both bodies, the power of the element's forces
!>     (force on body 2 at point 2, reaction on body 1 at its reaction point, with the
!>     point velocities v + omega x r written here) equals -dU/dt, U = 1/2 d.K d - f0.d
!>     evaluated from the points' positions and differentiated by central differences;
!>  3. damping: power = -d'.C d' with d' from central differences of the deflection;
!>  4. wheelset attachment frame: a spinning wheelset's axle-box points do not spin.
program test_linear_spring_damper
  use rd_kinds, only: wp, pi
  use rd_rotation, only: cross, rot_z
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_force_element, only: element_result_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_dynamics_test_support, only: canted_circle_t
  use rd_test_support, only: check, test_summary
  implicit none
  type(linear_spring_damper_t) :: sp
  type(body_kinematics_t) :: k1, k2
  type(element_result_t) :: res
  type(track_point_t) :: tp
  type(canted_circle_t) :: circle
  real(wp) :: xd(0), q1(6), q2(6), qd1(6), qd2(6), power, dudt, eps, e_scale
  character(len=120) :: buf

  ! ---- 1. hand-derived force
  tp = circle%evaluate(0.0_wp)                  ! kappa = 0, no cant: track = fixed axes
  call compute_body_kinematics(k1, tp, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.0_wp, pi / 2, 0.0_wp, 0.0_wp], &
                               [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
  call compute_body_kinematics(k2, tp, 0.0_wp, 0.0_wp, [0.0_wp, 0.01_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                               [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
  sp%body1 = 1; sp%body2 = 2
  sp%stiffness = [1.0e5_wp, 2.0e5_wp, 3.0e5_wp]
  call sp%evaluate(0.0_wp, k1, k2, xd, res, xd)
  call check(maxval(abs(res%force - [0.0_wp, -1.0e3_wp, 0.0_wp])) < 1e-9_wp, 'force along body 1 x = fixed Y: -kx d')
  call check(maxval(abs(res%deflection - [0.01_wp, 0.0_wp, 0.0_wp])) < 1e-15_wp, 'deflection in element axes')
  sp%free_length = [0.004_wp, 0.0_wp, 0.0_wp]
  sp%preload = [0.0_wp, 0.0_wp, 500.0_wp]
  sp%actuator = [0.0_wp, 70.0_wp, 0.0_wp]
  call sp%evaluate(0.0_wp, k1, k2, xd, res, xd)
  ! element y = body-1 y = fixed -X
  call check(maxval(abs(res%force - [-70.0_wp, -600.0_wp, 500.0_wp])) < 1e-9_wp, 'free length, preload, actuator')

  ! ---- 2./3. power balance on a canted curve, general configuration
  circle%kappa = 1.0_wp / 250; circle%cant = -0.1_wp
  tp = circle%evaluate(37.0_wp)
  sp = linear_spring_damper_t()
  sp%body1 = 1; sp%body2 = 2
  sp%u1 = [0.4_wp, -0.3_wp, 0.2_wp]; sp%u2 = [-0.1_wp, 0.5_wp, -0.6_wp]
  sp%axes = rot_z(0.3_wp)
  sp%stiffness = [1.0e5_wp, 2.0e5_wp, 3.0e5_wp]
  sp%free_length = [0.05_wp, -0.02_wp, 0.7_wp]
  sp%preload = [100.0_wp, -200.0_wp, 3000.0_wp]
  q1 = [0.1_wp, 0.2_wp, 0.3_wp, 0.2_wp, -0.15_wp, 0.25_wp]
  q2 = [0.2_wp, -0.1_wp, 1.1_wp, -0.1_wp, 0.12_wp, -0.3_wp]
  qd1 = [0.3_wp, -0.2_wp, 0.1_wp, 0.5_wp, -0.4_wp, 0.3_wp]
  qd2 = [-0.1_wp, 0.4_wp, 0.2_wp, -0.3_wp, 0.6_wp, 0.2_wp]
  call compute_body_kinematics(k1, tp, 0.0_wp, 0.0_wp, q1, qd1, .false.)
  call compute_body_kinematics(k2, tp, 0.0_wp, 0.0_wp, q2, qd2, .false.)
  call sp%evaluate(0.0_wp, k1, k2, xd, res, xd)
  power = dot_product(res%force, k2%v + cross(k2%omega, res%point2 - k2%r)) &
          - dot_product(res%force, k1%v + cross(k1%omega, res%reaction_point - k1%r))
  eps = 1.0e-6_wp
  dudt = (energy(q1 + eps * qd1, q2 + eps * qd2) - energy(q1 - eps * qd1, q2 - eps * qd2)) / (2 * eps)
  e_scale = norm2(res%force) * norm2(qd1(1:3) - qd2(1:3))
  write (buf, '(a,es12.5,a,es12.5)') 'power ', power, ' -dU/dt ', -dudt
  call check(abs(power + dudt) < 1e-7_wp * e_scale, 'spring is conservative (power = -dU/dt)', detail=trim(buf))

  sp%stiffness = 0; sp%preload = 0
  sp%damping = [1.0e3_wp, 2.0e3_wp, 5.0e3_wp]
  call sp%evaluate(0.0_wp, k1, k2, xd, res, xd)
  power = dot_product(res%force, k2%v + cross(k2%omega, res%point2 - k2%r)) &
          - dot_product(res%force, k1%v + cross(k1%omega, res%reaction_point - k1%r))
  block
    real(wp) :: ddot(3)
    ddot = (defl(q1 + eps * qd1, q2 + eps * qd2) - defl(q1 - eps * qd1, q2 - eps * qd2)) / (2 * eps)
    write (buf, '(a,es12.5,a,es12.5)') 'power ', power, ' -ddot.C ddot ', -sum(sp%damping * ddot**2)
    call check(abs(power + sum(sp%damping * ddot**2)) < 1e-7_wp * abs(power), 'damper dissipates -d''.C d''', detail=trim(buf))
  end block

  ! ---- 4. wheelset axle box does not spin
  call compute_body_kinematics(k1, tp, 30.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.46_wp, 0.01_wp, 0.02_wp, 1.3_wp], &
                               [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 65.0_wp], .true.)
  call compute_body_kinematics(k2, tp, 30.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.46_wp, 0.01_wp, 0.02_wp, 0.0_wp], &
                               [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .true.)
  call check(maxval(abs(k1%point_position([0.0_wp, 1.0_wp, 0.2_wp]) - k2%point_position([0.0_wp, 1.0_wp, 0.2_wp]))) < 1e-14_wp &
             .and. maxval(abs(k1%point_velocity([0.0_wp, 1.0_wp, 0.2_wp]) - k2%point_velocity([0.0_wp, 1.0_wp, 0.2_wp]))) < 1e-12_wp, 'axle-box point independent of the spin angle and rate')

  call test_summary('test_linear_spring_damper')

contains

  !> Deflection from the points' positions (fixed frame), element axes.
  function defl(qa, qb) result(d)
    real(wp), intent(in) :: qa(6), qb(6)
    real(wp) :: d(3)
    type(body_kinematics_t) :: ka, kb
    real(wp), parameter :: z6(6) = 0
    call compute_body_kinematics(ka, tp, 0.0_wp, 0.0_wp, qa, z6, .false.)
    call compute_body_kinematics(kb, tp, 0.0_wp, 0.0_wp, qb, z6, .false.)
    d = matmul(transpose(matmul(ka%rot, sp%axes)), (kb%r + matmul(kb%rot, sp%u2)) - (ka%r + matmul(ka%rot, sp%u1))) &
        - sp%free_length
  end function defl

  real(wp) function energy(qa, qb) result(u)
    real(wp), intent(in) :: qa(6), qb(6)
    real(wp) :: d(3)
    d = defl(qa, qb)
    u = 0.5_wp * sum(sp%stiffness * d**2) - dot_product(sp%preload, d)
  end function energy
end program test_linear_spring_damper
