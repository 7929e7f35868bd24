!> A scene: everything one deck describes, built, stepped and written.
!>
!> Life cycle (the C API and the runner follow it):
!>   load_file / load_string -> build (validate everything, no file touched)
!>   -> initialize (initial state, open the output, write step 0)
!>   -> advance(t) ... -> finalize (close the output with the run's metadata).
!> A failure at any stage returns an error; output written so far stays readable.
!> A failed initialize leaves the scene as loaded (nothing built, the results file closed
!> with the failure recorded), so initialize may be called again. A failed advance ends
!> the run: its results file is closed with `/meta status = 'failed: <message>'` here,
!> for the runner and the C API alike, and later stepping calls are refused with that
!> message; queries still answer with the last valid state.
module rd_scene
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_HANDLE, RD_ERR_IO, &
                      RD_ERR_RUNTIME
  use rd_deck, only: deck_t, read_deck_file, read_deck_string, deck_string_t
  use rd_file_kind, only: file_kind, FILE_DIRECTORY
  use rd_track_point, only: track_geometry_t, track_point_t
  use rd_speed_law, only: speed_law_t, constant_speed, table_speed
  use rd_hdf5_writer, only: h5_writer_t
  use rd_output_set, only: output_set_t
  use rd_output_average, only: output_average_t
  use rd_results_state, only: results_state_t, read_state_row
  use rd_frame_drift, only: frame_drift_t
  use rd_safety_maxima, only: safety_maxima_t
  use rd_text, only: int_text, real_text
  use rd_scene_track, only: build_scene_track, build_scene_irregularity
  use rd_track_irregularity, only: track_irregularity_t
  use rd_scene_vehicle, only: build_bodies, build_element, build_external_loads, body_index, &
                              build_wheelset_specs, check_rail_bodies, check_body_inertia, &
                              stiffness_warnings, load_wheelset_profiles
  use rd_scene_sensors, only: sensor_spec_t, build_sensors
  use rd_point_motion, only: point_motion_t, compute_point_motion
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_wheel_contact_result, only: MAX_PATCHES, N_PATCH_CHANNELS, N_WHEEL_CHANNELS, &
    N_WHEELSET_CHANNELS, patch_channel_names, patch_channel_units, wheel_channel_names, &
    wheel_channel_units, wheelset_channel_names, wheelset_channel_units, patch_channel_values, &
    wheel_channel_values, wheelset_channel_values
  use rd_body_spec, only: body_spec_t, DOF_Y, DOF_YAW, DOF_PITCH
  use rd_multibody, only: multibody_t, BODY_OUT_RELATIVE, BODY_OUT_FIXED, ELEMENT_OUT
  use rd_force_element, only: force_element_t
  use rd_force_provider, only: force_provider_t
  use rd_external_loads, only: external_loads_t
  use rd_static_preload, only: solve_static_preloads, solve_static_positions
  use rd_reference_radius, only: centred_rolling_radius
  use rd_level_straight_track, only: level_straight_track_t
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t, &
                           jacobian_sparsity_t
  use rd_scene_jacobian, only: scene_jacobian_sparsity
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_nonlinear_spring, only: nonlinear_spring_t
  use rd_series_spring_damper, only: series_spring_damper_t
  implicit none
  private
  public :: scene_t, raildyn_version, state_layout

  character(len=*), parameter :: raildyn_version = '0.1.0'

  type :: scene_t
    private
    type(deck_t) :: deck
    logical :: loaded = .false.
    logical :: built = .false.
    logical :: initialized = .false.
    logical :: writing = .false.
    character(len=:), allocatable :: output_override
    !> Pointers, not allocatables: the multibody system keeps a pointer to the track and
    !> the integrator one to the system, so they must not move (see destroy).
    class(track_geometry_t), pointer, public :: track => null()
    type(multibody_t), pointer :: mbs => null()
    type(external_loads_t), pointer :: loads => null()
    type(wheelset_contact_t), pointer :: contact => null()
    character(len=64), allocatable :: wheelset_names(:)
    type(sensor_spec_t), allocatable :: sensors(:)   !< &sensor points (rd_scene_sensors)
    type(integrator_t), pointer :: integrator => null()
    type(integrator_settings_t) :: solver
    !> Newton-matrix Jacobian of 'bdf' (&solver jacobian): 'coloured' difference quotients
    !> (rd_scene_jacobian) or CVODE's 'dense' ones.
    character(len=:), allocatable :: jacobian
    real(wp), allocatable :: y(:)        !< integrator state at time t
    integer :: nbodies = 0
    character(len=:), allocatable :: equilibrium
    real(wp) :: equilibrium_residual = 0
    real(wp), allocatable :: y_as_built(:)   !< the deck's initial state, before the equilibrium
    type(speed_law_t) :: speed
    real(wp) :: t = 0
    real(wp) :: t_end = 0
    real(wp) :: interval = 0
    real(wp) :: start_sigma = 0
    integer(i8) :: output_steps = 0      !< output steps written; next one at output_steps*interval
    !> interval means; average%samples = &output mean_samples (0: records are samples)
    type(output_average_t) :: average
    !> Contact statistics over the output samples (records and sub-samples) for the run's
    !> summary: samples taken, samples without contact per wheel (side, wheelset), largest
    !> sampled vertical wheel force [N].
    integer(i8) :: contact_samples = 0
    integer(i8), allocatable :: samples_without_contact(:, :)
    real(wp), allocatable :: max_sampled_q(:, :)
    !> how far bodies with free x left their track frames (run notes)
    type(frame_drift_t) :: drift
    !> the records' running-safety maxima for the completion line (rd_safety_maxima)
    type(safety_maxima_t) :: safety
    real(wp), allocatable :: frame_offsets(:)   !< track frames at sigma_vehicle + offset
    type(output_set_t) :: outputs
    !> &output groups: the channel groups written to the results file (channel_group)
    type(deck_string_t), allocatable :: written_groups(:)
    type(h5_writer_t) :: writer
    integer, allocatable :: series(:)    !< writer series id of each output channel
    integer(int64) :: clock_start = 0
    !> Set when a run failed (advance): the error's message; the run cannot go on.
    character(len=:), allocatable :: failure
    !> legal but suspicious input found while building (deck line first), for check and run
    type(deck_string_t), allocatable :: warning_list(:)
    !> A restart (set_start, continue_from): the run starts at start_time from start_state
    !> instead of the deck's initial state.
    real(wp) :: start_time = 0
    real(wp), allocatable :: start_state(:)
  contains
    procedure :: load_file => scene_load_file
    procedure :: load_string => scene_load_string
    procedure :: build => scene_build
    procedure :: initialize => scene_initialize
    procedure :: advance => scene_advance
    procedure :: finalize => scene_finalize
    procedure :: stop => scene_stop
    procedure :: set_output_file => scene_set_output_file
    procedure :: time => scene_time
    procedure :: end_time => scene_end_time
    procedure :: output_interval => scene_output_interval
    procedure :: running_speed => scene_running_speed
    procedure :: progress_wanted => scene_progress_wanted
    procedure :: state_size => scene_state_size
    procedure :: get_state => scene_get_state
    procedure :: set_state => scene_set_state
    procedure :: set_start => scene_set_start
    procedure :: continue_from => scene_continue_from
    procedure :: output_count => scene_output_count
    procedure :: output_name => scene_output_name
    procedure :: output_size => scene_output_size
    procedure :: get_output => scene_get_output
    procedure :: set_input => scene_set_input
    procedure :: summary => scene_summary
    procedure :: completion_summary => scene_completion_summary
    procedure :: check_report => scene_check_report
    procedure :: run_notes => scene_run_notes
    procedure :: warnings => scene_warnings
    procedure :: check_output_path => scene_check_output_path
    procedure :: default_output_file => scene_default_output_file
    procedure :: input_files => scene_input_files
    procedure :: vehicle_sigma => scene_vehicle_sigma
    procedure :: integrator_stats => scene_integrator_stats
    procedure :: system => scene_system
    procedure :: destroy => scene_destroy
    procedure, private :: build_mechanics
    procedure, private :: start_mechanics
    procedure, private :: refresh_outputs
    procedure, private :: write_step
    procedure, private :: write_record
    procedure, private :: check_values
    procedure, private :: note_sample
    procedure, private :: contact_notes
    procedure, private :: register_outputs
    procedure, private :: mbs_element_count
    procedure, private :: channel_written
  end type scene_t

  interface
    !> What a modeller checks first (raildyn check), after initialize: rd_scene_check_report.
    module function scene_check_report(self) result(text)
      class(scene_t), intent(inout) :: self
      character(len=:), allocatable :: text
    end function scene_check_report
  end interface

contains

  ! ------------------------------------------------------------------ loading
  subroutine scene_load_file(self, path, error)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(out) :: error
    call read_deck_file(self%deck, path, error)
    self%loaded = .not. allocated(error)
  end subroutine scene_load_file

  subroutine scene_load_string(self, text, base_dir, error)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: text, base_dir
    type(error_t), allocatable, intent(out) :: error
    call read_deck_string(self%deck, text, base_dir, '<string>', error)
    self%loaded = .not. allocated(error)
  end subroutine scene_load_string

  !> Override the deck's &output file (runner -o).
  subroutine scene_set_output_file(self, path)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    self%output_override = path
  end subroutine scene_set_output_file

  ! ------------------------------------------------------------------ building
  !> Build every model of the scene from the deck. All input errors surface here,
  !> before any file is written (raildyn check stops after this).
  subroutine scene_build(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    if (.not. self%loaded) then
      call make_error(error, RD_ERR_HANDLE, 'scene: no deck loaded')
      return
    end if
    if (self%built) return
    call build_models(self, error)
    ! A half-built scene holds the models of the groups read before the error: drop them,
    ! so that a retry builds from the deck again instead of allocating onto them.
    if (allocated(error)) call reset_to_loaded(self)
  end subroutine scene_build

  subroutine build_models(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: times(:), speeds(:)
    real(wp) :: v
    call self%deck%get('simulation', 1, 't_end', self%t_end, error)
    if (allocated(error)) return
    call self%deck%get('simulation', 1, 'start_sigma', self%start_sigma, error)
    if (allocated(error)) return
    call self%deck%get('output', 1, 'interval', self%interval, error)
    if (allocated(error)) return
    call self%deck%get('output', 1, 'mean_samples', self%average%samples, error)
    if (allocated(error)) return
    call self%deck%get('output', 1, 'groups', self%written_groups, error)
    if (allocated(error)) return

    if (self%deck%given('simulation', 1, 'speed_times')) then
      call self%deck%get('simulation', 1, 'speed_times', times, error)
      if (allocated(error)) return
      call self%deck%get('simulation', 1, 'speed_values', speeds, error)
      if (allocated(error)) return
      call table_speed(self%speed, times, speeds, error)
      if (allocated(error)) then
        call error_context(error, self%deck%origin('simulation', 1, 'speed_times'))
        return
      end if
    else
      call self%deck%get('simulation', 1, 'speed', v, error)
      if (allocated(error)) return
      self%speed = constant_speed(v)
    end if

    block
      class(track_geometry_t), allocatable :: track
      call build_scene_track(self%deck, track, error)
      if (allocated(error)) return
      allocate (self%track, source=track)
    end block

    self%nbodies = self%deck%count('body')
    if (self%nbodies > 0) then
      call self%build_mechanics(error)
      if (allocated(error)) return
    else
      ! Without bodies the scene follows the vehicle reference point only.
      allocate (self%frame_offsets(1))
      self%frame_offsets = 0
    end if

    ! sensors name bodies: without &body the reader has refused any &sensor already
    call build_sensors(self%deck, self%sensors, error)
    if (allocated(error)) return

    call self%register_outputs()
    self%built = .true.
  end subroutine build_models

  !> Back to the state after load: the deck (and an output override) kept, every model
  !> built from it freed. Used after a failed build or initialize.
  subroutine reset_to_loaded(scene)
    type(scene_t), intent(inout) :: scene
    type(scene_t) :: loaded
    call scene%destroy()
    loaded%deck = scene%deck
    loaded%loaded = scene%loaded
    if (allocated(scene%output_override)) loaded%output_override = scene%output_override
    ! a restart asked for stays asked for: a retry must not start from the deck silently
    if (allocated(scene%start_state)) then
      loaded%start_time = scene%start_time
      loaded%start_state = scene%start_state
    end if
    scene = loaded
  end subroutine reset_to_loaded

  subroutine register_outputs(self)
    class(scene_t), intent(inout) :: self
    integer :: k, id
    character(len=16) :: tag
    call self%outputs%clear()
    call self%outputs%add('vehicle/speed', 1, 'm/s', 'running speed V', 'V', id)
    call self%outputs%add('vehicle/distance', 1, 'm', &
                          'arc length sigma of the vehicle reference point', 'sigma', id)
    do k = 1, size(self%frame_offsets)
      write (tag, '(i0)') k
      associate (p => 'track/frames/' // trim(tag) // '/')
        call self%outputs%add(p // 'sigma', 1, 'm', 'arc length of the track frame', 'sigma', id)
        call self%outputs%add(p // 'position', 3, 'm', &
                              'track frame origin in the fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'angles', 3, 'rad', &
                              'heading, pitch (-atan gradient) and cant angle of the track frame', &
                              'heading pitch cant', id)
        call self%outputs%add(p // 'curvature', 1, '1/m', &
                              'horizontal curvature, > 0 for a left-hand curve', 'kappa', id)
        call self%outputs%add(p // 'superelevation', 1, 'm', &
                              'left rail over right rail', 'h', id)
        call self%outputs%add(p // 'angular_velocity', 3, 'rad/s', &
                              'angular velocity of the moving track frame, track components', &
                              'wx wy wz', id)
      end associate
    end do
    do k = 1, self%nbodies
      associate (p => 'bodies/' // self%mbs%bodies(k)%name // '/')
        call self%outputs%add(p // 'position_track', 6, 'm m m rad rad rad', &
          'coordinates q relative to the track frame (wheelset pitch: spin deviation beta)', &
          'x y z yaw roll pitch', id)
        call self%outputs%add(p // 'velocity_track', 6, 'm/s m/s m/s rad/s rad/s rad/s', &
          'dq/dt relative to the track frame', 'vx vy vz yaw_rate roll_rate pitch_rate', id)
        call self%outputs%add(p // 'acceleration_track', 6, 'm/s^2 m/s^2 m/s^2 rad/s^2 rad/s^2 rad/s^2', &
          'd2q/dt2 relative to the track frame', 'ax ay az yaw_acc roll_acc pitch_acc', id)
        call self%outputs%add(p // 'position_fixed', 3, 'm', 'centre of mass, fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'angles_fixed', 3, 'rad', &
          'Z-X-Y angles of the body frame relative to the fixed frame', 'yaw roll pitch', id)
        call self%outputs%add(p // 'velocity_fixed', 3, 'm/s', 'velocity of the centre of mass, fixed frame', &
          'vX vY vZ', id)
        call self%outputs%add(p // 'angular_velocity_fixed', 3, 'rad/s', 'angular velocity, fixed frame', &
          'wX wY wZ', id)
        call self%outputs%add(p // 'angular_velocity_body', 3, 'rad/s', 'angular velocity, body frame', &
          'wx wy wz', id)
        call self%outputs%add(p // 'acceleration_fixed', 3, 'm/s^2', &
          'acceleration of the centre of mass, fixed frame', 'aX aY aZ', id)
      end associate
    end do
    do k = 1, self%mbs_element_count()
      associate (p => 'elements/' // self%mbs%elements(k)%e%name // '/')
        call self%outputs%add(p // 'deflection', 3, 'm', &
          'deflection in element axes (torsion: rad)', 'dx dy dz', id)
        call self%outputs%add(p // 'force_element', 3, 'N', &
          'force on body 2 in element axes (torsion: moment, N*m)', 'fx fy fz', id)
        call self%outputs%add(p // 'force_fixed', 3, 'N', 'force on body 2, fixed frame', 'fX fY fZ', id)
      end associate
    end do
    if (associated(self%contact)) then
      do k = 1, size(self%wheelset_names)
        associate (p => 'wheelsets/' // trim(self%wheelset_names(k)) // '/')
          call self%outputs%add(p // 'summary', N_WHEELSET_CHANNELS, unit_tokens(wheelset_channel_units), &
            'derailment quotient (max Y/Q of the wheels) and sum of the guiding forces Y', &
            join(wheelset_channel_names), id)
          call self%outputs%add(p // 'rail_offsets', 4, 'm', 'rails displaced by the track irregularities ' // &
            'at the wheelset, track frame (zeros on the design track)', 'dy_left dz_left dy_right dz_right', id)
          block
            integer :: side, j
            character(len=5), parameter :: sides(2) = ['left ', 'right']
            character(len=8) :: tagj
            do side = 1, 2
              call self%outputs%add(p // trim(sides(side)) // '/wheel', N_WHEEL_CHANNELS, &
                unit_tokens(wheel_channel_units), 'wheel: patches, force on the wheel in track ' // &
                'components (longitudinal, Y, Q), Y/Q (> 0 towards flange climb), largest penetration', &
                join(wheel_channel_names), id)
              do j = 1, MAX_PATCHES
                write (tagj, '(i0)') j
                call self%outputs%add(p // trim(sides(side)) // '/patch' // trim(tagj), N_PATCH_CHANNELS, &
                  unit_tokens(patch_channel_units), 'contact patch (zeros when absent): geometry, ' // &
                  'normal force, creepages, creep forces on the wheel (contact frame)', &
                  join(patch_channel_names), id)
              end do
            end do
          end block
        end associate
      end do
    end if
    do k = 1, size(self%sensors)
      associate (p => 'sensors/' // self%sensors(k)%name // '/', &
                 on => ' of sensor ' // self%sensors(k)%name // ' (fixed to its body)')
        call self%outputs%add(p // 'position_track', 3, 'm', 'position' // on // &
          ' relative to its body''s track frame, track components', 'x y z', id)
        call self%outputs%add(p // 'position_fixed', 3, 'm', 'position' // on // ', fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'velocity_track', 3, 'm/s', 'absolute velocity' // on // &
          ', track-frame components', 'vx vy vz', id)
        call self%outputs%add(p // 'acceleration_track', 3, 'm/s^2', 'absolute acceleration' // on // &
          ', track-frame components', 'ax ay az', id)
        call self%outputs%add(p // 'velocity_body', 3, 'm/s', 'absolute velocity' // on // &
          ', body-frame components', 'vx vy vz', id)
        call self%outputs%add(p // 'acceleration_body', 3, 'm/s^2', 'absolute acceleration' // on // &
          ', body-frame components', 'ax ay az', id)
        call self%outputs%add(p // 'specific_force_body', 3, 'm/s^2', 'accelerometer reading' // on // &
          ': acceleration minus gravity, body-frame components', 'fx fy fz', id)
      end associate
    end do
    if (associated(self%mbs)) then
      block
        character(len=:), allocatable :: components, units
        call state_layout(self%mbs, components, units)
        call self%outputs%add('state/y', self%mbs%state_size(), units, 'integrator state y = [q_f; nu_f; ' // &
          'x_el] (free coordinates, generalized velocities, element states: rd_multibody); ' // &
          'raildyn run --restart continues from a row of it', components, id)
      end block
    end if
  end subroutine register_outputs

  !> Column names and SI unit tokens of the state vector, in rd_multibody's layout:
  !> '<body>.<coordinate>' for q_f (a wheelset's pitch slot is its spin deviation beta),
  !> '<body>.nu_<coordinate>' for nu_f, '<element>.x<k>' for the elements' internal states.
  subroutine state_layout(mbs, components, units)
    type(multibody_t), intent(in) :: mbs
    character(len=:), allocatable, intent(out) :: components, units
    character(len=5), parameter :: dof_names(6) = ['x    ', 'y    ', 'z    ', 'yaw  ', 'roll ', 'pitch']
    character(len=5), parameter :: dof_units(6) = ['m    ', 'm    ', 'm    ', 'rad  ', 'rad  ', 'rad  ']
    character(len=5), parameter :: rate_units(6) = ['m/s  ', 'm/s  ', 'm/s  ', 'rad/s', 'rad/s', 'rad/s']
    character(len=:), allocatable :: q_names, q_units, nu_names, nu_units
    character(len=16), allocatable :: el_units(:)
    integer :: i, j, k
    q_names = ''; q_units = ''; nu_names = ''; nu_units = ''
    do i = 1, mbs%body_count()
      do j = 1, 6
        if (mbs%free_slot(i, j) == 0) cycle
        q_names = q_names // ' ' // mbs%bodies(i)%name // '.' // trim(dof_names(j))
        q_units = q_units // ' ' // trim(dof_units(j))
        nu_names = nu_names // ' ' // mbs%bodies(i)%name // '.nu_' // trim(dof_names(j))
        nu_units = nu_units // ' ' // trim(rate_units(j))
      end do
    end do
    components = q_names // nu_names
    units = q_units // nu_units
    do i = 1, mbs%element_count()
      if (allocated(el_units)) deallocate (el_units)
      allocate (el_units(mbs%elements(i)%e%state_count()))
      call mbs%elements(i)%e%state_units(el_units)
      do k = 1, size(el_units)
        components = components // ' ' // mbs%elements(i)%e%name // '.x' // trim(int_text(k))
        units = units // ' ' // trim(el_units(k))
      end do
    end do
    components = components(2:)
    units = units(2:)
  end subroutine state_layout

  !> The &output groups entry a channel belongs to: its first path element, except the
  !> contact patch slots ('patches') under 'wheelsets'.
  pure function channel_group(name) result(group)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: group
    group = name(1:index(name // '/', '/') - 1)
    if (group == 'wheelsets' .and. index(name, '/patch', back=.true.) > 0) group = 'patches'
  end function channel_group

  !> The channel is written to the results file (&output groups).
  logical function channel_written(self, i)
    class(scene_t), intent(in) :: self
    integer, intent(in) :: i
    integer :: g
    channel_written = .false.
    do g = 1, size(self%written_groups)
      if (self%written_groups(g)%s == channel_group(self%outputs%channels(i)%name)) channel_written = .true.
    end do
  end function channel_written

  !> Space-separated unit tokens (docs/output.md: no spaces inside a token, '1' for none).
  pure function unit_tokens(units) result(text)
    character(len=*), intent(in) :: units(:)
    character(len=:), allocatable :: text
    integer :: i
    character(len=:), allocatable :: u
    text = ''
    do i = 1, size(units)
      u = trim(units(i))
      if (u == '-' .or. u == '') u = '1'
      if (u == 'N m') u = 'N*m'
      if (i > 1) text = text // ' '
      text = text // u
    end do
  end function unit_tokens

  pure function join(words) result(text)
    character(len=*), intent(in) :: words(:)
    character(len=:), allocatable :: text
    integer :: i
    text = trim(words(1))
    do i = 2, size(words)
      text = text // ' ' // trim(words(i))
    end do
  end function join

  pure integer function mbs_element_count(self)
    class(scene_t), intent(in) :: self
    mbs_element_count = 0
    if (associated(self%mbs)) mbs_element_count = self%mbs%element_count()
  end function mbs_element_count

  ! ------------------------------------------------------------------ running
  subroutine scene_initialize(self, write_output, error)
    class(scene_t), intent(inout) :: self
    logical, intent(in) :: write_output
    type(error_t), allocatable, intent(out) :: error
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'scene: already initialized')
      return
    end if
    call start_run(self, write_output, error)
    if (allocated(error)) then
      ! The results file, if opened, says why it holds no run; the scene goes back to the
      ! loaded deck, so that initialize can be called again (the same failure again, or a
      ! run once its cause, e.g. an unwritable folder, is gone).
      call record_failure_in_results(self, error)
      call reset_to_loaded(self)
    end if
  end subroutine scene_initialize

  !> Build, initial state, results file with step 0 (scene_initialize).
  subroutine start_run(self, write_output, error)
    class(scene_t), intent(inout) :: self
    logical, intent(in) :: write_output
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: path, title
    integer :: i, flush_every
    call self%build(error)
    if (allocated(error)) return
    call system_clock(self%clock_start)
    self%t = 0
    self%output_steps = 0
    self%contact_samples = 0
    if (allocated(self%samples_without_contact)) deallocate (self%samples_without_contact, self%max_sampled_q)
    if (associated(self%contact)) then
      allocate (self%samples_without_contact(2, size(self%wheelset_names)), &
                self%max_sampled_q(2, size(self%wheelset_names)))
      self%samples_without_contact = 0
      self%max_sampled_q = 0
    end if
    if (self%nbodies > 0) then
      call self%start_mechanics(error)
      if (allocated(error)) return
    end if
    if (allocated(self%start_state)) then
      ! a restart: the static setup above gave the elements their free lengths and
      ! preloads as in the original run (they are part of the model); the state and the
      ! time are the saved ones. Output rows stay on the grid k * interval after it.
      if (self%average%samples > 0 .and. abs(self%start_time / self%interval - &
          nint(self%start_time / self%interval)) > 1e-9_wp) then
        call make_error(error, RD_ERR_INPUT, 'restart at t = ' // trim(real_text(self%start_time)) // &
          ' s: with &output mean_samples > 0 the restart time must be a multiple of the output interval')
        return
      end if
      self%t = self%start_time
      self%y = self%start_state
      self%output_steps = int(self%start_time / self%interval + 1e-9_wp, i8)
      call self%integrator%reinit(self%t, self%y, error)
      if (allocated(error)) return
    end if
    if (self%nbodies > 0) call self%drift%start(self%mbs, self%y)
    self%safety = safety_maxima_t()
    if (associated(self%contact)) then
      do i = 1, size(self%wheelset_names)
        associate (b => self%mbs%bodies(self%contact%models(i)%body))
          call self%safety%add_wheelset(self%outputs, trim(self%wheelset_names(i)), b%name, b%frame)
        end associate
      end do
    end if

    if (write_output) then
      if (allocated(self%output_override)) then
        path = self%output_override
      else if (self%deck%given('output', 1, 'file')) then
        path = self%deck%path('output', 1, 'file')
      else
        path = self%default_output_file('.h5')
      end if
      call self%deck%get('output', 1, 'flush_every', flush_every, error)
      if (allocated(error)) return
      call self%writer%open(path, error, flush_every=flush_every)
      if (allocated(error)) then
        if (allocated(self%output_override)) then
          call error_context(error, 'results file given with -o')
        else
          call error_context(error, self%deck%origin('output', 1, 'file'))
        end if
        return
      end if
      self%writing = .true.
      call self%writer%write_text('meta/deck_text', self%deck%text(), error)
      if (allocated(error)) return
      call self%deck%get('simulation', 1, 'title', title, error)
      if (allocated(error)) return
      call self%writer%set_attribute('/', 'raildyn_version', raildyn_version, error)
      if (.not. allocated(error)) call self%writer%set_attribute('/', 'title', title, error)
      if (.not. allocated(error)) call self%writer%set_attribute('/', 'deck_file', self%deck%file_name(), error)
      if (.not. allocated(error)) call self%writer%set_attribute('/', 'output_mean_samples', self%average%samples, error)
      if (allocated(error)) return
      allocate (self%series(self%outputs%n))
      self%series = 0            ! 0: not written (&output groups)
      do i = 1, self%outputs%n
        if (.not. self%channel_written(i)) cycle
        associate (c => self%outputs%channels(i))
          call self%writer%add_series(c%name, size(c%values), c%unit, c%description, &
                                      self%series(i), error, component_names=c%components)
        end associate
        if (allocated(error)) return
      end do
    end if
    self%initialized = .true.
    call self%write_step(error)
    if (allocated(error)) return
    if (self%average%samples > 0) call self%average%start(self%outputs%packed())
  end subroutine start_run

  !> Close the results file (if open) with `status = 'failed: <message>'`: the one place
  !> where a failure is recorded, for the runner and the C API alike. A failure to record
  !> it is added to the error's message.
  subroutine record_failure_in_results(self, error)
    type(scene_t), intent(inout) :: self
    type(error_t), intent(inout) :: error
    type(error_t), allocatable :: close_error
    call close_output(self, 'failed: ' // error%message, close_error)
    if (allocated(close_error)) error%message = error%message // &
      '; the results file could not record this failure: ' // close_error%message
  end subroutine record_failure_in_results

  !> After a failed run: stepping calls get the failure again, with what to do.
  subroutine refuse_after_failure(self, error)
    type(scene_t), intent(in) :: self
    type(error_t), allocatable, intent(out) :: error
    if (.not. allocated(self%failure)) return
    call make_error(error, RD_ERR_HANDLE, 'scene: the run failed at t = ' // trim(real_text(self%t)) // &
                    ' s (' // self%failure // '); the results file records the failure and the ' // &
                    'run cannot go on: create a new model to run again')
  end subroutine refuse_after_failure

  !> Advance to t_target, writing every output step passed on the way.
  subroutine scene_advance(self, t_target, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: t_target
    type(error_t), allocatable, intent(out) :: error
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (.not. self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'scene: advance before initialize')
      return
    end if
    if (.not. ieee_is_finite(t_target) .or. t_target < self%t - 1e-12_wp * max(1.0_wp, abs(self%t))) then
      call make_error(error, RD_ERR_INPUT, 'advance: target time must be finite and >= the current time')
      return
    end if
    call step_to(self, t_target, error)
    if (allocated(error)) then
      ! The run ends here (the integrator's state is invalid or a record could not be
      ! written): the file says so, and the scene refuses to step on.
      self%failure = error%message
      call record_failure_in_results(self, error)
    end if
  end subroutine scene_advance

  !> Integrate to t_target, writing every output step passed on the way (scene_advance).
  subroutine step_to(self, t_target, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: t_target
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: t_out
    real(wp), allocatable :: sample(:)
    do
      if (self%average%samples == 0) then
        t_out = real(self%output_steps, wp) * self%interval
        if (t_out > t_target + 1e-9_wp * self%interval) exit
        call integrate_to(t_out)
        if (allocated(error)) return
        call self%write_step(error)
        if (allocated(error)) return
      else
        ! interval means (rd_output_average): sub-samples on a fixed grid of interval / N,
        ! so that advancing in pieces (C API) gives the same records. The integrator stops
        ! only at the record time (or the target, where inputs may change) and interpolates
        ! the sub-samples: they add no steps and leave the step sequence as without means.
        t_out = (real(self%output_steps - 1, wp) + self%average%next_fraction()) * self%interval
        if (t_out > t_target + 1e-9_wp * self%interval / self%average%samples) exit
        call integrate_to(t_out, min(real(self%output_steps, wp) * self%interval, max(t_target, t_out)))
        if (allocated(error)) return
        call self%refresh_outputs()
        call self%note_sample()
        sample = self%outputs%packed()
        ! a non-finite sub-sample stops the run at its own time (its mean would hide when)
        call self%check_values(sample, error)
        if (allocated(error)) return
        call self%average%add(sample)
        if (self%average%complete()) then
          call self%write_record(self%average%take_mean(), error)
          if (allocated(error)) return
        end if
      end if
    end do
    call integrate_to(t_target)
  contains
    !> To t_stop; the integrator may step on to t_limit (>= t_stop, default t_stop) and
    !> interpolate (rd_integrator advance).
    subroutine integrate_to(t_stop, t_limit)
      real(wp), intent(in) :: t_stop
      real(wp), intent(in), optional :: t_limit
      ! A track-only scene is kinematic: the vehicle position is an exact function of time.
      if (t_stop <= self%t) return
      if (associated(self%integrator)) then
        call self%integrator%advance(t_stop, self%y, error, t_limit)
        if (allocated(error)) then
          self%t = self%integrator%time()
          call error_context(error, 'scene')
          return
        end if
      end if
      self%t = t_stop
    end subroutine integrate_to
  end subroutine step_to

  !> Record the state at the current time.
  subroutine write_step(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    call self%refresh_outputs()
    call self%note_sample()
    call self%write_record(self%outputs%packed(), error)
  end subroutine write_step

  !> Write one record at the current time: the channels' values packed as
  !> rd_output_set%packed (the state, or an interval mean).
  subroutine write_record(self, values, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: values(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, k, n
    if (self%writing) then
      call self%check_values(values, error)
      if (allocated(error)) return
      k = 0
      do i = 1, self%outputs%n
        n = size(self%outputs%channels(i)%values)
        if (self%series(i) > 0) call self%writer%set(self%series(i), values(k + 1:k + n), error)
        if (allocated(error)) return
        k = k + n
      end do
      call self%writer%end_step(self%t, error)
      if (allocated(error)) return
    end if
    call self%safety%add_record(values)
    self%output_steps = self%output_steps + 1
  end subroutine write_record

  !> Count the sample just refreshed into the run's statistics: bodies' distance from their
  !> track frames (rd_frame_drift), wheels without any contact patch, largest vertical
  !> wheel force.
  subroutine note_sample(self)
    class(scene_t), intent(inout) :: self
    integer :: w, side
    if (allocated(self%y)) call self%drift%note(self%y)
    if (.not. associated(self%contact)) return
    self%contact_samples = self%contact_samples + 1
    do w = 1, size(self%wheelset_names)
      do side = 1, 2
        associate (wheel => self%contact%results(w)%wheel(side))
          if (wheel%n_patches == 0) self%samples_without_contact(side, w) = self%samples_without_contact(side, w) + 1
          self%max_sampled_q(side, w) = max(self%max_sampled_q(side, w), wheel%force_track(3))
        end associate
      end do
    end do
  end subroutine note_sample

  !> Error naming the first channel of the packed values that holds a non-finite number.
  subroutine check_values(self, values, error)
    class(scene_t), intent(in) :: self
    real(wp), intent(in) :: values(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, k, n
    k = 0
    do i = 1, self%outputs%n
      n = size(self%outputs%channels(i)%values)
      if (.not. all(ieee_is_finite(values(k + 1:k + n)))) then
        call make_error(error, RD_ERR_RUNTIME, 'non-finite value in output ' // &
                        self%outputs%channels(i)%name // ' at t = ' // trim(real_text(self%t)))
        return
      end if
      k = k + n
    end do
  end subroutine check_values

  pure function scene_vehicle_sigma(self, t) result(sigma)
    class(scene_t), intent(in) :: self
    real(wp), intent(in) :: t
    real(wp) :: sigma
    sigma = self%start_sigma + self%speed%distance(t)
  end function scene_vehicle_sigma

  subroutine refresh_outputs(self)
    class(scene_t), intent(inout) :: self
    integer :: k, j
    real(wp) :: v, sigma
    type(track_point_t) :: p
    v = self%speed%speed(self%t)
    sigma = self%vehicle_sigma(self%t)
    j = 1
    self%outputs%channels(j)%values(1) = v; j = j + 1
    self%outputs%channels(j)%values(1) = sigma; j = j + 1
    do k = 1, size(self%frame_offsets)
      p = self%track%evaluate(sigma + self%frame_offsets(k))
      self%outputs%channels(j)%values(1) = p%sigma; j = j + 1
      self%outputs%channels(j)%values = p%r; j = j + 1
      self%outputs%channels(j)%values = [p%heading, p%grade_angle, p%cant_angle]; j = j + 1
      self%outputs%channels(j)%values(1) = p%curvature; j = j + 1
      self%outputs%channels(j)%values(1) = p%superelevation; j = j + 1
      self%outputs%channels(j)%values = v * p%omega; j = j + 1
    end do
    if (self%nbodies == 0) return
    block
      real(wp) :: rel(BODY_OUT_RELATIVE), fix(BODY_OUT_FIXED), el(ELEMENT_OUT)
      real(wp), allocatable :: ydot(:)
      type(error_t), allocatable :: error
      logical :: recoverable
      integer :: i
      ! One RHS evaluation at the output state refreshes kinematics, accelerations and
      ! element forces (the integrator's last evaluation may be at another state).
      allocate (ydot(size(self%y)))
      call self%mbs%rhs(self%t, self%y, ydot, error, recoverable)
      do i = 1, self%nbodies
        call self%mbs%body_output_relative(i, rel)
        call self%mbs%body_output_fixed(i, fix)
        if (self%mbs%bodies(i)%is_wheelset) then
          ! docs/conventions.md: a wheelset's pitch output is the spin deviation from
          ! nominal rolling, beta = theta - s(t)/r0 (and its rates), not the spin angle.
          associate (r0 => self%mbs%bodies(i)%r0)
            rel(6) = rel(6) - self%mbs%speed%distance(self%t) / r0
            rel(12) = rel(12) - self%mbs%speed%speed(self%t) / r0
            rel(18) = rel(18) - self%mbs%speed%acceleration(self%t) / r0
          end associate
        end if
        self%outputs%channels(j)%values = rel(1:6); j = j + 1
        self%outputs%channels(j)%values = rel(7:12); j = j + 1
        self%outputs%channels(j)%values = rel(13:18); j = j + 1
        self%outputs%channels(j)%values = fix(1:3); j = j + 1
        self%outputs%channels(j)%values = fix(4:6); j = j + 1
        self%outputs%channels(j)%values = fix(7:9); j = j + 1
        self%outputs%channels(j)%values = fix(10:12); j = j + 1
        self%outputs%channels(j)%values = fix(13:15); j = j + 1
        self%outputs%channels(j)%values = fix(16:18); j = j + 1
      end do
      do i = 1, self%mbs%element_count()
        call self%mbs%element_output(i, el)
        self%outputs%channels(j)%values = el(1:3); j = j + 1
        self%outputs%channels(j)%values = el(4:6); j = j + 1
        self%outputs%channels(j)%values = el(7:9); j = j + 1
      end do
      if (associated(self%contact)) then
        block
          integer :: w, side, k
          do w = 1, size(self%wheelset_names)
            associate (res => self%contact%results(w))
              call wheelset_channel_values(res, self%outputs%channels(j)%values); j = j + 1
              self%outputs%channels(j)%values = self%contact%rail_offsets(:, w); j = j + 1
              do side = 1, 2
                call wheel_channel_values(res%wheel(side), self%outputs%channels(j)%values); j = j + 1
                do k = 1, MAX_PATCHES
                  call patch_channel_values(res%wheel(side), k, self%outputs%channels(j)%values); j = j + 1
                end do
              end do
            end associate
          end do
        end block
      end if
      ! sensors after the contact: their channels were registered before the state's
      block
        type(point_motion_t) :: m
        integer :: s
        do s = 1, size(self%sensors)
          m = compute_point_motion(self%mbs%kin(self%sensors(s)%body), self%sensors(s)%position, &
                                   self%mbs%gravity)
          self%outputs%channels(j)%values = m%position_track; j = j + 1
          self%outputs%channels(j)%values = m%position_fixed; j = j + 1
          self%outputs%channels(j)%values = m%velocity_track; j = j + 1
          self%outputs%channels(j)%values = m%acceleration_track; j = j + 1
          self%outputs%channels(j)%values = m%velocity_body; j = j + 1
          self%outputs%channels(j)%values = m%acceleration_body; j = j + 1
          self%outputs%channels(j)%values = m%specific_force_body; j = j + 1
        end do
      end block
      self%outputs%channels(j)%values = self%y; j = j + 1
    end block
  end subroutine refresh_outputs

  ! ------------------------------------------------------------------ mechanics
  !> Bodies, frames, elements and loads from the deck (no state yet).
  subroutine build_mechanics(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
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
    call self%mbs%init(bodies, self%frame_offsets, self%track, self%speed, error, &
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
    call self%deck%get('solver', 1, 'max_step', self%solver%max_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'min_step', self%solver%min_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'initial_step', self%solver%initial_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'max_num_steps', self%solver%max_num_steps, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'fixed_step', self%solver%fixed_step, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'max_order', self%solver%max_order, error); if (allocated(error)) return
    call self%deck%get('solver', 1, 'jacobian', self%jacobian, error); if (allocated(error)) return
  end subroutine build_mechanics

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
    call self%contact%init(specs, self%nbodies, error, labels)
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
  subroutine start_mechanics(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
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
                                      held=held)
      else
        call solve_static_preloads(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error)
      end if
    case ('solve')
      call solve_static_positions(self%mbs, 0.0_wp, self%y, self%equilibrium_residual, error, held=held)
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
          call self%integrator%init(self%mbs, 0.0_wp, self%y, self%solver, error)
        else
          call self%integrator%init(self%mbs, 0.0_wp, self%y, self%solver, error, &
                                    jacobian_sparsity=sparsity)
        end if
      end block
    else
      call self%integrator%init(self%mbs, 0.0_wp, self%y, self%solver, error)
    end if
    if (allocated(error)) call error_context(error, self%deck%origin('solver', 1))
  end subroutine start_mechanics

  !> Point-to-point elements are unstressed (apart from their preload) in the initial
  !> configuration: their free length is the separation of the attachment points there.
  !> `on_level_track`: the bodies at their initial coordinates relative to frames on
  !> straight level track (rd_static_preload), i.e. the vehicle as built.
  subroutine nominal_lengths_from_initial_configuration(mbs, y, on_level_track)
    type(multibody_t), intent(inout) :: mbs
    real(wp), intent(in) :: y(:)
    logical, intent(in) :: on_level_track
    real(wp), allocatable :: ydot(:)
    type(error_t), allocatable :: error
    logical :: recoverable
    integer :: e
    type(level_straight_track_t), target :: level
    class(track_geometry_t), pointer :: actual
    allocate (ydot(size(y)))
    actual => mbs%track
    if (on_level_track) mbs%track => level
    ! the deck's configuration as it stands: quasi-static wheelsets are not moved to their balance
    mbs%hold_quasi_static = .true.
    call mbs%rhs(0.0_wp, y, ydot, error, recoverable)
    mbs%hold_quasi_static = .false.
    mbs%track => actual
    do e = 1, mbs%element_count()
      select type (el => mbs%elements(e)%e)
      type is (linear_spring_damper_t)
        el%free_length = el%free_length + mbs%el_res(e)%deflection
      type is (nonlinear_spring_t)
        el%free_length = el%free_length + mbs%el_res(e)%deflection
      type is (series_spring_damper_t)
        el%free_length = el%free_length + mbs%el_res(e)%deflection(1)
      end select
    end do
  end subroutine nominal_lengths_from_initial_configuration

  !> Free what the pointers own (the C API calls this before deallocating the model).
  subroutine scene_destroy(self)
    class(scene_t), intent(inout) :: self
    if (associated(self%integrator)) then
      call self%integrator%destroy()
      deallocate (self%integrator)
    end if
    if (associated(self%mbs)) deallocate (self%mbs)
    if (associated(self%loads)) deallocate (self%loads)
    if (associated(self%contact)) deallocate (self%contact)
    if (associated(self%track)) deallocate (self%track)
  end subroutine scene_destroy

  subroutine scene_finalize(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    call close_output(self, 'completed', error)
  end subroutine scene_finalize

  !> Close the output of a run its caller ends without finalize (the C API's rd_destroy):
  !> 'completed' once the deck's t_end is reached, else 'stopped' (docs/output.md), so that
  !> a host that gave up half-way does not leave a file that reads as a complete run.
  subroutine scene_stop(self, error)
    class(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    if (self%t >= self%t_end - 1e-9_wp * max(1.0_wp, abs(self%t_end))) then
      call close_output(self, 'completed', error)
    else
      call close_output(self, 'stopped', error)
    end if
  end subroutine scene_stop

  subroutine close_output(self, status, error)
    type(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: status
    type(error_t), allocatable, intent(out) :: error
    integer(int64) :: clock, rate
    real(wp) :: wall
    if (.not. self%writing) return
    self%writing = .false.
    call system_clock(clock, rate)
    wall = real(clock - self%clock_start, wp) / real(rate, wp)
    if (associated(self%integrator)) then
      block
        type(integrator_stats_t) :: st
        call self%integrator%get_stats(st)
        call self%writer%close(status, self%t, wall, error, notes=self%run_notes(), &
          int_stat_names=[character(len=24) :: 'n_steps', 'n_rhs', 'n_rhs_jacobian', 'n_jac', &
                          'n_linear_setups', 'n_error_fail', 'n_newton_fail', 'n_reinit'], &
          int_stat_values=[st%steps, st%rhs_evals, st%rhs_evals_jacobian, st%jacobian_evals, &
                           st%linear_setups, st%error_test_failures, st%nonlinear_conv_failures, &
                           st%reinits], &
          real_stat_names=[character(len=24) :: 'h_last', 'equilibrium_residual'], &
          real_stat_values=[st%last_step, self%equilibrium_residual])
      end block
    else
      call self%writer%close(status, self%t, wall, error, notes=self%run_notes())
    end if
  end subroutine close_output

  ! ------------------------------------------------------------------ queries
  !> The integrator's counters so far (all zero before initialize or without bodies).
  subroutine scene_integrator_stats(self, stats)
    class(scene_t), intent(in) :: self
    type(integrator_stats_t), intent(out) :: stats
    if (associated(self%integrator)) then
      if (self%integrator%is_initialized()) call self%integrator%get_stats(stats)
    end if
  end subroutine scene_integrator_stats

  !> The multibody system the integrator advances (null before build or without bodies),
  !> for tools and tests that evaluate its right-hand side; the scene owns it.
  function scene_system(self) result(mbs)
    class(scene_t), intent(in) :: self
    type(multibody_t), pointer :: mbs
    mbs => self%mbs
  end function scene_system

  pure real(wp) function scene_time(self)
    class(scene_t), intent(in) :: self
    scene_time = self%t
  end function scene_time

  pure real(wp) function scene_end_time(self)
    class(scene_t), intent(in) :: self
    scene_end_time = self%t_end
  end function scene_end_time

  pure real(wp) function scene_output_interval(self)
    class(scene_t), intent(in) :: self
    scene_output_interval = self%interval
  end function scene_output_interval

  !> The running speed V [m/s] at the current time (the deck's law, or set_input's).
  pure real(wp) function scene_running_speed(self)
    class(scene_t), intent(in) :: self
    scene_running_speed = self%speed%speed(self%t)
  end function scene_running_speed

  !> Whether raildyn run shows its progress line (&output progress): 'on' always, 'off'
  !> never, 'auto' when its stderr is a terminal (`terminal`).
  logical function scene_progress_wanted(self, terminal)
    class(scene_t), intent(in) :: self
    logical, intent(in) :: terminal
    character(len=:), allocatable :: mode
    type(error_t), allocatable :: error
    call self%deck%get('output', 1, 'progress', mode, error)
    scene_progress_wanted = terminal
    if (allocated(error)) return
    if (mode == 'on') scene_progress_wanted = .true.
    if (mode == 'off') scene_progress_wanted = .false.
  end function scene_progress_wanted

  pure integer function scene_state_size(self)
    class(scene_t), intent(in) :: self
    scene_state_size = 0
    if (allocated(self%y)) scene_state_size = size(self%y)
  end function scene_state_size

  subroutine scene_get_state(self, y, error)
    class(scene_t), intent(in) :: self
    real(wp), intent(out) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    if (size(y) /= self%state_size()) then
      call make_error(error, RD_ERR_INPUT, 'get_state: the array has ' // trim(int_text(size(y))) // &
                      ' elements; expected the state size ' // trim(int_text(self%state_size())))
      return
    end if
    if (allocated(self%y)) y = self%y
  end subroutine scene_get_state

  !> Replace the state at the current time (after initialize; the integrator restarts its
  !> history there). y in the layout of rd_multibody (state/y, docs/output.md).
  subroutine scene_set_state(self, y, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (.not. self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_state before initialize (set_start gives a ' // &
                      'state to start from)')
      return
    end if
    call check_state(self, y, 'set_state', error)
    if (allocated(error)) return
    self%y = y
    call self%integrator%reinit(self%t, self%y, error)
  end subroutine scene_set_state

  !> Start the run at time t [s] from state y instead of the deck's initial state (a
  !> restart; before initialize). The first output row is (t, y).
  subroutine scene_set_start(self, t, y, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    if (self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_start after initialize (set_state replaces ' // &
                      'the state at the current time)')
      return
    end if
    call self%build(error)
    if (allocated(error)) return
    if (.not. (ieee_is_finite(t) .and. t >= 0)) then
      call make_error(error, RD_ERR_INPUT, 'set_start: the time must be finite and >= 0 [s]')
      return
    end if
    call check_state(self, y, 'set_start', error)
    if (allocated(error)) return
    self%start_time = t
    self%start_state = y
  end subroutine scene_set_start

  !> A restart from the last complete row of a results file's /state/y (rd_results_state),
  !> or from row `row` (counted from 0; raildyn eigen --state FILE:ROW): the deck must
  !> describe the same state (the column names, i.e. bodies, their free coordinates and the
  !> elements' states, must agree) and the file's rows must be states, not interval means.
  subroutine scene_continue_from(self, path, error, row)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(out) :: error
    integer, intent(in), optional :: row
    type(results_state_t) :: saved
    integer :: id, row_wanted
    call self%build(error)
    if (allocated(error)) return
    row_wanted = -1
    if (present(row)) row_wanted = row
    call read_state_row(path, row_wanted, saved, error)
    if (allocated(error)) return
    if (saved%mean_samples > 0) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": its rows are interval means ' // &
        '(output_mean_samples = ' // trim(int_text(saved%mean_samples)) // '), not states; ' // &
        'a run cannot continue from it')
      return
    end if
    call self%outputs%find('state/y', id, error)
    if (allocated(error)) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": the deck has no bodies, so no state ' // &
                      'to continue from')
      return
    end if
    if (saved%components /= self%outputs%channels(id)%components) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": its state (' // &
        trim(int_text(size(saved%y))) // ' values) is not the state of this deck (' // &
        trim(int_text(self%mbs%state_size())) // ' values): ' // &
        first_difference(saved%components, self%outputs%channels(id)%components))
      return
    end if
    call self%set_start(saved%time, saved%y, error)
    if (allocated(error)) call error_context(error, '"' // path // '"')
  contains
    !> "column k is 'a' in the file, 'b' in the deck" for the first differing word.
    pure function first_difference(file_words, deck_words) result(text)
      character(len=*), intent(in) :: file_words, deck_words
      character(len=:), allocatable :: text
      character(len=:), allocatable :: a, b
      integer :: k, ia, ib
      a = file_words // ' '; b = deck_words // ' '
      k = 0
      do
        k = k + 1
        ia = index(a, ' '); ib = index(b, ' ')
        if (a(1:ia) /= b(1:ib) .or. len(a) <= 1 .or. len(b) <= 1) exit
        a = a(ia + 1:); b = b(ib + 1:)
      end do
      text = 'column ' // trim(int_text(k)) // " is '" // trim(a(1:max(ia, 1))) // "' in the file, '" // &
             trim(b(1:max(ib, 1))) // "' in the deck"
    end function first_difference
  end subroutine scene_continue_from

  !> A state vector for this scene: the state size, finite.
  subroutine check_state(self, y, what, error)
    type(scene_t), intent(in) :: self
    real(wp), intent(in) :: y(:)
    character(len=*), intent(in) :: what
    type(error_t), allocatable, intent(out) :: error
    integer :: n
    n = 0
    if (associated(self%mbs)) n = self%mbs%state_size()
    if (size(y) /= n .or. n == 0) then
      call make_error(error, RD_ERR_INPUT, what // ': the state has ' // trim(int_text(size(y))) // &
                      ' values; expected the state size ' // trim(int_text(n)))
      return
    end if
    if (.not. all(ieee_is_finite(y))) then
      call make_error(error, RD_ERR_INPUT, what // ': the state values must be finite')
    end if
  end subroutine check_state

  pure integer function scene_output_count(self)
    class(scene_t), intent(in) :: self
    scene_output_count = self%outputs%n
  end function scene_output_count

  subroutine scene_output_name(self, index, name, error)
    class(scene_t), intent(in) :: self
    integer, intent(in) :: index
    character(len=:), allocatable, intent(out) :: name
    type(error_t), allocatable, intent(out) :: error
    if (index < 1 .or. index > self%outputs%n) then
      call make_error(error, RD_ERR_INPUT, 'output index ' // trim(int_text(index)) // &
                      ' out of range; expected 1 to ' // trim(int_text(self%outputs%n)))
      name = ''
      return
    end if
    name = self%outputs%channels(index)%name
  end subroutine scene_output_name

  subroutine scene_output_size(self, name, n, error)
    class(scene_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(out) :: n
    type(error_t), allocatable, intent(out) :: error
    integer :: id
    n = 0
    call self%outputs%find(name, id, error)
    if (allocated(error)) return
    n = size(self%outputs%channels(id)%values)
  end subroutine scene_output_size

  subroutine scene_get_output(self, name, values, error)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(wp), intent(out) :: values(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: id
    call self%outputs%find(name, id, error)
    if (allocated(error)) return
    if (size(values) /= size(self%outputs%channels(id)%values)) then
      call make_error(error, RD_ERR_INPUT, 'output ' // name // ' has ' // &
                      trim(int_text(size(self%outputs%channels(id)%values))) // ' values; got an array of ' // &
                      trim(int_text(size(values))))
      return
    end if
    call self%refresh_outputs()
    values = self%outputs%channels(id)%values
  end subroutine scene_get_output

  subroutine scene_set_input(self, name, values, error)
    class(scene_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    type(error_t), allocatable, intent(out) :: error
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (.not. self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_input before initialize')
      return
    end if
    if (.not. all(ieee_is_finite(values))) then
      call make_error(error, RD_ERR_INPUT, 'input ' // name // ': values must be finite')
      return
    end if
    select case (name)
    case ('speed')
      if (size(values) /= 1 .or. values(1) < 0) then
        call make_error(error, RD_ERR_INPUT, "input 'speed': expected one value >= 0 [m/s]")
        return
      end if
      call self%speed%override(self%t, values(1), error=error)
      if (allocated(error)) return
      if (associated(self%mbs)) then
        call self%mbs%speed%override(self%t, values(1), error=error)
        if (allocated(error)) return
        ! The right-hand side changes here: restart the integrator's history.
        call self%integrator%reinit(self%t, self%y, error)
      end if
    case default
      if (index(name, 'body/') == 1 .and. index(name, '/external_force') == len(name) - 14) then
        block
          integer :: ib
          ib = 0
          if (associated(self%mbs)) ib = body_index(self%deck, name(6:len(name) - 15))
          if (ib < 1) then
            call make_error(error, RD_ERR_INPUT, "input '" // name // "': no such body")
            return
          end if
          if (size(values) /= 6) then
            call make_error(error, RD_ERR_INPUT, "input '" // name // &
                            "': expected 6 values (force [N] and moment [N m], fixed frame)")
            return
          end if
          call self%mbs%set_override_load(ib, values(1:3), values(4:6), error)
          if (.not. allocated(error)) call self%integrator%reinit(self%t, self%y, error)
        end block
        return
      end if
      call make_error(error, RD_ERR_INPUT, "unknown input '" // name // &
                      "'; expected 'speed' or 'body/<name>/external_force'")
    end select
  end subroutine scene_set_input

  function scene_summary(self) result(text)
    class(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    text = 'track ' // trim(real_text(self%track%length())) // ' m, ' // &
           trim(int_text(self%deck%count('segment'))) // ' segments, ' // &
           trim(int_text(self%deck%count('body'))) // ' bodies, ' // &
           trim(int_text(self%deck%count('element'))) // ' elements, ' // &
           trim(int_text(self%deck%count('wheelset'))) // ' wheelsets, t_end ' // trim(real_text(self%t_end)) // ' s'
  end function scene_summary

  !> One line for the runner: time reached, output steps and the integrator's effort (the
  !> counters /meta/solver keeps: a run that took many steps or failed many error tests
  !> shows it without opening the file), then 'note: ' + each run note.
  function scene_completion_summary(self) result(text)
    class(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    type(integrator_stats_t) :: st
    character(len=:), allocatable :: safety
    text = 'completed t = ' // trim(real_text(self%t)) // ' s, ' // trim(int_text(int(self%output_steps))) // &
           ' output steps'
    if (associated(self%integrator)) then
      call self%integrator_stats(st)
      text = text // '; solver: ' // trim(int_text(st%steps)) // ' steps, ' // &
             trim(int_text(st%rhs_evals + st%rhs_evals_jacobian)) // ' RHS calls (' // &
             trim(int_text(st%rhs_evals_jacobian)) // ' for Jacobians), ' // &
             trim(int_text(st%error_test_failures)) // ' error-test failures, ' // &
             trim(int_text(st%nonlinear_conv_failures)) // ' Newton failures'
    end if
    safety = self%safety%summary()
    if (len(safety) > 0) text = text // new_line('a') // safety
    text = text // self%contact_notes(new_line('a') // 'note: ')
    if (associated(self%mbs)) text = text // self%drift%notes(self%mbs, new_line('a') // 'warning: ')
  end function scene_completion_summary

  !> The run's notes for readers, one per line ('' when there are none): wheels that lost
  !> contact, bodies that left their track frames (rd_frame_drift). A user must know that
  !> the results contain flights and impacts (flange bouncing, lift-off) or a vehicle left
  !> behind before reading means off them; the runner prints them and the results file
  !> keeps them (/meta attribute 'notes', docs/output.md).
  !> Warnings about legal but suspicious input (one line each, deck line first; empty
  !> before build): raildyn check and run print them.
  function scene_warnings(self) result(list)
    class(scene_t), intent(in) :: self
    type(deck_string_t), allocatable :: list(:)
    if (allocated(self%warning_list)) then
      list = self%warning_list
    else
      allocate (list(0))
    end if
  end function scene_warnings

  !> The results file could be created: its directory exists and the path is not a
  !> directory (raildyn check; run finds the same when it opens the file). Errors name
  !> the deck line of &output 'file', or the -o option.
  subroutine scene_check_output_path(self, error)
    class(scene_t), intent(in) :: self
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: path, where, dir
    integer :: slash
    if (allocated(self%output_override)) then
      path = self%output_override
      where = 'results file given with -o'
    else
      path = self%deck%path('output', 1, 'file')
      where = self%deck%origin('output', 1, 'file')
    end if
    slash = index(path, '/', back=.true.)
    dir = '.'
    if (slash == 1) dir = '/'
    if (slash > 1) dir = path(1:slash - 1)
    if (file_kind(path) == FILE_DIRECTORY .or. slash == len(path)) then
      call make_error(error, RD_ERR_IO, where // ": '" // path // "' is a directory; expected " // &
        'the name of a results file (.h5)')
    else if (file_kind(dir) /= FILE_DIRECTORY) then
      call make_error(error, RD_ERR_IO, where // ": the directory '" // dir // "' of '" // path // &
        "' does not exist; expected an existing directory for the results file")
    end if
  end subroutine scene_check_output_path

  function scene_run_notes(self) result(notes)
    class(scene_t), intent(in) :: self
    character(len=:), allocatable :: notes
    notes = self%contact_notes(new_line('a'))
    if (associated(self%mbs)) notes = notes // self%drift%notes(self%mbs, new_line('a'))
    notes = notes(2:)            ! '' stays ''
  end function scene_run_notes

  !> Each wheel that had no contact patch in some output samples, as `lead` followed by its
  !> note (share of the samples, largest sampled vertical force).
  function contact_notes(self, lead) result(notes)
    class(scene_t), intent(in) :: self
    character(len=*), intent(in) :: lead
    character(len=:), allocatable :: notes
    integer :: w, side
    character(len=16) :: pct, qmax
    notes = ''
    if (.not. allocated(self%samples_without_contact)) return
    do w = 1, size(self%wheelset_names)
      do side = 1, 2
        if (self%samples_without_contact(side, w) == 0) cycle
        write (pct, '(f0.1)') 100.0_wp * real(self%samples_without_contact(side, w), wp) / &
                              real(self%contact_samples, wp)
        write (qmax, '(f0.1)') 1.0e-3_wp * self%max_sampled_q(side, w)
        notes = notes // lead // 'wheelset ' // trim(self%wheelset_names(w)) // ' ' // &
                trim(merge('left ', 'right', side == 1)) // ' wheel without contact in ' // trim(pct) // &
                ' % of ' // trim(int_text(int(self%contact_samples))) // ' output samples (largest sampled Q ' // &
                trim(qmax) // ' kN)'
      end do
    end do
  end function contact_notes

  !> Every file the scene's deck reads (rd_deck input_files): the deck, its includes at any
  !> depth, profile, irregularity and survey files. Empty before a deck was loaded.
  function scene_input_files(self) result(files)
    class(scene_t), intent(in) :: self
    type(deck_string_t), allocatable :: files(:)
    files = self%deck%input_files()
  end function scene_input_files

  !> The results file's name with its extension replaced by `suffix` (e.g. '_track.h5'): in the
  !> working directory, named after the deck, unless the deck names a results file.
  function scene_default_output_file(self, suffix) result(path)
    class(scene_t), intent(in) :: self
    character(len=*), intent(in) :: suffix
    character(len=:), allocatable :: path
    integer :: dot
    path = self%deck%path('output', 1, 'file')
    ! a results file the deck names is where the deck says (relative to the deck); without
    ! one, the results go to the working directory (a deck may sit in a read-only folder
    ! shared by many runs), named after the deck
    if (.not. self%deck%given('output', 1, 'file')) path = path(index(path, '/', back=.true.) + 1:)
    dot = index(path, '.', back=.true.)
    if (dot > index(path, '/', back=.true.)) path = path(1:dot - 1)
    path = path // suffix
  end function scene_default_output_file

end module rd_scene
