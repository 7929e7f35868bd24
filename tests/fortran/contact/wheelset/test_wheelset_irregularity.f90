!> Rails displaced by track irregularities (rd_contact_geometry rail_offset,
!> rd_wheelset_contact set_irregularity), both contact models (knife-edge cones with a
!> flange stop; analytic S1002 on 60E1 1:40):
!>
!> 1. One rail offset (dy, dz): that wheel's contact equals the nominal contact of the pose
!>    (y - dy, z - dz) with the rail point shifted by (dy, dz); the other wheel is unchanged.
!> 2. Translation invariance: the wheelset and both rails moved together by (d, e) give the
!>    nominal contact (same penetrations, normals, wheel points), rail points shifted.
!> 3. Knife edge, closed forms (thesis eqs. 5.2-5.4 for a centred, unrolled wheelset): a
!>    left rail moved by (dy, dz) touches the cone at the rail's new line Y = e0 + dy with
!>    rolling radius r0 + lambda (y - dy) and approach (r0 + lambda (y - dy) + dz - z) cos(gamma);
!>    the flange stop engages at y - dy > clearance.
!> 4. Provider: the forces with an alignment a and level l at the wheelset's track position
!>    equal the forces of the pose (y - a, z - l) on the nominal track (the rail material is
!>    at rest either way), and the geometry cache tells two track positions with the same
!>    pose apart.
program test_wheelset_irregularity
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  use rd_contact_patch, only: wheel_contact_t, PATCH_FLANGE_SPRING
  use rd_contact_geometry, only: contact_geometry_t, wheelset_contact, wheel_contact, SIDE_LEFT, SIDE_RIGHT
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_track_irregularity, only: track_irregularity_t, build_track_irregularity
  use wheelset_test_support, only: circle_track_t, pose_kinematics
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp
  character(len=16), parameter :: models(2) = [character(len=16) :: 'knife_edge', 'profile']
  integer :: im

  do im = 1, 2
    call geometry_checks(trim(models(im)))
    call provider_checks(trim(models(im)))
  end do
  call knife_closed_forms()
  call test_summary('test_wheelset_irregularity')

