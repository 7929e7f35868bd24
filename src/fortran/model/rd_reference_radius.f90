!> The reference rolling radius r0 of a wheelset: the radius of the nominal spin V / r0
!> from which the wheelset's spin coordinate is measured (beta = theta - s / r0,
!> docs/conventions.md) and with which a wheelset starts to roll. It is not the tape-circle
!> radius of the profile geometry (&wheelset nominal_radius): a wheelset rolling centred on
!> real profiles touches its rails away from the tape circle, and a nominal spin at the
!> tape-circle radius would start such a wheelset with a longitudinal creepage
!> 1 - r / r_tape on both wheels.
!>
!> Profile contact: the mean of the left and right rolling radii of rigid contact at the
!> centred pose (y = 0, zero yaw), each wheel's deepest patch with the wheelset lowered by
!> CENTRED_LOWERING, as `raildyn profile-scan` reports its row y = 0 (so the two agree).
!> The nominal rails (no irregularity, no rail-body displacement) are meant: r0 is a
!> property of the wheelset and its track, not of a track position. Knife edge: the cone
!> radius at its contact point, nominal_radius.
module rd_reference_radius
  use rd_kinds, only: wp
  use rd_error, only: error_t, error_context
  use rd_contact_patch, only: wheel_contact_t
  use rd_contact_geometry, only: contact_geometry_t, CONTACT_MODEL_STRIP
  use rd_rigid_contact, only: rigid_contact
  implicit none
  private
  public :: centred_rolling_radius, CENTRED_LOWERING

  !> [m]: rigid contact touches in points; lowered by this the touching points form
  !> patches (the default lowering of raildyn profile-scan).
  real(wp), parameter :: CENTRED_LOWERING = 5.0e-6_wp

contains

  !> r0 [m] of the contact geometry `geo` (see the module header).
  subroutine centred_rolling_radius(geo, r0, error)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(out) :: r0
    type(error_t), allocatable, intent(out) :: error
    type(wheel_contact_t) :: left, right
    real(wp) :: z, roll
    r0 = geo%placement%nominal_radius
    if (geo%model /= CONTACT_MODEL_STRIP) return
    call rigid_contact(geo, 0.0_wp, 0.0_wp, z, roll, error, left, right, CENTRED_LOWERING)
    if (allocated(error)) then
      call error_context(error, 'centred rolling radius')
      return
    end if
    r0 = 0.5_wp * (deepest_patch_radius(left) + deepest_patch_radius(right))
  end subroutine centred_rolling_radius

  !> Rolling radius of the patch with the largest penetration (a wheel lowered into its
  !> rail has at least one patch).
  pure real(wp) function deepest_patch_radius(wheel) result(r)
    type(wheel_contact_t), intent(in) :: wheel
    integer :: k
    k = maxloc(wheel%patch(1:wheel%n_patches)%penetration, dim=1)
    r = wheel%patch(k)%rolling_radius
  end function deepest_patch_radius
end module rd_reference_radius
