!> The energy-consistent strip normal force (`strip_normal_force = 'potential'`;
!> rd_strip_potential; docs/theory_flange_chatter.md section 13), S1002 / 60E1 1:40, the
!> Manchester wheelset.
!>
!> Oracles independent of the implementation's algebra:
!> 1. A Hertzian gap of closed form: a conical wheel (conicity 0.05) on a circular rail head
!>    (R 0.3 m). The effective penetration equals the refined peak of the classic model
!>    (both are the peak depth of a parabolic gap) within 1 %, and the force direction is
!>    the cone's normal (-sin g, cos g) with tan g = 0.05 (left wheel), within 1e-3.
!> 2. Gradients by central differences of the geometry itself (poses on the tread, the
!>    flange root, the flange-root / flange jump and the flange, both wheels, yawed):
!>    force_dir (Y, Z) and force_moment (roll, yaw) against -dE/d(Y, Z, roll, yaw), the
!>    patch's Hertz curvatures against curv_grad; along X (the extruded rail) the
!>    derivative is zero, so is the direction's X component (up to the neglected shift of
!>    the deepest points along the yawed lines in the depth's slope factor).
!> (The pipeline's force is checked as a gradient of its potential in test_wheelset_energy:
!> loop works and the power balance.)
program test_strip_potential
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT, SIDE_RIGHT
  use strip_force_test_support, only: cone_on_circle
  use geometry_test_support, only: gradient_pose_y, gradient_pose_yaw, &
    gradient_pose_name, gradient_pose_side
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use rd_test_support, only: fail, check, check_within, test_summary
  implicit none
  type(wheelset_contact_spec_t) :: spec
  type(contact_geometry_t) :: geo
  type(error_t), allocatable :: error
  type(wheel_contact_t) :: res, res_c
  integer :: ip

  ! 1. cone on a circular rail head
  call cone_on_circle('potential', spec, res, res_c)
  if (res%n_patches /= 1 .or. res_c%n_patches /= 1) then
    write (*, '(a,2i3)') 'FAIL  cone on circle: expected one patch each, got ', res%n_patches, res_c%n_patches
    call fail()
  else
    write (*, '(a,3f10.6,a,2es12.4)') '      cone on circle: force direction ', res%potential(1)%force_dir, &
      ', E, refined peak ', res%patch(1)%penetration, res_c%patch(1)%penetration
    call check_within('cone on circle: E / refined peak - 1', res%patch(1)%penetration / res_c%patch(1)%penetration - 1, &
               1.0e-2_wp)
    call check_within('cone on circle: |force direction - cone normal|', norm2(res%potential(1)%force_dir - &
               [0.0_wp, -0.05_wp, 1.0_wp] / sqrt(1 + 0.05_wp**2)), 1.0e-3_wp)
    if (.not. allocated(res%potential) .or. allocated(res_c%potential)) then
      write (*, '(a)') 'FAIL  the potential data not present as selected'
      call fail()
    end if
  end if

  ! the Manchester profiles
  spec = wheelset_contact_spec_t()
  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  spec%strip_normal_force = 'potential'
  call build_contact_geometry(spec, geo, error)
  if (allocated(error)) error stop error%message

  ! 2. gradients at single-patch poses on the tread, flange root, root / face jump and flange,
  ! yawed, both wheels
  do ip = 1, size(gradient_pose_y)
    call full_gradient_check(gradient_pose_y(ip), gradient_pose_yaw(ip), trim(gradient_pose_name(ip)), &
      merge(SIDE_LEFT, SIDE_RIGHT, gradient_pose_side(ip) == 1))
  end do
  call test_summary('test_strip_potential')

