!> `raildyn eigen`: the linear modes of a deck (docs/theory_stability.md).
!>
!>   raildyn eigen DECK [--speed V | --speeds V1,V2,...] [--time T | --state RESULTS.h5[:ROW]]
!>                      [--dofs D1,D2,...] [--json] [--csv FILE] [--plot FILE]
!>
!> The scene starts as `raildyn run` starts it (static equilibrium), optionally runs to T or
!> takes a results file's state row, then for each speed (default: the deck's speed at that
!> time) is linearised there (rd_scene_linearization) and its modes found
!> (rd_linear_modes). Text, one JSON object, a CSV of every mode at every speed (a root
!> locus) and its plot (python -m raildyn.plots root-locus).
module rd_cmd_eigen
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_IO, RD_ERR_INPUT
  use rd_scene, only: scene_t
  use rd_deck, only: deck_string_t
  use rd_linear_modes, only: linear_mode_t, linear_modes
  use rd_scene_linearization, only: linearize_scene, scene_state_names, scene_state_weights, select_states, &
                                    spin_rate_rows
  use rd_runner_scene, only: start_scene
  use rd_json, only: json_string, json_real
  use rd_text, only: int_text, real_text, fixed_text, sci_text
  use rd_build_info, only: python_command, shell_quote
  implicit none
  private
  public :: run_eigen_command, eigen_usage, split_words

  character(len=*), parameter :: eigen_usage = &
    'usage: raildyn eigen DECK [--speed V | --speeds V1,V2,...] [--time T | --state RESULTS.h5[:ROW]] ' // &
    '[--dofs D1,D2,...] [--json] [--csv FILE] [--plot FILE]'

  !> A state about which the scene is linearised "at rest" should not accelerate: above
  !> this [m/s^2 or rad/s^2] eigen warns (a deck with equilibrium = 'none' starts far from
  !> rest: the TGV wheelset deck 90 m/s^2). Below it: the small longitudinal creep forces
  !> of a loaded rolling radius slightly off r0 at speed (TGV bogie at 40 m/s: 0.18 m/s^2
  !> on a wheelset's x), which the static solve at V = 0 cannot know.
  real(wp), parameter :: REST_ACCELERATION = 0.5_wp

  !> The modes at one speed.
  type :: speed_modes_t
    real(wp) :: speed = 0
    type(linear_mode_t), allocatable :: modes(:)
  end type speed_modes_t

contains

  subroutine run_eigen_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: deck, state_file, csv, plot, where
    real(wp), allocatable :: speeds(:)
    type(deck_string_t), allocatable :: dofs(:), names(:)
    real(wp) :: time
    integer :: state_row
    logical :: json
    type(scene_t) :: scene
    type(error_t), allocatable :: error
    type(speed_modes_t), allocatable :: locus(:)
    integer, allocatable :: kept(:)
    real(wp) :: rest
    integer :: rest_state

    call parse_eigen_args(args, deck, speeds, time, state_file, state_row, dofs, json, csv, plot, status)
    if (status /= 0) return
    call start_scene(scene, deck, '', .false., error, restart=state_file, restart_row=state_row, &
                     check_results_path=.false.)
    if (.not. allocated(error) .and. scene%state_size() == 0) &
      call make_error(error, RD_ERR_INPUT, deck // ': no &body: a track alone has no modes to linearise')
    if (.not. allocated(error) .and. time > 0) call scene%advance(time, error)
    if (.not. allocated(error)) call select_states(scene, dofs, kept, error)
    if (.not. allocated(error)) call modes_at_speeds(scene, speeds, kept, locus, rest, rest_state, error)
    if (.not. allocated(error) .and. len(csv) > 0) call write_locus_csv(csv, locus, scene_state_names(scene), kept, error)
    if (.not. allocated(error) .and. len(plot) > 0) call plot_locus(plot, csv, locus, scene_state_names(scene), kept, error)
    if (allocated(error)) then
      write (error_unit, '(2a)') 'raildyn: error: ', error%message
      status = error%code
      return
    end if
    names = scene_state_names(scene)
    if (len(state_file) > 0) then
      where = 'the state of ' // state_file // ' at t = ' // trim(real_text(scene%time())) // ' s'
    else if (time > 0) then
      where = 'the state of the run at t = ' // trim(real_text(scene%time())) // ' s'
    else
      where = 'the initial state (after &simulation equilibrium)'
    end if
    if (rest > REST_ACCELERATION .and. len(state_file) == 0 .and. .not. time > 0) &
      write (error_unit, '(a)') 'raildyn: warning: the initial state is not at rest at V = ' // &
        trim(real_text(locus(1)%speed)) // ' m/s (d/dt ' // names(rest_state)%s // ' = ' // trim(sci_text(rest, 2)) // &
        ' in SI units): the modes are those of a linearisation about a moving state'
    if (json) then
      call print_json(deck, where, scene%time(), size(names), kept, names, locus, rest)
    else
      call print_text(deck, where, size(names), kept, names, locus)
    end if
    status = 0
  end subroutine run_eigen_command

  !> Linearise at each speed (none given: the scene's own) and find the modes of the kept
  !> states. `rest`: the largest acceleration of the kept rates at the first speed, of the
  !> state `rest_state` (wheelset spin rates left out: spin_rate_rows).
  subroutine modes_at_speeds(scene, speeds, kept, locus, rest, rest_state, error)
    type(scene_t), intent(inout) :: scene
    real(wp), intent(in) :: speeds(:)
    integer, intent(in) :: kept(:)
    type(speed_modes_t), allocatable, intent(out) :: locus(:)
    real(wp), intent(out) :: rest
    integer, intent(out) :: rest_state
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: a(:, :), rate(:), weights(:)
    logical, allocatable :: is_rate(:)
    integer :: i, n_coordinates
    weights = scene_state_weights(scene)
    ! coordinate rows have weights; their rates follow them in the layout (rd_multibody)
    n_coordinates = count(weights > 0)
    allocate (is_rate(size(weights)), source=.false.)
    is_rate(n_coordinates + 1:2 * n_coordinates) = .true.
    is_rate = is_rate .and. .not. spin_rate_rows(scene)
    allocate (locus(max(1, size(speeds))))
    rest = 0
    rest_state = 1
    do i = 1, size(locus)
      if (size(speeds) > 0) then
        call scene%set_input('speed', [speeds(i)], error)
        if (allocated(error)) return
      end if
      locus(i)%speed = scene%running_speed()
      call linearize_scene(scene, a, error, rate)
      if (allocated(error)) return
      if (i == 1 .and. any(is_rate(kept))) then
        rest_state = kept(maxloc(abs(rate(kept)), mask=is_rate(kept), dim=1))
        rest = abs(rate(rest_state))
      end if
      call linear_modes(a(kept, kept), weights(kept), locus(i)%modes, error)
      if (allocated(error)) return
    end do
  end subroutine modes_at_speeds

  ! ------------------------------------------------------------------ arguments
  subroutine parse_eigen_args(args, deck, speeds, time, state_file, state_row, dofs, json, csv, plot, status)
    character(len=*), intent(in) :: args(:)
    character(len=:), allocatable, intent(out) :: deck, state_file, csv, plot
    real(wp), allocatable, intent(out) :: speeds(:)
    real(wp), intent(out) :: time
    integer, intent(out) :: state_row
    type(deck_string_t), allocatable, intent(out) :: dofs(:)
    logical, intent(out) :: json
    integer, intent(out) :: status
    integer :: i, colon, ios
    character(len=:), allocatable :: option, value
    deck = ''; state_file = ''; csv = ''; plot = ''; time = 0; state_row = -1; json = .false.
    allocate (speeds(0), dofs(0))
    status = 0
    i = 1
    do while (i <= size(args))
      option = trim(args(i))
      select case (option)
      case ('--json')
        json = .true.
        i = i + 1
        cycle
      case ('--speed', '--speeds', '--time', '--state', '--dofs', '--csv', '--plot')
        if (i == size(args)) then
          call usage_error('option ' // option // ' needs a value', status)
          return
        end if
        value = trim(args(i + 1))
        i = i + 2
      case default
        if (option(1:1) == '-') then
          call usage_error("unknown option '" // option // "'", status)
          return
        end if
        if (len(deck) > 0) then
          call usage_error("more than one deck given ('" // deck // "', '" // option // "')", status)
          return
        end if
        deck = option
        i = i + 1
        cycle
      end select
      select case (option)
      case ('--speed', '--speeds')
        if (size(speeds) > 0) then
          call usage_error('give --speed or --speeds once', status)
          return
        end if
        call read_speeds(option, value, speeds, status)
        if (status /= 0) return
        if (option == '--speed' .and. size(speeds) /= 1) then
          call usage_error('--speed expects one speed (--speeds takes a list)', status)
          return
        end if
      case ('--time')
        read (value, *, iostat=ios) time
        if (ios /= 0 .or. .not. (time >= 0 .and. time <= huge(time))) then
          call usage_error('--time expects a time >= 0 in seconds, got ' // value, status)
          return
        end if
      case ('--state')
        state_file = value
        colon = index(value, ':', back=.true.)
        if (colon > 1 .and. colon < len(value)) then
          if (verify(value(colon + 1:), '0123456789') == 0) then
            read (value(colon + 1:), *) state_row
            state_file = value(:colon - 1)
          end if
        end if
      case ('--dofs')
        dofs = split_words(value)
        if (size(dofs) == 0) then
          call usage_error('--dofs expects a comma-separated list of coordinates or bodies', status)
          return
        end if
      case ('--csv'); csv = value
      case ('--plot'); plot = value
      end select
    end do
    if (len(deck) == 0) then
      call usage_error('no deck given', status)
    else if (len(state_file) > 0 .and. time > 0) then
      call usage_error('give --time or --state, not both', status)
    end if
  end subroutine parse_eigen_args

  !> Speeds [m/s] >= 0, comma-separated.
  subroutine read_speeds(option, value, speeds, status)
    character(len=*), intent(in) :: option, value
    real(wp), allocatable, intent(out) :: speeds(:)
    integer, intent(out) :: status
    type(deck_string_t), allocatable :: words(:)
    integer :: k, ios
    status = 0
    words = split_words(value)
    allocate (speeds(size(words)))
    do k = 1, size(words)
      read (words(k)%s, *, iostat=ios) speeds(k)
      if (ios /= 0 .or. .not. (speeds(k) >= 0 .and. speeds(k) <= huge(1.0_wp))) then
        call usage_error(option // " expects speeds >= 0 in m/s separated by commas, got '" // words(k)%s // "'", status)
        return
      end if
    end do
    if (size(speeds) == 0) call usage_error(option // ' expects at least one speed in m/s', status)
  end subroutine read_speeds

  !> The non-empty words of a comma-separated list, blanks removed.
  function split_words(text) result(words)
    character(len=*), intent(in) :: text
    type(deck_string_t), allocatable :: words(:)
    integer :: start, comma
    character(len=:), allocatable :: word
    allocate (words(0))
    start = 1
    do while (start <= len(text))
      comma = index(text(start:), ',')
      if (comma == 0) comma = len(text) - start + 2
      word = trim(adjustl(text(start:start + comma - 2)))
      if (len(word) > 0) words = [words, deck_string_t(word)]
      start = start + comma
    end do
  end function split_words

  subroutine usage_error(message, status)
    character(len=*), intent(in) :: message
    integer, intent(out) :: status
    write (error_unit, '(2a)') 'raildyn: ', message
    write (error_unit, '(a)') eigen_usage
    status = 1
  end subroutine usage_error

  ! ------------------------------------------------------------------ output
  !> '<body>' and '<dof>' of a state name '<body>.<dof>' (an element's state: '<element>', 'x<k>').
  subroutine owner_and_dof(name, owner, dof)
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: owner, dof
    integer :: dot
    dot = index(name, '.', back=.true.)
    owner = name(:dot - 1)
    dof = name(dot + 1:)
  end subroutine owner_and_dof

  function dominant_text(mode, names, kept, separator) result(text)
    type(linear_mode_t), intent(in) :: mode
    type(deck_string_t), intent(in) :: names(:)
    integer, intent(in) :: kept(:)
    character(len=*), intent(in) :: separator
    character(len=:), allocatable :: text
    integer :: k
    text = ''
    do k = 1, mode%n_dominant
      if (k > 1) text = text // separator
      text = text // names(kept(mode%dominant(k)))%s // ' ' // trim(fixed_text(mode%share(k), 2))
    end do
  end function dominant_text

  subroutine print_text(deck, where, n_states, kept, names, locus)
    character(len=*), intent(in) :: deck, where
    integer, intent(in) :: n_states
    integer, intent(in) :: kept(:)
    type(deck_string_t), intent(in) :: names(:)
    type(speed_modes_t), intent(in) :: locus(:)
    character(len=160) :: line
    integer :: i, j
    do i = 1, size(locus)
      write (output_unit, '(a)') 'raildyn: linear modes of ' // deck // ' at V = ' // trim(real_text(locus(i)%speed)) // &
        ' m/s about ' // where // ' (' // trim(int_text(size(kept))) // ' of ' // trim(int_text(n_states)) // &
        ' states; least damped first)'
      write (output_unit, '(a)') '  frequency [Hz]  damping ratio     real [1/s]   imag [rad/s]  ' // &
        'dominant (share of the kinetic energy)'
      do j = 1, size(locus(i)%modes)
        associate (m => locus(i)%modes(j))
          write (line, '(f16.4, f15.6, 2es15.5)') m%frequency, m%damping_ratio, m%real_part, m%imag_part
          write (output_unit, '(a)') trim(line) // '  ' // dominant_text(m, names, kept, ', ')
        end associate
      end do
    end do
  end subroutine print_text

  !> One JSON object: the linearisation point and "modes" (one speed) or "root_locus"
  !> (a list of {"speed", "modes"} for --speeds), docs/theory_stability.md section 4.
  subroutine print_json(deck, where, time, n_states, kept, names, locus, rest)
    character(len=*), intent(in) :: deck, where
    real(wp), intent(in) :: time, rest
    integer, intent(in) :: n_states
    integer, intent(in) :: kept(:)
    type(deck_string_t), intent(in) :: names(:)
    type(speed_modes_t), intent(in) :: locus(:)
    character(len=:), allocatable :: text
    integer :: i, k
    text = '{"deck": ' // json_string(deck) // ', "linearised_about": ' // json_string(where) // &
           ', "time": ' // json_real(time) // ', "states": ' // trim(int_text(n_states)) // ', "kept_states": ['
    do k = 1, size(kept)
      if (k > 1) text = text // ', '
      text = text // json_string(names(kept(k))%s)
    end do
    text = text // '], "largest_acceleration": ' // json_real(rest)
    if (size(locus) == 1) then
      text = text // ', "speed": ' // json_real(locus(1)%speed) // ', "modes": ' // modes_json(locus(1)%modes)
    else
      text = text // ', "root_locus": ['
      do i = 1, size(locus)
        if (i > 1) text = text // ', '
        text = text // '{"speed": ' // json_real(locus(i)%speed) // ', "modes": ' // modes_json(locus(i)%modes) // '}'
      end do
      text = text // ']'
    end if
    write (output_unit, '(a)') text // '}'
  contains
    function modes_json(modes) result(json)
      type(linear_mode_t), intent(in) :: modes(:)
      character(len=:), allocatable :: json, owner, dof
      integer :: j, d
      json = '['
      do j = 1, size(modes)
        associate (m => modes(j))
          if (j > 1) json = json // ', '
          json = json // '{"frequency_hz": ' // json_real(m%frequency) // ', "damping_ratio": ' // &
                 json_real(m%damping_ratio) // ', "real": ' // json_real(m%real_part) // ', "imag": ' // &
                 json_real(m%imag_part) // ', "neutral": ' // trim(merge('true ', 'false', m%neutral)) // &
                 ', "dominant": ['
          do d = 1, m%n_dominant
            call owner_and_dof(names(kept(m%dominant(d)))%s, owner, dof)
            if (d > 1) json = json // ', '
            json = json // '{"body": ' // json_string(owner) // ', "dof": ' // json_string(dof) // &
                   ', "share": ' // json_real(m%share(d)) // '}'
          end do
          json = json // ']}'
        end associate
      end do
      json = json // ']'
    end function modes_json
  end subroutine print_json

  !> The root locus as CSV: one row per mode and speed (docs/theory_stability.md section 4).
  subroutine write_locus_csv(path, locus, names, kept, error)
    character(len=*), intent(in) :: path
    type(speed_modes_t), intent(in) :: locus(:)
    type(deck_string_t), intent(in) :: names(:)
    integer, intent(in) :: kept(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: unit, ios, i, j
    open (newunit=unit, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, '--csv ' // path // ': cannot write the file')
      return
    end if
    write (unit, '(a)') 'speed,mode,frequency_hz,damping_ratio,real,imag,neutral,dominant'
    do i = 1, size(locus)
      do j = 1, size(locus(i)%modes)
        associate (m => locus(i)%modes(j))
          write (unit, '(a)') trim(sci_text(locus(i)%speed, 16, 3)) // ',' // trim(int_text(j)) // ',' // &
            trim(sci_text(m%frequency, 16, 3)) // ',' // trim(sci_text(m%damping_ratio, 16, 3)) // ',' // &
            trim(sci_text(m%real_part, 16, 3)) // ',' // trim(sci_text(m%imag_part, 16, 3)) // ',' // &
            trim(merge('1', '0', m%neutral)) // ',' // dominant_text(m, names, kept, '; ')
        end associate
      end do
    end do
    close (unit)
  end subroutine write_locus_csv

  !> The root-locus plot (python -m raildyn.plots root-locus), from the CSV (written to a
  !> scratch file beside the plot when --csv is not given, removed afterwards).
  subroutine plot_locus(plot, csv, locus, names, kept, error)
    character(len=*), intent(in) :: plot, csv
    type(speed_modes_t), intent(in) :: locus(:)
    type(deck_string_t), intent(in) :: names(:)
    integer, intent(in) :: kept(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: source
    integer :: status, unit
    source = csv
    if (len(source) == 0) then
      source = plot // '.locus.csv'
      call write_locus_csv(source, locus, names, kept, error)
      if (allocated(error)) return
    end if
    call execute_command_line(python_command() // ' -m raildyn.plots root-locus ' // shell_quote(source) // &
                              ' ' // shell_quote(plot), exitstat=status)
    if (len(csv) == 0) then
      open (newunit=unit, file=source, status='old')
      close (unit, status='delete')
    end if
    if (status /= 0) call make_error(error, RD_ERR_IO, '--plot ' // plot // ': plotting failed (needs Python 3 ' // &
                                     'with matplotlib)')
  end subroutine plot_locus
end module rd_cmd_eigen
