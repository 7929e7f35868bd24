!> Wheel-rail contact geometry of a wheelset: the model chosen per wheelset (strip
!> interpenetration with real profiles, or knife-edge conical wheels), its parameters fixed
!> after build, and one pure entry point returning the patches of both wheels.
!>
!> Both models are written for the left wheel; the right wheel is evaluated as the left
!> wheel of the mirrored pose (y, phi, psi) -> (-y, -phi, -psi) and the result mirrored back
!> (reflection Y -> -Y), so symmetric profiles give exactly mirror-symmetric contacts.
!>
!> Per-side profiles (docs/conventions.md "Profiles"): a right wheel or rail profile is
!> given in the same profile frame as a left one (lateral coordinate positive towards the
!> field side), so its surface, built exactly like the left one, IS the right side seen in
!> the mirrored frame; the mirrored evaluation above then uses it unchanged. The right
!> surfaces are built and stored only when a right profile is given; otherwise the right
!> side shares the left surfaces (no copy).
module rd_contact_geometry
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_profile, only: profile_t
  use rd_contact_surfaces, only: track_placement_t, surface_options_t, wheel_surface_t, rail_surface_t, &
    build_wheel_surface, build_rail_surface
  use rd_contact_patch, only: wheel_contact_t, mirror_wheel_contact
  use rd_strip_contact, only: strip_wheel_contact
  use rd_knife_edge_contact, only: knife_edge_t, knife_wheel_contact
  use rd_contact_table, only: contact_table_t, contact_table_options_t, table_wheel_contact
  use rd_contact_table_cache, only: obtain_contact_table
  implicit none
  private
  public :: contact_geometry_t, CONTACT_MODEL_STRIP, CONTACT_MODEL_KNIFE_EDGE, CONTACT_MODEL_TABLE
  public :: build_strip_contact, build_knife_edge_contact, build_table_contact, wheelset_contact, wheel_contact
  public :: SIDE_LEFT, SIDE_RIGHT

  integer, parameter :: CONTACT_MODEL_STRIP = 1
  integer, parameter :: CONTACT_MODEL_KNIFE_EDGE = 2
  !> profiles through pre-computed tables of the strip model (rd_contact_table)
  integer, parameter :: CONTACT_MODEL_TABLE = 3
  integer, parameter :: SIDE_LEFT = 1, SIDE_RIGHT = 2

  type :: contact_geometry_t
    integer :: model = 0
    type(track_placement_t) :: placement
    type(wheel_surface_t) :: wheel      !< strip model: left wheel, wheelset frame
    type(rail_surface_t) :: rail        !< strip model: left rail, track frame
    !> strip model, right side in the mirrored frame (as the left one); allocated only when
    !> the right profile differs (own_*_right), else the left surface serves both sides
    type(wheel_surface_t) :: wheel_right
    type(rail_surface_t) :: rail_right
    logical :: own_wheel_right = .false.
    logical :: own_rail_right = .false.
    type(knife_edge_t) :: knife         !< knife-edge model
    !> table model: tables of the left pair and, when the right side has its own surfaces,
    !> of the right pair (mirrored frame); the surfaces above stay for the derailment checks
    type(contact_table_t) :: table
    type(contact_table_t) :: table_right
    !> strip model: the energy-consistent normal force (rd_strip_potential)
    logical :: potential_normal = .false.
    !> the distributed strip normal force (rd_hertz_strip; `strip_normal_force = 'distributed'`)
    logical :: distributed_normal = .false.
  end type contact_geometry_t

