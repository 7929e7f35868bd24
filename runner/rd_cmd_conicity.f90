!> `raildyn conicity`: EN 15302 equivalent conicity of a given rolling-radius difference
!> function, the way the standard's benchmark tests a calculation method.
!>
!>   raildyn conicity --delta-r FILE.csv --r0 R0 --e0 E0 [--amplitudes A1,A2,...] [--json]
!>
!> FILE.csv: two comma-separated columns without header, y and Delta r = r_left - r_right in
!> metres, y ascending, linear between rows (rd_delta_r_table). R0: nominal rolling radius,
!> E0: half the distance between the contact points [m]. Amplitudes [m]: half the
!> peak-to-peak kinematic motion about the zero of Delta r; default every 0.5 mm up to the
!> largest amplitude the table supports. Prints a table, or with --json one object
!>   {"delta_r_file", "r0", "e0", "amplitude": [m], "conicity": [integration (Klingel)],
!>    "conicity_regression": [...], "wavelength": [m, null where the motion stays inside a
!>    zone with Delta r = 0]}.
!> Exit status 0; 1 bad usage or bad input (the message names file and line), 4 a file that
!> cannot be read.
module rd_cmd_conicity
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_text, only: int_text, real_text, fixed_text
  use rd_error, only: error_t, error_context
  use rd_delta_r_table, only: delta_r_table_t, read_delta_r_file
  use rd_equivalent_conicity, only: kinematic_motion_t, en15302_conicity, largest_amplitude, AMPLITUDE_ROUNDING
  implicit none
  private
  public :: run_conicity_command, conicity_usage, default_amplitudes

  character(len=*), parameter :: conicity_usage = 'usage: raildyn conicity --delta-r FILE.csv --r0 R0 --e0 E0 ' // &
    '[--amplitudes A1,A2,...] [--json]'
  !> Step of the default amplitudes [m].
  real(wp), parameter :: DEFAULT_AMPLITUDE_STEP = 0.0005_wp

