!> The closed-form Hertzian gap of the strip normal force tests (test_strip_potential,
!> test_strip_distributed): a conical wheel (conicity 0.05) on a circular rail head (R 0.3 m),
!> lowered 30 um below rigid contact at zero shift, seen through the centroid force (its
!> refined peak is the gap's exact approach) and through the force under test; and the
!> Manchester profiles' geometry with a given strip normal force.
module strip_force_test_support
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use geometry_test_support, only: cone_wheel_profile, circle_rail_profile
  implicit none
  private
  public :: cone_on_circle, manchester_geometry

  real(wp), parameter, public :: cone_conicity = 0.05_wp, rail_head_radius = 0.3_wp, lowering = 3.0e-5_wp

contains

  !> The left wheel's contact with `force` (res) and with the centroid force (res_c); spec is
  !> the wheelset's (for its Hertz parameters).
  subroutine cone_on_circle(force, spec, res, res_c)
    character(len=*), intent(in) :: force
    type(wheelset_contact_spec_t), intent(out) :: spec
    type(wheel_contact_t), intent(out) :: res, res_c
    type(contact_geometry_t) :: geo, geo_c
    type(error_t), allocatable :: error
    real(wp) :: z, phi
    call cone_wheel_profile(cone_conicity, spec%wheel_profile_data)
    call circle_rail_profile(rail_head_radius, spec%rail_profile_data)
    spec%wheel_profile = 'cone'
    spec%rail_profile = 'circle'
    spec%strip_normal_force = 'centroid'
    call build_contact_geometry(spec, geo_c, error)
    if (allocated(error)) error stop error%message
    spec%strip_normal_force = force
    call build_contact_geometry(spec, geo, error)
    if (allocated(error)) error stop error%message
    call rigid_contact(geo, 0.0_wp, 0.0_wp, z, phi, error)
    if (allocated(error)) error stop error%message
    call wheel_contact(geo, SIDE_LEFT, 0.0_wp, z - lowering, phi, 0.0_wp, res)
    call wheel_contact(geo_c, SIDE_LEFT, 0.0_wp, z - lowering, phi, 0.0_wp, res_c)
  end subroutine cone_on_circle

  !> S1002 on 60E1 (the wheelset defaults otherwise) with the strip normal force `force`.
  subroutine manchester_geometry(force, geo)
    character(len=*), intent(in) :: force
    type(contact_geometry_t), intent(out) :: geo
    type(wheelset_contact_spec_t) :: spec
    type(error_t), allocatable :: error
    spec = wheelset_contact_spec_t()
    spec%wheel_profile = 's1002'
    spec%rail_profile = '60e1'
    spec%strip_normal_force = force
    call build_contact_geometry(spec, geo, error)
    if (allocated(error)) error stop error%message
  end subroutine manchester_geometry

end module strip_force_test_support
