!> The distributed strip normal force (`strip_normal_force = 'distributed'`; rd_hertz_strip,
!> rd_strip_contact; docs/theory_flange_chatter.md section 14) at the geometry level.
!>
!> Oracles independent of the implementation's algebra:
!> 1. A Hertzian gap of closed form: a conical wheel (conicity 0.05) on a circular rail head
!>    (R 0.3 m), lowered 30 um below rigid contact. Its relative curvatures are the cone's
!>    rolling one cos(g) / r and the rail's 1 / 0.3 m (the cone has no lateral curvature), its
!>    approach the classic model's refined peak (exact for a parabolic gap); Hertz
!>    (rd_hertz, checked against Johnson's tables in test_hertz) then gives the load N. The
!>    strip sum must carry N (1 %: the strips sample the patch 0.2 mm apart), store
!>    (2/5) N delta0, push along the cone's normal (-sin g, cos g), tan g = 0.05 (1e-3), and
!>    hand the patch its whole load.
!> 2. The force is minus the gradient of the energy the geometry reports: central differences
!>    of U along Y, Z, roll and yaw against the force and moment, on the tread, the flange
!>    root, the flange root / flange jump (two regions) and the flange of S1002 / 60E1 1:40,
!>    yawed, both wheels.
!> (The pipeline's force as a gradient field over closed loops and its power balance:
!> test_wheelset_energy; the strip stiffness itself: test_hertz_strip.)
program test_strip_distributed
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry, build_hertz_params
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT, SIDE_RIGHT
  use strip_force_test_support, only: cone_on_circle, manchester_geometry
  use geometry_test_support, only: gradient_pose_y, gradient_pose_yaw, &
    gradient_pose_name, gradient_pose_side
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use rd_hertz, only: hertz_params_t, hertz_patch_t, hertz_from_penetration
  use rd_test_support, only: fail, check, check_within, test_summary
  implicit none
  type(wheelset_contact_spec_t) :: spec
  type(contact_geometry_t) :: geo
  type(hertz_params_t) :: hertz
  type(hertz_patch_t) :: hp
  type(error_t), allocatable :: error
  type(wheel_contact_t) :: res, res_c
  real(wp) :: n_strips, g, rr
  integer :: ip

  ! 1. cone on a circular rail head
  call cone_on_circle('distributed', spec, res, res_c)
  call build_hertz_params(spec, hertz, error)
  if (allocated(error)) error stop error%message
  if (res%n_patches /= 1 .or. res_c%n_patches /= 1 .or. .not. allocated(res%distributed) &
      .or. allocated(res_c%distributed)) then
    write (*, '(a,2i3)') 'FAIL  cone on circle: expected one patch each and the distributed data as selected, got ', &
      res%n_patches, res_c%n_patches
    call fail()
  else
    g = atan(0.05_wp)
    rr = res_c%patch(1)%rolling_radius
    call hertz_from_penetration(hertz, [cos(g) / rr, 0.0_wp, 0.0_wp, 1 / 0.3_wp], res_c%patch(1)%penetration, hp)
    n_strips = hertz%e_star * norm2(res%distributed%force)
    write (*, '(a,es12.5,a,es12.5,a,3f10.6)') '      cone on circle: strip load ', n_strips, ' N, Hertz ', &
      hp%normal_force, ' N; direction ', res%distributed%force / norm2(res%distributed%force)
    call check_within('cone on circle: strip load / Hertz load - 1', n_strips / hp%normal_force - 1, 1.0e-2_wp)
    call check_within('cone on circle: strip energy / ((2/5) N delta0) - 1', hertz%e_star * res%distributed%energy / &
                     (0.4_wp * hp%normal_force * res_c%patch(1)%penetration) - 1, 1.0e-2_wp)
    call check_within('cone on circle: |force direction - cone normal|', norm2(res%distributed%force &
                     / norm2(res%distributed%force) - [0.0_wp, -sin(g), cos(g)]), 1.0e-3_wp)
    call check_within('cone on circle: the patch''s load / the strips'' load - 1', &
                     res%distributed%patch_load(1) / norm2(res%distributed%force) - 1, 1.0e-3_wp)
  end if

  ! 2. the Manchester profiles
  call manchester_geometry('distributed', geo)
  do ip = 1, size(gradient_pose_y)
    call gradient_check(gradient_pose_y(ip), gradient_pose_yaw(ip), trim(gradient_pose_name(ip)), &
      merge(SIDE_LEFT, SIDE_RIGHT, gradient_pose_side(ip) == 1))
  end do
  call test_summary('test_strip_distributed')

contains

  !> Central differences of the strip energy with respect to Y, Z, roll and yaw against the
  !> force (track frame) and the moment (intermediate frame: roll is about its x axis, yaw
  !> about the track's Z, which is (0, sin(roll), cos(roll)) there), 30 um below rigid contact.
  subroutine gradient_check(y0, psi, what, side)
    real(wp), intent(in) :: y0, psi
    integer, intent(in) :: side
    character(len=*), intent(in) :: what
    real(wp), parameter :: h = 2.0e-7_wp
    real(wp) :: zz, ph, q0(4), qp(4), up, um, fd(4), an(4)
    type(wheel_contact_t) :: r
    integer :: d
    call rigid_contact(geo, y0, psi, zz, ph, error)
    if (allocated(error)) error stop error%message
    zz = zz - 3.0e-5_wp
    q0 = [y0, zz, ph, psi]
    call wheel_contact(geo, side, q0(1), q0(2), q0(3), q0(4), r)
    associate (s => r%distributed)
      an = -[s%force(2), s%force(3), s%moment(1), s%moment(2) * sin(ph) + s%moment(3) * cos(ph)]
    end associate
    do d = 1, 4
      qp = q0; qp(d) = q0(d) + h
      up = energy(qp, side)
      qp = q0; qp(d) = q0(d) - h
      um = energy(qp, side)
      fd(d) = (up - um) / (2 * h)
    end do
    write (*, '(a,i0,a,4es12.4,a,4es12.4)') '      ' // what // ' (', r%n_patches, ' patches): -F, -M analytic ', an, &
      ', dU differences ', fd
    call check_within(what // ': |dU analytic - differences| / max', maxval(abs(an - fd)) / maxval(abs(fd)), 1.0e-3_wp)
  end subroutine gradient_check

  real(wp) function energy(q, side) result(u)
    real(wp), intent(in) :: q(4)
    integer, intent(in) :: side
    type(wheel_contact_t) :: rr
    call wheel_contact(geo, side, q(1), q(2), q(3), q(4), rr)
    u = rr%distributed%energy
  end function energy

end program test_strip_distributed