contains

  !> Strip model. The optional right profiles (same profile frame as the left ones) and
  !> right rail precant (tan; default placement%rail_precant) give the right side its own
  !> surfaces; absent, the right side is the mirror image of the left one.
  subroutine build_strip_contact(geo, wheel_profile, rail_profile, placement, options, error, &
                                wheel_profile_right, rail_profile_right, rail_precant_right)
    type(contact_geometry_t), intent(out) :: geo
    type(profile_t), intent(in) :: wheel_profile, rail_profile
    type(track_placement_t), intent(in) :: placement
    type(surface_options_t), intent(in) :: options
    type(error_t), allocatable, intent(out) :: error
    type(profile_t), intent(in), optional :: wheel_profile_right, rail_profile_right
    real(wp), intent(in), optional :: rail_precant_right
    type(track_placement_t) :: placement_right
    geo%model = CONTACT_MODEL_STRIP
    geo%placement = placement
    call build_wheel_surface(wheel_profile, placement, options, geo%wheel, error)
    if (.not. allocated(error)) call build_rail_surface(rail_profile, placement, options, geo%rail, error)
    if (allocated(error)) then
      call error_context(error, 'build_strip_contact')
      return
    end if
    call check_overlap(geo%wheel, geo%rail, 'left', error)
    if (allocated(error)) return
    placement_right = placement
    if (present(rail_precant_right)) placement_right%rail_precant = rail_precant_right
    ! a right profile equal to the left one (same points) shares the left surface
    if (present(wheel_profile_right)) geo%own_wheel_right = .not. same_points(wheel_profile_right, wheel_profile)
    if (geo%own_wheel_right) then
      call build_wheel_surface(wheel_profile_right, placement_right, options, geo%wheel_right, error)
      if (allocated(error)) then
        call error_context(error, 'build_strip_contact: right wheel')
        return
      end if
    end if
    ! a precant differing from the left one turns the same rail data differently
    if (present(rail_profile_right)) geo%own_rail_right = .not. same_points(rail_profile_right, rail_profile)
    if (placement_right%rail_precant /= placement%rail_precant) geo%own_rail_right = .true.
    if (geo%own_rail_right) then
      if (present(rail_profile_right)) then
        call build_rail_surface(rail_profile_right, placement_right, options, geo%rail_right, error)
      else
        call build_rail_surface(rail_profile, placement_right, options, geo%rail_right, error)
      end if
      if (allocated(error)) then
        call error_context(error, 'build_strip_contact: right rail')
        return
      end if
    end if
    if (geo%own_wheel_right .and. geo%own_rail_right) then
      call check_overlap(geo%wheel_right, geo%rail_right, 'right', error)
    else if (geo%own_wheel_right) then
      call check_overlap(geo%wheel_right, geo%rail, 'right', error)
    else if (geo%own_rail_right) then
      call check_overlap(geo%wheel, geo%rail_right, 'right', error)
    end if
  end subroutine build_strip_contact

  pure logical function same_points(a, b)
    type(profile_t), intent(in) :: a, b
    same_points = .false.
    if (.not. (allocated(a%y) .and. allocated(b%y) .and. allocated(a%z) .and. allocated(b%z))) return
    if (size(a%y) /= size(b%y) .or. size(a%z) /= size(b%z)) return
    same_points = all(a%y == b%y) .and. all(a%z == b%z)
  end function same_points

  subroutine check_overlap(wheel, rail, side_name, error)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    character(len=*), intent(in) :: side_name
    type(error_t), allocatable, intent(out) :: error
    if (wheel%y(wheel%n) < rail%y(1) .or. wheel%y(1) > rail%y(rail%n)) then
      call make_error(error, RD_ERR_INPUT, 'build_strip_contact: ' // side_name // ' wheel and rail do not ' // &
        'overlap laterally; check gauge, back-to-back distance and flange back position')
    end if
  end subroutine check_overlap

  !> Table model from an initialised strip model: each side's pair tabulated once
  !> (rd_contact_table) or read from the table cache (rd_contact_table_cache); the strip
  !> surfaces stay for the profile-based checks.
  subroutine build_table_contact(geo, options, error, directory)
    type(contact_geometry_t), intent(inout) :: geo
    type(contact_table_options_t), intent(in) :: options
    type(error_t), allocatable, intent(out) :: error
    !> the cache directory instead of the user cache (raildyn profile-scan --table DIR)
    character(len=*), intent(in), optional :: directory
    if (geo%model /= CONTACT_MODEL_STRIP) then
      call make_error(error, RD_ERR_INPUT, 'build_table_contact: contact tables need the profile (strip) model')
      return
    end if
    call obtain_contact_table(geo%wheel, geo%rail, options, geo%table, error, directory=directory)
    if (allocated(error)) return
    if (geo%own_wheel_right .and. geo%own_rail_right) then
      call obtain_contact_table(geo%wheel_right, geo%rail_right, options, geo%table_right, error, &
                                directory=directory)
    else if (geo%own_wheel_right) then
      call obtain_contact_table(geo%wheel_right, geo%rail, options, geo%table_right, error, directory=directory)
    else if (geo%own_rail_right) then
      call obtain_contact_table(geo%wheel, geo%rail_right, options, geo%table_right, error, directory=directory)
    end if
    if (allocated(error)) then
      call error_context(error, 'right side')
      return
    end if
    geo%model = CONTACT_MODEL_TABLE
  end subroutine build_table_contact

  subroutine build_knife_edge_contact(geo, knife, error)
    type(contact_geometry_t), intent(out) :: geo
    type(knife_edge_t), intent(in) :: knife
    type(error_t), allocatable, intent(out) :: error
    if (.not. (knife%cone_angle >= 0 .and. knife%cone_angle < 0.8_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_knife_edge_contact: cone angle must be in [0, 0.8) rad')
    else if (.not. (knife%e0 > 0.2_wp .and. knife%e0 < 1.5_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_knife_edge_contact: e0 must be in (0.2, 1.5) m')
    else if (.not. (knife%r0 > 0.1_wp .and. knife%r0 < 2.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_knife_edge_contact: r0 must be in (0.1, 2) m')
    else if (.not. (knife%rail_crown_radius > 0)) then
      call make_error(error, RD_ERR_INPUT, 'build_knife_edge_contact: rail crown radius must be > 0')
    end if
    if (allocated(error)) return
    geo%model = CONTACT_MODEL_KNIFE_EDGE
    geo%knife = knife
    geo%placement%nominal_radius = knife%r0
  end subroutine build_knife_edge_contact

  !> One wheel (SIDE_LEFT or SIDE_RIGHT) for the wheelset pose relative to its track frame.
  pure subroutine wheel_contact(geo, side, y, z, phi, psi, res)
    type(contact_geometry_t), intent(in) :: geo
    integer, intent(in) :: side
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t), intent(out) :: res
    real(wp) :: sgn
    sgn = merge(1.0_wp, -1.0_wp, side == SIDE_LEFT)
    select case (geo%model)
    case (CONTACT_MODEL_STRIP)
      ! the right side's own surfaces when given (flags fixed at build), else the shared left ones
      if (side == SIDE_LEFT .or. .not. (geo%own_wheel_right .or. geo%own_rail_right)) then
        call strip_wheel_contact(geo%wheel, geo%rail, sgn * y, z, sgn * phi, sgn * psi, res, &
                                 potential=geo%potential_normal, distributed=geo%distributed_normal)
      else if (geo%own_wheel_right .and. geo%own_rail_right) then
        call strip_wheel_contact(geo%wheel_right, geo%rail_right, sgn * y, z, sgn * phi, sgn * psi, res, &
                                 potential=geo%potential_normal, distributed=geo%distributed_normal)
      else if (geo%own_wheel_right) then
        call strip_wheel_contact(geo%wheel_right, geo%rail, sgn * y, z, sgn * phi, sgn * psi, res, &
                                 potential=geo%potential_normal, distributed=geo%distributed_normal)
      else
        call strip_wheel_contact(geo%wheel, geo%rail_right, sgn * y, z, sgn * phi, sgn * psi, res, &
                                 potential=geo%potential_normal, distributed=geo%distributed_normal)
      end if
    case (CONTACT_MODEL_KNIFE_EDGE)
      call knife_wheel_contact(geo%knife, sgn * y, z, sgn * phi, sgn * psi, res)
    case (CONTACT_MODEL_TABLE)
      if (side == SIDE_LEFT .or. .not. (geo%own_wheel_right .or. geo%own_rail_right)) then
        call table_wheel_contact(geo%table, sgn * y, z, sgn * phi, sgn * psi, res)
      else
        call table_wheel_contact(geo%table_right, sgn * y, z, sgn * phi, sgn * psi, res)
      end if
    case default
      res%n_patches = 0
    end select
    if (side == SIDE_RIGHT) call mirror_wheel_contact(res)
  end subroutine wheel_contact

  !> Both wheels. Pose: lateral y, vertical z [m] of the wheelset centre in its track frame,
  !> roll phi, yaw psi [rad] (docs/conventions.md). Fails on a non-finite pose or an
  !> uninitialised geometry.
  !>
  !> rail_offset(:, side) = (dy, dz) [m]: that rail displaced in the track frame (track
  !> irregularities, rd_track_irregularity). A translated rail seen from a wheel is the
  !> nominal rail seen from the pose (y - dy, z - dz); the rail points found are shifted back
  !> by (dy, dz). Normals, curvatures, penetrations and the wheel points (relative to the
  !> wheelset centre) are invariant under the translation.
  pure subroutine wheelset_contact(geo, y, z, phi, psi, left, right, error, rail_offset)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t), intent(out) :: left, right
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: rail_offset(2, 2)
    if (geo%model == 0) then
      call make_error(error, RD_ERR_INPUT, 'wheelset_contact: contact geometry not initialised')
      return
    end if
    ! ieee_is_finite first: an ordered comparison with NaN would trap in Debug builds
    if (.not. all(ieee_is_finite([y, z, phi, psi]))) then
      call make_error(error, RD_ERR_RUNTIME, 'wheelset_contact: wheelset pose is not finite (NaN or Inf)')
      return
    end if
    if (.not. (abs(y) < 1 .and. abs(z) < 10 .and. abs(phi) < 1 .and. abs(psi) < 1)) then
      call make_error(error, RD_ERR_RUNTIME, 'wheelset_contact: wheelset pose not finite or out of range '// &
        '(|y| < 1 m, |z| < 10 m, |roll|, |yaw| < 1 rad)')
      return
    end if
    if (present(rail_offset)) then
      if (.not. all(ieee_is_finite(rail_offset))) then
        call make_error(error, RD_ERR_RUNTIME, 'wheelset_contact: rail offset is not finite (NaN or Inf)')
        return
      end if
      call offset_wheel_contact(SIDE_LEFT, left)
      call offset_wheel_contact(SIDE_RIGHT, right)
    else
      call wheel_contact(geo, SIDE_LEFT, y, z, phi, psi, left)
      call wheel_contact(geo, SIDE_RIGHT, y, z, phi, psi, right)
    end if
  contains
    pure subroutine offset_wheel_contact(side, res)
      integer, intent(in) :: side
      type(wheel_contact_t), intent(out) :: res
      integer :: k
      call wheel_contact(geo, side, y - rail_offset(1, side), z - rail_offset(2, side), phi, psi, res)
      do k = 1, res%n_patches
        res%patch(k)%point_rail(2:3) = res%patch(k)%point_rail(2:3) + rail_offset(:, side)
      end do
    end subroutine offset_wheel_contact
  end subroutine wheelset_contact

end module rd_contact_geometry
