!> Nonlinear force-deflection table with clearance against hand-computed values: zero force
!> inside the clearance, linear interpolation between table points, extrapolation with the
!> last slope, asymmetric tables and clearances, damping only while engaged, and input
!> validation.
program test_nonlinear_spring
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_force_element, only: element_result_t
  use rd_nonlinear_spring, only: nonlinear_spring_t, force_table_t, build_force_table, table_force
  use rd_dynamics_test_support, only: canted_circle_t
  use rd_test_support, only: check, test_summary
  implicit none
  type(nonlinear_spring_t) :: bs
  type(force_table_t) :: tab
  type(error_t), allocatable :: error
  type(canted_circle_t) :: circle
  type(track_point_t) :: tp

  ! table: 0 -> 0, 5 mm -> 1 kN, 15 mm -> 11 kN (progressive), beyond: slope 1e6 N/m
  call build_force_table(tab, [0.0_wp, 0.005_wp, 0.015_wp], [0.0_wp, 1000.0_wp, 11000.0_wp], error)
  call check(.not. allocated(error), 'table accepted')
  call check(abs(table_force(tab, 0.002_wp) - 400.0_wp) < 1e-9_wp, 'interpolation first segment')
  call check(abs(table_force(tab, 0.010_wp) - 6000.0_wp) < 1e-9_wp, 'interpolation second segment')
  call check(abs(table_force(tab, 0.020_wp) - 16000.0_wp) < 1e-9_wp, 'extrapolation with last slope')
  call build_force_table(tab, [0.001_wp, 0.005_wp], [0.0_wp, 1000.0_wp], error)
  call check(allocated(error), 'table must start at 0')
  call build_force_table(tab, [0.0_wp, 0.005_wp, 0.004_wp], [0.0_wp, 1.0_wp, 2.0_wp], error)
  call check(allocated(error), 'table must increase')

  bs%body1 = 1; bs%body2 = 2
  bs%clearance_pos = [0.0_wp, 0.02_wp, 0.0_wp]
  bs%clearance_neg = [0.0_wp, 0.03_wp, 0.0_wp]
  bs%damping = [0.0_wp, 500.0_wp, 0.0_wp]
  call build_force_table(bs%table_pos(2), [0.0_wp, 0.005_wp, 0.015_wp], [0.0_wp, 1000.0_wp, 11000.0_wp], error)
  call build_force_table(bs%table_neg(2), [0.0_wp, 0.01_wp], [0.0_wp, 500.0_wp], error)
  tp = circle%evaluate(0.0_wp)

  call check(abs(lateral(0.015_wp, 0.3_wp)) == 0, 'inside the clearance: no force (even moving)')
  call check(abs(lateral(-0.025_wp, 0.3_wp)) == 0, 'inside the negative clearance: no force')
  call check(abs(lateral(0.030_wp, 0.0_wp) + 6000.0_wp) < 1e-9_wp, 'positive side: -F(d - c+)')
  call check(abs(lateral(0.030_wp, 0.2_wp) + 6000.0_wp + 100.0_wp) < 1e-9_wp, 'positive side with damping')
  call check(abs(lateral(-0.035_wp, 0.0_wp) - 250.0_wp) < 1e-9_wp, 'negative side: own table +F(-d - c-)')
  deallocate (bs%table_neg(2)%e, bs%table_neg(2)%f)
  call check(abs(lateral(-0.040_wp, 0.0_wp) - 6000.0_wp) < 1e-9_wp, 'symmetric when no negative table')

  call test_summary('test_nonlinear_spring')
contains
  !> Lateral force on body 2 when it sits at y = d with lateral rate yd (body 1 at rest).
  real(wp) function lateral(d, yd) result(f)
    real(wp), intent(in) :: d, yd
    type(body_kinematics_t) :: k1, k2
    type(element_result_t) :: res
    real(wp) :: xd(0)
    call compute_body_kinematics(k1, tp, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                                 [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
    call compute_body_kinematics(k2, tp, 0.0_wp, 0.0_wp, [0.0_wp, d, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                                 [0.0_wp, yd, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], .false.)
    call bs%evaluate(0.0_wp, k1, k2, xd, res, xd)
    f = res%force(2)
  end function lateral
end program test_nonlinear_spring
