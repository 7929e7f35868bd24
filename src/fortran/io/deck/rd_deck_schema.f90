!> The single definition of every deck group and parameter: type, SI unit,
!> default or "required", valid range or allowed values, path and reference
!> kinds, and a one-line meaning. The reader (rd_deck), the cross-checks and
!> the generated reference (docs/input_reference.md, write_schema_markdown)
!> are all driven by this table, so they cannot disagree.
!>
!> Conditional rules that involve several parameters (radius required for a
!> curve, profiles required for profile contact, ...) are listed in a
!> parameter's `condition` text for the reference and enforced in
!> rd_deck_checks.
module rd_deck_schema
  use rd_kinds, only: wp, standard_gravity
  use rd_deck_text, only: deck_string_t, joined, single_string, to_lower, real_to_str, int_to_str, edit_distance
  implicit none
  private
  public :: param_schema_t, group_schema_t, deck_schema_t, build_deck_schema
  public :: find_group, find_param, suggest_name, type_text, default_text, range_text
  public :: write_schema_markdown, used_text
  public :: PT_REAL, PT_INTEGER, PT_STRING, PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST
  public :: DEF_REQUIRED, DEF_VALUE, DEF_OPTIONAL, DEF_PREVIOUS, DEF_DECK_STEM

  integer, parameter :: PT_REAL = 1, PT_INTEGER = 2, PT_STRING = 3, PT_LOGICAL = 4, &
                        PT_REAL_ARRAY = 5, PT_STRING_LIST = 6

  !> How a parameter the user did not write gets its value.
  integer, parameter :: DEF_REQUIRED = 1   !< must be written
  integer, parameter :: DEF_VALUE = 2      !< the schema default
  integer, parameter :: DEF_OPTIONAL = 3   !< no value; ask deck%given first
  integer, parameter :: DEF_PREVIOUS = 4   !< previous occurrence's value, else the default
  integer, parameter :: DEF_DECK_STEM = 5  !< the deck's stem + a suffix (output file)

  type :: param_schema_t
    character(len=:), allocatable :: name, unit, meaning
    integer :: ptype = PT_REAL
    integer :: size = 1                 !< fixed length of a real array; 0 = variable
    integer :: default_kind = DEF_VALUE
    real(wp), allocatable :: default_reals(:)
    integer :: default_integer = 0
    logical :: default_logical = .false.
    type(deck_string_t), allocatable :: default_strings(:)  !< string, or list, or stem suffix
    logical :: has_min = .false., has_max = .false., min_open = .false., max_open = .false.
    real(wp) :: min = 0.0_wp, max = 0.0_wp
    logical :: increasing = .false.     !< real array must be strictly increasing
    type(deck_string_t), allocatable :: allowed(:)   !< allowed strings (lower case)
    logical :: is_path = .false., must_exist = .false.
    type(deck_string_t), allocatable :: path_keywords(:)  !< e.g. 's1002' instead of a file
    character(len=:), allocatable :: ref_group      !< value names an entity of this group
    type(deck_string_t), allocatable :: ref_keywords(:)   !< e.g. 'ground', 'own'
    logical :: unique = .false.         !< value unique among the group's entities ('name')
    character(len=:), allocatable :: condition      !< cross-parameter rule, for the docs
    !> Parameters that only some kinds of their group read: the parameter is read only when
    !> the group's parameter `used_with` has one of the values `used_values` (after
    !> defaults), or, with used_values = ['(given)'] / ['(not given)'], only when
    !> `used_with` is / is not written. Given where it is not read, it is an input error
    !> (rd_deck_resolve check_unused): nothing in a deck is silently ignored.
    character(len=:), allocatable :: used_with
    type(deck_string_t), allocatable :: used_values(:)
    !> Allowed values that are study options, not fidelity levels a user picks for production
    !> runs: a deck that selects one is accepted with a warning (rd_deck_resolve) ending in
    !> `study_note`.
    type(deck_string_t), allocatable :: study_values(:)
    character(len=:), allocatable :: study_note
  end type param_schema_t

  type :: group_schema_t
    character(len=:), allocatable :: name, meaning
    logical :: repeatable = .false.
    type(param_schema_t), allocatable :: params(:)
  end type group_schema_t

  type :: deck_schema_t
    type(group_schema_t), allocatable :: groups(:)
  end type deck_schema_t

