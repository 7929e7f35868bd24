!> What defines the wheel-rail contact of one wheelset: plain data the scene builder fills
!> from the deck's `&wheelset` group, and the routines that turn it into the parameters of
!> the pipeline (profiles -> contact geometry, materials -> Hertz, creep law by name).
!>
!> Units SI; frames, signs and side numbering (1 left, 2 right) as docs/conventions.md.
!> The pipeline itself is rd_wheelset_contact (docs/theory_wheelset.md).
module rd_wheelset_contact_spec
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL, validate_profile
  use rd_profile_source, only: load_wheel_profile, load_rail_profile
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_knife_edge_contact, only: knife_edge_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, build_knife_edge_contact, &
                                 build_table_contact, SIDE_LEFT, SIDE_RIGHT
  use rd_contact_table, only: contact_table_options_t
  use rd_hertz, only: hertz_params_t, build_hertz
  use rd_hertz_strip, only: fill_strip_stiffness_table
  use rd_creep_law, only: creep_law_options_t
  use rd_creepage, only: default_creep_v0
  implicit none
  private
  public :: wheelset_contact_spec_t, load_contact_profiles, build_contact_geometry, build_hertz_params
  public :: validate_wheelset_contact_spec, flange_tip_coordinate, field_end_coordinate
  public :: SIDE_LEFT, SIDE_RIGHT, CONTACT_MODEL_NAMES

  character(len=*), parameter :: CONTACT_MODEL_NAMES = '''profile'' or ''knife_edge'''
  !> Point spacing of the analytic profiles [m] (the surfaces are resampled anyway); a finer
  !> strip spacing (&wheelset strip_spacing) samples them at its own spacing, so finer strips
  !> see the analytic curve and not chords of a 0.2 mm polyline.
  real(wp), parameter :: analytic_spacing = 2.0e-4_wp

  !> One wheelset's contact, as read from the deck. Defaults: Manchester benchmark wheelset
  !> (S1002 / 60E1 1:40, gauge 1435 mm, back-to-back 1360 mm, r0 0.46 m, G 82 GPa, nu 0.28,
  !> mu 0.3, FASTSIM).
  type :: wheelset_contact_spec_t
    integer :: body = 0                              !< index of the wheelset body (1-based)
    !> Flexible track (docs/theory_track_flexibility.md): index of the body that is the left
    !> (side 1) resp. right rail under this wheelset, 0 = rigid rail fixed in the track frame.
    !> The rail body's (y, z) in its track frame displace the rail like an irregularity; it
    !> gets the reaction of the wheel's contact force.
    integer :: rail_body(2) = 0
    character(len=16) :: model = 'profile'           !< 'profile' (strips) | 'knife_edge'
    !> profile model: 'strips' (online strip search) | 'table' (pre-computed tables of it,
    !> rd_contact_table, with `table` options)
    character(len=16) :: contact_geometry = 'strips'
    !> online strips: 'distributed' (every strip along its depth gradient, rd_hertz_strip) |
    !> 'centroid' (per patch, along the normal at its centroid) | 'potential' (per patch, an
    !> effective penetration's gradient, rd_strip_potential)
    character(len=16) :: strip_normal_force = 'distributed'
    type(contact_table_options_t) :: table
    !> profiles: a file path (SIMPACK .prw/.prr or table) or 's1002' / '60e1' / '54e1'.
    !> Ignored when the corresponding *_data profile is given (points allocated).
    character(len=:), allocatable :: wheel_profile
    character(len=:), allocatable :: rail_profile
    type(profile_t) :: wheel_profile_data           !< already-read wheel profile (optional)
    type(profile_t) :: rail_profile_data            !< already-read rail profile (optional)
    !> right wheel / right rail (side 2), same forms; not allocated: the same as the left
    !> ones. Given in the left profile frame (docs/conventions.md "Profiles"): lateral
    !> coordinate positive towards that wheel's / rail's field side; raildyn mirrors it.
    character(len=:), allocatable :: wheel_profile_right
    character(len=:), allocatable :: rail_profile_right
    real(wp) :: nominal_radius = 0.46_wp             !< r0 [m] (tape circle)
    real(wp) :: back_to_back = 1.360_wp              !< [m]
    real(wp) :: flange_back = -0.070_wp              !< wheel profile coordinate of the flange back [m]
    real(wp) :: gauge = 1.435_wp                     !< [m], measured gauge_depth below the rail top
    real(wp) :: gauge_depth = 0.014_wp               !< [m]
    real(wp) :: rail_inclination = 0.025_wp          !< tan of the rail cant (1:40)
    real(wp) :: rail_precant = 0.0_wp                !< tan of an inclination already in the rail file
    real(wp) :: rail_precant_right = -1.0_wp         !< the same for the right rail file; < 0: rail_precant
    type(surface_options_t) :: surface               !< resampling / curvature filter of the profiles
    ! knife-edge model (thesis 5.3.3)
    real(wp) :: knife_conicity = 0.2_wp              !< lambda = tan(gamma) of the cones [-]
    real(wp) :: knife_e0 = 0.75_wp                   !< half the distance between the contact points [m]
    real(wp) :: knife_rail_crown_radius = 0.3_wp     !< rail head radius for Hertz [m]
    real(wp) :: knife_flange_clearance = -1.0_wp     !< lateral free play to a flange stop [m]; <= 0: none
    real(wp) :: knife_flange_stiffness = 0.0_wp      !< lateral stiffness of that stop [N/m]
    ! material: E > 0 wins, else E = 2 G (1 + nu) (same material for wheel and rail)
    real(wp) :: young_modulus = 0.0_wp               !< [Pa]; 0: from shear_modulus and poisson
    real(wp) :: shear_modulus = 82.0e9_wp            !< G [Pa]
    real(wp) :: poisson = 0.28_wp                    !< nu [-]
    character(len=16) :: hertz_method = 'elliptic_table'   !< 'elliptic_table' | 'elliptic' | 'table'
    real(wp) :: max_equivalent_radius = 10.0_wp      !< conformal-contact bound of Hertz [m]
    real(wp) :: contact_damping = 0.0_wp             !< normal damping c_n [N s/m] per patch
    real(wp) :: friction = 0.3_wp                    !< mu [-]
    character(len=16) :: creep_law = 'fastsim'       !< 'linear' | 'fastsim' | 'polach'
    type(creep_law_options_t) :: creep_options
    !> .false.: the creep law gets zero spin creepage (thesis 5.5-5.6 compare FASTSIM and Polach
    !> "as the spin creepage is not taken into account"); the spin itself is still output
    logical :: spin_creep = .true.
    real(wp) :: creep_v0 = default_creep_v0          !< creep velocity regularisation [m/s]
    !> run-time limits: a wheel whose smallest gap exceeds liftoff_limit is an error [m]
    real(wp) :: liftoff_limit = 0.02_wp
  end type wheelset_contact_spec_t

contains

  !> Check the numbers that no downstream build checks; `nbodies` bounds `body`.
  subroutine validate_wheelset_contact_spec(spec, nbodies, error)
    type(wheelset_contact_spec_t), intent(in) :: spec
    integer, intent(in) :: nbodies
    type(error_t), allocatable, intent(out) :: error
    if (spec%body < 1 .or. spec%body > nbodies) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: body index out of range 1..number of bodies')
    else if (any(spec%rail_body < 0 .or. spec%rail_body > nbodies)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: rail body index out of range; expected 0 (rigid rail) ' // &
                      'or 1..number of bodies')
    else if (any(spec%rail_body == spec%body)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: a rail body must differ from the wheelset body')
    else if (spec%rail_body(1) > 0 .and. spec%rail_body(1) == spec%rail_body(2)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: the left and right rail bodies must differ')
    else if (trim(spec%model) /= 'profile' .and. trim(spec%model) /= 'knife_edge') then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: contact model "' // trim(spec%model) // &
                      '" unknown; expected ' // CONTACT_MODEL_NAMES)
    else if (trim(spec%contact_geometry) /= 'strips' .and. trim(spec%contact_geometry) /= 'table') then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: contact geometry "' // trim(spec%contact_geometry) // &
                      '" unknown; expected ''strips'' or ''table''')
    else if (trim(spec%contact_geometry) == 'table' .and. trim(spec%model) /= 'profile') then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: contact_geometry = ''table'' needs profile contact')
    else if (trim(spec%strip_normal_force) /= 'centroid' .and. trim(spec%strip_normal_force) /= 'potential' .and. &
             trim(spec%strip_normal_force) /= 'distributed') then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: strip normal force "' // trim(spec%strip_normal_force) // &
                      '" unknown; expected ''centroid'', ''potential'' or ''distributed''')
    else if (.not. (spec%friction >= 0 .and. spec%friction < 5)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: friction coefficient must be in [0, 5)')
    else if (.not. (spec%contact_damping >= 0 .and. spec%contact_damping < 1.0e12_wp)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: contact damping must be >= 0 N s/m (finite)')
    else if (.not. (spec%creep_v0 > 0 .and. spec%creep_v0 < 100)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: creep velocity regularisation v0 must be in (0, 100) m/s')
    else if (.not. (spec%liftoff_limit > 0 .and. spec%liftoff_limit < 1)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: lift-off limit must be in (0, 1) m')
    else if (.not. (spec%knife_flange_stiffness >= 0 .and. spec%knife_flange_stiffness < 1.0e15_wp)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: knife-edge flange stiffness must be >= 0 N/m')
    else if (trim(spec%model) == 'knife_edge' .and. spec%knife_flange_clearance > 0 .and. &
             .not. (spec%knife_flange_stiffness > 0)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: a knife-edge flange clearance needs a flange stiffness > 0 N/m')
    else if (.not. (spec%young_modulus >= 0 .and. spec%shear_modulus > 0 .and. spec%shear_modulus < 1.0e15_wp)) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact: expected shear modulus G > 0 Pa and Young''s modulus E >= 0 Pa')
    end if
  end subroutine validate_wheelset_contact_spec

  !> The wheel and rail profiles of a spec: the given *_data profile if it has points,
  !> else the keyword ('s1002'; '60e1', '54e1') or the file path.
  subroutine load_contact_profiles(spec, wheel, rail, error)
    type(wheelset_contact_spec_t), intent(in) :: spec
    type(profile_t), intent(out) :: wheel, rail
    type(error_t), allocatable, intent(out) :: error
    if (allocated(spec%wheel_profile_data%y)) then
      wheel = spec%wheel_profile_data
      wheel%kind = PROFILE_WHEEL
      if (.not. allocated(wheel%source)) wheel%source = '(given)'
      call validate_profile(wheel, error)
    else if (.not. allocated(spec%wheel_profile)) then
      call make_error(error, RD_ERR_INPUT, 'no wheel profile given; expected a file path or ''s1002''')
    else
      call load_wheel_profile(spec%wheel_profile, wheel, error, min(analytic_spacing, spec%surface%wheel_spacing))
    end if
    if (allocated(error)) then
      call error_context(error, 'load_contact_profiles')
      return
    end if
    if (allocated(spec%rail_profile_data%y)) then
      rail = spec%rail_profile_data
      rail%kind = PROFILE_RAIL
      if (.not. allocated(rail%source)) rail%source = '(given)'
      call validate_profile(rail, error)
    else if (.not. allocated(spec%rail_profile)) then
      call make_error(error, RD_ERR_INPUT, 'no rail profile given; expected a file path, ''60e1'' or ''54e1''')
    else
      call load_rail_profile(spec%rail_profile, rail, error, min(analytic_spacing, spec%surface%rail_spacing))
    end if
    if (allocated(error)) call error_context(error, 'load_contact_profiles')
  end subroutine load_contact_profiles

  !> The contact geometry of the spec's model (profiles loaded when the model needs them).
  subroutine build_contact_geometry(spec, geo, error)
    type(wheelset_contact_spec_t), intent(in) :: spec
    type(contact_geometry_t), intent(out) :: geo
    type(error_t), allocatable, intent(out) :: error
    type(profile_t) :: wheel, rail, wheel_right, rail_right
    type(track_placement_t) :: placement
    real(wp) :: precant_right
    type(knife_edge_t) :: knife
    if (trim(spec%model) == 'knife_edge') then
      if (.not. (spec%knife_conicity >= 0 .and. spec%knife_conicity < 1)) then
        call make_error(error, RD_ERR_INPUT, 'build_contact_geometry: knife-edge conicity must be in [0, 1)')
        return
      end if
      knife%cone_angle = atan(spec%knife_conicity)
      knife%e0 = spec%knife_e0
      knife%r0 = spec%nominal_radius
      knife%flange_clearance = spec%knife_flange_clearance
      knife%rail_crown_radius = spec%knife_rail_crown_radius
      call build_knife_edge_contact(geo, knife, error)
    else
      call load_contact_profiles(spec, wheel, rail, error)
      if (allocated(error)) return
      placement%gauge = spec%gauge
      placement%gauge_depth = spec%gauge_depth
      placement%inclination = spec%rail_inclination
      placement%rail_precant = spec%rail_precant
      placement%back_to_back = spec%back_to_back
      placement%flange_back = spec%flange_back
      placement%nominal_radius = spec%nominal_radius
      precant_right = spec%rail_precant
      if (spec%rail_precant_right >= 0) precant_right = spec%rail_precant_right
      ! right profiles only when named; build_strip_contact shares surfaces equal to the left ones
      if (allocated(spec%wheel_profile_right)) then
        call load_wheel_profile(spec%wheel_profile_right, wheel_right, error, &
                                min(analytic_spacing, spec%surface%wheel_spacing))
        if (allocated(error)) call error_context(error, 'right wheel profile')
      end if
      if (allocated(spec%rail_profile_right) .and. .not. allocated(error)) then
        call load_rail_profile(spec%rail_profile_right, rail_right, error, &
                               min(analytic_spacing, spec%surface%rail_spacing))
        if (allocated(error)) call error_context(error, 'right rail profile')
      end if
      if (allocated(error)) then
        call error_context(error, 'build_contact_geometry')
        return
      end if
      if (allocated(spec%wheel_profile_right) .and. allocated(spec%rail_profile_right)) then
        call build_strip_contact(geo, wheel, rail, placement, spec%surface, error, wheel_profile_right=wheel_right, &
                                rail_profile_right=rail_right, rail_precant_right=precant_right)
      else if (allocated(spec%wheel_profile_right)) then
        call build_strip_contact(geo, wheel, rail, placement, spec%surface, error, wheel_profile_right=wheel_right, &
                                rail_precant_right=precant_right)
      else if (allocated(spec%rail_profile_right)) then
        call build_strip_contact(geo, wheel, rail, placement, spec%surface, error, rail_profile_right=rail_right, &
                                rail_precant_right=precant_right)
      else
        call build_strip_contact(geo, wheel, rail, placement, spec%surface, error, rail_precant_right=precant_right)
      end if
      ! (online strips only: a contact table tabulates the classic patches, a knife edge has none)
      geo%potential_normal = trim(spec%strip_normal_force) == 'potential' .and. trim(spec%contact_geometry) == 'strips'
      geo%distributed_normal = trim(spec%strip_normal_force) == 'distributed' .and. &
                               trim(spec%contact_geometry) == 'strips'
      if (geo%distributed_normal) call fill_strip_stiffness_table()
      ! the provider: online strips, or tables of them (one line, the rest is shared)
      if (.not. allocated(error) .and. trim(spec%contact_geometry) == 'table') call build_table_contact(geo, spec%table, error)
    end if
    if (allocated(error)) call error_context(error, 'build_contact_geometry')
  end subroutine build_contact_geometry

  !> Hertz parameters: one material for wheel and rail.
  subroutine build_hertz_params(spec, params, error)
    type(wheelset_contact_spec_t), intent(in) :: spec
    type(hertz_params_t), intent(out) :: params
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: e
    e = spec%young_modulus
    if (.not. (e > 0)) e = 2 * spec%shear_modulus * (1 + spec%poisson)
    call build_hertz(params, error, young_wheel=e, poisson_wheel=spec%poisson, young_rail=e, &
                    poisson_rail=spec%poisson, method=trim(spec%hertz_method), &
                    max_equivalent_radius=spec%max_equivalent_radius)
    if (allocated(error)) call error_context(error, 'build_hertz_params')
  end subroutine build_hertz_params

  !> Wheel profile coordinate s of the flange tip (largest radius) of the strip geometry's
  !> wheel on `side` (default left; the right wheel's own profile when it has one); a
  !> contact at smaller s has climbed over the flange.
  pure real(wp) function flange_tip_coordinate(geo, side) result(s_tip)
    type(contact_geometry_t), intent(in) :: geo
    integer, intent(in), optional :: side
    integer :: k
    logical :: right
    s_tip = -huge(1.0_wp)
    right = .false.
    if (present(side)) right = side == SIDE_RIGHT .and. geo%own_wheel_right
    if (right) then
      k = maxloc(geo%wheel_right%r, dim=1)
      s_tip = geo%wheel_right%s(k)
    else
      if (.not. allocated(geo%wheel%r)) return
      k = maxloc(geo%wheel%r, dim=1)
      s_tip = geo%wheel%s(k)
    end if
  end function flange_tip_coordinate

  !> Wheel profile coordinate s of the field-side end of the strip geometry's wheel on
  !> `side` (huge when there is no strip geometry).
  pure real(wp) function field_end_coordinate(geo, side) result(s_end)
    type(contact_geometry_t), intent(in) :: geo
    integer, intent(in) :: side
    s_end = huge(1.0_wp)
    if (side == SIDE_RIGHT .and. geo%own_wheel_right) then
      s_end = geo%wheel_right%s(geo%wheel_right%n)
    else if (allocated(geo%wheel%s)) then
      s_end = geo%wheel%s(geo%wheel%n)
    end if
  end function field_end_coordinate


end module rd_wheelset_contact_spec
