!> Start-up of a scene's mechanics: bodies, elements, loads and contact built from the deck
!> (build_mechanics), then the initial state, static equilibrium, free lengths and the
!> integrator (start_mechanics).
submodule (rd_scene) rd_scene_startup
  implicit none

contains

  !> Bodies, frames, elements and loads from the deck (no state yet).
  module procedure build_mechanics
    type(body_spec_t), allocatable :: bodies(:)
    class(force_element_t), allocatable :: element
    class(force_provider_t), pointer :: provider
    real(wp) :: gravity
    integer :: i
    character(len=:), allocatable :: method

    call build_bodies(self%deck, bodies, self%frame_offsets, error)
    if (allocated(error)) return
    self%warning_list = self%deck%notes()
    call check_body_inertia(self%deck, bodies, self%warning_list, error)
    if (allocated(error)) return
    call check_rail_bodies(self%deck, bodies, self%frame_offsets, error)
    if (allocated(error)) return
    ! the contact first: a wheelset's reference rolling radius comes from its geometry
    if (self%deck%count('wheelset') > 0) then
      call build_contact(self, error)
      if (allocated(error)) return
      call set_reference_radii(self, bodies, error)
      if (allocated(error)) return
    end if
    call self%deck%get('simulation', 1, 'gravity', gravity, error); if (allocated(error)) return
    allocate (self%mbs)
    call self%mbs%build(bodies, self%frame_offsets, self%track, self%speed, error, &
                       sigma0=self%start_sigma, gravity=gravity)
    if (allocated(error)) return
    do i = 1, self%deck%count('element')
      call build_element(self%deck, i, element, error)
      if (allocated(error)) return
      call self%mbs%add_element(element, error)
      if (allocated(error)) then
        call error_context(error, self%deck%origin('element', i))
        return
      end if
    end do
    call stiffness_warnings(self%deck, bodies, self%warning_list)
    allocate (self%loads)
    call build_external_loads(self%deck, self%loads, error)
    if (allocated(error)) return
    provider => self%loads
    call self%mbs%add_provider(provider)
    if (associated(self%contact)) then
      provider => self%contact
      call self%mbs%add_provider(provider)
    end if

    call self%deck%get('simulation', 1, 'equilibrium', self%equilibrium, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'method', method, error); if (allocated(error)) return
    self%solver%method = method
    call self%deck%get('solver', 1, 'rtol', self%solver%rtol, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'atol', self%solver%atol, error); if (allocated(error)) return
    if (self%deck%given('solver', 1, 'atol_velocity')) then
      block   ! rates in m/s and rad/s get their own tolerance (rd_multibody absolute_tolerances)
        real(wp) :: atol_velocity
        call self%deck%get('solver', 1, 'atol_velocity', atol_velocity, error); if (allocated(error)) return
        self%solver%atol_vector = self%mbs%absolute_tolerances(self%solver%atol, atol_velocity)
      end block
    end if
    call self%deck%get('solver', 1, 'max_step', self%solver%max_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'min_step', self%solver%min_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'initial_step', self%solver%initial_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'max_num_steps', self%solver%max_num_steps, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'fixed_step', self%solver%fixed_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'max_order', self%solver%max_order, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'jacobian_max_age', self%solver%jacobian_max_age, error)
    if (allocated(error)) return
    call self%deck%get('solver', 1, 'jacobian', self%jacobian, error); if (allocated(error)) return
  end procedure build_mechanics

  !> The wheel-rail contact of every &wheelset (profiles, geometry, Hertz, creep law,
  !> irregularities).
  subroutine build_contact(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    type(wheelset_contact_spec_t), allocatable :: specs(:)
    type(track_irregularity_t), allocatable :: irregularity
    character(len=:), allocatable :: name
    character(len=512), allocatable :: labels(:)
    integer :: i
    call build_wheelset_specs(self%deck, specs, error)
    if (allocated(error)) return
    ! profile files read here, so that their errors name the deck line and the wheelset
    call load_wheelset_profiles(self%deck, specs, error)
    if (allocated(error)) return
    allocate (labels(size(specs)))
    do i = 1, size(specs)
      labels(i) = self%deck%origin('wheelset', i)
    end do
    allocate (self%contact)
    call self%contact%build(specs, self%nbodies, error, labels)
    if (allocated(error)) then
      ! wheel and rail that do not overlap: the values that place them may come from other
      ! lines (or files) than the &wheelset's own, so name where each one was given
      if (index(error%message, 'overlap laterally') > 0) then
        do i = 1, size(specs)
          if (index(error%message, trim(labels(i))) /= 1) cycle
          error%message = error%message // '; values used: ' // &
            self%deck%origin('wheelset', i, 'back_to_back') // ', ' // &
            self%deck%origin('wheelset', i, 'flange_back') // ', ' // self%deck%origin('track', 1, 'gauge')
          exit
        end do
      end if
      return
    end if
    ! track irregularities displace the rails under every wheelset (rd_track_irregularity)
    call build_scene_irregularity(self%deck, irregularity, error)
    if (allocated(error)) return
    if (allocated(irregularity)) call self%contact%set_irregularity(irregularity)
    allocate (self%wheelset_names(size(specs)))
    do i = 1, size(specs)
      call self%deck%get('wheelset', i, 'name', name, error); if (allocated(error)) return
      self%wheelset_names(i) = name
    end do
  end subroutine build_contact

  !> Each wheelset body's reference rolling radius r0 (nominal spin V / r0): &wheelset
  !> reference_radius when given, else computed from its contact geometry
  !> (rd_reference_radius: the centred rolling radius of the profiles; knife edge:
  !> nominal_radius).
  subroutine set_reference_radii(self, bodies, error)
    class(scene_t), intent(in) :: self
    type(body_spec_t), intent(inout) :: bodies(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: reason
    integer :: w
    do w = 1, size(self%contact%models)
      associate (r0 => bodies(self%contact%models(w)%body)%r0)
        if (self%deck%given('wheelset', w, 'reference_radius')) then
          call self%deck%get('wheelset', w, 'reference_radius', r0, error)
        else
          call centred_rolling_radius(self%contact%models(w)%geo, r0, error)
          if (allocated(error)) then
            reason = error%message     ! (make_error deallocates error first)
            call make_error(error, RD_ERR_INPUT, self%deck%origin('wheelset', w, 'reference_radius') // &
              ': not given, and the centred rolling radius of the profiles failed (' // reason // &
              '); expected profiles on which the centred wheelset touches both rails, or ' // &
              'reference_radius in (0.2, 0.7) m')
          end if
        end if
      end associate
      if (allocated(error)) return
    end do
  end subroutine set_reference_radii

  !> Initial state: elements at their nominal length in the initial configuration,
  !> preloads for static equilibrium (thesis 5.2.1 d), then the integrator.
  module procedure start_mechanics
    logical :: supported(self%nbodies), held(6, self%nbodies)
    integer :: w
    allocate (self%y(self%mbs%state_size()))
    call self%mbs%initial_state(self%y, error)
    if (allocated(error)) return
    ! With a static position solve to follow, the vehicle is built on level straight track
    ! (free lengths and preloads), so that a start inside a curve does not build the curve's
    ! offsets between the body frames into the springs; the solve then deflects them.
    ! Without one ('none', or preloads alone for a scene without wheel-rail contact) the
    ! initial configuration stays the unstressed one.
    call nominal_lengths_from_initial_configuration(self%mbs, self%y, on_level_track= &
      self%equilibrium == 'solve' .or. (self%equilibrium == 'preload' .and. associated(self%contact)))
    ! the elements' internal states again, from the final free lengths: a series damper's
    ! initial elongation was taken with the deck's free length (0), i.e. x_d = |p2 - p1|,
    ! which would start it with a tension k |p2 - p1| instead of relaxed
    call self%mbs%initial_state(self%y, error)
    if (allocated(error)) return
    self%y_as_built = self%y     ! what the equilibrium moves is reported (check_report)
    ! Bodies in wheel-rail contact: at V = 0 no creep force holds them laterally nor on
    ! their spin, so the static solve holds their lateral position and spin
    ! (rd_static_preload, module header)
    supported = .false.
    held = .false.
    if (associated(self%contact)) then
      do w = 1, size(self%contact%models)
        supported(self%contact%models(w)%body) = .true.
        held([DOF_Y, DOF_PITCH], self%contact%models(w)%body) = .true.
      end do
    end if
    select case (self%equilibrium)
    case ('preload')
      if (associated(self%contact)) then
        ! Thesis 5.2.1 d: suspension preloads carry the bodies above the wheelsets (found on
        ! level track: they belong to the vehicle, not to the cant where it starts); the
        ! wheelsets are carried by the rails, so their equations are left to a static
        ! position solve (contact penetration, suspension settling, lean in the cant) that
        ! follows.
        call solve_static_preloads(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error, &
                                   supported=supported, level_track=.true.)
        if (.not. allocated(error)) &
          call solve_static_positions(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error, &
                                      held=held, seated=supported)
      else
        call solve_static_preloads(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error)
      end if
    case ('solve')
      call solve_static_positions(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error, held=held, &
                                  seated=supported)
    end select
    if (allocated(error)) then
      call error_context(error, self%deck%origin('simulation', 1, 'equilibrium'))
      return
    end if
    allocate (self%integrator)
    if (self%solver%method == 'bdf' .and. self%jacobian == 'coloured') then
      ! Bodies that share no force are perturbed in the same RHS call (rd_scene_jacobian);
      ! a provider without stated coupling keeps CVODE's dense difference quotients.
      block
        type(jacobian_sparsity_t) :: sparsity
        character(len=:), allocatable :: dense_reason
        call scene_jacobian_sparsity(self%mbs, sparsity, dense_reason, error)
        if (allocated(error)) return
        if (allocated(dense_reason)) then
          call self%integrator%build(self%mbs, 0.0_wp, self%y, self%solver, error)
        else
          call self%integrator%build(self%mbs, 0.0_wp, self%y, self%solver, error, &
                                    jacobian_sparsity=sparsity)
        end if
      end block
    else
      call self%integrator%build(self%mbs, 0.0_wp, self%y, self%solver, error)
    end if
    if (allocated(error)) call error_context(error, self%deck%origin('solver', 1))
  end procedure start_mechanics

  !> Point-to-point elements are unstressed (apart from their preload) in the initial
  !> configuration: their free length is the separation of the attachment points there.
  !> `on_level_track`: the bodies at their initial coordinates relative to frames on
  !> straight level track (rd_static_preload), i.e. the vehicle as built.
  subroutine nominal_lengths_from_initial_configuration(mbs, y, on_level_track)
    type(multibody_t), intent(inout) :: mbs
    real(wp), intent(in) :: y(:)
    logical, intent(in) :: on_level_track
    real(wp), allocatable :: ydot(:)
    integer :: e
    type(level_straight_track_t), target :: level
    class(track_geometry_t), pointer :: actual
    allocate (ydot(size(y)))
    actual => mbs%track
    if (on_level_track) mbs%track => level
    ! the elements alone (no contact, no right-hand side whose error would be dropped), in
    ! the deck's configuration as it stands: quasi-static wheelsets are not moved to their balance
    call mbs%evaluate_kinematics(0.0_wp, y)
    call mbs%element_loads(0.0_wp, y, ydot)
    mbs%track => actual
    do e = 1, mbs%element_count()
      call mbs%elements(e)%e%reset_free_length(mbs%scratch%el_res(e)%deflection)
    end do
  end subroutine nominal_lengths_from_initial_configuration

end submodule rd_scene_startup