contains

  ! ---------------------------------------------------------------------
  ! Small constructors so the schema below reads like a table.
  ! ---------------------------------------------------------------------
  function strs(list) result(out)
    character(len=*), intent(in) :: list   !< '|'-separated
    type(deck_string_t), allocatable :: out(:)
    integer :: k, start, n
    n = 0
    if (len(list) > 0) n = count([(list(k:k) == '|', k=1, len(list))]) + 1
    allocate (out(n))
    start = 1
    do k = 1, n
      if (k < n) then
        out(k)%s = list(start:start + index(list(start:), '|') - 2)
        start = start + index(list(start:), '|')
      else
        out(k)%s = list(start:)
      end if
    end do
  end function strs

  function base(name, ptype, unit, meaning, required, cond) result(p)
    character(len=*), intent(in) :: name, unit, meaning
    integer, intent(in) :: ptype
    logical, intent(in), optional :: required
    character(len=*), intent(in), optional :: cond
    type(param_schema_t) :: p
    p%name = name; p%ptype = ptype; p%unit = unit; p%meaning = meaning
    p%default_kind = DEF_OPTIONAL
    if (present(required)) then
      if (required) p%default_kind = DEF_REQUIRED
    end if
    p%condition = ''
    if (present(cond)) p%condition = cond
    allocate (p%default_reals(0), p%default_strings(0), p%allowed(0), p%path_keywords(0), &
              p%ref_keywords(0), p%used_values(0))
    p%ref_group = ''
    p%used_with = ''
  end function base

  subroutine set_range(p, min, max, min_open, max_open)
    type(param_schema_t), intent(inout) :: p
    real(wp), intent(in), optional :: min, max
    logical, intent(in), optional :: min_open, max_open
    if (present(min)) then
      p%has_min = .true.; p%min = min
    end if
    if (present(max)) then
      p%has_max = .true.; p%max = max
    end if
    if (present(min_open)) p%min_open = min_open
    if (present(max_open)) p%max_open = max_open
  end subroutine set_range

  !> Real scalar.
  function preal(name, unit, meaning, default, required, min, max, min_open, max_open, &
                 previous, cond) result(p)
    character(len=*), intent(in) :: name, unit, meaning
    real(wp), intent(in), optional :: default, min, max
    logical, intent(in), optional :: required, min_open, max_open, previous
    character(len=*), intent(in), optional :: cond
    type(param_schema_t) :: p
    p = base(name, PT_REAL, unit, meaning, required, cond)
    if (present(default)) then
      p%default_kind = DEF_VALUE; p%default_reals = [default]
    end if
    if (present(previous)) then
      if (previous) p%default_kind = DEF_PREVIOUS
    end if
    call set_range(p, min, max, min_open, max_open)
  end function preal

  function pint(name, unit, meaning, default, min, max) result(p)
    character(len=*), intent(in) :: name, unit, meaning
    integer, intent(in) :: default
    integer, intent(in), optional :: min, max
    type(param_schema_t) :: p
    p = base(name, PT_INTEGER, unit, meaning)
    p%default_kind = DEF_VALUE; p%default_integer = default
    if (present(min)) call set_range(p, min=real(min, wp))
    if (present(max)) call set_range(p, max=real(max, wp))
  end function pint

  function plog(name, meaning, default) result(p)
    character(len=*), intent(in) :: name, meaning
    logical, intent(in) :: default
    type(param_schema_t) :: p
    p = base(name, PT_LOGICAL, '-', meaning)
    p%default_kind = DEF_VALUE; p%default_logical = default
  end function plog

  !> String; `allowed` is a '|'-separated list (compared case-insensitively).
  function pstr(name, meaning, default, allowed, required, cond) result(p)
    character(len=*), intent(in) :: name, meaning
    character(len=*), intent(in), optional :: default, allowed
    logical, intent(in), optional :: required
    character(len=*), intent(in), optional :: cond
    type(param_schema_t) :: p
    p = base(name, PT_STRING, '-', meaning, required, cond)
    if (present(default)) then
      p%default_kind = DEF_VALUE
      p%default_strings = single_string(default)
    end if
    if (present(allowed)) p%allowed = strs(allowed)
  end function pstr

  !> Real array of fixed length n (n > 0) or variable length (n = 0).
  function parray(name, unit, meaning, n, default, increasing, cond) result(p)
    character(len=*), intent(in) :: name, unit, meaning
    integer, intent(in) :: n
    real(wp), intent(in), optional :: default(:)
    logical, intent(in), optional :: increasing
    character(len=*), intent(in), optional :: cond
    type(param_schema_t) :: p
    p = base(name, PT_REAL_ARRAY, unit, meaning, cond=cond)
    p%size = n
    if (present(default)) then
      p%default_kind = DEF_VALUE; p%default_reals = default
    end if
    if (present(increasing)) p%increasing = increasing
  end function parray

  !> String list; `allowed` and `default` (default: empty) are '|'-separated.
  function pstrlist(name, meaning, allowed, default) result(p)
    character(len=*), intent(in) :: name, meaning, allowed
    character(len=*), intent(in), optional :: default
    type(param_schema_t) :: p
    p = base(name, PT_STRING_LIST, '-', meaning)
    p%size = 0
    p%default_kind = DEF_VALUE
    p%allowed = strs(allowed)
    if (present(default)) p%default_strings = strs(default)
  end function pstrlist

  function path_param(p, must_exist, keywords) result(q)
    type(param_schema_t), intent(in) :: p
    logical, intent(in) :: must_exist
    character(len=*), intent(in), optional :: keywords
    type(param_schema_t) :: q
    q = p
    q%is_path = .true.; q%must_exist = must_exist
    if (present(keywords)) q%path_keywords = strs(keywords)
  end function path_param

  function ref_param(p, group, keywords) result(q)
    type(param_schema_t), intent(in) :: p
    character(len=*), intent(in) :: group
    character(len=*), intent(in), optional :: keywords
    type(param_schema_t) :: q
    q = p
    q%ref_group = group
    if (present(keywords)) q%ref_keywords = strs(keywords)
  end function ref_param

  !> The parameter is read only when `selector` (a parameter of the same group) has one of
  !> the '|'-separated `values`, or is given ('(given)') / not given ('(not given)').
  function only_with(p, selector, values) result(q)
    type(param_schema_t), intent(in) :: p
    character(len=*), intent(in) :: selector, values
    type(param_schema_t) :: q
    q = p
    q%used_with = selector
    q%used_values = strs(values)
  end function only_with

  !> p with the allowed values `values` ('|'-separated) marked as study options (see
  !> param_schema_t%study_values).
  function study_options(p, values, note) result(q)
    type(param_schema_t), intent(in) :: p
    character(len=*), intent(in) :: values, note
    type(param_schema_t) :: q
    q = p
    q%study_values = strs(values)
    q%study_note = note
  end function study_options

  function unique_name(meaning) result(p)
    character(len=*), intent(in) :: meaning
    type(param_schema_t) :: p
    p = pstr('name', meaning, required=.true.)
    p%unique = .true.
  end function unique_name

  function vec3(name, unit, meaning) result(p)
    character(len=*), intent(in) :: name, unit, meaning
    type(param_schema_t) :: p
    p = parray(name, unit, meaning, 3, [0.0_wp, 0.0_wp, 0.0_wp])
  end function vec3

  subroutine add_group(s, name, repeatable, meaning, params)
    type(deck_schema_t), intent(inout) :: s
    character(len=*), intent(in) :: name, meaning
    logical, intent(in) :: repeatable
    type(param_schema_t), intent(in) :: params(:)
    type(group_schema_t) :: g
    g%name = name; g%repeatable = repeatable; g%meaning = meaning
    g%params = params
    s%groups = [s%groups, g]
  end subroutine add_group

  ! ---------------------------------------------------------------------
  ! The schema.
  ! ---------------------------------------------------------------------
  function build_deck_schema() result(s)
    type(deck_schema_t) :: s
    real(wp), parameter :: zero = 0.0_wp
    type(param_schema_t) :: p
    allocate (s%groups(0))

    call add_group(s, 'simulation', .false., 'the run: duration, gravity, running speed, start', [ &
      pstr('title', 'free text stored with the results', default=''), &
      preal('t_end', 's', 'simulated time', required=.true., min=zero, min_open=.true.), &
      preal('gravity', 'm/s2', 'gravitational acceleration', default=standard_gravity, &
            min=zero, max=100.0_wp), &
      preal('speed', 'm/s', 'constant running speed along the track', default=zero, min=zero, &
            cond='not together with speed_times'), &
      parray('speed_times', 's', 'times of the piecewise-linear speed law', 0, increasing=.true., &
             cond='strictly increasing; same length as speed_values'), &
      parray('speed_values', 'm/s', 'speeds of the piecewise-linear speed law', 0, &
             cond='same length as speed_times; each >= 0'), &
      preal('start_sigma', 'm', 'track position of the vehicle reference at t = 0', default=zero), &
      pstr('equilibrium', 'initial static equilibrium (docs/theory.md section 7): preload = ' // &
           'suspension preloads on level track, then (with wheelsets) a static solve; solve = static solve ' // &
           'only; none = the deck''s configuration. The solve holds the wheelsets'' lateral ' // &
           'position and spin (no creep forces at rest), so a scene may start in a canted curve', &
           default='preload', allowed='preload|solve|none'), &
      preal('max_wheel_lift', 'm', 'wheel lift-off beyond this stops the run', default=0.005_wp, &
            min=zero, max=1.0_wp, min_open=.true., max_open=.true.)])

    call add_group(s, 'solver', .false., 'time integration', [ &
      pstr('method', 'integrator (bdf, adams: CVODE; erk: ARKODE explicit; rk4: fixed step)', &
           default='bdf', allowed='bdf|adams|erk|rk4'), &
      only_with(preal('rtol', '-', 'relative tolerance', default=1.0e-6_wp, min=zero, max=1.0_wp, &
                      min_open=.true., max_open=.true.), 'method', 'bdf|adams|erk'), &
      only_with(preal('atol', '-', 'absolute tolerance (state units)', default=1.0e-8_wp, min=zero, &
                      min_open=.true.), 'method', 'bdf|adams|erk'), &
      only_with(preal('atol_velocity', '-', 'absolute tolerance of the velocity states (m/s, rad/s); ' // &
                      'not given: atol (docs/theory_solver.md "Tolerances")', min=zero, min_open=.true.), &
                'method', 'bdf|adams|erk'), &
      only_with(preal('max_step', 's', 'largest step; 0 = unlimited', default=zero, min=zero), &
                'method', 'bdf|adams|erk'), &
      only_with(preal('min_step', 's', 'smallest step', default=zero, min=zero), 'method', 'bdf|adams|erk'), &
      only_with(preal('initial_step', 's', 'first step; 0 = automatic', default=zero, min=zero), &
                'method', 'bdf|adams|erk'), &
      pint('max_num_steps', '-', 'steps allowed between two outputs', 100000, min=1), &
      only_with(preal('fixed_step', 's', 'step of the fixed-step rk4 method', default=1.0e-4_wp, min=zero, &
                      min_open=.true.), 'method', 'rk4'), &
      only_with(pint('max_order', '-', 'largest method order; 0 = method default (bdf: at most 5, ' // &
                     'checked when the scene is built; adams: at most 12)', 0, min=0, max=12), &
                'method', 'bdf|adams'), &
      only_with(pint('jacobian_max_age', '-', 'most steps between two evaluations of the Jacobian of ' // &
                     "bdf's Newton matrix (CVODE's default 51); CVODE evaluates it sooner where Newton " // &
                     'fails to converge: an older one costs Newton iterations and changes the step ' // &
                     'sizes, not the tolerances (docs/theory_solver.md "Jacobian age")', 51, min=1), &
                'method', 'bdf'), &
      only_with(pstr('jacobian', 'Newton-matrix Jacobian of bdf: difference quotients grouping bodies ' // &
                     'that share no force element (coloured) or one state at a time (dense, CVODE)', &
                     default='coloured', allowed='coloured|dense'), 'method', 'bdf')])

    p = pstr('file', 'results file (HDF5), relative to the deck unless absolute; not given: ' // &
             'the deck stem + .h5 in the working directory (raildyn run -o overrides both)')
    p = path_param(p, .false.)
    p%default_kind = DEF_DECK_STEM; p%default_strings = single_string('.h5')
    call add_group(s, 'output', .false., 'results file and output rate', [ &
      p, &
      preal('interval', 's', 'output interval', default=0.01_wp, min=zero, min_open=.true.), &
      pint('mean_samples', '-', 'records as interval means: 0 = the state at each output time; ' // &
           'N >= 1 = each record after the first is the mean over the preceding interval ' // &
           '(trapezoid rule on N sub-intervals: anti-aliasing of motions faster than the output rate)', &
           0, min=0, max=10000), &
      pint('flush_every', '-', 'output steps between flushes of the file', 50, min=1), &
      pstrlist('groups', 'channel groups written to the results file (docs/output.md): vehicle ' // &
               '(speed, distance), track (track frames), bodies, elements, wheelsets (summary, ' // &
               'rail offsets, wheel resultants), patches (contact patch slots), state (integrator ' // &
               'state, needed by raildyn run --restart), sensors (&sensor points); the C API ' // &
               'sees every channel', &
               'vehicle|track|bodies|elements|wheelsets|patches|state|sensors', &
               default='vehicle|track|bodies|elements|wheelsets|patches|state|sensors'), &
      pstr('progress', 'progress line of raildyn run on stderr: auto = when stderr is a terminal, ' // &
           'on = always, off = never (raildyn run --progress and --quiet override it)', default='auto', &
           allowed='auto|on|off')])

    call add_group(s, 'track', .false., 'track layout and rail geometry', [ &
      preal('gauge', 'm', 'track gauge', default=1.435_wp, min=0.5_wp, max=2.0_wp, min_open=.true.), &
      preal('cant_base', 'm', 'distance between the rail contact points used for cant', &
            default=1.5_wp, min=0.5_wp, max=2.5_wp), &
      preal('rail_inclination', '-', 'tangent of the rail cant (1:40 = 0.025)', default=0.025_wp, &
            min=zero, max=0.1_wp), &
      path_param(pstr('survey_file', 'track survey points instead of &segment groups', &
                      cond='no &segment allowed when given'), .true.), &
      path_param(pstr('irregularity_file', 'track irregularities: text columns sigma alignment level ' // &
                      'cross_level gauge [m] (signs: docs/conventions.md)'), .true.), &
      only_with(preal('irregularity_scale', '-', 'factor on every irregularity offset', default=1.0_wp, &
                      min=zero), 'irregularity_file', '(given)'), &
      only_with(preal('irregularity_fade', 'm', 'length of the linear fade-in after the first and ' // &
                      'fade-out before the last irregularity point', default=zero, min=zero), &
                'irregularity_file', '(given)'), &
      only_with(preal('start_heading', 'rad', 'heading of the track at sigma = 0 (a survey file''s ' // &
                      'points place the track themselves)', default=zero), 'survey_file', '(not given)'), &
      only_with(vec3('start_position', 'm', 'fixed-frame position of the track at sigma = 0'), &
                'survey_file', '(not given)')])

    call add_group(s, 'segment', .true., 'one piece of track layout, in running order', [ &
      pstr('type', 'segment kind', required=.true., allowed='straight|clothoid|curve'), &
      preal('length', 'm', 'length along the horizontal projection', required=.true., min=zero, &
            min_open=.true.), &
      preal('radius', 'm', 'curve radius; for a clothoid the radius at its end (the bound lies ' // &
            'below the tightest tramway curves, about 15 m, and well above the lateral offsets of ' // &
            'bodies and contact points in the track frames, which the track-frame kinematics ' // &
            'divide by; radius = 1e-300 gave NaN accelerations)', min=10.0_wp, &
            cond='required for curve; clothoid without it ends straight'), &
      pstr('side', 'side towards which the track curves', allowed='left|right', &
           cond='required with radius'), &
      preal('cant', 'm', 'superelevation of the outer rail at the segment end', default=zero, &
            min=-0.2_wp, max=0.3_wp, &
            cond='for a curve the default is the previous segment''s end cant'), &
      only_with(pstr('cant_ramp', 'shape of the cant transition along the segment (only a clothoid ' // &
                     'ramps the cant)', default='linear', allowed='linear|cosine'), 'type', 'clothoid'), &
      preal('gradient', '-', 'longitudinal gradient at the segment end', default=zero, &
            min=-0.1_wp, max=0.1_wp, previous=.true., &
            cond='not given: the previous segment''s end gradient')])

    call add_group(s, 'body', .true., 'a rigid body with 6 degrees of freedom in a track frame', [ &
      unique_name('unique body name'), &
      preal('mass', 'kg', 'mass', required=.true., min=zero, min_open=.true.), &
      preal('ixx', 'kg m2', 'roll moment of inertia about the CG', required=.true., min=zero, &
            min_open=.true.), &
      preal('iyy', 'kg m2', 'pitch moment of inertia about the CG', required=.true., min=zero, &
            min_open=.true.), &
      preal('izz', 'kg m2', 'yaw moment of inertia about the CG', required=.true., min=zero, &
            min_open=.true.), &
      preal('ixy', 'kg m2', 'product of inertia', default=zero), &
      preal('ixz', 'kg m2', 'product of inertia', default=zero), &
      preal('iyz', 'kg m2', 'product of inertia', default=zero), &
      vec3('position', 'm', 'initial CG position x y z in its track frame'), &
      vec3('orientation', 'rad', 'initial yaw roll pitch'), &
      vec3('velocity', 'm/s', 'initial CG velocity relative to its track frame'), &
      vec3('angular_rate', 'rad/s', 'initial yaw roll pitch rates'), &
      ref_param(pstr('frame', 'track frame: own, or the name of a body whose frame it shares', &
                     default='own'), 'body', 'own'), &
      only_with(preal('frame_offset', 'm', 'own frame at sigma_vehicle + frame_offset (a body sharing ' // &
                      'another''s frame has that body''s offset)', default=zero), 'frame', 'own'), &
      pstrlist('frozen', 'coordinates held at their initial value', 'x|y|z|yaw|roll|pitch')])

    call add_group(s, 'wheelset', .true., 'wheel-rail contact of a wheelset body', [ &
      unique_name('unique wheelset name'), &
      ref_param(pstr('body', 'the body that is the wheelset', required=.true.), 'body'), &
      ref_param(pstr('left_rail_body', 'flexible track: the body that is the left rail (same ' // &
                     'frame offset as the wheelset, x yaw roll pitch frozen, on pad elements; ' // &
                     'none = rigid rail)', default='none'), 'body', 'none'), &
      ref_param(pstr('right_rail_body', 'flexible track: the body that is the right rail (as ' // &
                     'left_rail_body)', default='none'), 'body', 'none'), &
      pstr('contact', 'contact model', default='profile', allowed='knife_edge|profile'), &
      pstr('normal_contact', 'wheelset height and roll: elastic (integrated on the Hertz springs) or ' // &
           'quasi_static (solved from their force balance at every evaluation; docs/theory.md)', &
           default='elastic', allowed='elastic|quasi_static'), &
      only_with(pstr('contact_geometry', 'profile contact geometry: the strip search online, or pre-computed ' // &
             'tables of it (docs/theory_contact_geometry.md section 10)', default='strips', allowed='strips|table'), &
                'contact', 'profile'), &
      only_with(study_options(pstr('strip_normal_force', 'online strips: the normal force: distributed (every ' // &
             'penetrating strip pushes along its own depth gradient with a stiffness that reproduces Hertz ' // &
             'on Hertzian gaps: a conservative, smooth force field; the patches take their loads from their ' // &
             'strips and CONTACT''s reference point; docs/theory_flange_chatter.md section 14), centroid ' // &
             '(per patch: the refined peak penetration along the rail normal at the centroid of the ' // &
             'virtual-penetration region; not conservative where the contact jumps; the default before ' // &
             'the distributed force, kept to compare with earlier results) or potential (per ' // &
             'patch: an effective penetration and its gradient; experimental: several times the CPU; its ' // &
             'direction can leave the surface normals at conformal flange contact (not for derailment ' // &
             'studies); section 13); centroid and potential are study options, not fidelity levels ' // &
             '(docs/performance.md "Which fidelity level for what")', default='distributed', &
             allowed='distributed|centroid|potential'), 'centroid|potential', &
             'for comparisons with earlier results and studies of the flange contact; centroid is not ' // &
             'conservative where the contact jumps, potential can point outside the surface normals at ' // &
             'conformal flange contact (docs/performance.md "Which fidelity level for what")'), &
                'contact_geometry', 'strips'), &
      only_with(preal('table_shift_step', 'm', 'contact tables: node spacing in the lateral shift (the build ' // &
              'time grows as 1/step: about 1-4 s at 1e-4)', default=1.0e-4_wp, &
              min=2.0e-5_wp, max=1.0e-3_wp), 'contact_geometry', 'table'), &
      only_with(preal('strip_spacing', 'm', 'arc-length spacing of the resampled wheel points and rail ' // &
              'lines (strips) of the profile contact, also of the strips a contact table tabulates ' // &
              '(docs/theory_contact_geometry.md section 2; the strip search costs about 1/spacing; analytic ' // &
              'profiles are sampled at min(0.2 mm, spacing))', default=2.0e-4_wp, &
              min=5.0e-5_wp, max=1.0e-3_wp), 'contact', 'profile'), &
      only_with(path_param(pstr('wheel_profile', 'wheel profile file or analytic keyword', &
                        cond='required for profile contact'), .true., 's1002|60e1|54e1'), 'contact', 'profile'), &
      only_with(path_param(pstr('rail_profile', 'rail profile file or analytic keyword', &
                        cond='required for profile contact'), .true., 's1002|60e1|54e1'), 'contact', 'profile'), &
      only_with(path_param(pstr('wheel_profile_right', 'right wheel profile file or analytic keyword, in the ' // &
                        'same profile frame as a left one (docs/conventions.md Profiles)', &
                        cond='profile contact; default: wheel_profile'), .true., 's1002|60e1|54e1'), 'contact', 'profile'), &
      only_with(path_param(pstr('rail_profile_right', 'right rail profile file or analytic keyword, in the ' // &
                        'same profile frame as a left one (docs/conventions.md Profiles)', &
                        cond='profile contact; default: rail_profile'), .true., 's1002|60e1|54e1'), 'contact', 'profile'), &
      preal('nominal_radius', 'm', 'wheel radius at the tape circle, where the wheel profile''s ' // &
            'radius increase F(s) is 0 (profile contact: places the wheel profile; knife edge: the ' // &
            'cone radius at the contact point)', default=0.46_wp, min=0.2_wp, &
            max=0.7_wp, min_open=.true., max_open=.true.), &
      preal('reference_radius', 'm', 'reference rolling radius r0: the wheelset starts rolling at ' // &
            'the spin V / r0, and its pitch outputs are the deviation from it (docs/conventions.md)', &
            min=0.2_wp, max=0.7_wp, min_open=.true., max_open=.true., &
            cond='default: profile contact: the centred rolling radius of the profiles, the mean ' // &
            'of the left and right rolling radii at y = 0 and zero yaw (as raildyn profile-scan); ' // &
            'knife edge: nominal_radius; raildyn check prints it'), &
      only_with(preal('contact_distance', 'm', 'distance between nominal contact points (knife edge)', &
              default=1.5_wp, min=0.4_wp, max=3.0_wp, min_open=.true., max_open=.true.), 'contact', 'knife_edge'), &
      only_with(preal('conicity', '-', 'cone slope of the knife-edge wheels', default=0.05_wp, min=zero, &
              max=1.0_wp, max_open=.true.), 'contact', 'knife_edge'), &
      only_with(preal('back_to_back', 'm', 'distance between the wheel inner faces', default=1.360_wp, &
              min=0.5_wp, max=2.0_wp, min_open=.true., max_open=.true., cond='the wheels must ' // &
              'meet the rails, checked when the scene is built: S1002 on 60E1 at gauge 1.435 m ' // &
              'needs about 1.2 to 1.42 m'), 'contact', 'profile'), &
      only_with(preal('flange_back', 'm', 'lateral position of the flange back in the profile frame', &
              default=-0.070_wp), 'contact', 'profile'), &
      pstr('creep_law', 'tangential contact law', default='fastsim', &
           allowed='linear|fastsim|polach'), &
      plog('spin_creep', 'spin creepage enters the creep law (.false.: creep forces from xi and eta ' // &
           'only, as the thesis 5.5-5.6 comparison; the spin is still computed and written)', .true.), &
      only_with(pstr('creep_saturation', 'saturation of the linear law', default='none', &
             allowed='none|shen_hedrick_elkins'), 'creep_law', 'linear'), &
      preal('friction', '-', 'wheel-rail friction coefficient', default=0.3_wp, min=zero, &
            max=1.0_wp, cond='read by fastsim, polach and a saturated linear law; not with ' // &
            'creep_law = linear and creep_saturation = none'), &
      preal('shear_modulus', 'Pa', 'combined shear modulus (the bound keeps E = 2 G (1 + poisson) ' // &
            'below the 1e15 Pa Hertz limit; steel: 8.2e10)', default=82.0e9_wp, min=zero, max=1.0e14_wp, &
            min_open=.true., max_open=.true.), &
      preal('poisson', '-', 'Poisson ratio', default=0.28_wp, min=zero, max=0.5_wp, &
            max_open=.true.), &
      only_with(pint('fastsim_grid', '-', 'FASTSIM strips and elements per strip', 10, min=2, max=200), 'creep_law', 'fastsim'), &
      only_with(pstr('fastsim_bound', 'FASTSIM traction bound', default='parabolic', &
             allowed='parabolic|elliptic'), 'creep_law', 'fastsim'), &
      only_with(preal('fastsim_saturation_width', '-', 'FASTSIM: width w of the smooth clip of each ' // &
              'element''s traction onto the bound (0 = Kalker''s sharp clip; docs/theory_contact_mechanics.md)', &
              default=0.2_wp, min=zero, max=0.5_wp), 'creep_law', 'fastsim'), &
      only_with(preal('polach_ka', '-', 'Polach reduction in the adhesion area', default=1.0_wp, min=zero, &
              max=1.0_wp, min_open=.true.), 'creep_law', 'polach'), &
      only_with(preal('polach_ks', '-', 'Polach reduction in the slip area', default=1.0_wp, min=zero, &
              max=1.0_wp, min_open=.true.), 'creep_law', 'polach'), &
      preal('creep_velocity_min', 'm/s', 'regularisation of the creepage reference velocity', &
            default=0.05_wp, min=zero, max=100.0_wp, min_open=.true., max_open=.true.), &
      preal('contact_damping', 'N s/m', 'normal contact damping', default=zero, min=zero, &
            max=1.0e12_wp, max_open=.true.), &
      pstr('hertz_method', 'Hertz ellipse coefficients', default='elliptic_table', &
           allowed='elliptic|elliptic_table|table'), &
      only_with(preal('rail_precant', '-', 'inclination already contained in the rail profile file (tan)', &
              default=zero, min=zero, max=0.1_wp), 'contact', 'profile'), &
      only_with(preal('rail_precant_right', '-', 'inclination already contained in the right rail profile ' // &
              'file (tan)', min=zero, max=0.1_wp, cond='default: rail_precant'), 'contact', 'profile'), &
      only_with(preal('rail_crown_radius', 'm', 'rail head radius seen by Hertz (knife edge)', &
              default=0.3_wp, min=zero, min_open=.true.), 'contact', 'knife_edge'), &
      only_with(preal('flange_clearance', 'm', 'lateral free play to the flange stop (knife edge; 0 = no stop)', &
              default=zero, min=zero), 'contact', 'knife_edge'), &
      only_with(preal('flange_stiffness', 'N/m', 'lateral stiffness of the flange stop (knife edge)', &
              default=zero, min=zero, max=1.0e15_wp, max_open=.true., &
              cond='> 0 when flange_clearance > 0'), 'contact', 'knife_edge'), &
      only_with(preal('polach_friction_ratio', '-', 'Polach 2005: mu_inf / mu_0 (1 = no decay)', &
              default=1.0_wp, min=zero, max=1.0_wp, min_open=.true.), 'creep_law', 'polach'), &
      only_with(preal('polach_friction_decay', 's/m', 'Polach 2005: B in mu = mu0((1-A) exp(-B w) + A)', &
              default=zero, min=zero), 'creep_law', 'polach')])

    call add_group(s, 'element', .true., 'a suspension force element between two bodies', [ &
      unique_name('unique element name'), &
      pstr('type', 'element kind', required=.true., &
           allowed='spring_damper|torsion|table|series_spring_damper'), &
      ref_param(pstr('body1', 'body the element acts from, or ground (the track frame)', &
                     default='ground'), 'body', 'ground'), &
      ref_param(pstr('body2', 'body the element acts on', required=.true.), 'body'), &
      only_with(vec3('point1', 'm', 'attachment in body1''s frame (track frame for ground); a ' // &
                     'torsion element is a pure couple and has none'), 'type', &
                'spring_damper|table|series_spring_damper'), &
      only_with(vec3('point2', 'm', 'attachment in body2''s frame'), 'type', &
                'spring_damper|table|series_spring_damper'), &
      only_with(vec3('axes', 'rad', 'yaw roll pitch of the element axes relative to body1 / track ' // &
                     'frame (a series spring-damper acts along the line joining its points)'), 'type', &
                'spring_damper|torsion|table'), &
      only_with(vec3('stiffness', 'N/m', 'stiffness along the element axes'), 'type', 'spring_damper'), &
      only_with(parray('damping', 'N s/m', 'viscous damping along the element axes', 3, &
                       [zero, zero, zero], cond='table: ' // &
                     'only the table_axis component, the others 0; series_spring_damper: along ' // &
                     'the line, damping(1) > 0, the others 0'), 'type', &
                'spring_damper|table|series_spring_damper'), &
      only_with(vec3('preload', 'N', 'force at zero deflection along the element axes'), 'type', 'spring_damper'), &
      only_with(vec3('actuator_force', 'N', 'constant actuator force along the element axes'), 'type', &
                'spring_damper'), &
      only_with(vec3('torsion_stiffness', 'N m/rad', 'rotational stiffness about the element axes'), &
                'type', 'torsion'), &
      only_with(vec3('torsion_damping', 'N m s/rad', 'rotational damping about the element axes'), &
                'type', 'torsion'), &
      only_with(pstr('table_axis', 'axis of the force-deflection table', allowed='x|y|z', &
                     cond='required for table'), 'type', 'table'), &
      only_with(parray('table_deflection', 'm', 'deflections of the table', 0, increasing=.true., &
                       cond='required for table; strictly increasing'), 'type', 'table'), &
      only_with(parray('table_force', 'N', 'forces of the table', 0, &
                       cond='required for table; same length as table_deflection'), 'type', 'table'), &
      only_with(preal('clearance', 'm', 'free play before the element engages', default=zero, min=zero), &
                'type', 'table'), &
      only_with(preal('series_stiffness', 'N/m', 'stiffness in series with the damper', min=zero, &
                      min_open=.true., cond='required for series_spring_damper'), 'type', &
                'series_spring_damper')])

    call add_group(s, 'external_force', .true., 'a prescribed force and moment on a body', [ &
      ref_param(pstr('body', 'body loaded', required=.true.), 'body'), &
      pstr('frame', 'frame of the components', default='fixed', allowed='fixed|track|body'), &
      vec3('force', 'N', 'force at the CG'), &
      vec3('moment', 'N m', 'moment'), &
      preal('t_start', 's', 'start of the load', default=zero), &
      preal('t_end', 's', 'end of the load', default=huge(1.0_wp), cond='> t_start')])

    p = parray('position', 'm', 'the point in the body frame (x forward, y left, z up, from ' // &
               'the CG; on a wheelset in its non-spinning axle-box frame)', 3)
    p%default_kind = DEF_REQUIRED
    call add_group(s, 'sensor', .true., 'a measurement point on a body: its position, absolute ' // &
      'velocity and acceleration in the track and body frames (docs/output.md /sensors)', [ &
      unique_name('unique sensor name (the results group /sensors/<name>)'), &
      ref_param(pstr('body', 'the body carrying the point', required=.true.), 'body'), &
      p])

    call add_group(s, 'include', .true., 'insert another deck here (its paths relative to it)', [ &
      path_param(pstr('file', 'deck to insert', required=.true.), .true.)])
  end function build_deck_schema

  ! ---------------------------------------------------------------------
  ! Look-ups.
  ! ---------------------------------------------------------------------
  pure integer function find_group(s, name)
    type(deck_schema_t), intent(in) :: s
    character(len=*), intent(in) :: name
    integer :: i
    find_group = 0
    if (.not. allocated(s%groups)) return
    do i = 1, size(s%groups)
      if (s%groups(i)%name == to_lower(name)) then
        find_group = i; return
      end if
    end do
  end function find_group

  pure integer function find_param(g, name)
    type(group_schema_t), intent(in) :: g
    character(len=*), intent(in) :: name
    integer :: i
    find_param = 0
    do i = 1, size(g%params)
      if (g%params(i)%name == to_lower(name)) then
        find_param = i; return
      end if
    end do
  end function find_param

  !> The closest candidate within a small edit distance, or '' (for "did you mean").
  function suggest_name(word, candidates) result(best)
    character(len=*), intent(in) :: word
    type(deck_string_t), intent(in) :: candidates(:)
    character(len=:), allocatable :: best
    integer :: i, d, dbest
    best = ''
    dbest = max(2, len(word) / 3) + 1
    do i = 1, size(candidates)
      d = edit_distance(word, candidates(i)%s)
      if (d < dbest) then
        dbest = d; best = candidates(i)%s
      end if
    end do
  end function suggest_name

  ! ---------------------------------------------------------------------
  ! Text for messages and the reference tables.
  ! ---------------------------------------------------------------------
  function type_text(p) result(t)
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: t
    select case (p%ptype)
    case (PT_REAL); t = 'real'
    case (PT_INTEGER); t = 'integer'
    case (PT_LOGICAL); t = 'logical'
    case (PT_STRING)
      t = 'string'
      if (p%is_path) t = 'path'
      if (len(p%ref_group) > 0) t = 'name of a &' // p%ref_group
    case (PT_REAL_ARRAY)
      if (p%size > 0) then
        t = 'real(' // int_to_str(p%size) // ')'
      else
        t = 'real list'
      end if
    case (PT_STRING_LIST); t = 'string list'
    case default; t = '?'
    end select
  end function type_text

  function default_text(p) result(t)
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: t
    integer :: i
    select case (p%default_kind)
    case (DEF_REQUIRED); t = 'required'
    case (DEF_OPTIONAL); t = 'none'
    case (DEF_DECK_STEM); t = 'deck stem + ' // p%default_strings(1)%s
    case default
      select case (p%ptype)
      case (PT_REAL, PT_REAL_ARRAY)
        t = ''
        do i = 1, size(p%default_reals)
          if (i > 1) t = t // ' '
          t = t // real_to_str(p%default_reals(i))
        end do
        if (size(p%default_reals) == 0) t = 'empty'
      case (PT_INTEGER); t = int_to_str(p%default_integer)
      case (PT_LOGICAL); t = merge('.true. ', '.false.', p%default_logical)
        t = trim(t)
      case (PT_STRING); t = "'" // p%default_strings(1)%s // "'"
      case (PT_STRING_LIST)
        t = joined(p%default_strings, '')
        if (size(p%default_strings) == 0) t = 'empty'
      end select
      if (p%default_kind == DEF_PREVIOUS) t = 'previous, first ' // t
    end select
  end function default_text

  !> "[0, 100]", "(0, 1)", "> 0", ">= 0", "one of: bdf, adams" or "".
  function range_text(p) result(t)
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: t
    t = ''
    if (size(p%allowed) > 0) then
      t = 'one of: '
      if (p%ptype == PT_STRING_LIST) t = 'any of: '
      t = t // joined(p%allowed, '')
      if (len(p%ref_group) > 0 .or. size(p%ref_keywords) > 0) return
    end if
    if (size(p%ref_keywords) > 0) then
      t = 'a &' // p%ref_group // ' name or: ' // joined(p%ref_keywords, '')
      return
    end if
    if (size(p%path_keywords) > 0) then
      t = 'a file or one of: ' // joined(p%path_keywords, '')
      return
    end if
    if (p%has_min .and. p%has_max) then
      t = merge('(', '[', p%min_open) // real_to_str(p%min) // ', ' // real_to_str(p%max) // &
          merge(')', ']', p%max_open)
    else if (p%has_min) then
      t = merge('> ', '>=', p%min_open)
      t = trim(t) // ' ' // real_to_str(p%min)
    else if (p%has_max) then
      t = merge('< ', '<=', p%max_open)
      t = trim(t) // ' ' // real_to_str(p%max)
    end if
  end function range_text

  !> Where a parameter is read, for messages and the reference: "type = spring_damper,
  !> table or series_spring_damper", "with irregularity_file", "without survey_file";
  !> '' for a parameter every kind of its group reads.
  function used_text(p) result(t)
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: t
    integer :: i, n
    t = ''
    n = size(p%used_values)
    if (len(p%used_with) == 0 .or. n == 0) return
    if (p%used_values(1)%s == '(given)') then
      t = 'with ' // p%used_with
    else if (p%used_values(1)%s == '(not given)') then
      t = 'without ' // p%used_with
    else
      t = 'with ' // p%used_with // ' = '
      do i = 1, n
        if (i > 1 .and. i < n) t = t // ', '
        if (i > 1 .and. i == n) t = t // ' or '
        t = t // p%used_values(i)%s
      end do
    end if
  end function used_text

  !> The reference tables of docs/input_reference.md, one per group.
  subroutine write_schema_markdown(unit)
    integer, intent(in) :: unit
    type(deck_schema_t) :: s
    integer :: i, j
    character(len=:), allocatable :: notes, flags
    s = build_deck_schema()
    do i = 1, size(s%groups)
      associate (g => s%groups(i))
        write (unit, '(a)') '### &' // g%name
        write (unit, '(a)') ''
        notes = g%meaning
        notes(1:1) = achar(iachar(notes(1:1)) - 32)   ! sentence case (meanings start lower case)
        write (unit, '(a)') notes // trim(merge(' (repeatable)  ', ' (at most once)', g%repeatable)) &
                            // '.'
        write (unit, '(a)') ''
        write (unit, '(a)') '| parameter | type | unit | default | valid | meaning |'
        write (unit, '(a)') '|---|---|---|---|---|---|'
        do j = 1, size(g%params)
          associate (p => g%params(j))
            notes = p%meaning
            flags = ''
            if (p%unique) flags = flags // '; unique'
            if (p%must_exist) flags = flags // '; the file must exist'
            if (len(p%condition) > 0) notes = notes // ' (' // p%condition // ')'
            if (len(used_text(p)) > 0) flags = flags // '; read only ' // used_text(p)
            if (len(flags) > 0) notes = notes // ' [' // flags(3:) // ']'
            write (unit, '(a)') '| `' // p%name // '` | ' // type_text(p) // ' | ' // p%unit // &
              ' | ' // default_text(p) // ' | ' // range_text(p) // ' | ' // notes // ' |'
          end associate
        end do
        write (unit, '(a)') ''
      end associate
    end do
  end subroutine write_schema_markdown
end module rd_deck_schema
