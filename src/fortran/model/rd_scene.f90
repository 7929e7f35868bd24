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
!> This file holds the type and its life cycle; submodules hold the rest, one concern each:
!> rd_scene_output_table, rd_scene_startup, rd_scene_by_name, rd_scene_notes and
!> rd_scene_check_report.
module rd_scene
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, make_error, error_context, run_status, RD_ERR_INPUT, RD_ERR_HANDLE, &
                      RD_ERR_IO, RD_ERR_RUNTIME
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
  use rd_point_motion, only: point_motion_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_wheel_contact_result, only: wheelset_result_t
  use rd_body_spec, only: body_spec_t, DOF_Y, DOF_YAW, DOF_PITCH
  use rd_multibody, only: multibody_t, multibody_output_t
  use rd_force_element, only: force_element_t
  use rd_force_provider, only: force_provider_t
  use rd_external_loads, only: external_loads_t
  use rd_static_preload, only: solve_static_preloads, solve_static_positions
  use rd_reference_radius, only: centred_rolling_radius
  use rd_level_straight_track, only: level_straight_track_t
  use rd_integrator, only: integrator_t, integrator_settings_t, integrator_stats_t, &
                           jacobian_sparsity_t
  use rd_scene_jacobian, only: scene_jacobian_sparsity
  implicit none
  private
  public :: scene_t, raildyn_version

  character(len=*), parameter :: raildyn_version = '0.1.0'

  !> The scene's outputs at its time and state (calc_output), what the output table reads.
  type :: scene_output_t
    real(wp) :: speed = 0, sigma = 0               !< vehicle speed [m/s], arc length [m]
    type(track_point_t), allocatable :: frames(:)  !< track frames at sigma + frame offset
    type(multibody_output_t) :: mbs
    type(wheelset_result_t), allocatable :: contact(:)
    type(point_motion_t), allocatable :: sensors(:)
  end type scene_output_t

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
    procedure, private :: calc_output
    procedure, private :: refresh_outputs
    procedure, private :: write_step
    procedure, private :: write_record
    procedure, private :: check_values
    procedure, private :: note_sample
    procedure, private :: register_outputs
    procedure, private :: channel_written
  end type scene_t

  interface
    !> What a modeller checks first (raildyn check), after initialize: rd_scene_check_report.
    module function scene_check_report(self) result(text)
      class(scene_t), intent(inout) :: self
      character(len=:), allocatable :: text
    end function scene_check_report
    !> After a failed run: stepping calls get the failure again (rd_scene_by_name).
    module subroutine refuse_after_failure(self, error)
      type(scene_t), intent(in) :: self
      type(error_t), allocatable, intent(out) :: error
    end subroutine refuse_after_failure
    ! rd_scene_output_table: the channels, filled and written
    module subroutine register_outputs(self)
      class(scene_t), intent(inout) :: self
    end subroutine register_outputs
    logical module function channel_written(self, i)
      class(scene_t), intent(in) :: self
      integer, intent(in) :: i
    end function channel_written
    module subroutine write_step(self, error)
      class(scene_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
    end subroutine write_step
    module subroutine write_record(self, values, error)
      class(scene_t), intent(inout) :: self
      real(wp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine write_record
    module subroutine note_sample(self)
      class(scene_t), intent(inout) :: self
    end subroutine note_sample
    module subroutine check_values(self, values, error)
      class(scene_t), intent(in) :: self
      real(wp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine check_values
    module subroutine calc_output(self, out, error)
      class(scene_t), intent(inout) :: self
      type(scene_output_t), intent(out) :: out
      type(error_t), allocatable, intent(out) :: error
    end subroutine calc_output
    module subroutine refresh_outputs(self, error)
      class(scene_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
    end subroutine refresh_outputs
    ! rd_scene_startup: the mechanics built and started
    module subroutine build_mechanics(self, error)
      class(scene_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
    end subroutine build_mechanics
    module subroutine start_mechanics(self, error)
      class(scene_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
    end subroutine start_mechanics
    ! rd_scene_by_name: state, outputs and inputs for the C API
    module subroutine scene_get_state(self, y, error)
      class(scene_t), intent(in) :: self
      real(wp), intent(out) :: y(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_get_state
    module subroutine scene_set_state(self, y, error)
      class(scene_t), intent(inout) :: self
      real(wp), intent(in) :: y(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_set_state
    module subroutine scene_set_start(self, t, y, error)
      class(scene_t), intent(inout) :: self
      real(wp), intent(in) :: t
      real(wp), intent(in) :: y(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_set_start
    module subroutine scene_continue_from(self, path, error, row)
      class(scene_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: row
    end subroutine scene_continue_from
    pure integer module function scene_output_count(self)
      class(scene_t), intent(in) :: self
    end function scene_output_count
    module subroutine scene_output_name(self, index, name, error)
      class(scene_t), intent(in) :: self
      integer, intent(in) :: index
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_output_name
    module subroutine scene_output_size(self, name, n, error)
      class(scene_t), intent(in) :: self
      character(len=*), intent(in) :: name
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_output_size
    module subroutine scene_get_output(self, name, values, error)
      class(scene_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(wp), intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_get_output
    module subroutine scene_set_input(self, name, values, error)
      class(scene_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(wp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine scene_set_input
    ! rd_scene_notes: summary, completion line, run notes, warnings
    module function scene_summary(self) result(text)
      class(scene_t), intent(in) :: self
      character(len=:), allocatable :: text
    end function scene_summary
    module function scene_completion_summary(self) result(text)
      class(scene_t), intent(in) :: self
      character(len=:), allocatable :: text
    end function scene_completion_summary
    module function scene_warnings(self) result(list)
      class(scene_t), intent(in) :: self
      type(deck_string_t), allocatable :: list(:)
    end function scene_warnings
    module function scene_run_notes(self) result(notes)
      class(scene_t), intent(in) :: self
      character(len=:), allocatable :: notes
    end function scene_run_notes
    module function scene_input_files(self) result(files)
      class(scene_t), intent(in) :: self
      type(deck_string_t), allocatable :: files(:)
    end function scene_input_files
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

  !> Close the results file (if open) with rd_error's run_status ('failed: <message>'): the
  !> one place where a failure is recorded, for the runner and the C API alike. A failure
  !> to record it is added to the error's message.
  subroutine record_failure_in_results(self, error)
    type(scene_t), intent(inout) :: self
    type(error_t), allocatable, intent(inout) :: error
    type(error_t), allocatable :: close_error
    call close_output(self, run_status(error), close_error)
    if (allocated(close_error)) error%message = error%message // &
      '; the results file could not record this failure: ' // close_error%message
  end subroutine record_failure_in_results


  !> Advance to t_target, writing every output step passed on the way.
  !> t_horizon (>= t_target, default t_target): the caller promises not to change the
  !> scene's inputs before t_horizon, so the integrator may step on towards it and
  !> interpolate t_target. A runner that advances in chunks only to show progress passes
  !> its end time: a stop at every chunk end cut a step short there, and BDF needed
  !> several steps to grow back (docs/performance.md "Stepping through the records").
  subroutine scene_advance(self, t_target, error, t_horizon)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: t_target
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: t_horizon
    real(wp) :: t_limit
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
    t_limit = t_target
    if (present(t_horizon)) then
      if (.not. (t_horizon >= t_target)) then
        call make_error(error, RD_ERR_INPUT, 'advance: the horizon must be >= the target time')
        return
      end if
      t_limit = t_horizon
    end if
    call step_to(self, t_target, t_limit, error)
    if (allocated(error)) then
      ! The run ends here (the integrator's state is invalid or a record could not be
      ! written): the file says so, and the scene refuses to step on.
      self%failure = error%message
      call record_failure_in_results(self, error)
    end if
  end subroutine scene_advance

  !> Integrate to t_target, writing every output step passed on the way (scene_advance);
  !> the integrator may step as far as t_limit.
  subroutine step_to(self, t_target, t_limit, error)
    class(scene_t), intent(inout) :: self
    real(wp), intent(in) :: t_target, t_limit
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
        ! so that advancing in pieces (C API) gives the same records; interpolated like the
        ! records (integrate_to), they add no steps.
        t_out = (real(self%output_steps - 1, wp) + self%average%next_fraction()) * self%interval
        if (t_out > t_target + 1e-9_wp * self%interval / self%average%samples) exit
        call integrate_to(t_out)
        if (allocated(error)) return
        call self%refresh_outputs(error)
        if (allocated(error)) return
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
    !> To t_stop (a record, a sub-sample or the target). The integrator steps on to the
    !> limit (the target or the caller's horizon), where inputs may change, and
    !> interpolates t_stop (rd_integrator advance's t_stop): stopping it at every record
    !> cut a step at each and BDF needed several steps to grow back (the Manchester decks:
    !> 16-17 % of their steps, docs/performance.md).
    subroutine integrate_to(t_stop)
      real(wp), intent(in) :: t_stop
      ! A track-only scene is kinematic: the vehicle position is an exact function of time.
      if (t_stop <= self%t) return
      if (associated(self%integrator)) then
        call self%integrator%advance(t_stop, self%y, error, max(t_limit, t_stop))
        if (allocated(error)) then
          self%t = self%integrator%time()
          call error_context(error, 'scene')
          return
        end if
      end if
      self%t = t_stop
    end subroutine integrate_to
  end subroutine step_to

  pure function scene_vehicle_sigma(self, t) result(sigma)
    class(scene_t), intent(in) :: self
    real(wp), intent(in) :: t
    real(wp) :: sigma
    sigma = self%start_sigma + self%speed%distance(t)
  end function scene_vehicle_sigma

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
                          'n_linear_setups', 'n_error_fail', 'n_newton_fail', 'n_reinit', &
                          'n_rhs_retries'], &
          int_stat_values=[st%steps, st%rhs_evals, st%rhs_evals_jacobian, st%jacobian_evals, &
                           st%linear_setups, st%error_test_failures, st%nonlinear_conv_failures, &
                           st%reinits, st%rhs_retries], &
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
