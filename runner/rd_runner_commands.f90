!> Sub-commands of the `raildyn` executable: argument parsing, progress, exit codes.
!> The physics lives in the library; this module only drives it and reports.
module rd_runner_commands
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
  use, intrinsic :: iso_c_binding, only: c_int
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_scene, only: scene_t, raildyn_version
  use rd_integrator_settings, only: integrator_stats_t
  use rd_deck, only: deck_string_t
  use rd_cmd_hertz, only: run_hertz_command, hertz_usage
  use rd_cmd_creep, only: run_creep_command, creep_usage
  use rd_cmd_profile_scan, only: run_profile_scan_command, profile_scan_usage
  use rd_cmd_conicity, only: run_conicity_command, conicity_usage
  use rd_track_export, only: export_track
  use rd_build_info, only: python_command, shell_quote, runner_path
  use rd_json, only: json_string, json_real
  use rd_runner_scene, only: start_scene
  use rd_cmd_eigen, only: run_eigen_command, eigen_usage
  use rd_deck, only: deck_string_t, deck_t, read_deck_file
  use rd_deck_schema, only: deck_schema_t, param_schema_t, build_deck_schema, PT_REAL, PT_INTEGER, &
                            PT_STRING, PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST
  use rd_text, only: int_text
  implicit none
  private
  public :: run_command

  interface
    function rd_stderr_is_terminal() result(yes) bind(C, name='rd_stderr_is_terminal')
      import :: c_int
      integer(c_int) :: yes
    end function rd_stderr_is_terminal
  end interface

  character(len=*), parameter :: usage = &
    'usage: raildyn run DECK [-o OUT.h5] [--restart RESULTS.h5] [--progress|--quiet] | check DECK [--json] | ' // &
    'track DECK [-o OUT.h5] [--step DS] [--csv FILE] [--plot FILE] | profile-scan ... | eigen DECK ... | ' // &
    'critical-speed DECK --method linear|bisection|ramp ... | ' // &
    'conicity ... | ' // &
    'campaign run|summary|decks CAMPAIGN.toml | export RESULTS.h5 --csv DIR | ' // &
    'assess RESULTS.h5 [--json] [--csv DIR] [--html DIR] | hertz ... | creep ... | ' // &
    'version | help [COMMAND]' // &
    new_line('a') // '(raildyn COMMAND --help: the options of one command)'
  ! One usage line per command, printed by `raildyn COMMAND --help` (or -h) and `raildyn help
  ! COMMAND`, and with that command's usage errors. The campaign's options are its own
  ! (python -m raildyn.campaign answers --help itself).
  character(len=*), parameter :: run_usage = &
    'usage: raildyn run DECK [-o OUT.h5] [--restart RESULTS.h5] [--progress|--quiet]'
  character(len=*), parameter :: check_usage = 'usage: raildyn check DECK [--json]'
  character(len=*), parameter :: track_usage = &
    'usage: raildyn track DECK [-o OUT.h5] [--step DS] [--csv FILE] [--plot FILE]'
  character(len=*), parameter :: critical_speed_usage = &
    'usage: raildyn critical-speed DECK --method linear|bisection|ramp [--speeds LO,HI] [--resolution DV] ' // &
    '[--dofs ...] [--channel SERIES] [--t-end T] [--t-from T] [--jobs N] [--backend local|slurm] ' // &
    '[--slurm-option OPT] [--hold T] [--duration T1,T2] [--work DIR] [--json]'
  character(len=*), parameter :: export_usage = 'usage: raildyn export RESULTS.h5 --csv DIR'
  character(len=*), parameter :: assess_usage = &
    'usage: raildyn assess RESULTS.h5 [--json] [--csv DIR] [--html DIR] [--prudhomme-alpha ALPHA] ' // &
    '[--instability-frequency HZ] [--shear-yield K]'
  character(len=*), parameter :: version_usage = 'usage: raildyn version'
  character(len=*), parameter :: help_usage = 'usage: raildyn help [COMMAND]'