contains

  function model_spec(model) result(spec)
    character(len=*), intent(in) :: model
    type(wheelset_contact_spec_t) :: spec
    spec = wheelset_contact_spec_t()
    spec%body = 1
    spec%model = model
    spec%wheel_profile = 's1002'
    spec%rail_profile = '60e1'
    spec%nominal_radius = r0
    spec%creep_law = 'fastsim'
    if (model == 'knife_edge') then
      spec%knife_flange_clearance = 6.0e-3_wp
      spec%knife_flange_stiffness = 1.0e7_wp
    end if
  end function model_spec

  subroutine geometry_checks(model)
    character(len=*), intent(in) :: model
    type(contact_geometry_t) :: geo
    type(error_t), allocatable :: error
    type(wheel_contact_t) :: l, r, ref(2), l0, r0_
    real(wp) :: off(2, 2), pose(4), d(2)
    real(wp), parameter :: poses(4, 3) = reshape([ &
      2.0e-3_wp, r0 - 2.5e-3_wp, 2.0e-4_wp, 2.0e-3_wp, &
      -4.5e-3_wp, r0 - 2.5e-3_wp, -2.0e-4_wp, -1.0e-3_wp, &
      5.5e-3_wp, r0 - 2.5e-3_wp, 3.0e-4_wp, 4.0e-3_wp], [4, 3])
    integer :: ip, side, other
    logical :: ok_one, ok_other, ok_inv
    call build_contact_geometry(model_spec(model), geo, error)
    if (allocated(error)) error stop error%message
    ok_one = .true.; ok_other = .true.; ok_inv = .true.
    do ip = 1, size(poses, 2)
      pose = poses(:, ip)
      do side = SIDE_LEFT, SIDE_RIGHT
        other = 3 - side
        off = 0
        off(:, side) = [1.5e-3_wp, -3.0e-4_wp]
        call wheelset_contact(geo, pose(1), pose(2), pose(3), pose(4), l, r, error, rail_offset=off)
        if (allocated(error)) error stop error%message
        call wheel_contact(geo, side, pose(1) - off(1, side), pose(2) - off(2, side), pose(3), pose(4), ref(side))
        call shift_rail(ref(side), off(:, side))
        call wheel_contact(geo, other, pose(1), pose(2), pose(3), pose(4), ref(other))
        ok_one = ok_one .and. same(pick(l, r, side), ref(side), 0.0_wp)
        ok_other = ok_other .and. same(pick(l, r, other), ref(other), 0.0_wp)
      end do
      ! whole track and wheelset translated by d: the contact is the nominal one
      d = [2.5e-3_wp, 7.0e-4_wp]
      off(:, 1) = d; off(:, 2) = d
      call wheelset_contact(geo, pose(1) + d(1), pose(2) + d(2), pose(3), pose(4), l, r, error, rail_offset=off)
      if (allocated(error)) error stop error%message
      call wheelset_contact(geo, pose(1), pose(2), pose(3), pose(4), l0, r0_, error)
      call shift_rail(l0, d)
      call shift_rail(r0_, d)
      ! y + d - d and z + d - d round to within an ulp of y, z: compare to 1e-9 of a metre
      ok_inv = ok_inv .and. same(l, l0, 1.0e-9_wp) .and. same(r, r0_, 1.0e-9_wp)
    end do
    call check(ok_one, model // ': one rail offset = nominal contact of the pose (y - dy, z - dz), rail point + offset')
    call check(ok_other, model // ': the other wheel does not see that rail''s offset')
    call check(ok_inv, model // ': wheelset and both rails translated together: contact unchanged, rail points moved')
  end subroutine geometry_checks

  !> Knife edge at zero roll and yaw: closed forms of thesis eqs. 5.2-5.4 with the rail moved.
  subroutine knife_closed_forms()
    type(contact_geometry_t) :: geo
    type(error_t), allocatable :: error
    type(wheel_contact_t) :: l, r
    type(wheelset_contact_spec_t) :: spec
    real(wp) :: off(2, 2), y, z, lam, g, rr, pen
    spec = model_spec('knife_edge')
    call build_contact_geometry(spec, geo, error)
    if (allocated(error)) error stop error%message
    lam = spec%knife_conicity
    g = atan(lam)
    y = 1.0e-3_wp
    z = r0 - 5.0e-4_wp
    off = 0
    off(:, 1) = [2.0e-3_wp, 5.0e-4_wp]
    call wheelset_contact(geo, y, z, 0.0_wp, 0.0_wp, l, r, error, rail_offset=off)
    rr = r0 + lam * (y - off(1, 1))
    pen = (rr + off(2, 1) - z) * cos(g)
    write (*, '(a, 3es14.6)') 'knife, left rail moved: rolling radius, approach, rail point y: ', &
      l%patch(1)%rolling_radius, l%patch(1)%penetration, l%patch(1)%point_rail(2)
    call check(l%n_patches == 1 .and. abs(l%patch(1)%rolling_radius - rr) < 1.0e-12_wp, &
               'knife: rolling radius r0 + lambda (y - dy) on the moved rail')
    call check(abs(l%patch(1)%penetration - pen) < 1.0e-12_wp, &
               'knife: approach (r0 + lambda (y - dy) + dz - z) cos(gamma)')
    call check(abs(l%patch(1)%point_rail(2) - (spec%knife_e0 + off(1, 1))) < 1.0e-15_wp .and. &
               abs(l%patch(1)%point_rail(3) - off(2, 1)) < 1.0e-15_wp, 'knife: rail point on the moved edge (e0 + dy, dz)')
    ! right rail untouched: rolling radius r0 - lambda y, approach (r0 - lambda y - z) cos(gamma)
    call check(abs(r%patch(1)%rolling_radius - (r0 - lam * y)) < 1.0e-12_wp .and. &
               abs(r%patch(1)%penetration - (r0 - lam * y - z) * cos(g)) < 1.0e-12_wp, &
               'knife: right wheel on the nominal rail')
    ! flange stop: y = 5 mm is inside the 6 mm clearance, the left rail moved 2 mm to the
    ! right puts the wheel 7 mm from it: 1 mm overlap
    off = 0
    off(1, 1) = -2.0e-3_wp
    z = r0 - 1.5e-3_wp
    call wheelset_contact(geo, 5.0e-3_wp, z, 0.0_wp, 0.0_wp, l, r, error, rail_offset=off)
    call check(l%n_patches == 2 .and. l%patch(2)%kind == PATCH_FLANGE_SPRING .and. &
               abs(l%patch(2)%penetration - 1.0e-3_wp) < 1.0e-15_wp .and. r%n_patches == 1, &
               'knife: flange stop at y - dy = 7 mm > 6 mm clearance, overlap 1 mm, on the moved rail only')
  end subroutine knife_closed_forms

  !> The provider with irregularities: forces at (y, z) over a rail offset (a, l) equal the
  !> nominal forces at (y - a, z - l); the cache keys on the offsets.
  subroutine provider_checks(model)
    character(len=*), intent(in) :: model
    type(wheelset_contact_t) :: with_irr, nominal
    type(track_irregularity_t) :: irr
    type(error_t), allocatable :: error
    type(circle_track_t) :: straight
    type(body_kinematics_t) :: kin
    real(wp), parameter :: v = 20.0_wp, a = 1.2e-3_wp, lvl = 2.0e-4_wp
    real(wp) :: values(4, 2), q(6), qd(6), f(3), m(3), fr(3), mr(3), fz(3), mz(3)
    logical :: ok_rail
    call with_irr%build([model_spec(model)], 1, error)
    if (allocated(error)) error stop error%message
    call nominal%build([model_spec(model)], 1, error)
    if (allocated(error)) error stop error%message
    values = 0
    values(1, :) = a       ! alignment
    values(2, :) = lvl     ! level
    call build_track_irregularity(irr, [100.0_wp, 200.0_wp], values, error)
    if (allocated(error)) error stop error%message
    call with_irr%set_irregularity(irr)
    q = [0.0_wp, 5.0e-4_wp, r0 - 4.0e-4_wp, 1.0e-3_wp, 1.0e-4_wp, 0.0_wp]
    qd = [0.0_wp, 0.05_wp, 0.0_wp, 0.01_wp, 0.0_wp, v / r0]
    ! inside the record (sigma 150 m)
    kin = pose_kinematics(straight, 150.0_wp, v, q, qd)
    call with_irr%evaluate(1, 0.0_wp, kin, f, m, error)
    if (allocated(error)) error stop error%message
    kin = pose_kinematics(straight, 150.0_wp, v, q - [0.0_wp, a, lvl, 0.0_wp, 0.0_wp, 0.0_wp], qd)
    call nominal%evaluate(1, 0.0_wp, kin, fr, mr, error)
    if (allocated(error)) error stop error%message
    write (*, '(a, 6es13.5)') model // ': force with irregularity, nominal at (y - a, z - l): ', f, fr
    call check(maxval(abs(f - fr)) <= 1.0e-9_wp * maxval(abs(fr)) .and. maxval(abs(m - mr)) <= 1.0e-9_wp * maxval(abs(mr)), &
               model // ': forces over displaced rails = nominal forces of the relative pose')
    ok_rail = abs(with_irr%results(1)%wheel(1)%patch(1)%point_rail(2) - &
                  (nominal%results(1)%wheel(1)%patch(1)%point_rail(2) + a)) < 1.0e-12_wp .and. &
              abs(with_irr%results(1)%wheel(2)%patch(1)%point_rail(3) - &
                  (nominal%results(1)%wheel(2)%patch(1)%point_rail(3) + lvl)) < 1.0e-12_wp
    call check(ok_rail, model // ': reported rail points moved with the rails')
    ! same pose outside the record (sigma 50 m): nominal forces at (y, z), not the cached ones
    kin = pose_kinematics(straight, 50.0_wp, v, q, qd)
    call with_irr%evaluate(1, 0.0_wp, kin, fz, mz, error)
    if (allocated(error)) error stop error%message
    call nominal%evaluate(1, 0.0_wp, kin, fr, mr, error)
    if (allocated(error)) error stop error%message
    call check(all(fz == fr) .and. all(mz == mr) .and. maxval(abs(fz - f)) > 1.0e-3_wp * maxval(abs(f)), &
               model // ': same pose at another track position: the cache does not return the old geometry')
  end subroutine provider_checks

  function pick(l, r, side) result(w)
    type(wheel_contact_t), intent(in) :: l, r
    integer, intent(in) :: side
    type(wheel_contact_t) :: w
    if (side == SIDE_LEFT) then
      w = l
    else
      w = r
    end if
  end function pick

  subroutine shift_rail(w, d)
    type(wheel_contact_t), intent(inout) :: w
    real(wp), intent(in) :: d(2)
    integer :: k
    do k = 1, w%n_patches
      w%patch(k)%point_rail(2:3) = w%patch(k)%point_rail(2:3) + d
    end do
  end subroutine shift_rail

  !> Same patches within tol [m] (and tol on unit vectors, angles).
  logical function same(a, b, tol)
    type(wheel_contact_t), intent(in) :: a, b
    real(wp), intent(in) :: tol
    integer :: k
    same = a%n_patches == b%n_patches .and. a%n_patches > 0 .and. abs(a%max_penetration - b%max_penetration) <= tol
    if (.not. same) return
    do k = 1, a%n_patches
      associate (p => a%patch(k), o => b%patch(k))
        same = same .and. p%kind == o%kind .and. abs(p%penetration - o%penetration) <= tol &
               .and. maxval(abs(p%point_rail - o%point_rail)) <= tol .and. maxval(abs(p%point_wheel - o%point_wheel)) <= tol &
               .and. maxval(abs(p%normal - o%normal)) <= tol .and. abs(p%contact_angle - o%contact_angle) <= tol &
               .and. abs(p%rolling_radius - o%rolling_radius) <= tol
      end associate
    end do
  end function same

end program test_wheelset_irregularity
