!> The wheel-rail contact force provider: the contact pipeline assembled per wheelset
!> (thesis 4.7-4.8; docs/theory_wheelset.md):
!>
!>   pose (y, z, roll, yaw relative to the track frame; the spin does not matter for a body
!>   of revolution, so the geometry works in the intermediate frame A Rz(psi) Rx(phi),
!>   thesis eq. 4.78)
!>   -> geometry (patches per wheel) -> Hertz normal force from the penetration and the
!>   principal curvatures (+ damping on the approach rate)
!>   -> creepages from the velocity of the wheel's MATERIAL point at the contact relative to
!>   the rail (fixed in the fixed frame), in contact-frame components (thesis 4.80-4.86)
!>   -> creep law -> force N n + Fx x_c + Fy y_c and spin moment Mz n on the wheel
!>   -> force at the CG and moment about the CG, fixed-frame components, added to the
!>   wheelset's load. The multibody projects them on the generalized coordinates (H^T),
!>   which is what thesis eqs. 4.87-4.102 intend (see the theory doc for their errors).
!>
!> Flexible track (docs/theory_track_flexibility.md): a side with a rail body sees its rail
!> displaced by that body's (y, z) in its track frame (added to the irregularity offsets),
!> the rail material moving with the body's displacement rate, and the body gets the
!> reaction (minus the wheel's contact force) at its CG; no moment: the rail body's
!> rotations are frozen, and the moment of the reaction about its CG is carried by those
!> frozen coordinates (a co-moving rail mass, as SIMPACK's/GENSYS' "rail bodies").
!>
!> Parameters are fixed by `build`; `add_forces` allocates nothing and keeps the per-patch
!> results of the last evaluation in `results` for the outputs.
module rd_wheelset_contact
  use rd_kinds, only: wp
  use rd_text, only: int_text, sci_text
  use rd_error, only: error_t, make_error, error_context, retry_error, finite, RD_ERR_INPUT, RD_ERR_PHYSICS
  use rd_rotation, only: cross
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_provider, only: force_provider_t, body_load_t
  use rd_contact_patch, only: patch_geometry_t, patch_potential_t, wheel_contact_t, PATCH_FLANGE_SPRING
  use rd_contact_geometry, only: contact_geometry_t, wheelset_contact, CONTACT_MODEL_STRIP, CONTACT_MODEL_TABLE, &
    SIDE_LEFT, SIDE_RIGHT
  use rd_hertz, only: hertz_params_t, hertz_patch_t, hertz_from_penetration, hertz_from_force, hertz_damped_force
  use rd_creepage, only: creepage_t, creepages_from_velocities
  use rd_creep_law, only: creep_law_t, creep_force_t, creep_patch_t
  use rd_creep_factory, only: build_creep_law
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, validate_wheelset_contact_spec, &
    build_contact_geometry, build_hertz_params, flange_tip_coordinate, &
    field_end_coordinate
  use rd_wheel_contact_result, only: patch_result_t, wheel_result_t, wheelset_result_t
  use rd_track_irregularity, only: track_irregularity_t
  implicit none
  private
  public :: wheelset_contact_t, wheelset_model_t, SIDE_LEFT, SIDE_RIGHT, patch_frame_and_point

  !> Loads below this are "no vertical load" for Y/Q [N].
  real(wp), parameter :: q_min = 1.0_wp
  !> A contact within this distance of the field-side end of the wheel profile means the
  !> rail has left the tread [m].
  real(wp), parameter :: field_end_margin = 1.0e-3_wp
  !> Poses kept besides the last one in a wheelset's geometry cache (wheelset_cache_t).
  integer, parameter :: cache_history = 2
  !> Inputs of a wheelset's pipeline after its geometry (pipeline_key): the pose with the rail
  !> offsets (8), the rails' material velocities (6), the wheelset's velocity and angular
  !> velocity (6), its track frame (9), its attachment rotation (9) and its x (1).
  integer, parameter :: pipeline_key_size = 39

  !> Scratch of a wheelset's contact: the geometry of the last pose (y, z, roll, yaw) evaluated,
  !> reused when the next call has bitwise the same pose: a finite-difference Jacobian perturbs
  !> one state per RHS call, and only 4 of a scene's states move a given wheelset's geometry,
  !> which is ~75 % of the RHS cost (docs/performance.md). Exact: same input, same result.
  !> With track irregularities the key also holds the rail offsets (dy, dz per side).
  type :: wheelset_cache_t
    logical :: valid = .false.
    real(wp) :: pose(8) = 0
    type(wheel_contact_t) :: geo(2)
    !> The two poses used before it, with their geometry (a pose found here swaps places with
    !> the last one, which stays pose / geo): the quasi-static solve and the output's
    !> sub-samples come back to a pose two or three evaluations later. Measured on the
    !> acceptance deck (docs/performance.md): 11.6 % of the evaluations find their pose in the
    !> three, 5.0 % in the last one alone. Exact, as the last pose.
    logical :: history_valid(cache_history) = .false.
    real(wp) :: history_pose(8, cache_history) = 0
    type(wheel_contact_t) :: history_geo(2, cache_history)
    integer :: history_next = 1            !< the history slot the next new pose pushes out
    !> The whole result of the last evaluation (every wheel's patches through Hertz, the
    !> creep law and the forces) and the inputs it came from (pipeline_key): a call with
    !> bitwise the same inputs returns it without running the pipeline. It catches what the
    !> geometry cache cannot save, the creep law (FASTSIM: a fifth of the tables deck's
    !> instructions): the integrator's coloured difference quotients perturb a few bodies per
    !> call and the quasi-static solve comes back to a wheelset's solution, so that a call
    !> often finds a wheelset exactly where the last one left it. Exact: same input, same
    !> result; only successful evaluations are kept.
    logical :: result_valid = .false.
    real(wp) :: result_key(pipeline_key_size) = 0
    type(wheelset_result_t) :: result
    real(wp) :: result_wheel_force(3, 2) = 0
  end type wheelset_cache_t

  !> Parameters of one wheelset's contact (fixed after build), and its geometry cache.
  type :: wheelset_model_t
    integer :: body = 0
    integer :: rail_body(2) = 0            !< left/right rail body, 0 = rigid rail
    type(contact_geometry_t) :: geo
    type(hertz_params_t) :: hertz
    class(creep_law_t), allocatable :: law
    real(wp) :: friction = 0.3_wp
    logical :: spin_creep = .true.      !< spin creepage passed to the creep law
    real(wp) :: damping = 0
    real(wp) :: v0 = 0.05_wp
    real(wp) :: liftoff_limit = 0.02_wp
    real(wp) :: flange_stiffness = 0       !< knife-edge lateral stop [N/m]
    !> strip model, per side (each wheel's own profile): wheel coordinate of the flange tip
    !> and of the field-side end of the wheel profile [m]
    real(wp) :: s_flange_tip(2) = -huge(1.0_wp)
    real(wp) :: s_field_end(2) = huge(1.0_wp)
    type(wheelset_cache_t) :: cache        !< scratch: the geometry of the last poses
  end type wheelset_model_t

  type, extends(force_provider_t) :: wheelset_contact_t
    type(wheelset_model_t), allocatable :: models(:)
    type(wheelset_result_t), allocatable :: results(:)   !< last evaluation, per wheelset
    !> Track irregularities seen by every wheelset (none when not allocated).
    type(track_irregularity_t), allocatable :: irregularity
  contains
    procedure :: build => wheelset_contact_build
    procedure :: set_irregularity => wheelset_contact_set_irregularity
    procedure :: add_forces => wheelset_contact_add_forces
    procedure :: evaluate => wheelset_contact_evaluate
    procedure :: wheelset_count
    procedure :: coupled_bodies => wheelset_contact_coupled_bodies
    procedure :: wheel_unloaded => wheelset_contact_wheel_unloaded
  end type wheelset_contact_t

contains

  !> Build the pipeline of every wheelset from its spec. `nbodies` bounds the body indices.
  !> `labels` (e.g. the deck line of each &wheelset) prefix the errors of each wheelset
  !> instead of "wheelset contact N".
  subroutine wheelset_contact_build(self, specs, nbodies, error, labels)
    class(wheelset_contact_t), intent(inout) :: self
    type(wheelset_contact_spec_t), intent(in) :: specs(:)
    integer, intent(in) :: nbodies
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: labels(:)
    integer :: i, j
    character(len=16) :: num
    if (allocated(self%models)) deallocate (self%models)
    if (allocated(self%results)) deallocate (self%results)
    allocate (self%models(size(specs)), self%results(size(specs)))
    do i = 1, size(specs)
      call build_one(specs(i), self%models(i), error)
      if (allocated(error)) then
        write (num, '(i0)') i
        if (present(labels)) then
          call error_context(error, trim(labels(i)))
        else
          call error_context(error, 'wheelset contact ' // trim(num))
        end if
        return
      end if
      do j = 1, i - 1
        if (self%models(j)%body == specs(i)%body) then
          write (num, '(i0)') i
          call make_error(error, RD_ERR_INPUT, 'wheelset contact ' // trim(num) // &
                          ': body already has a wheelset contact; expected one &wheelset per body')
          return
        end if
      end do
    end do
    ! a rail body is a plain body on pads, never a wheelset itself
    do i = 1, size(specs)
      do j = 1, size(specs)
        if (any(specs(i)%rail_body == specs(j)%body)) then
          write (num, '(i0)') i
          call make_error(error, RD_ERR_INPUT, 'wheelset contact ' // trim(num) // &
                          ': a rail body is the body of a wheelset; expected a body on pad elements')
          return
        end if
      end do
    end do
  contains
    subroutine build_one(spec, m, error)
      type(wheelset_contact_spec_t), intent(in) :: spec
      type(wheelset_model_t), intent(out) :: m
      type(error_t), allocatable, intent(out) :: error
      call validate_wheelset_contact_spec(spec, nbodies, error)
      if (allocated(error)) return
      call build_contact_geometry(spec, m%geo, error)
      if (allocated(error)) return
      call build_hertz_params(spec, m%hertz, error)
      if (allocated(error)) return
      call build_creep_law(spec%creep_law, spec%creep_options, m%law, error)
      if (allocated(error)) return
      m%body = spec%body
      m%rail_body = spec%rail_body
      m%friction = spec%friction
      m%spin_creep = spec%spin_creep
      m%damping = spec%contact_damping
      m%v0 = spec%creep_v0
      m%liftoff_limit = spec%liftoff_limit
      m%flange_stiffness = spec%knife_flange_stiffness
      if (m%geo%model == CONTACT_MODEL_STRIP .or. m%geo%model == CONTACT_MODEL_TABLE) then
        m%s_flange_tip = [flange_tip_coordinate(m%geo, SIDE_LEFT), flange_tip_coordinate(m%geo, SIDE_RIGHT)]
        m%s_field_end = [field_end_coordinate(m%geo, SIDE_LEFT), field_end_coordinate(m%geo, SIDE_RIGHT)]
      end if
    end subroutine build_one
  end subroutine wheelset_contact_build

  !> Rails displaced by track irregularities (docs/theory_track.md): each wheelset's contact
  !> sees both rails offset by `irregularity%rail_offsets` at its track position. Call after
  !> build, before the first evaluation.
  subroutine wheelset_contact_set_irregularity(self, irregularity)
    class(wheelset_contact_t), intent(inout) :: self
    type(track_irregularity_t), intent(in) :: irregularity
    integer :: i
    self%irregularity = irregularity
    if (allocated(self%models)) then
      do i = 1, size(self%models)
        self%models(i)%cache%valid = .false.
        self%models(i)%cache%history_valid = .false.
      end do
    end if
  end subroutine wheelset_contact_set_irregularity

  pure integer function wheelset_count(self)
    class(wheelset_contact_t), intent(in) :: self
    wheelset_count = 0
    if (allocated(self%models)) wheelset_count = size(self%models)
  end function wheelset_count

  !> Each wheelset's contact acts on that wheelset from its own kinematics, and with flexible
  !> track between the wheelset and its rail bodies (force_provider_t coupled_bodies).
  subroutine wheelset_contact_coupled_bodies(self, pairs, known)
    class(wheelset_contact_t), intent(in) :: self
    integer, allocatable, intent(out) :: pairs(:, :)
    logical, intent(out) :: known
    integer :: j, k
    allocate (pairs(2, 0))
    do j = 1, self%wheelset_count()
      do k = 1, 2
        if (self%models(j)%rail_body(k) > 0) pairs = reshape([pairs, self%models(j)%body, &
          self%models(j)%rail_body(k)], [2, size(pairs, 2) + 1])
      end do
    end do
    known = .true.
  end subroutine wheelset_contact_coupled_bodies

  !> force_provider_t: body `body` is a wheelset one of whose wheels, at the last evaluation,
  !> had its contact open (gap, no patch) or carried at most q_min of vertical load.
  logical function wheelset_contact_wheel_unloaded(self, body) result(unloaded)
    class(wheelset_contact_t), intent(in) :: self
    integer, intent(in) :: body
    integer :: i
    unloaded = .false.
    do i = 1, self%wheelset_count()
      if (self%models(i)%body /= body) cycle
      associate (w => self%results(i)%wheel)
        unloaded = any(w%n_patches == 0 .or. w%max_penetration <= 0 .or. w%force_track(3) <= q_min)
      end associate
    end do
  end function wheelset_contact_wheel_unloaded

  !> force_provider_t: add every wheelset's contact force and moment to its body's load,
  !> and the reaction of each wheel to its rail body (if any).
  subroutine wheelset_contact_add_forces(self, t, kin, forces, error)
    class(wheelset_contact_t), intent(inout) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin(:)
    type(body_load_t), intent(inout) :: forces(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, ib, side, rb
    real(wp) :: f(3), m(3), fw(3, 2)
    if (.not. allocated(self%models)) return
    do i = 1, size(self%models)
      ib = self%models(i)%body
      if (ib > size(kin) .or. any(self%models(i)%rail_body > size(kin))) then
        call make_error(error, RD_ERR_INPUT, 'wheelset contact: body index beyond the multibody''s bodies')
        return
      end if
      call self%evaluate(i, t, kin(ib), f, m, error, all_kin=kin, wheel_force=fw)
      if (allocated(error)) return
      ! actio = reactio: a rail body gets minus the wheel's contact force, at its CG (no
      ! moment: its rotations are frozen, the moment goes into those frozen coordinates)
      do side = SIDE_LEFT, SIDE_RIGHT
        rb = self%models(i)%rail_body(side)
        if (rb > 0) forces(rb)%force = forces(rb)%force - fw(:, side)
      end do
      forces(ib)%force = forces(ib)%force + f
      forces(ib)%moment = forces(ib)%moment + m
    end do
  end subroutine wheelset_contact_add_forces

  !> The whole pipeline for wheelset i with kinematics `kin` at time t: resultant force
  !> (at the CG) and moment (about the CG) on the wheelset, fixed-frame components.
  !> Fills results(i). Errors: RD_ERR_PHYSICS on lift-off / derailment, a recoverable
  !> RD_ERR_RUNTIME (rd_error retry_error) on a non-finite result, both naming time,
  !> wheelset and side.
  !> A wheelset with rail bodies needs `all_kin` (every body's kinematics, indexed by body
  !> number, as add_forces gets them); `wheel_force(:, side)` returns each wheel's contact
  !> force (fixed-frame components), whose opposite acts on that side's rail.
  subroutine wheelset_contact_evaluate(self, i, t, kin, force, moment, error, all_kin, wheel_force)
    class(wheelset_contact_t), intent(inout) :: self
    integer, intent(in) :: i
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin
    real(wp), intent(out) :: force(3), moment(3)
    type(error_t), allocatable, intent(out) :: error
    type(body_kinematics_t), intent(in), optional :: all_kin(:)
    real(wp), intent(out), optional :: wheel_force(3, 2)
    type(wheel_contact_t) :: geo_res(2)
    real(wp) :: fw(3), mw(3), pose(8), v_rail(3, 2), key(pipeline_key_size), fw_both(3, 2)
    integer :: side, rb, k, hist
    force = 0
    moment = 0
    if (present(wheel_force)) wheel_force = 0
    if (.not. kin%is_wheelset) then
      call make_error(error, RD_ERR_INPUT, 'wheelset contact ' // trim(int_text(i)) // &
                      ': the body is not a wheelset (its spin must be a separate angle)')
      return
    end if
    ! a NaN velocity would reach the creep laws' comparisons (FP traps in Debug builds)
    if (.not. (all(finite(kin%v)) .and. all(finite(kin%omega)) .and. all(finite(kin%track%a)))) then
      call retry_error(error, 'wheelset contact ' // trim(int_text(i)) // ' at t = ' // trim(sci_text(t, 5)) // &
                       ' s: non-finite wheelset velocity or track frame')
      return
    end if
    associate (m => self%models(i), res => self%results(i))
      ! thesis eq. 4.78: the geometry needs only the intermediate frame (y, z, roll, yaw),
      ! plus the rail offsets of the track irregularities at the wheelset centre's track
      ! position sigma + x (the rails are displaced, the rail material stays at rest, so the
      ! creepages need no extra term), and on flexible track the rail bodies' displacements
      ! (whose rates do enter: v_rail below)
      pose(1:4) = [kin%q(2), kin%q(3), kin%q(5), kin%q(4)]
      pose(5:8) = 0
      if (allocated(self%irregularity)) &
        pose(5:8) = reshape(self%irregularity%rail_offsets(kin%track%sigma + kin%q(1)), [4])
      v_rail = 0
      do side = SIDE_LEFT, SIDE_RIGHT
        rb = m%rail_body(side)
        if (rb == 0) cycle
        if (.not. present(all_kin)) then
          call make_error(error, RD_ERR_INPUT, 'wheelset contact ' // trim(int_text(i)) // &
                          ': has rail bodies; expected the kinematics of every body')
          return
        end if
        if (rb > size(all_kin)) then
          call make_error(error, RD_ERR_INPUT, 'wheelset contact ' // trim(int_text(i)) // &
                          ': rail body index beyond the given bodies')
          return
        end if
        associate (rail => all_kin(rb))
          ! the rail displaced by the rail body's (y, z) in its track frame (the wheelset's,
          ! checked by the scene), like an irregularity offset
          pose(3 + 2 * side:4 + 2 * side) = pose(3 + 2 * side:4 + 2 * side) + rail%q(2:3)
          ! velocity of the rail MATERIAL at the contact: the displacement rate relative to
          ! the track frame. Not rail%v, which holds the co-moving frame's V X_T: the rail
          ! does not travel with the wheelset, only its deflection does.
          v_rail(:, side) = rail%track%a(:, 2) * rail%qdot(2) + rail%track%a(:, 3) * rail%qdot(3)
        end associate
        if (.not. all(finite(v_rail(:, side)))) then
          call retry_error(error, 'wheelset contact ' // trim(int_text(i)) // ' at t = ' // &
                           trim(sci_text(t, 5)) // ' s: non-finite ' // side_name(side) // ' rail body velocity')
          return
        end if
      end do
      key = pipeline_key(pose, v_rail, kin)
      if (m%cache%result_valid) then
        if (all(key == m%cache%result_key)) then
          res = m%cache%result
          force = res%force
          moment = res%moment
          if (present(wheel_force)) wheel_force = m%cache%result_wheel_force
          return
        end if
      end if
      m%cache%result_valid = .false.
      res%rail_offsets = pose(5:8)
      hist = 0
      if (.not. (m%cache%valid .and. all(pose == m%cache%pose))) then
        do k = 1, cache_history
          if (m%cache%history_valid(k)) then
            if (all(pose == m%cache%history_pose(:, k))) hist = k
          end if
          if (hist > 0) exit
        end do
      end if
      if (m%cache%valid .and. all(pose == m%cache%pose)) then
        geo_res = m%cache%geo
      else if (hist > 0) then
        ! found in the history: it becomes the last pose, the last pose takes its slot
        geo_res = m%cache%history_geo(:, hist)
        m%cache%history_geo(:, hist) = m%cache%geo
        m%cache%history_pose(:, hist) = m%cache%pose
        m%cache%history_valid(hist) = m%cache%valid
        m%cache%geo = geo_res
        m%cache%pose = pose
        m%cache%valid = .true.
      else
        if (m%cache%valid) then                ! the last pose goes into the history
          m%cache%history_geo(:, m%cache%history_next) = m%cache%geo
          m%cache%history_pose(:, m%cache%history_next) = m%cache%pose
          m%cache%history_valid(m%cache%history_next) = .true.
          m%cache%history_next = mod(m%cache%history_next, cache_history) + 1
        end if
        m%cache%valid = .false.
        call wheelset_contact(m%geo, pose(1), pose(2), pose(3), pose(4), geo_res(1), geo_res(2), error, &
                              rail_offset=reshape(pose(5:8), [2, 2]))
        if (allocated(error)) then
          call error_context(error, 'wheelset contact ' // trim(int_text(i)) // ' at t = ' // trim(sci_text(t, 5)) // ' s')
          return
        end if
        m%cache%geo = geo_res
        m%cache%pose = pose
        m%cache%valid = .true.
      end if
      do side = SIDE_LEFT, SIDE_RIGHT
        call wheel_pipeline(m, side, kin, v_rail(:, side), geo_res(side), res%wheel(side), fw, mw)
        call check_wheel(m, side, geo_res(side), res%wheel(side), fw, mw, error)
        if (allocated(error)) then
          call error_context(error, 'wheelset contact ' // trim(int_text(i)) // ', ' // side_name(side) // &
                             ' wheel, t = ' // trim(sci_text(t, 5)) // ' s')
          return
        end if
        force = force + fw
        moment = moment + mw
        fw_both(:, side) = fw
      end do
      res%force = force
      res%moment = moment
      res%guiding_force_sum = res%wheel(1)%force_track(2) + res%wheel(2)%force_track(2)
      res%derailment_quotient = max(res%wheel(1)%y_over_q, res%wheel(2)%y_over_q)
      m%cache%result = res
      m%cache%result_key = key
      m%cache%result_wheel_force = fw_both
      m%cache%result_valid = .true.
      if (present(wheel_force)) wheel_force = fw_both
    end associate
  end subroutine wheelset_contact_evaluate

  !> What a wheelset's pipeline reads besides its geometry and its fixed parameters
  !> (wheel_pipeline, patch_frame_and_point): the key of the result cache (wheelset_cache_t).
  pure function pipeline_key(pose, v_rail, kin) result(key)
    real(wp), intent(in) :: pose(8), v_rail(3, 2)
    type(body_kinematics_t), intent(in) :: kin
    real(wp) :: key(pipeline_key_size)
    integer :: j
    key(1:8) = pose
    key(9:11) = v_rail(:, 1)
    key(12:14) = v_rail(:, 2)
    key(15:17) = kin%v
    key(18:20) = kin%omega
    do j = 1, 3
      key(18 + 3 * j:20 + 3 * j) = kin%track%a(:, j)
      key(27 + 3 * j:29 + 3 * j) = kin%rot_attach(:, j)
    end do
    key(39) = kin%q(1)
  end function pipeline_key

  !> One wheel: every patch through Hertz, creepages and the creep law; the wheel's
  !> resultant force fw (fixed frame) and moment mw about the wheelset CG. `v_rail`: the
  !> velocity of the rail material (zero for a rigid rail; a rail body's displacement rate).
  subroutine wheel_pipeline(m, side, kin, v_rail, wc, out, fw, mw)
    type(wheelset_model_t), intent(in) :: m
    integer, intent(in) :: side
    type(body_kinematics_t), intent(in) :: kin
    real(wp), intent(in) :: v_rail(3)
    type(wheel_contact_t), intent(in) :: wc
    type(wheel_result_t), intent(inout) :: out
    real(wp), intent(out) :: fw(3), mw(3)
    real(wp), parameter :: zero3(3) = 0
    type(hertz_patch_t) :: hp
    type(creepage_t) :: creep
    type(creep_force_t) :: cf
    type(creep_patch_t) :: cp
    real(wp) :: a(3, 3), n(3), xc(3), yc(3), frame(3, 3), r_c(3), v_c(3), f(3), nf, rate, ft(3), fn(3), mn(3)
    integer :: k
    a = kin%track%a
    fw = 0
    mw = 0
    out%n_patches = wc%n_patches
    out%max_penetration = wc%max_penetration
    do k = 1, wc%n_patches
      associate (p => wc%patch(k), o => out%patch(k))
        call patch_frame_and_point(kin, p%normal, p%point_wheel, &
                                   merge(p%point_depth, p%penetration, allocated(wc%distributed)), frame, r_c, v_c)
        xc = frame(:, 1); yc = frame(:, 2); n = frame(:, 3)
        ! d(approach)/dt: the wheel point's velocity relative to the rail material along -n
        rate = -dot_product(v_c - v_rail, n)
        cf = creep_force_t()
        creep = creepage_t()
        if (p%kind == PATCH_FLANGE_SPRING) then
          ! knife-edge lateral stop: linear spring on the lateral overlap, no creep
          hp = hertz_patch_t()
          nf = hertz_damped_force(m%flange_stiffness * p%penetration, m%damping, rate)
        else
          ! a blended patch (share < 1) is that share of its bump's full description: the
          ! bump's ellipse and creep forces, scaled (its penetration share^(2/3) delta gives
          ! N = share N_bump by itself, but an ellipse growing like share^(1/3), whose creep
          ! forces rose with infinite slope where a split began)
          if (allocated(wc%distributed)) then
            ! the distributed force's load of the patch's strips (rd_hertz_strip) sizes the
            ! ellipse and loads the creep law: the same normal force as the one applied
            call hertz_from_force(m%hertz, [p%curv_wheel_roll, p%curv_wheel_lat, p%curv_rail_roll, &
                                  p%curv_rail_lat], m%hertz%e_star * wc%distributed%patch_load(k) / p%share, hp)
          else
            call hertz_from_penetration(m%hertz, [p%curv_wheel_roll, p%curv_wheel_lat, &
                                        p%curv_rail_roll, p%curv_rail_lat], p%penetration / p%share**(2.0_wp / 3), hp)
          end if
          nf = hertz_damped_force(p%share * hp%normal_force, m%damping, rate)
          ! creepages (thesis 3.6.1; eqs. 4.80-4.86): wheel material point relative to the rail
          ! (the rail material moves with v_rail, translation only: a rail body's rotations
          ! are frozen)
          call creepages_from_velocities(kin%v, v_c, v_rail, kin%omega, zero3, frame, m%v0, creep)
          cp%a = hp%a
          cp%b = hp%b
          cp%normal_force = nf / p%share
          cp%shear_modulus = m%hertz%shear_modulus
          cp%poisson = m%hertz%poisson
          cp%friction = m%friction
          cp%rolling_speed = creep%v_ref
          if (m%spin_creep) then
            call m%law%compute(cp, creep, cf)
          else
            call m%law%compute(cp, creepage_t(xi=creep%xi, eta=creep%eta, phi=0.0_wp, v_ref=creep%v_ref), cf)
          end if
          cf = creep_force_t(fx=p%share * cf%fx, fy=p%share * cf%fy, mz=p%share * cf%mz)
        end if
        ! forces on the wheel (thesis 4.90 in contact components, 4.96 spin couple); the
        ! energy-consistent strip force acts along its own direction (rd_strip_potential)
        if (allocated(wc%distributed)) then
          ! the distributed strip force carries the elastic normal force (added below, for
          ! the whole wheel); the patch keeps its damping part along its normal and the
          ! creep forces
          f = (nf - p%share * hp%normal_force) * n + cf%fx * xc + cf%fy * yc
          fw = fw + f
          mw = mw + cross(r_c, f) + cf%mz * n
        else if (allocated(wc%potential)) then
          ! the normal force on its own line of action (moment about the CG, whose
          ! intermediate frame is the geometry's) with the Hertz constant's gradient term,
          ! the creep forces at the patch point (rd_strip_potential)
          call potential_normal_wrench(m, p, wc%potential(k), nf, hp%normal_force, fn, mn)
          f = cf%fx * xc + cf%fy * yc
          mw = mw + cross(r_c, f) + cf%mz * n + matmul(kin%rot_attach, mn)
          f = f + matmul(a, fn)
          fw = fw + f
        else
          f = nf * n + cf%fx * xc + cf%fy * yc
          fw = fw + f
          mw = mw + cross(r_c, f) + cf%mz * n
        end if
        o%kind = p%kind
        o%penetration = p%penetration
        o%normal_force = nf
        o%xi = creep%xi; o%eta = creep%eta; o%spin = creep%phi; o%v_ref = creep%v_ref
        o%fx = cf%fx; o%fy = cf%fy; o%mz = cf%mz
        o%s_wheel = p%s_wheel
        o%u_rail = p%u_rail
        o%point_wheel = p%point_wheel
        o%point_rail = p%point_rail + [kin%q(1), 0.0_wp, 0.0_wp]
        o%contact_angle = p%contact_angle
        o%rolling_radius = p%rolling_radius
        o%a = hp%a; o%b = hp%b
        o%hertz_warning = hp%warning
        o%force_fixed = f
        o%normal_fixed = n
        o%lever_fixed = r_c
      end associate
    end do
    do k = wc%n_patches + 1, size(out%patch)
      out%patch(k) = patch_result_t()
    end do
    if (allocated(wc%distributed)) then
      fw = fw + m%hertz%e_star * matmul(a, wc%distributed%force)
      mw = mw + m%hertz%e_star * matmul(kin%rot_attach, wc%distributed%moment)
    end if
    ft = matmul(fw, a)
    out%force_track = ft
    ! flange contact pushes the left wheel to -Y and the right wheel to +Y
    out%y_over_q = 0
    if (ft(3) > q_min) out%y_over_q = merge(-1.0_wp, 1.0_wp, side == SIDE_LEFT) * ft(2) / ft(3)
  end subroutine wheel_pipeline

  !> The energy-consistent normal force of a potential patch (rd_strip_potential): with
  !> U = share (2/5) K(kappa) E^(5/2) (K the Hertz constant of the patch's curvatures kappa,
  !> E its effective penetration, N = share K E^(3/2) = nf), minus the gradient of U is
  !>    N (-grad E) - (2/5) E [share sum_j (dN_bump / d kappa_j) grad kappa_j + N_bump grad share],
  !> with dN/dkappa_j at fixed E by central differences of the Hertz model (its tables are
  !> C1). fn: force (track frame), mn: moment about the wheelset centre (intermediate frame).
  subroutine potential_normal_wrench(m, p, q, nf, n_bump, fn, mn)
    type(wheelset_model_t), intent(in) :: m
    type(patch_geometry_t), intent(in) :: p
    type(patch_potential_t), intent(in) :: q
    real(wp), intent(in) :: nf
    real(wp), intent(in) :: n_bump      !< the Hertz force of the bump at E (share 1)
    real(wp), intent(out) :: fn(3), mn(3)
    type(hertz_patch_t) :: hp
    real(wp) :: curv(4), cp(4), e, h, dn_droll, dn_dlat, grad(6)
    fn = nf * q%force_dir
    mn = nf * q%force_moment
    e = p%penetration / p%share**(2.0_wp / 3)
    if (.not. (e > 0)) return
    curv = [p%curv_wheel_roll, p%curv_wheel_lat, p%curv_rail_roll, p%curv_rail_lat]
    ! Hertz depends on the curvatures through A = (wheel + rail rolling) / 2 and B = (wheel +
    ! rail lateral) / 2 (eq. 4.73-4.75): dN/dkappa = (dN/dA or dN/dB) / 2, one-sided
    ! differences (the Hertz tables are C1; the step's truncation, ~1e-6 relative, is far
    ! below what this term needs)
    h = 1.0e-6_wp * (abs(curv(1)) + abs(curv(3)) + 1)
    cp = curv; cp(1) = curv(1) + h
    call hertz_from_penetration(m%hertz, cp, e, hp)
    dn_droll = (hp%normal_force - n_bump) / h
    h = 1.0e-6_wp * (abs(curv(2)) + abs(curv(4)) + 1)
    cp = curv; cp(2) = curv(2) + h
    call hertz_from_penetration(m%hertz, cp, e, hp)
    dn_dlat = (hp%normal_force - n_bump) / h
    grad = p%share * (dn_droll * q%curv_grad(:, 1) + dn_dlat * (q%curv_grad(:, 2) + q%curv_grad(:, 3))) &
           + n_bump * q%share_grad
    ! the share term: U = share U_bump, U_bump = (2/5) N_bump E
    fn = fn - 0.4_wp * e * grad(1:3)
    mn = mn - 0.4_wp * e * grad(4:6)
  end subroutine potential_normal_wrench

  !> Contact frame and wheel material point of a patch (thesis eqs. 4.80-4.85), fixed frame.
  !> frame(:, 1:3) = x_c, y_c, n (docs/conventions.md): n from the rail into the wheel
  !> (`normal`, track frame, rotated by the wheelset's track frame), x_c = X_T projected on
  !> the contact plane, y_c = n x x_c. r_c: the material point relative to the CG; the
  !> geometry returns the deepest rail point (`point_wheel`, wheelset intermediate frame),
  !> `penetration` inside the undeformed wheel, and with equal elastic constants each body
  !> takes half the approach, so the deformed surfaces meet half-way (the wheel's material
  !> point at the patch centre, as in CONTACT). v_c: its velocity, rigid body incl. spin
  !> (the track frame's motion and curvature are in kin%v and kin%omega).
  pure subroutine patch_frame_and_point(kin, normal, point_wheel, penetration, frame, r_c, v_c)
    type(body_kinematics_t), intent(in) :: kin
    real(wp), intent(in) :: normal(3), point_wheel(3), penetration
    real(wp), intent(out) :: frame(3, 3), r_c(3), v_c(3)
    real(wp) :: n(3), tx(3), xc(3)
    n = matmul(kin%track%a, normal)
    tx = kin%track%a(:, 1)
    xc = tx - dot_product(tx, n) * n
    xc = xc / norm2(xc)
    frame(:, 1) = xc; frame(:, 2) = cross(n, xc); frame(:, 3) = n
    r_c = matmul(kin%rot_attach, point_wheel) - 0.5_wp * penetration * n
    v_c = kin%v + cross(kin%omega, r_c)
  end subroutine patch_frame_and_point

  !> Run-time checks of one wheel (messages get time, wheelset and side from the caller).
  subroutine check_wheel(m, side, wc, out, fw, mw, error)
    type(wheelset_model_t), intent(in) :: m
    integer, intent(in) :: side
    type(wheel_contact_t), intent(in) :: wc
    type(wheel_result_t), intent(in) :: out
    real(wp), intent(in) :: fw(3), mw(3)
    type(error_t), allocatable, intent(out) :: error
    integer :: k
    if (.not. (all(finite(fw)) .and. all(finite(mw)) .and. finite(out%y_over_q))) then
      call retry_error(error, 'non-finite contact force (NaN or Inf)')
      return
    end if
    if (m%geo%model == CONTACT_MODEL_STRIP .or. m%geo%model == CONTACT_MODEL_TABLE) then
      if (wc%max_penetration <= -0.5_wp * huge(1.0_wp)) then
        call make_error(error, RD_ERR_PHYSICS, 'derailment: no rail under the wheel')
        return
      end if
      do k = 1, wc%n_patches
        if (wc%patch(k)%s_wheel < m%s_flange_tip(side)) then
          call make_error(error, RD_ERR_PHYSICS, 'derailment: contact point at wheel coordinate s = ' // &
                          trim(sci_text(wc%patch(k)%s_wheel, 5)) // ' m, beyond the flange tip (s = ' // &
                          trim(sci_text(m%s_flange_tip(side), 5)) // ' m)')
          return
        end if
        ! the geometry clamps a rail line beyond the tread to the profile's end
        if (wc%patch(k)%s_wheel > m%s_field_end(side) - field_end_margin) then
          call make_error(error, RD_ERR_PHYSICS, 'derailment: the rail is beyond the field side of the tread '// &
                          '(contact at wheel coordinate s = ' // trim(sci_text(wc%patch(k)%s_wheel, 5)) // ' m)')
          return
        end if
      end do
    end if
    if (wc%max_penetration < -m%liftoff_limit) then
      call make_error(error, RD_ERR_PHYSICS, 'wheel lift-off: gap ' // trim(sci_text(-wc%max_penetration, 5)) // &
                      ' m exceeds the limit ' // trim(sci_text(m%liftoff_limit, 5)) // ' m')
    end if
  end subroutine check_wheel

  pure function side_name(side) result(s)
    integer, intent(in) :: side
    character(len=:), allocatable :: s
    if (side == SIDE_LEFT) then
      s = 'left'
    else
      s = 'right'
    end if
  end function side_name
end module rd_wheelset_contact