contains

  !> Finite differences of E and of the three Hertz curvatures of the deepest patch with
  !> respect to Y, Z, roll and yaw against the patch's force_dir, force_moment, curv_grad.
  subroutine full_gradient_check(y0, psi, what, side)
    real(wp), intent(in) :: y0, psi
    integer, intent(in) :: side
    character(len=*), intent(in) :: what
    real(wp), parameter :: h = 2.0e-7_wp
    real(wp) :: zz, ph, q0(4), qp(4), vp(4), vm(4), fd(4, 4), an(4, 4), scale(4)
    type(wheel_contact_t) :: r
    integer :: d, k, v
    call rigid_contact(geo, y0, psi, zz, ph, error)
    if (allocated(error)) error stop error%message
    zz = zz - 3.0e-5_wp
    q0 = [y0, zz, ph, psi]
    call wheel_contact(geo, side, q0(1), q0(2), q0(3), q0(4), r)
    if (r%n_patches /= 1) then
      write (*, '(a,i0,a)') 'FAIL  ' // what // ': expected a single patch, got ', r%n_patches, ' (pose choice)'
      call fail()
      return
    end if
    k = 1
    ! along X (the extruded rail) E does not change: the direction's X component is zero (up
    ! to the neglected shift of the deepest points along the yawed lines)
    call check_within(what // ': F(X)', r%potential(k)%force_dir(1), 2.0e-3_wp)
    associate (p => r%patch(k), q => r%potential(k))
      ! analytic derivatives d/d(Y, Z, roll, yaw) of (E, kappa_wheel_roll, kappa_wheel_lat, kappa_rail_lat)
      an(1, :) = -[q%force_dir(2), q%force_dir(3), q%force_moment(1), &
                   q%force_moment(2) * sin(ph) + q%force_moment(3) * cos(ph)]
      do v = 1, 3
        an(v + 1, :) = [q%curv_grad(2, v), q%curv_grad(3, v), q%curv_grad(4, v), &
                        q%curv_grad(5, v) * sin(ph) + q%curv_grad(6, v) * cos(ph)]
      end do
      scale = [1.0_wp, abs(p%curv_wheel_roll) + 1, abs(p%curv_wheel_lat) + 1, abs(p%curv_rail_lat) + 1]
    end associate
    do d = 1, 4
      qp = q0; qp(d) = q0(d) + h
      call values(qp, k, side, vp)
      qp = q0; qp(d) = q0(d) - h
      call values(qp, k, side, vm)
      fd(:, d) = (vp - vm) / (2 * h)
    end do
    do v = 1, 4
      write (*, '(a,i0,a,4es12.4,a,4es12.4)') '      ' // what // ' value ', v, ': analytic ', an(v, :), &
        ', differences ', fd(v, :)
    end do
    ! E: to 2e-3 of its largest derivative (the neglected shift of the deepest points along
    ! yawed lines, ~1e-4); the curvatures: each derivative to 10 % (the differences cross
    ! the polygonal wheel's points, where the depths' slope factor kinks; a wrong sign or a
    ! missing term, as the shift along yawed lines was, is 100 %; below 1e-4 of (|kappa| + 1)
    ! per metre or radian the differences are rounding)
    call check_within(what // ': |F(Y,Z) - (-dE/d(Y,Z))|', norm2(an(1, 1:2) - fd(1, 1:2)), 2.0e-3_wp)
    call check_within(what // ': |dE analytic - differences| / max', maxval(abs(an(1, :) - fd(1, :))) / maxval(abs(fd(1, :))), &
               2.0e-3_wp)
    do v = 2, 4
      call check_within(what // ': curvature ' // achar(iachar('0') + v - 1) // ' derivatives, worst relative error', &
                 maxval(abs(an(v, :) - fd(v, :)) / (abs(fd(v, :)) + 1.0e-3_wp * maxval(abs(fd(v, :))) + 1.0e-4_wp * scale(v))), &
                 0.1_wp)
    end do
  end subroutine full_gradient_check

  !> E and the three Hertz curvatures of patch slot k of the left wheel at pose q.
  subroutine values(q, k, side, out)
    real(wp), intent(in) :: q(4)
    integer, intent(in) :: k, side
    real(wp), intent(out) :: out(4)
    type(wheel_contact_t) :: rr
    call wheel_contact(geo, side, q(1), q(2), q(3), q(4), rr)
    out = [rr%patch(k)%penetration, rr%patch(k)%curv_wheel_roll, rr%patch(k)%curv_wheel_lat, rr%patch(k)%curv_rail_lat]
  end subroutine values






end program test_strip_potential
