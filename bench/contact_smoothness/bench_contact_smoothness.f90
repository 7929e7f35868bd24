!> Smoothness of the wheel-rail forces (issue "smooth wheel-rail forces", item 1): where the
!> outputs of the public contact pipeline (wheelset_contact_t%evaluate) and of the creep
!> laws (rd_creep_factory) jump or kink along fine sweeps of the state, per fidelity level.
!>
!> Pose sweeps (S1002 / 60E1 1:40, gauge 1.435 m, the Manchester wheelset defaults of
!> wheelset_contact_spec_t), each with `npoints` samples:
!> - lateral shift y = 0..8 mm at yaw 15 mrad (the leading wheelset of the Manchester curve)
!>   and at yaw 0, on two paths: at the wheel load (z, roll solved at each y for Q = Q0 on
!>   both wheels, Newton continued from the previous sample; the sweep ends where that
!>   fails) and at a fixed approach (rigid contact of rd_rigid_contact at each y lowered by
!>   delta0, the approach that gives Q0 per wheel at y = 0, yaw 0, solved once, printed);
!> - vertical approach 0.5..1.5 delta0 and roll +-0.5 delta0 / 0.75 m (each wheel's approach
!>   then spans about 0.5..1.5 delta0) at y = 0, yaw 0 (tread) and y = 6.5 mm, yaw 15 mrad
!>   (flange).
!> The wheelset rolls forward at v with spin v / r0, no other velocity: the creepages come
!> from the pose (rolling radius difference, yaw).
!> Outputs per wheel (L, R): force on the wheel in track components (Fx, Y, Q), moment of
!> the wheel's patches about the wheelset centre (Mx, My, Mz), lateral contact position
!> (normal-force-weighted mean of the patches' rail points), total normal force N, creep
!> forces Tx, Ty and spin moment Msp (sums over patches, contact-frame components); and the
!> path's z and roll.
!>
!> Creepage sweeps through each creep law directly, for the patch of the centred wheelset
!> (a, b, N of the first level's left wheel at y = 0, yaw 0 at delta0): xi and eta over +-5e-3, spin
!> over +-4 1/m (others zero), and eta at spin 1.5 1/m (a flange patch's spin); and the patch
!> itself at xi = eta = 1e-3, spin 0.5 1/m: a/b from 0.2 to 5 at constant a b (uniform in
!> ln(a/b)), and N from 0.5 to 1.5 times its value with a, b scaled as N^(1/3) (Hertz).
!>
!> Jumps and kinks: rd_sweep_smoothness (find_jumps_and_kinks, ratio 20, window 10), with a
!> floor of 5e-8 of each output's scale (forces Q0, moments Q0 x 1 m, creep forces mu N,
!> spin moment mu N sqrt(a b), positions 1 mm): features smaller than 1e-6 of the scale are
!> not reported.
!>
!> Fidelity levels: one line each in `pose_levels` / `creep_levels` below ('label | key=value
!> ...', keys in `apply_setting`), more on the command line:
!>   bench_contact_smoothness [--points N] [--csv FILE] [--pose-level 'label | k=v ...']
!>                            [--creep-level 'label | k=v ...']
!> Prints markdown tables (run.sh writes them into docs/performance.md); --csv writes every
!> feature found (level, sweep, output, kind, x, size, relative size, prominence, width).
program bench_contact_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_text, only: real_text, sci_text, int_text
  use rd_rotation, only: cross
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_rigid_contact, only: rigid_contact
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_wheel_contact_result, only: wheel_result_t
  use rd_creep_law, only: creep_law_t, creep_patch_t, creep_force_t, creepage_t
  use rd_creep_factory, only: build_creep_law
  use rd_sweep_smoothness, only: smoothness_feature_t, find_jumps_and_kinks, FEATURE_JUMP, FEATURE_KINK
  implicit none

  !> Fidelity levels: 'label | key=value ...' applied to the default spec (apply_setting).
  !> A new level is one line here (or --pose-level / --creep-level on the command line).
  character(len=*), parameter :: pose_levels(*) = [character(len=160) :: &
    'strips 0.4 mm, FASTSIM 10x10 | rail_spacing=4e-4 creep_law=fastsim fastsim_grid=10', &
    'strips 0.2 mm, FASTSIM 10x10 sharp clip | rail_spacing=2e-4 creep_law=fastsim fastsim_grid=10', &
    'strips 0.1 mm, FASTSIM 10x10 | rail_spacing=1e-4 creep_law=fastsim fastsim_grid=10', &
    'strips 0.05 mm, FASTSIM 10x10 | rail_spacing=5e-5 creep_law=fastsim fastsim_grid=10', &
    'strips 0.2 mm, FASTSIM 5x5 | creep_law=fastsim fastsim_grid=5', &
    'strips 0.2 mm, FASTSIM 20x20 | creep_law=fastsim fastsim_grid=20', &
    'strips 0.2 mm, Polach | creep_law=polach', &
    'strips 0.2 mm, linear | creep_law=linear', &
    'strips 0.2 mm, FASTSIM 10x10, centroid normal force | creep_law=fastsim fastsim_grid=10 strip_normal_force=centroid', &
    'strips 0.2 mm, FASTSIM 10x10, potential normal force | creep_law=fastsim fastsim_grid=10 strip_normal_force=potential', &
    'tables of strips 0.2 mm, FASTSIM 10x10 | contact_geometry=table creep_law=fastsim fastsim_grid=10', &
    'strips 0.2 mm, FASTSIM 10x10 smooth clip 0.2 (deck defaults, acceptance deck) | creep_law=fastsim ' // &
    'fastsim_grid=10 ' // &
    'fastsim_saturation_width=0.2']
  character(len=*), parameter :: creep_levels(*) = [character(len=160) :: &
    'linear | creep_law=linear', &
    'linear + Shen-Hedrick-Elkins | creep_law=linear creep_saturation=shen_hedrick_elkins', &
    'FASTSIM 5x5 | creep_law=fastsim fastsim_grid=5', &
    'FASTSIM 10x10 | creep_law=fastsim fastsim_grid=10', &
    'FASTSIM 20x20 | creep_law=fastsim fastsim_grid=20', &
    'FASTSIM 10x10, elliptic bound | creep_law=fastsim fastsim_grid=10 fastsim_bound=elliptic', &
    'FASTSIM 10x10, smooth clip 0.2 | creep_law=fastsim fastsim_grid=10 fastsim_saturation_width=0.2', &
    'Polach | creep_law=polach']

  real(wp), parameter :: wheel_load = 55.0e3_wp   !< nominal vertical force per wheel Q0 [N]
  real(wp), parameter :: speed = 10.0_wp           !< forward speed [m/s]
  real(wp), parameter :: yaw_leading = 15.0e-3_wp  !< yaw of the leading wheelset [rad]
  real(wp), parameter :: y_flange = 6.5e-3_wp      !< lateral shift of the flange pose [m]
  real(wp), parameter :: half_track = 0.75_wp      !< lever of roll on a wheel's approach [m]
  real(wp), parameter :: ratio = 20.0_wp, relative_floor = 5.0e-8_wp
  !> counted apart as relevant: jumps of at least 0.1 % of the scale, kinks whose slope
  !> change times the sweep's range is at least 1 % of the scale
  real(wp), parameter :: relevant_jump = 1.0e-3_wp, relevant_kink = 1.0e-2_wp
  integer, parameter :: n_wheel_out = 11
  character(len=*), parameter :: wheel_out_names(n_wheel_out) = [character(len=4) :: &
    'Fx', 'Y', 'Q', 'Mx', 'My', 'Mz', 'y_c', 'N', 'Tx', 'Ty', 'Msp']
  character(len=*), parameter :: wheel_out_units(n_wheel_out) = [character(len=3) :: &
    'N', 'N', 'N', 'N m', 'N m', 'N m', 'm', 'N', 'N', 'N', 'N m']
  integer, parameter :: OUT_POSITION = 7
  integer, parameter :: n_pose_out = 2 * n_wheel_out + 2   !< + path z, roll
  integer, parameter :: n_creep_out = 3

  !> One sweep's samples and what they mean.
  type :: sweep_t
    character(len=90) :: name = ''
    character(len=8) :: x_unit = ''       !< unit of x as printed
    real(wp) :: x_print = 1               !< factor from SI x to the printed unit
    character(len=12) :: x_si_unit = ''   !< SI unit of x (for kink sizes)
    real(wp), allocatable :: x(:)
    real(wp), allocatable :: values(:, :) !< (sample, output)
    !> samples computed: a sweep ends early where the pipeline returns an error (a new
    !> fidelity option's limit, a derailment) or a wheel-load path finds no pose; why:
    integer :: n_valid = huge(1)
    character(len=:), allocatable :: end_reason
  end type sweep_t

  !> Per output: name, unit, scale (for relative sizes and the floor), is it a force-like
  !> output (forces, moments) or a position/path.
  type :: output_t
    character(len=12) :: name = ''
    character(len=4) :: unit = ''
    real(wp) :: scale = 1
    logical :: force_like = .true.
  end type output_t

  integer :: npoints = 4001
  character(len=:), allocatable :: csv_file
  character(len=240), allocatable :: extra_pose(:), extra_creep(:)
  character(len=240), allocatable :: all_pose(:), all_creep(:)
  type(wheelset_contact_spec_t) :: reference_spec
  type(creep_patch_t) :: patch
  real(wp) :: delta0, t_start, t_end
  integer :: csv_unit, k

  !> One feature of the detailed level, for the list of the largest.
  type :: listed_feature_t
    character(len=90) :: sweep = ''
    character(len=12) :: output = ''
    character(len=4) :: unit = ''
    character(len=12) :: x_si_unit = ''
    character(len=8) :: x_unit = ''
    real(wp) :: x_print = 1
    real(wp) :: step = 0                  !< the sweep's sample step [SI unit of x]
    type(smoothness_feature_t) :: feature
    real(wp) :: relative = 0
  end type listed_feature_t
  !> Index in pose_levels of the level listed feature by feature (the acceptance deck's model, the last).
  integer, parameter :: detail_level = 12
  integer, parameter :: n_listed = 12
  type(listed_feature_t), allocatable :: listed(:)

  call read_arguments()
  allocate (listed(0))
  all_pose = [character(len=240) :: pose_levels, extra_pose]
  all_creep = [character(len=240) :: creep_levels, extra_creep]
  csv_unit = 0
  if (allocated(csv_file)) then
    open (newunit=csv_unit, file=csv_file, status='replace', action='write')
    write (csv_unit, '(a)') 'level,sweep,output,kind,x,size,relative_size,prominence,width'
  end if
  call cpu_time(t_start)

  reference_spec = default_spec()
  call apply_level(reference_spec, all_pose(1))
  call static_approach(reference_spec, delta0, patch)

  write (*, '(a)') 'Jumps and kinks of the wheel-rail contact outputs along fine sweeps of the state '// &
    '(bench/contact_smoothness;'
  write (*, '(a)') 'detector rd_sweep_smoothness, ratio ' // trim(real_text(ratio)) // ', features below 1e-6 of the '// &
    'scale not reported).'
  write (*, '(a)') 'S1002 / 60E1 1:40, gauge 1.435 m, r0 0.46 m, mu 0.3, ' // trim(real_text(speed)) // ' m/s; ' // &
    trim(int_text(npoints)) // ' samples per sweep. Fixed approach delta0 = ' // trim(real_text(delta0 * 1.0e6_wp)) // &
    ' um below rigid contact'
  write (*, '(a)') '(Q = ' // trim(real_text(wheel_load / 1.0e3_wp)) // ' kN per wheel at y = 0, yaw 0, first level). '// &
    'Creep sweeps: patch a = ' // trim(real_text(patch%a * 1.0e3_wp)) // ' mm, b = ' // &
    trim(real_text(patch%b * 1.0e3_wp)) // ' mm, N = ' // trim(real_text(patch%normal_force / 1.0e3_wp)) // ' kN.'
  write (*, '(a)') 'Pose sweeps: the wheel-load path solves z and roll for Q = Q0 on both wheels at each y '// &
    '(it ends where no such pose is found);'
  write (*, '(a)') 'the fixed-approach path is rigid contact lowered by delta0. Approach and roll sweeps: '// &
    'one coordinate moves, the others fixed.'
  write (*, '(a)') 'Counts are distinct places (features of several outputs within 3 samples count once), '// &
    'in parentheses those'
  write (*, '(a)') 'that matter: jumps >= 0.1 % of the scale, kinks whose slope change times the sweep range is '// &
    '>= 1 % of the scale.'
  write (*, '(a)') 'Scales: forces Q0, moments Q0 x 1 m, creep forces mu N, spin moment mu N sqrt(ab). "Forces" = '// &
    'Fx, Y, Q (track frame), Mx, My, Mz'
  write (*, '(a)') '(about the wheelset centre), N, Tx, Ty, Msp (contact frame, summed over patches) of both '// &
    'wheels; the largest is given by its relative size.'
  write (*, '(a)') 'Contact point = normal-force-weighted lateral position of the patches (continuous where a '// &
    'patch appears at zero load; it jumps where a patch''s point or load jumps).'
  write (*, '(a)') 'Per-output details of every feature: bench_contact_smoothness --csv FILE.'

  call pose_sweeps()
  call creep_sweeps()

  call cpu_time(t_end)
  write (*, '(a)') ''
  write (*, '(a)') 'Whole bench: ' // trim(real_text(real(nint((t_end - t_start) * 10), wp) / 10)) // ' CPU s.'
  if (csv_unit /= 0) close (csv_unit)

contains

  !> ----------------------------------------------------------------------- levels
  function default_spec() result(spec)
    type(wheelset_contact_spec_t) :: spec
    spec%body = 1
    spec%wheel_profile = 's1002'
    spec%rail_profile = '60e1'
  end function default_spec

  !> Apply 'label | key=value key=value ...' to spec.
  subroutine apply_level(spec, level)
    type(wheelset_contact_spec_t), intent(inout) :: spec
    character(len=*), intent(in) :: level
    character(len=:), allocatable :: rest, item
    integer :: bar, sp, eq
    bar = index(level, '|')
    if (bar == 0) error stop 'bench_contact_smoothness: a level is ''label | key=value ...'', got: ' // trim(level)
    rest = trim(adjustl(level(bar + 1:)))
    do while (len(rest) > 0)
      sp = index(rest, ' ')
      if (sp == 0) sp = len(rest) + 1
      item = rest(1:sp - 1)
      rest = trim(adjustl(rest(min(sp, len(rest) + 1):)))
      eq = index(item, '=')
      if (eq < 2) error stop 'bench_contact_smoothness: expected key=value in level ''' // trim(level) // ''', got ' // item
      call apply_setting(spec, item(1:eq - 1), item(eq + 1:))
    end do
  end subroutine apply_level

  !> One fidelity setting of the spec (the deck's names where the deck has them).
  subroutine apply_setting(spec, key, value)
    type(wheelset_contact_spec_t), intent(inout) :: spec
    character(len=*), intent(in) :: key, value
    select case (key)
    case ('model'); spec%model = value
    case ('contact_geometry'); spec%contact_geometry = value
    case ('rail_spacing'); spec%surface%rail_spacing = real_setting(key, value)
    case ('wheel_spacing'); spec%surface%wheel_spacing = real_setting(key, value)
    case ('curvature_sigma'); spec%surface%curvature_sigma = real_setting(key, value)
    case ('creep_law'); spec%creep_law = value
    case ('fastsim_grid')
      spec%creep_options%grid_nx = nint(real_setting(key, value)); spec%creep_options%grid_ny = spec%creep_options%grid_nx
    case ('fastsim_bound'); spec%creep_options%bound = value
    case ('fastsim_saturation_width'); spec%creep_options%saturation_width = real_setting(key, value)
    case ('creep_saturation'); spec%creep_options%saturation = value
    case ('polach_ka'); spec%creep_options%polach_ka = real_setting(key, value)
    case ('polach_ks'); spec%creep_options%polach_ks = real_setting(key, value)
    case ('spin_creep'); spec%spin_creep = value == 'true' .or. value == '.true.'
    case ('hertz_method'); spec%hertz_method = value
    case ('strip_normal_force'); spec%strip_normal_force = value
    case ('friction'); spec%friction = real_setting(key, value)
    case default
      error stop 'bench_contact_smoothness: unknown level setting ''' // key // '''; expected model, ' // &
        'contact_geometry, rail_spacing, wheel_spacing, curvature_sigma, creep_law, fastsim_grid, fastsim_bound, fastsim_saturation_width, ' // &
        'strip_normal_force, ' // &
        'creep_saturation, polach_ka, ' // &
        'polach_ks, spin_creep, hertz_method or friction'
    end select
  end subroutine apply_setting

  real(wp) function real_setting(key, value) result(r)
    character(len=*), intent(in) :: key, value
    integer :: ios
    read (value, *, iostat=ios) r
    if (ios /= 0) error stop 'bench_contact_smoothness: level setting ' // key // ' expects a number, got ''' // value // ''''
  end function real_setting

  pure function level_label(level) result(label)
    character(len=*), intent(in) :: level
    character(len=:), allocatable :: label
    integer :: bar
    bar = index(level, '|')
    label = trim(adjustl(level(1:max(bar - 1, 0))))
  end function level_label

  subroutine read_arguments()
    integer :: i, n, ios
    character(len=:), allocatable :: arg, val
    allocate (extra_pose(0), extra_creep(0))
    n = command_argument_count()
    i = 1
    do while (i <= n)
      arg = argument(i)
      if (i == n .and. arg /= '') error stop 'bench_contact_smoothness: ' // arg // ' expects a value'
      val = argument(i + 1)
      select case (arg)
      case ('--points')
        read (val, *, iostat=ios) npoints
        if (ios /= 0 .or. npoints < 101) error stop 'bench_contact_smoothness: --points expects an integer >= 101'
      case ('--csv'); csv_file = val
      case ('--pose-level'); extra_pose = [character(len=240) :: extra_pose, val]
      case ('--creep-level'); extra_creep = [character(len=240) :: extra_creep, val]
      case default
        error stop 'bench_contact_smoothness: unknown argument ' // arg // &
          '; expected --points N, --csv FILE, --pose-level LEVEL, --creep-level LEVEL'
      end select
      i = i + 2
    end do
  end subroutine read_arguments

  !> command-line argument k ('' beyond the last)
  function argument(k) result(a)
    integer, intent(in) :: k
    character(len=:), allocatable :: a
    integer :: l
    if (k > command_argument_count()) then
      a = ''
      return
    end if
    call get_command_argument(k, length=l)
    allocate (character(len=l) :: a)
    call get_command_argument(k, a)
  end function argument

  !> ----------------------------------------------------------------------- pipeline
  !> The approach below rigid contact that gives the wheel load Q0 on the left wheel at
  !> y = 0, yaw 0 (bisection: Q grows with the approach), and that pose's left patch.
  subroutine static_approach(spec, delta, p)
    type(wheelset_contact_spec_t), intent(in) :: spec
    real(wp), intent(out) :: delta
    type(creep_patch_t), intent(out) :: p
    type(wheelset_contact_t) :: ws
    type(error_t), allocatable :: error
    real(wp) :: z, phi, lo, hi, out(n_pose_out)
    integer :: it
    call ws%build([spec], 1, error)
    if (allocated(error)) error stop error%message
    call rigid_contact(ws%models(1)%geo, 0.0_wp, 0.0_wp, z, phi, error)
    if (allocated(error)) error stop error%message
    lo = 0
    hi = 1.0e-3_wp
    do it = 1, 60
      delta = 0.5_wp * (lo + hi)
      call evaluate_pose(ws, 0.0_wp, z - delta, phi, 0.0_wp, out, error)
      if (allocated(error)) error stop 'bench_contact_smoothness: centred wheelset: ' // error%message
      if (out(3) > wheel_load) then
        hi = delta
      else
        lo = delta
      end if
    end do
    associate (pr => ws%results(1)%wheel(1)%patch(1))
      p%a = pr%a
      p%b = pr%b
      p%normal_force = pr%normal_force
    end associate
    p%shear_modulus = spec%shear_modulus
    p%poisson = spec%poisson
    p%friction = spec%friction
    p%rolling_speed = speed
  end subroutine static_approach

  !> Outputs at pose (y, z, roll, yaw), wheelset rolling forward at `speed`.
  subroutine evaluate_pose(ws, y, z, phi, psi, out, error)
    type(wheelset_contact_t), intent(inout) :: ws
    real(wp), intent(in) :: y, z, phi, psi
    real(wp), intent(out) :: out(n_pose_out)
    type(error_t), allocatable, intent(out) :: error
    type(track_point_t) :: tp
    type(body_kinematics_t) :: kin
    real(wp) :: f(3), m(3)
    integer :: side
    tp%a = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    tp%dr = [1.0_wp, 0.0_wp, 0.0_wp]
    call compute_body_kinematics(kin, tp, speed, 0.0_wp, [0.0_wp, y, z, psi, phi, 0.0_wp], &
                                 [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, speed / reference_spec%nominal_radius], .true.)
    out = 0
    call ws%evaluate(1, 0.0_wp, kin, f, m, error)
    if (allocated(error)) return
    do side = 1, 2
      out((side - 1) * n_wheel_out + 1:side * n_wheel_out) = wheel_outputs(ws%results(1)%wheel(side))
    end do
    out(n_pose_out - 1:n_pose_out) = [z, phi]
  end subroutine evaluate_pose

  !> Fx, Y, Q, Mx, My, Mz, y_c, N, Tx, Ty, Msp of one wheel (track frame = fixed frame here).
  pure function wheel_outputs(w) result(o)
    type(wheel_result_t), intent(in) :: w
    real(wp) :: o(n_wheel_out), moment(3), ny, nsum
    integer :: k
    moment = 0; ny = 0; nsum = 0
    o = 0
    do k = 1, w%n_patches
      associate (p => w%patch(k))
        moment = moment + cross(p%lever_fixed, p%force_fixed) + p%mz * p%normal_fixed
        ny = ny + p%normal_force * p%point_rail(2)
        nsum = nsum + p%normal_force
        o(9:11) = o(9:11) + [p%fx, p%fy, p%mz]
      end associate
    end do
    o(1:3) = w%force_track
    o(4:6) = moment
    if (nsum > 0) o(7) = ny / nsum
    o(8) = nsum
  end function wheel_outputs

  function pose_outputs() result(outs)
    type(output_t) :: outs(n_pose_out)
    integer :: side, j
    character(len=1), parameter :: side_letter(2) = ['L', 'R']
    do side = 1, 2
      do j = 1, n_wheel_out
        associate (o => outs((side - 1) * n_wheel_out + j))
          o%name = side_letter(side) // ' ' // trim(wheel_out_names(j))
          o%unit = wheel_out_units(j)
          o%scale = wheel_load
          if (o%unit == 'N m') o%scale = wheel_load * 1.0_wp
          o%force_like = j /= OUT_POSITION
          if (j == OUT_POSITION) o%scale = 1.0e-3_wp
        end associate
      end do
    end do
    outs(n_pose_out - 1) = output_t(name='path z', unit='m', scale=1.0e-3_wp, force_like=.false.)
    outs(n_pose_out) = output_t(name='path roll', unit='rad', scale=1.0e-3_wp, force_like=.false.)
  end function pose_outputs

  !> ----------------------------------------------------------------------- sweeps
  subroutine pose_sweeps()
    type(wheelset_contact_t) :: ws
    type(wheelset_contact_spec_t) :: spec
    type(error_t), allocatable :: error
    integer, parameter :: nsweep = 8
    type(sweep_t) :: sweeps(nsweep)
    type(output_t) :: outs(n_pose_out)
    real(wp) :: z0(2), phi0(2), t0, t1, cost(size(all_pose))
    character(len=400), allocatable :: ended(:)
    character(len=400), allocatable :: rows(:, :)
    integer :: lv, j, i, sw
    outs = pose_outputs()
    sweeps(1)%name = 'lateral shift at wheel load Q0, yaw 15 mrad'
    sweeps(2)%name = 'lateral shift at wheel load Q0, yaw 0'
    sweeps(3)%name = 'lateral shift at fixed approach, yaw 15 mrad'
    sweeps(4)%name = 'lateral shift at fixed approach, yaw 0'
    sweeps(5)%name = 'approach at y = 0, yaw 0'
    sweeps(6)%name = 'approach at y = 6.5 mm, yaw 15 mrad'
    sweeps(7)%name = 'roll at y = 0, yaw 0'
    sweeps(8)%name = 'roll at y = 6.5 mm, yaw 15 mrad'
    do sw = 1, nsweep
      allocate (sweeps(sw)%values(npoints, n_pose_out))
    end do
    sweeps(1:4)%x_unit = 'mm'; sweeps(1:4)%x_print = 1.0e3_wp; sweeps(1:4)%x_si_unit = 'm'
    sweeps(5:6)%x_unit = 'um'; sweeps(5:6)%x_print = 1.0e6_wp; sweeps(5:6)%x_si_unit = 'm'
    sweeps(7:8)%x_unit = 'mrad'; sweeps(7:8)%x_print = 1.0e3_wp; sweeps(7:8)%x_si_unit = 'rad'
    sweeps(1)%x = [(8.0e-3_wp * (i - 1) / (npoints - 1), i = 1, npoints)]
    do sw = 2, 4
      sweeps(sw)%x = sweeps(1)%x
    end do
    sweeps(5)%x = [(delta0 * (0.5_wp + real(i - 1, wp) / (npoints - 1)), i = 1, npoints)]
    sweeps(6)%x = sweeps(5)%x
    sweeps(7)%x = [(delta0 / half_track * (-0.5_wp + real(i - 1, wp) / (npoints - 1)), i = 1, npoints)]
    sweeps(8)%x = sweeps(7)%x
    allocate (rows(nsweep, size(all_pose)), ended(0))
    do lv = 1, size(all_pose)
      call cpu_time(t0)
      spec = default_spec()
      call apply_level(spec, all_pose(lv))
      call ws%build([spec], 1, error)
      if (allocated(error)) error stop 'bench_contact_smoothness: level ' // trim(all_pose(lv)) // ': ' // error%message
      ! rigid contact at the two poses of the approach and roll sweeps
      call rigid_contact(ws%models(1)%geo, 0.0_wp, 0.0_wp, z0(1), phi0(1), error)
      if (allocated(error)) error stop error%message
      call rigid_contact(ws%models(1)%geo, y_flange, yaw_leading, z0(2), phi0(2), error)
      if (allocated(error)) error stop error%message
      sweeps%n_valid = npoints
      do sw = 1, nsweep
        if (allocated(sweeps(sw)%end_reason)) deallocate (sweeps(sw)%end_reason)
      end do
      do i = 1, npoints
        call loaded_sample(ws, sweeps(1), i, yaw_leading)
        call loaded_sample(ws, sweeps(2), i, 0.0_wp)
        call lateral_sample(ws, sweeps(3), i, yaw_leading)
        call lateral_sample(ws, sweeps(4), i, 0.0_wp)
        call pose_sample(ws, sweeps(5), i, 0.0_wp, z0(1) - sweeps(5)%x(i), phi0(1), 0.0_wp)
        call pose_sample(ws, sweeps(6), i, y_flange, z0(2) - sweeps(6)%x(i), phi0(2), yaw_leading)
        call pose_sample(ws, sweeps(7), i, 0.0_wp, z0(1) - delta0, phi0(1) + sweeps(7)%x(i), 0.0_wp)
        call pose_sample(ws, sweeps(8), i, y_flange, z0(2) - delta0, phi0(2) + sweeps(8)%x(i), yaw_leading)
      end do
      do sw = 1, nsweep
        if (allocated(sweeps(sw)%end_reason)) ended = [character(len=400) :: ended, level_label(all_pose(lv)) // &
          ', ' // trim(sweeps(sw)%name) // ': after ' // trim(real_text(sweeps(sw)%x(max(sweeps(sw)%n_valid, 1)) * &
          sweeps(sw)%x_print)) // ' ' // trim(sweeps(sw)%x_unit) // ', ' // sweeps(sw)%end_reason]
      end do
      call cpu_time(t1)
      cost(lv) = t1 - t0
      do sw = 1, nsweep
        rows(sw, lv) = analyse(level_label(all_pose(lv)), sweeps(sw), outs, with_positions=.true., &
                               keep=lv == detail_level)
      end do
    end do
    do sw = 1, nsweep
      write (*, '(a)') ''
      write (*, '(a)') '#### Pose sweep: ' // trim(sweeps(sw)%name) // ' (x in ' // trim(sweeps(sw)%x_unit) // ')'
      write (*, '(a)') ''
      write (*, '(a)') '| level | force jumps | largest force jump | force kinks | largest force kink | '// &
        'contact-point jumps (largest) | path jumps / kinks |'
      write (*, '(a)') '|---|---|---|---|---|---|---|'
      do lv = 1, size(all_pose)
        write (*, '(a)') trim(rows(sw, lv))
      end do
    end do
    write (*, '(a)') ''
    if (size(ended) > 0) then
      write (*, '(a)') ''
      write (*, '(a)') 'Sweeps that ended early (the tables cover the samples before):'
      write (*, '(a)') ''
      do i = 1, size(ended)
        write (*, '(a)') '- ' // trim(ended(i))
      end do
    end if
    call print_largest(FEATURE_JUMP, 'jumps')
    call print_largest(FEATURE_KINK, 'kinks')
    write (*, '(a)') ''
    write (*, '(a)') 'CPU s per level (' // trim(int_text(nsweep)) // ' pose sweeps of ' // trim(int_text(npoints)) // &
      ' samples, the paths included): ' // trim(cost_list(cost, all_pose)) // '.'

  end subroutine pose_sweeps

  !> Sample i of a lateral sweep at the wheel load: (z, roll) with Q = Q0 on both wheels,
  !> Newton from the previous sample's (z, roll) (the first: rigid contact lowered by
  !> delta0) with a forward-difference Jacobian and steps of at most 20 um at a wheel, to
  !> |Q - Q0| < 1e-9 Q0. When 40 iterations do not get there (on a flange steeper than
  !> Nadal's limit for the creep force of the yaw no normal force gives Q0: Q = N (cos g -
  !> mu sin g) <= 0), or the pipeline returns an error, the sweep ends (end_sweep).
  subroutine loaded_sample(ws, s, i, psi)
    type(wheelset_contact_t), intent(inout) :: ws
    type(sweep_t), intent(inout) :: s
    integer, intent(in) :: i
    real(wp), intent(in) :: psi
    real(wp), parameter :: dz = 1.0e-9_wp, dphi = 1.0e-9_wp, tol = 1.0e-9_wp
    type(error_t), allocatable :: error
    real(wp) :: z, phi, r(2), rz(2), rp(2), jac(2, 2), det, step(2), out(n_pose_out)
    integer :: it
    if (i > s%n_valid) return
    if (i == 1) then
      call rigid_contact(ws%models(1)%geo, s%x(i), psi, z, phi, error)
      if (allocated(error)) then
        call end_sweep(s, i, error%message)
        return
      end if
      z = z - delta0
    else
      z = s%values(i - 1, n_pose_out - 1)
      phi = s%values(i - 1, n_pose_out)
    end if
    do it = 1, 40
      call evaluate_pose(ws, s%x(i), z, phi, psi, out, error)
      if (allocated(error)) exit
      r = [out(3), out(n_wheel_out + 3)] - wheel_load
      if (maxval(abs(r)) < tol * wheel_load) then
        s%values(i, :) = out
        return
      end if
      call evaluate_pose(ws, s%x(i), z + dz, phi, psi, out, error)
      if (allocated(error)) exit
      rz = [out(3), out(n_wheel_out + 3)] - wheel_load
      call evaluate_pose(ws, s%x(i), z, phi + dphi, psi, out, error)
      if (allocated(error)) exit
      rp = [out(3), out(n_wheel_out + 3)] - wheel_load
      jac(:, 1) = (rz - r) / dz
      jac(:, 2) = (rp - r) / dphi
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      if (.not. (abs(det) > 0)) exit
      step = [jac(2, 2) * r(1) - jac(1, 2) * r(2), jac(1, 1) * r(2) - jac(2, 1) * r(1)] / det
      ! damped: no step moves a wheel by more than 20 um (z, and roll times 0.75 m)
      step = step * min(1.0_wp, 2.0e-5_wp / max(abs(step(1)), abs(step(2)) * half_track, tiny(1.0_wp)))
      z = z - step(1)
      phi = phi - step(2)
    end do
    if (allocated(error)) then
      call end_sweep(s, i, error%message)
    else
      call end_sweep(s, i, 'no (z, roll) with Q0 on both wheels found in 40 Newton iterations')
    end if
  end subroutine loaded_sample

  !> Sample i of a lateral sweep: rigid contact at (y, yaw) lowered by delta0.
  subroutine lateral_sample(ws, s, i, psi)
    type(wheelset_contact_t), intent(inout) :: ws
    type(sweep_t), intent(inout) :: s
    integer, intent(in) :: i
    real(wp), intent(in) :: psi
    type(error_t), allocatable :: error
    real(wp) :: z, phi
    if (i > s%n_valid) return
    call rigid_contact(ws%models(1)%geo, s%x(i), psi, z, phi, error)
    if (allocated(error)) then
      call end_sweep(s, i, error%message)
      return
    end if
    call pose_sample(ws, s, i, s%x(i), z - delta0, phi, psi)
  end subroutine lateral_sample

  !> Sample i of a sweep at pose (y, z, roll, yaw); an error of the pipeline ends the sweep.
  subroutine pose_sample(ws, s, i, y, z, phi, psi)
    type(wheelset_contact_t), intent(inout) :: ws
    type(sweep_t), intent(inout) :: s
    integer, intent(in) :: i
    real(wp), intent(in) :: y, z, phi, psi
    type(error_t), allocatable :: error
    if (i > s%n_valid) return
    call evaluate_pose(ws, y, z, phi, psi, s%values(i, :), error)
    if (allocated(error)) call end_sweep(s, i, error%message)
  end subroutine pose_sample

  !> The sweep ends before sample i, because of `reason`.
  pure subroutine end_sweep(s, i, reason)
    type(sweep_t), intent(inout) :: s
    integer, intent(in) :: i
    character(len=*), intent(in) :: reason
    s%n_valid = min(s%n_valid, i - 1)
    if (.not. allocated(s%end_reason)) s%end_reason = reason
  end subroutine end_sweep

  subroutine creep_sweeps()
    class(creep_law_t), allocatable :: law
    type(wheelset_contact_spec_t) :: spec
    type(error_t), allocatable :: error
    integer, parameter :: nsweep = 6
    !> creepages of the patch sweeps: partial slip, near the flange-root spin
    real(wp), parameter :: patch_creep(3) = [1.0e-3_wp, 1.0e-3_wp, 0.5_wp]
    type(sweep_t) :: sweeps(nsweep)
    type(output_t) :: outs(n_creep_out)
    type(creep_force_t) :: cf
    type(creep_patch_t) :: p
    character(len=400), allocatable :: rows(:, :)
    real(wp) :: c(3)
    integer :: lv, i, sw
    outs(1) = output_t(name='Fx', unit='N', scale=patch%friction * patch%normal_force)
    outs(2) = output_t(name='Fy', unit='N', scale=patch%friction * patch%normal_force)
    outs(3) = output_t(name='Mz', unit='N m', scale=patch%friction * patch%normal_force * sqrt(patch%a * patch%b))
    sweeps(1)%name = 'xi (eta = spin = 0)'
    sweeps(2)%name = 'eta (xi = spin = 0)'
    sweeps(3)%name = 'spin (xi = eta = 0)'
    sweeps(4)%name = 'eta at spin 1.5 1/m'
    sweeps(5)%name = 'ellipse ln(a/b) at constant a b (xi = eta = 1e-3, spin 0.5 1/m)'
    sweeps(6)%name = 'normal force, a and b ~ N^(1/3) as Hertz (xi = eta = 1e-3, spin 0.5 1/m)'
    sweeps%x_unit = '-'; sweeps%x_print = 1; sweeps%x_si_unit = '-'
    sweeps(3)%x_unit = '1/m'; sweeps(3)%x_si_unit = '1/m'
    sweeps(6)%x_unit = 'kN'; sweeps(6)%x_print = 1.0e-3_wp; sweeps(6)%x_si_unit = 'N'
    sweeps(1)%x = [(-5.0e-3_wp + 1.0e-2_wp * (i - 1) / (npoints - 1), i = 1, npoints)]
    sweeps(2)%x = sweeps(1)%x
    sweeps(3)%x = [(-4.0_wp + 8.0_wp * (i - 1) / (npoints - 1), i = 1, npoints)]
    sweeps(4)%x = sweeps(1)%x
    ! a/b from 0.2 to 5 (Kalker's tables span 0.1..10)
    sweeps(5)%x = [(log(0.2_wp) + 2 * log(5.0_wp) * (i - 1) / (npoints - 1), i = 1, npoints)]
    sweeps(6)%x = [(patch%normal_force * (0.5_wp + real(i - 1, wp) / (npoints - 1)), i = 1, npoints)]
    do sw = 1, nsweep
      allocate (sweeps(sw)%values(npoints, n_creep_out))
    end do
    allocate (rows(nsweep, size(all_creep)))
    do lv = 1, size(all_creep)
      spec = default_spec()
      call apply_level(spec, all_creep(lv))
      call build_creep_law(spec%creep_law, spec%creep_options, law, error)
      if (allocated(error)) error stop 'bench_contact_smoothness: level ' // trim(all_creep(lv)) // ': ' // error%message
      do sw = 1, nsweep
        do i = 1, npoints
          p = patch
          c = patch_creep
          select case (sw)
          case (1); c = [sweeps(sw)%x(i), 0.0_wp, 0.0_wp]
          case (2); c = [0.0_wp, sweeps(sw)%x(i), 0.0_wp]
          case (3); c = [0.0_wp, 0.0_wp, sweeps(sw)%x(i)]
          case (4); c = [0.0_wp, sweeps(sw)%x(i), 1.5_wp]
          case (5)
            p%a = sqrt(patch%a * patch%b) * exp(0.5_wp * sweeps(sw)%x(i))
            p%b = sqrt(patch%a * patch%b) * exp(-0.5_wp * sweeps(sw)%x(i))
          case default
            p%normal_force = sweeps(sw)%x(i)
            p%a = patch%a * (sweeps(sw)%x(i) / patch%normal_force)**(1.0_wp / 3)
            p%b = patch%b * (sweeps(sw)%x(i) / patch%normal_force)**(1.0_wp / 3)
          end select
          call law%compute(p, creepage_t(xi=c(1), eta=c(2), phi=c(3), v_ref=speed), cf)
          sweeps(sw)%values(i, :) = [cf%fx, cf%fy, cf%mz]
        end do
        rows(sw, lv) = analyse(level_label(all_creep(lv)), sweeps(sw), outs, with_positions=.false.)
      end do
    end do
    do sw = 1, nsweep
      write (*, '(a)') ''
      write (*, '(a)') '#### Creep law sweep: ' // trim(sweeps(sw)%name) // ' (x in ' // trim(sweeps(sw)%x_unit) // ')'
      write (*, '(a)') ''
      write (*, '(a)') '| creep law | jumps | largest jump | kinks | largest kink |'
      write (*, '(a)') '|---|---|---|---|---|'
      do lv = 1, size(all_creep)
        write (*, '(a)') trim(rows(sw, lv))
      end do
    end do
  end subroutine creep_sweeps

  !> The n_listed largest force features of one kind of the detailed level (all pose sweeps),
  !> by relative size, one per place (the largest output there; the others within 3 samples
  !> of it in the same sweep are counted in 'outputs').
  subroutine print_largest(kind, what)
    integer, intent(in) :: kind
    character(len=*), intent(in) :: what
    logical, allocatable :: left(:), here(:)
    integer :: k, best
    character(len=:), allocatable :: size_text
    left = listed%feature%kind == kind
    write (*, '(a)') ''
    write (*, '(a)') '#### The largest force ' // what // ' of ' // level_label(all_pose(detail_level)) // ', all pose sweeps'
    write (*, '(a)') ''
    write (*, '(a)') 'Relative: a jump over its scale; a kink''s slope change times the sweep''s range over the scale.'
    write (*, '(a)') ''
    write (*, '(a)') '| sweep | output | at | size | relative | outputs there |'
    write (*, '(a)') '|---|---|---|---|---|---|'
    do k = 1, n_listed
      if (.not. any(left)) exit
      best = maxloc(listed%relative, dim=1, mask=left)
      here = left .and. listed%sweep == listed(best)%sweep .and. &
             abs(listed%feature%x - listed(best)%feature%x) <= 3 * listed(best)%step
      left = left .and. .not. here
      associate (f => listed(best))
        size_text = trim(sci_text(f%feature%size, 2)) // ' ' // trim(f%unit)
        if (kind == FEATURE_KINK) size_text = size_text // '/' // trim(f%x_si_unit)
        write (*, '(a)') '| ' // trim(f%sweep) // ' | ' // trim(f%output) // ' | ' // &
          trim(real_text(f%feature%x * f%x_print)) // ' ' // trim(f%x_unit) // ' | ' // size_text // ' | ' // &
          trim(sci_text(100 * f%relative, 1)) // ' % | ' // trim(int_text(count(here))) // ' |'
      end associate
    end do
  end subroutine print_largest

  !> ----------------------------------------------------------------------- analysis
  !> Detect the features of every output of a sweep, write them to the CSV, and return the
  !> table row: counts of distinct places and the largest (relative to its output's scale).
  function analyse(label, s, outs, with_positions, keep) result(row)
    character(len=*), intent(in) :: label
    type(sweep_t), intent(in) :: s
    type(output_t), intent(in) :: outs(:)
    logical, intent(in) :: with_positions
    !> keep the force features in `listed` (the level listed feature by feature)
    logical, intent(in), optional :: keep
    character(len=400) :: row
    type(smoothness_feature_t), allocatable :: feat(:)
    type(error_t), allocatable :: error
    real(wp), allocatable :: jump_x(:), kink_x(:), pos_x(:), path_x(:), path_jump_x(:), big_jump_x(:), big_kink_x(:)
    real(wp) :: best_jump, best_kink, best_pos, h, rel
    character(len=120) :: jump_text, kink_text, pos_text
    character(len=:), allocatable :: cell
    integer :: j, k, m
    allocate (jump_x(0), kink_x(0), pos_x(0), path_x(0), path_jump_x(0), big_jump_x(0), big_kink_x(0))
    m = min(s%n_valid, size(s%x))
    cell = label
    if (m < size(s%x)) cell = cell // ' (path ends at ' // trim(real_text(s%x(max(m, 1)) * s%x_print)) // ')'
    if (m < 7) then
      row = '| ' // cell // ' | - | - | - | - |'
      if (with_positions) row = trim(row) // ' - | - |'
      return
    end if
    best_jump = 0; best_kink = 0; best_pos = 0
    jump_text = '-'; kink_text = '-'; pos_text = ''
    h = abs(s%x(2) - s%x(1))
    do j = 1, size(outs)
      call find_jumps_and_kinks(s%x(1:m), s%values(1:m, j), outs(j)%scale, feat, error, ratio=ratio, &
                                relative_floor=relative_floor)
      if (allocated(error)) error stop 'bench_contact_smoothness: ' // error%message
      do k = 1, size(feat)
        if (feat(k)%kind == FEATURE_JUMP) then
          rel = abs(feat(k)%size) / outs(j)%scale
        else
          ! a kink relative to the scale per unit of the sweep's whole range
          rel = abs(feat(k)%size) * abs(s%x(m) - s%x(1)) / outs(j)%scale
        end if
        if (csv_unit /= 0) write (csv_unit, '(a,4(",",a),4(",",es14.6))') '"' // label // '"', '"' // &
          trim(s%name) // '"', trim(outs(j)%name), trim(merge('jump', 'kink', feat(k)%kind == FEATURE_JUMP)), &
          sci_text(feat(k)%x, 8), feat(k)%size, rel, feat(k)%prominence, feat(k)%width
        if (outs(j)%force_like) then
          if (present(keep)) then
            if (keep) listed = [listed, listed_feature_t(sweep=s%name, output=outs(j)%name, unit=outs(j)%unit, &
                                x_si_unit=s%x_si_unit, x_unit=s%x_unit, x_print=s%x_print, step=h, &
                                feature=feat(k), relative=rel)]
          end if
          if (feat(k)%kind == FEATURE_JUMP) then
            call add_place(jump_x, feat(k)%x, h)
            if (rel >= relevant_jump) call add_place(big_jump_x, feat(k)%x, h)
            if (rel > best_jump) then
              best_jump = rel
              jump_text = trim(outs(j)%name) // ' ' // trim(sci_text(feat(k)%size, 2)) // ' ' // trim(outs(j)%unit) // &
                ' (' // trim(sci_text(100 * rel, 1)) // ' %) at ' // trim(real_text(feat(k)%x * s%x_print))
            end if
          else
            call add_place(kink_x, feat(k)%x, h)
            if (rel >= relevant_kink) call add_place(big_kink_x, feat(k)%x, h)
            if (rel > best_kink) then
              best_kink = rel
              kink_text = trim(outs(j)%name) // ' ' // trim(sci_text(feat(k)%size, 2)) // ' ' // trim(outs(j)%unit) // &
                '/' // trim(s%x_si_unit) // ' at ' // trim(real_text(feat(k)%x * s%x_print))
            end if
          end if
        else if (j <= 2 * n_wheel_out) then
          if (feat(k)%kind == FEATURE_JUMP) then
            call add_place(pos_x, feat(k)%x, h)
            if (abs(feat(k)%size) > best_pos) then
              best_pos = abs(feat(k)%size)
              pos_text = trim(sci_text(feat(k)%size * 1.0e3_wp, 2)) // ' mm at ' // trim(real_text(feat(k)%x * s%x_print))
            end if
          end if
        else if (feat(k)%kind == FEATURE_KINK) then
          call add_place(path_x, feat(k)%x, h)
        else
          call add_place(path_jump_x, feat(k)%x, h)
        end if
      end do
    end do
    row = '| ' // cell // ' | ' // trim(int_text(size(jump_x))) // ' (' // trim(int_text(size(big_jump_x))) // ') | ' // &
          trim(jump_text) // ' | ' // trim(int_text(size(kink_x))) // ' (' // trim(int_text(size(big_kink_x))) // ') | ' // &
          trim(kink_text) // ' |'
    if (with_positions) then
      if (size(pos_x) > 0) then
        row = trim(row) // ' ' // trim(int_text(size(pos_x))) // ' (' // trim(pos_text) // ') |'
      else
        row = trim(row) // ' 0 |'
      end if
      row = trim(row) // ' ' // trim(int_text(size(path_jump_x))) // ' / ' // trim(int_text(size(path_x))) // ' |'
    end if
  end function analyse

  !> Count a place once: not added when another lies within 3 samples (step h).
  pure subroutine add_place(places, x, h)
    real(wp), allocatable, intent(inout) :: places(:)
    real(wp), intent(in) :: x, h
    if (size(places) > 0) then
      if (any(abs(places - x) <= 3 * h)) return
    end if
    places = [places, x]
  end subroutine add_place

  function cost_list(cost, levels) result(text)
    real(wp), intent(in) :: cost(:)
    character(len=*), intent(in) :: levels(:)
    character(len=:), allocatable :: text
    integer :: k
    text = ''
    do k = 1, size(cost)
      if (k > 1) text = text // '; '
      text = text // level_label(levels(k)) // ' ' // trim(real_text(real(nint(cost(k) * 10), wp) / 10))
    end do
  end function cost_list

end program bench_contact_smoothness