contains

  subroutine run_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    if (size(args) == 0) then
      write (error_unit, '(a)') usage
      status = 1
      return
    end if
    if (trim(args(1)) /= 'campaign' .and. len(command_usage(args(1))) > 0) then
      if (any(args(2:) == '--help') .or. any(args(2:) == '-h')) then
        write (output_unit, '(a)') command_usage(args(1))
        status = 0
        return
      end if
    end if
    select case (trim(args(1)))
    case ('run')
      call command_run(args(2:), status)
    case ('check')
      call command_check(args(2:), status)
    case ('track')
      call command_track(args(2:), status)
    case ('profile-scan')
      call run_profile_scan_command(args(2:), status)
    case ('eigen')
      call run_eigen_command(args(2:), status)
    case ('critical-speed')
      call command_critical_speed(args(2:), status)
    case ('conicity')
      call run_conicity_command(args(2:), status)
    case ('campaign')
      call command_python('raildyn.campaign', args(2:), status)
    case ('export')
      call command_python('raildyn.export', args(2:), status)
    case ('assess')
      call command_python('raildyn.assess', args(2:), status)
    case ('hertz')
      call run_hertz_command(args(2:), status)
    case ('creep')
      call run_creep_command(args(2:), status)
    case ('version', '--version')
      if (size(args) > 1) then
        call usage_error("version takes no arguments, got '" // trim(args(2)) // "'", version_usage, status)
        return
      end if
      write (output_unit, '(2a)') 'raildyn ', raildyn_version
      status = 0
    case ('help', '--help', '-h')
      call command_help(args(2:), status)
    case default
      write (error_unit, '(3a)') "raildyn: unknown command '", trim(args(1)), "'"
      write (error_unit, '(a)') usage
      status = 1
    end select
  end subroutine run_command

  !> Print an error as one line and return its class as exit status.
  subroutine report(error, status)
    type(error_t), intent(in) :: error
    integer, intent(out) :: status
    write (error_unit, '(2a)') 'raildyn: error: ', error%message
    status = error%code
  end subroutine report

  !> A usage error: the message and the usage line of the command, exit status 1.
  subroutine usage_error(message, usage_line, status)
    character(len=*), intent(in) :: message, usage_line
    integer, intent(out) :: status
    write (error_unit, '(2a)') 'raildyn: ', message
    write (error_unit, '(a)') usage_line
    status = 1
  end subroutine usage_error

  !> The usage line of a command ('' for a name that is not a command).
  function command_usage(name) result(text)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: text
    select case (trim(name))
    case ('run'); text = run_usage
    case ('check'); text = check_usage
    case ('track'); text = track_usage
    case ('profile-scan'); text = profile_scan_usage
    case ('eigen'); text = eigen_usage
    case ('critical-speed'); text = critical_speed_usage
    case ('conicity'); text = conicity_usage
    case ('campaign'); text = 'usage: raildyn campaign run|summary|decks CAMPAIGN.toml [options] ' // &
                              '(raildyn campaign --help: the options)'
    case ('export'); text = export_usage
    case ('assess'); text = assess_usage
    case ('hertz'); text = hertz_usage
    case ('creep'); text = creep_usage
    case ('version', '--version'); text = version_usage
    case ('help', '--help', '-h'); text = help_usage
    case default; text = ''
    end select
  end function command_usage

  !> `help [COMMAND]`: the overview, or one command's usage line.
  subroutine command_help(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    status = 0
    if (size(args) == 0) then
      write (output_unit, '(a)') usage
    else if (size(args) > 1) then
      call usage_error('help takes at most one command', help_usage, status)
    else if (len(command_usage(args(1))) == 0) then
      call usage_error("unknown command '" // trim(args(1)) // "'", usage, status)
    else
      write (output_unit, '(a)') command_usage(args(1))
    end if
  end subroutine command_help

  !> Split args into one positional deck and options; -o/--output, --step, --csv, --plot,
  !> --restart (run only) take values. Usage errors print usage_line, the command's own.
  subroutine parse_deck_args(args, usage_line, deck, output, step, csv, plot, progress, status, restart)
    character(len=*), intent(in) :: args(:)
    character(len=*), intent(in) :: usage_line
    character(len=:), allocatable, intent(out) :: deck, output, csv, plot
    character(len=:), allocatable, intent(out), optional :: restart
    real(wp), intent(out) :: step
    integer, intent(out) :: progress   !< -1 quiet, 0 auto, 1 forced
    integer, intent(out) :: status
    integer :: i, ios
    deck = ''; output = ''; csv = ''; plot = ''; step = 0; progress = 0; status = 0
    if (present(restart)) restart = ''
    i = 1
    do while (i <= size(args))
      if (trim(args(i)) == '--restart' .and. .not. present(restart)) then
        call usage_error("unknown option '--restart' (raildyn run only)", usage_line, status)
        return
      end if
      select case (trim(args(i)))
      case ('-o', '--output', '--step', '--csv', '--plot', '--restart')
        if (i == size(args)) then
          call usage_error('option ' // trim(args(i)) // ' needs a value', usage_line, status)
          return
        end if
        select case (trim(args(i)))
        case ('-o', '--output'); output = trim(args(i + 1))
        case ('--csv'); csv = trim(args(i + 1))
        case ('--plot'); plot = trim(args(i + 1))
        case ('--restart'); restart = trim(args(i + 1))
        case ('--step')
          read (args(i + 1), *, iostat=ios) step
          if (ios /= 0 .or. .not. (step > 0)) then
            call usage_error('--step expects a positive length in metres, got ' // trim(args(i + 1)), usage_line, status)
            return
          end if
        end select
        i = i + 2
      case ('--progress')
        progress = 1; i = i + 1
      case ('--quiet', '-q')
        progress = -1; i = i + 1
      case default
        if (args(i)(1:1) == '-') then
          call usage_error("unknown option '" // trim(args(i)) // "'", usage_line, status)
          return
        end if
        if (len(deck) > 0) then
          call usage_error("more than one deck given ('" // deck // "', '" // trim(args(i)) // "')", usage_line, status)
          return
        end if
        deck = trim(args(i)); i = i + 1
      end select
    end do
    if (len(deck) == 0) call usage_error('no deck given', usage_line, status)
  end subroutine parse_deck_args

  !> `check DECK [--json]`: build the scene. --json prints one JSON object on stdout
  !> instead of the ok line (errors still go to stderr too): deck, status ('ok' or
  !> 'error'), exit_code, message, version and input_files, every file the deck reads
  !> (rd_deck input_files; listed when the deck could be read, even if the build fails),
  !> for tools that must know what a run depends on (the campaigns' cache); then the
  !> resolved deck (resolved_deck_json): decks (the deck and its includes) and groups, for
  !> tools that must know what a deck says (the validation harness) without parsing it.
  subroutine command_check(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: deck, output, csv, plot
    real(wp) :: step
    integer :: progress
    logical :: json
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    json = any(args == '--json')
    call parse_deck_args(pack(args, args /= '--json'), check_usage, deck, output, step, csv, plot, progress, status)
    if (status /= 0) return
    call start_scene(scene, deck, output, .false., error)
    status = 0
    if (allocated(error)) call report(error, status)
    if (json) then
      call print_check_json(deck, scene, error, status)
    else if (status == 0) then
      write (output_unit, '(3a)') 'raildyn: ', deck, ': ok (' // scene%summary() // ')'
      write (output_unit, '(a)') scene%check_report()
    end if
  end subroutine command_check

  subroutine print_check_json(deck, scene, error, status)
    character(len=*), intent(in) :: deck
    type(scene_t), intent(in) :: scene
    type(error_t), allocatable, intent(in) :: error
    integer, intent(in) :: status
    type(deck_string_t), allocatable :: files(:)
    character(len=:), allocatable :: text, message
    integer :: i
    message = ''
    if (allocated(error)) message = error%message
    files = scene%input_files()
    text = '{"deck": ' // json_string(deck) // ', "status": ' // &
           json_string(trim(merge('ok   ', 'error', status == 0))) // ', "exit_code": ' // trim(int_text(status)) // &
           ', "message": ' // json_string(message) // ', "version": ' // json_string(raildyn_version) // &
           ', "input_files": ['
    do i = 1, size(files)
      if (i > 1) text = text // ', '
      text = text // json_string(files(i)%s)
    end do
    write (output_unit, '(a)') text // ']' // resolved_deck_json(deck, files) // '}'
  end subroutine print_check_json

  !> The deck as the scene reads it, for `check --json` (read once more: the scene keeps its
  !> deck to itself): "decks", the deck and its includes in reading order (the input files no
  !> parameter names), and "groups", per kind of group (in schema order) its occurrences in
  !> deck order, each an object of every parameter of the group with overrides merged and
  !> defaults applied (docs/input_reference.md): numbers with 17 digits, path parameters
  !> resolved against the deck naming them, null for an optional parameter not given. Empty
  !> when the deck does not read.
  function resolved_deck_json(path, files) result(text)
    character(len=*), intent(in) :: path
    type(deck_string_t), intent(in) :: files(:)
    character(len=:), allocatable :: text, groups, sep
    type(deck_t) :: deck
    type(deck_schema_t) :: schema
    type(error_t), allocatable :: error
    integer :: f, g, i, p
    logical :: named
    text = ', "decks": ['
    groups = ''
    call read_deck_file(deck, path, error)
    if (.not. allocated(error)) then
      schema = build_deck_schema()
      sep = ''
      do f = 1, size(files)
        named = .false.
        do g = 1, size(schema%groups)
          if (schema%groups(g)%name == 'include') cycle     ! its file is a deck
          do i = 1, deck%count(schema%groups(g)%name)
            do p = 1, size(schema%groups(g)%params)
              associate (q => schema%groups(g)%params(p))
                if (q%is_path .and. q%must_exist) named = named .or. &
                  deck%path(schema%groups(g)%name, i, q%name) == files(f)%s
              end associate
            end do
          end do
        end do
        if (named) cycle
        text = text // sep // json_string(files(f)%s)
        sep = ', '
      end do
      do g = 1, size(schema%groups)
        if (deck%count(schema%groups(g)%name) == 0) cycle
        if (len(groups) > 0) groups = groups // ', '
        groups = groups // json_string(schema%groups(g)%name) // ': ['
        do i = 1, deck%count(schema%groups(g)%name)
          if (i > 1) groups = groups // ', '
          groups = groups // '{'
          do p = 1, size(schema%groups(g)%params)
            if (p > 1) groups = groups // ', '
            groups = groups // json_string(schema%groups(g)%params(p)%name) // ': ' // &
                     parameter_json(deck, schema%groups(g)%name, i, schema%groups(g)%params(p))
          end do
          groups = groups // '}'
        end do
        groups = groups // ']'
      end do
    end if
    text = text // '], "groups": {' // groups // '}'
  end function resolved_deck_json

  !> One parameter's value in JSON (the getter of its type; null when it has none).
  function parameter_json(deck, group, i, p) result(json)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: group
    integer, intent(in) :: i
    type(param_schema_t), intent(in) :: p
    character(len=:), allocatable :: json, word
    type(error_t), allocatable :: error
    real(wp) :: x
    real(wp), allocatable :: xs(:)
    type(deck_string_t), allocatable :: words(:)
    integer :: n, k
    logical :: flag
    select case (p%ptype)
    case (PT_REAL)
      call deck%get(group, i, p%name, x, error)
      json = json_real(x)
    case (PT_INTEGER)
      call deck%get(group, i, p%name, n, error)
      json = trim(int_text(n))
    case (PT_LOGICAL)
      call deck%get(group, i, p%name, flag, error)
      json = trim(merge('true ', 'false', flag))
    case (PT_STRING)
      call deck%get(group, i, p%name, word, error)
      if (p%is_path .and. len(deck%path(group, i, p%name)) > 0) word = deck%path(group, i, p%name)
      json = json_string(word)
    case (PT_REAL_ARRAY)
      call deck%get(group, i, p%name, xs, error)
      json = '['
      if (.not. allocated(error)) then
        do k = 1, size(xs)
          if (k > 1) json = json // ', '
          json = json // json_real(xs(k))
        end do
      end if
      json = json // ']'
    case (PT_STRING_LIST)
      call deck%get(group, i, p%name, words, error)
      json = '['
      if (.not. allocated(error)) then
        do k = 1, size(words)
          if (k > 1) json = json // ', '
          json = json // json_string(words(k)%s)
        end do
      end if
      json = json // ']'
    case default
      json = 'null'
    end select
    if (allocated(error)) json = 'null'
  end function parameter_json

  subroutine command_run(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: deck, output, csv, plot, restart
    real(wp) :: step, t_end, t_next, chunk
    integer :: progress, dot
    logical :: show
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    integer(int64) :: clock0, clock, rate, last_report
    call parse_deck_args(args, run_usage, deck, output, step, csv, plot, progress, status, restart)
    if (status /= 0) return
    if (len(restart) > 0) then
      ! a restart writes a new file (default RESULTS_restart.h5 beside RESULTS.h5), never
      ! the one it continues: that one stays as it was
      if (len(output) == 0) then
        dot = index(restart, '.', back=.true.)
        if (dot <= index(restart, '/', back=.true.)) dot = len(restart) + 1
        output = restart(1:dot - 1) // '_restart.h5'
      end if
      if (output == restart) then
        call usage_error('--restart ' // restart // ': the continued run writes a new file; ' // &
                         '-o must name another one', run_usage, status)
        return
      end if
    end if
    call start_scene(scene, deck, output, .true., error, restart)
    if (allocated(error)) then
      call report(error, status)
      return
    end if
    show = progress == 1 .or. (progress == 0 .and. scene%progress_wanted(rd_stderr_is_terminal() /= 0))
    t_end = scene%end_time()
    ! Advance in chunks so that progress can be shown. Nothing changes the inputs between
    ! chunks, so the integrator steps through their ends (horizon t_end): the steps do not
    ! depend on the chunking at all.
    chunk = max(t_end / 200.0_wp, scene%output_interval())
    call system_clock(clock0, rate)
    last_report = clock0
    do while (scene%time() < t_end)
      t_next = min(scene%time() + chunk, t_end)
      call scene%advance(t_next, error, t_end)
      if (allocated(error)) exit
      call system_clock(clock)
      if (show .and. (clock - last_report) * 2 > rate) then
        call print_progress(scene, t_end, real(clock - clock0, wp) / rate)
        last_report = clock
      end if
    end do
    if (show) then
      call system_clock(clock)
      call print_progress(scene, t_end, real(clock - clock0, wp) / rate)
      write (error_unit, '(a)') ''
    end if
    if (allocated(error)) then
      call report(error, status)   ! the scene has recorded the failure in the results file
      return
    end if
    call scene%finalize(error)
    if (allocated(error)) then
      call report(error, status)
      return
    end if
    if (progress >= 0) write (output_unit, '(a)') 'raildyn: ' // scene%completion_summary()
    status = 0
  end subroutine command_run

  !> One line, rewritten in place: simulated time, real-time factor, and the integrator's
  !> steps and last step size (a step size that collapses in a quiet scene is worth seeing
  !> while the run goes on, not only in the completion line).
  subroutine print_progress(scene, t_end, wall)
    type(scene_t), intent(inout) :: scene
    real(wp), intent(in) :: t_end, wall
    character(len=160) :: line
    type(integrator_stats_t) :: stats
    real(wp) :: speed, t
    t = scene%time()
    call scene%integrator_stats(stats)
    speed = 0
    if (wall > 0) speed = t / wall
    write (line, '(a,f10.3,a,f10.3,a,f6.1,a,es9.2,a,i0,a,es8.1,a)') 't = ', t, ' s / ', t_end, ' s (', &
      100 * t / max(t_end, tiny(t_end)), '%), ', speed, ' x real time, ', stats%steps, ' steps, h = ', &
      stats%last_step, ' s'
    write (error_unit, '(a,a)', advance='no') achar(13), trim(line)
    flush (error_unit)
  end subroutine print_progress

  subroutine command_track(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: deck, output, csv, plot
    real(wp) :: step
    integer :: progress
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    call parse_deck_args(args, track_usage, deck, output, step, csv, plot, progress, status)
    if (status /= 0) return
    call scene%load_file(deck, error)
    if (.not. allocated(error)) call scene%build(error)
    if (.not. allocated(error)) then
      if (len(output) == 0) output = scene%default_output_file('_track.h5')
      call export_track(scene, output, csv, plot, step, error)
    end if
    if (allocated(error)) then
      call report(error, status)
      return
    end if
    if (progress >= 0) write (output_unit, '(2a)') 'raildyn: track alignment written to ', output
    status = 0
  end subroutine command_track
  !> `critical-speed`: raildyn.stability, told to run this very runner for its probes
  !> (eigen, run) with --exe.
  subroutine command_critical_speed(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: exe, forwarded(:)
    integer :: i
    exe = runner_path()
    allocate (character(len=max(len(args), len(exe), 5)) :: forwarded(size(args) + 2))
    forwarded(1) = '--exe'
    forwarded(2) = exe
    do i = 1, size(args)
      forwarded(i + 2) = args(i)
    end do
    call command_python('raildyn.stability', forwarded, status)
  end subroutine command_critical_speed

  !> Commands driven by the Python package: parametric campaigns (raildyn.campaign runs this
  !> executable once per parameter set, locally or as a Slurm job array), the CSV export
  !> of a results file (raildyn.export, h5py) and the assessment of a results file against
  !> EN 14363 / EN 12299 (raildyn.assess). The module's exit status is the command's.
  subroutine command_python(module, args, status)
    character(len=*), intent(in) :: module
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: cmd
    integer :: i
    cmd = python_command() // ' -m ' // module
    do i = 1, size(args)
      cmd = cmd // ' ' // shell_quote(trim(args(i)))
    end do
    call execute_command_line(cmd, exitstat=status)
  end subroutine command_python
end module rd_runner_commands