contains

  subroutine run_conicity_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: path, list
    real(wp) :: r0, e0, value
    real(wp), allocatable :: amplitudes(:)
    type(delta_r_table_t) :: table
    type(kinematic_motion_t), allocatable :: motions(:)
    type(error_t), allocatable :: error
    logical :: json
    integer :: i, k, ios

    status = 1
    path = ''; list = ''; r0 = -1; e0 = -1; json = .false.
    i = 1
    do while (i <= size(args))
      select case (trim(args(i)))
      case ('--help', '-h')
        write (output_unit, '(a)') conicity_usage
        status = 0
        return
      case ('--json')
        json = .true.
        i = i + 1
        cycle
      case ('--delta-r', '--amplitudes', '--r0', '--e0')
        if (i + 1 > size(args)) then
          call bad(trim(args(i)) // ' expects a value'); return
        end if
        select case (trim(args(i)))
        case ('--delta-r'); path = trim(args(i + 1))
        case ('--amplitudes'); list = trim(args(i + 1))
        case default
          read (args(i + 1), *, iostat=ios) value
          if (ios /= 0 .or. scan(args(i + 1), '/*,') /= 0) value = -1
          if (.not. ieee_is_finite(value)) value = -1
          if (.not. (value > 0 .and. value < 10)) then
            call bad(trim(args(i)) // " expects a length in metres in (0, 10), got '" // trim(args(i + 1)) // "'")
            return
          end if
          if (trim(args(i)) == '--r0') then
            r0 = value
          else
            e0 = value
          end if
        end select
        i = i + 2
        cycle
      case default
        call bad("unknown option '" // trim(args(i)) // "'"); return
      end select
    end do
    if (len(path) == 0) then
      call bad('--delta-r FILE is required'); return
    end if
    if (r0 < 0 .or. e0 < 0) then
      call bad('--r0 and --e0 are required (nominal rolling radius, half the distance between the contact ' // &
               'points, metres)'); return
    end if
    if (len(list) > 0) then
      call parse_amplitudes(list, amplitudes, status)
      if (status /= 0) return
      status = 1
    end if

    call read_delta_r_file(path, table, error)
    if (.not. allocated(error) .and. len(list) == 0) call default_amplitudes(table, DEFAULT_AMPLITUDE_STEP, amplitudes, error)
    if (.not. allocated(error)) then
      allocate (motions(size(amplitudes)))
      do k = 1, size(amplitudes)
        call en15302_conicity(table, amplitudes(k), r0, e0, motions(k), error)
        if (allocated(error)) exit
      end do
    end if
    if (allocated(error)) then
      if (index(error%message, path) /= 1) call error_context(error, path)
      write (error_unit, '(a)') 'raildyn conicity: ' // error%message
      status = error%code
      return
    end if
    if (json) then
      call print_json(path, r0, e0, motions)
    else
      call print_table(path, r0, e0, motions)
    end if
    status = 0
  contains
    subroutine bad(msg)
      character(len=*), intent(in) :: msg
      write (error_unit, '(a)') 'raildyn conicity: ' // msg
      write (error_unit, '(a)') conicity_usage
    end subroutine bad

    subroutine parse_amplitudes(text, values, status)
      character(len=*), intent(in) :: text
      real(wp), allocatable, intent(out) :: values(:)
      integer, intent(out) :: status
      integer :: first, last, n
      real(wp) :: v
      allocate (values(0))
      status = 0
      first = 1
      n = 0
      do while (first <= len(text) + 1)
        last = index(text(first:), ',')
        if (last == 0) then
          last = len(text)
        else
          last = first + last - 2
        end if
        n = n + 1
        v = -1
        if (last >= first) then
          read (text(first:last), *, iostat=ios) v
          if (ios /= 0 .or. scan(text(first:last), '/*') /= 0) v = -1
          if (.not. ieee_is_finite(v)) v = -1
        end if
        if (.not. (v > 0)) then
          call bad("--amplitudes: entry " // trim(int_text(n)) // " '" // text(first:max(first, last)) // &
                   "' is not a positive length in metres (a comma-separated list, e.g. 0.001,0.002,0.003)")
          status = 1
          return
        end if
        values = [values, v]
        first = last + 2
      end do
    end subroutine parse_amplitudes
  end subroutine run_conicity_command

  !> Every `step` up to the largest amplitude the table supports.
  subroutine default_amplitudes(table, step, amplitudes, error)
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: step
    real(wp), allocatable, intent(out) :: amplitudes(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: a_max
    integer :: n, k
    a_max = largest_amplitude(table, error)
    if (allocated(error)) return
    n = min(int(a_max / step * (1 + AMPLITUDE_ROUNDING)), 400)
    amplitudes = [(step * k, k=1, n)]
    if (n == 0) amplitudes = [a_max]
  end subroutine default_amplitudes

  subroutine print_json(path, r0, e0, motions)
    use rd_json, only: json_string, json_real
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: r0, e0
    type(kinematic_motion_t), intent(in) :: motions(:)
    character(len=:), allocatable :: amp, lam, reg, wl
    integer :: k
    amp = ''; lam = ''; reg = ''; wl = ''
    do k = 1, size(motions)
      if (k > 1) then
        amp = amp // ', '; lam = lam // ', '; reg = reg // ', '; wl = wl // ', '
      end if
      amp = amp // json_real(motions(k)%amplitude)
      lam = lam // json_real(motions(k)%conicity_integration)
      reg = reg // json_real(motions(k)%conicity_regression)
      if (motions(k)%oscillates) then
        wl = wl // json_real(motions(k)%wavelength)
      else
        wl = wl // 'null'
      end if
    end do
    write (output_unit, '(a)') '{"delta_r_file": ' // json_string(path) // ', "r0": ' // json_real(r0) // &
      ', "e0": ' // json_real(e0) // ', "amplitude": [' // amp // '], "conicity": [' // lam // &
      '], "conicity_regression": [' // reg // '], "wavelength": [' // wl // ']}'
  end subroutine print_json

  subroutine print_table(path, r0, e0, motions)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: r0, e0
    type(kinematic_motion_t), intent(in) :: motions(:)
    character(len=16) :: wl
    integer :: k
    write (output_unit, '(a)') '# EN 15302 equivalent conicity of ' // path // ' (r0 ' // trim(real_text(r0)) // &
      ' m, e0 ' // trim(real_text(e0)) // ' m)'
    write (output_unit, '(a)') '# amplitude[mm]  integration  regression  wavelength[m]  y_min[mm]  y_max[mm]'
    do k = 1, size(motions)
      associate (m => motions(k))
        wl = 'inf'
        if (m%oscillates) wl = fixed_text(m%wavelength, 3)
        write (output_unit, '(f14.3,2f12.5,a15,2f11.4)') 1000 * m%amplitude, m%conicity_integration, &
          m%conicity_regression, trim(wl), 1000 * m%y_min, 1000 * m%y_max
      end associate
    end do
  end subroutine print_table
end module rd_cmd_conicity
