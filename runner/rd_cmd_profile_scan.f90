!> `raildyn profile-scan`: wheel-rail contact characteristics (contact table) and
!> equivalent conicity of a wheel/rail pair.
!>
!>   raildyn profile-scan [--wheel FILE|s1002] [--rail FILE|60e1|54e1|uic60]
!>                        [--wheel-right FILE|s1002] [--rail-right FILE|60e1|54e1|uic60]
!>                        [--inclination 0.025] [--rail-precant 0] [--rail-precant-right P] [--gauge 1.435]
!>                        [--back-to-back 1.360] [--radius 0.46] [--ymax 0.010]
!>                        [--step 0.0005] [--yaw-per-shift 0] [--amplitude 0.003]...
!>                        [--lowering 5e-6] [--csv OUT.csv] [--h5 OUT.h5] [--plot OUT.png]
!>                        [--conicity-csv OUT.csv] [--conicity-plot OUT.png] [--contact-plot OUT.png]
!>                        [--table DIR]
!> --table DIR: build the pair's contact table into DIR (or read it when DIR has it; the
!> same files and keys as the run-time cache, docs/theory_contact_geometry.md section 10)
!> and scan through the table instead of the online strips.
!> Profile files: SIMPACK .prw/.prr or y-z tables (rd_profile_io). --rail-precant is the
!> inclination already contained in a rail file (e.g. 0.025 for the Manchester UIC60 v3).
!> --wheel-right / --rail-right: a different right wheel / rail (default: the same as the
!> left), given in the same profile frame as a left one (docs/conventions.md "Profiles");
!> --rail-precant-right defaults to --rail-precant.
!> Equivalent conicity per --amplitude: harmonic (rd_profile_scan) and EN 15302's
!> integration (Klingel) and regression methods (rd_equivalent_conicity) on the scan's Delta r,
!> with r0 = --radius and e0 = half the distance between the centred wheelset's contact
!> points. --conicity-csv: the three against the amplitude (every 0.1 mm up to what the scan
!> supports), --conicity-plot its plot; --contact-plot: both profiles with lines joining their
!> contact points for the scanned shifts (writes OUT_profiles.csv beside it and the scan's
!> HDF5 file as --plot does).
!> All values SI. Prints a table and the equivalent conicities; exit status 0, 1 when the
!> computation fails, 2 for bad usage (one line on stderr).
module rd_cmd_profile_scan
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_text, only: sci_text
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_IO
  use rd_profile, only: profile_t
  use rd_profile_source, only: load_wheel_profile, load_rail_profile
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, build_table_contact
  use rd_contact_table, only: contact_table_options_t
  use rd_contact_patch, only: MAX_PATCHES
  use rd_profile_scan, only: profile_scan_t, run_profile_scan, equivalent_conicity
  use rd_delta_r_table, only: delta_r_table_t, build_delta_r_table
  use rd_equivalent_conicity, only: kinematic_motion_t, en15302_conicity
  use rd_cmd_conicity, only: default_amplitudes
  use rd_profile_curves_csv, only: write_profile_curves_csv
  use rd_hdf5_writer, only: h5_writer_t
  use rd_build_info, only: python_command, shell_quote
  implicit none
  private
  public :: run_profile_scan_command, profile_scan_usage, write_profile_scan_csv, write_profile_scan_h5

  character(len=*), parameter :: profile_scan_usage = 'usage: raildyn profile-scan [--wheel FILE|s1002] ' // &
    '[--rail FILE|60e1|54e1|uic60] [--wheel-right FILE|s1002] [--rail-right FILE|60e1|54e1|uic60] ' // &
    '[--inclination 0.025] [--rail-precant 0] [--rail-precant-right P] [--gauge 1.435] ' // &
    '[--back-to-back 1.360] [--radius 0.46] [--ymax 0.010] [--step 0.0005] [--yaw-per-shift 0] ' // &
    '[--amplitude 0.003]... [--lowering 5e-6] [--csv OUT.csv] [--h5 OUT.h5] [--plot OUT.png] ' // &
    '[--conicity-csv OUT.csv] [--conicity-plot OUT.png] [--contact-plot OUT.png] [--table DIR]'
  !> Step of the amplitudes of --conicity-csv [m].
  real(wp), parameter :: CONICITY_CSV_STEP = 1.0e-4_wp

contains

  subroutine run_profile_scan_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: wheel_name, rail_name, csv, h5, plot, wheel_right_name, rail_right_name
    character(len=:), allocatable :: pair  !< the profiles, as the scan's header and plot title name them
    character(len=:), allocatable :: conicity_csv, conicity_plot, contact_plot, curves_csv
    type(delta_r_table_t) :: table
    type(kinematic_motion_t) :: motions(32)
    real(wp) :: harmonic(32), e0
    character(len=:), allocatable :: table_dir
    type(contact_table_options_t) :: table_options
    type(track_placement_t) :: pl
    type(surface_options_t) :: opt
    type(profile_t) :: wprof, rprof, wprof_right, rprof_right
    type(contact_geometry_t) :: geo
    type(profile_scan_t) :: scan
    type(error_t), allocatable :: error
    real(wp) :: ymax, step, yaw_per_shift, lowering, value, amps(32), precant_right
    integer :: i, namp, k, ios
    logical :: ok

    status = 2
    wheel_name = 's1002'; rail_name = '60e1'; csv = ''; h5 = ''; plot = ''
    conicity_csv = ''; conicity_plot = ''; contact_plot = ''
    table_dir = ''
    wheel_right_name = ''; rail_right_name = ''; precant_right = -1
    ymax = 0.010_wp; step = 0.0005_wp; yaw_per_shift = 0; lowering = 5.0e-6_wp
    namp = 0
    i = 1
    do while (i <= size(args))
      select case (trim(args(i)))
      case ('--help', '-h')
        write (output_unit, '(a)') profile_scan_usage
        status = 0
        return
      case ('--wheel', '--rail', '--wheel-right', '--rail-right', '--csv', '--h5', '--plot', '--conicity-csv', &
            '--conicity-plot', '--contact-plot', '--table')
        if (i + 1 > size(args)) then
          call bad(trim(args(i)) // ' expects a value'); return
        end if
        select case (trim(args(i)))
        case ('--wheel'); wheel_name = trim(args(i + 1))
        case ('--rail'); rail_name = trim(args(i + 1))
        case ('--wheel-right'); wheel_right_name = trim(args(i + 1))
        case ('--rail-right'); rail_right_name = trim(args(i + 1))
        case ('--csv'); csv = trim(args(i + 1))
        case ('--h5'); h5 = trim(args(i + 1))
        case ('--plot'); plot = trim(args(i + 1))
        case ('--conicity-csv'); conicity_csv = trim(args(i + 1))
        case ('--conicity-plot'); conicity_plot = trim(args(i + 1))
        case ('--contact-plot'); contact_plot = trim(args(i + 1))
        case ('--table'); table_dir = trim(args(i + 1))
        end select
        i = i + 2
        cycle
      case ('--inclination', '--rail-precant', '--rail-precant-right', '--gauge', '--back-to-back', '--radius', '--ymax', '--step', &
            '--yaw-per-shift', '--amplitude', '--lowering')
        if (i + 1 > size(args)) then
          call bad(trim(args(i)) // ' expects a number (SI units)'); return
        end if
        read (args(i + 1), *, iostat=k) value
        ok = k == 0
        if (ok) ok = ieee_is_finite(value)
        if (.not. ok) then
          call bad(trim(args(i)) // " expects a number (SI units), got '" // trim(args(i + 1)) // "'"); return
        end if
        select case (trim(args(i)))
        case ('--inclination'); pl%inclination = value
        case ('--rail-precant'); pl%rail_precant = value
        case ('--rail-precant-right')
          if (.not. (value >= 0 .and. value <= 0.1_wp)) then
            call bad('--rail-precant-right expects a slope in [0, 0.1] (tan)'); return
          end if
          precant_right = value
        case ('--gauge'); pl%gauge = value
        case ('--back-to-back'); pl%back_to_back = value
        case ('--radius'); pl%nominal_radius = value
        case ('--ymax'); ymax = value
        case ('--step'); step = value
        case ('--yaw-per-shift'); yaw_per_shift = value
        case ('--lowering'); lowering = value
        case ('--amplitude')
          if (namp == size(amps)) then
            call bad('at most 32 --amplitude values'); return
          end if
          namp = namp + 1
          amps(namp) = value
        end select
        i = i + 2
        cycle
      case default
        call bad("unknown option '" // trim(args(i)) // "'"); return
      end select
    end do
    if (namp == 0) then
      namp = 1; amps(1) = 0.003_wp
    end if

    status = 1
    call load_wheel_profile(wheel_name, wprof, error)
    if (.not. allocated(error)) call load_rail_profile(rail_name, rprof, error)
    ! right side: its own profile when named, else the left one (shared, not copied)
    if (.not. allocated(error)) then
      if (len(wheel_right_name) > 0) then
        call load_wheel_profile(wheel_right_name, wprof_right, error)
      else
        wprof_right = wprof
      end if
    end if
    if (.not. allocated(error)) then
      if (len(rail_right_name) > 0) then
        call load_rail_profile(rail_right_name, rprof_right, error)
      else
        rprof_right = rprof
      end if
    end if
    if (precant_right < 0) precant_right = pl%rail_precant
    if (.not. allocated(error)) call build_strip_contact(geo, wprof, rprof, pl, opt, error, &
      wheel_profile_right=wprof_right, rail_profile_right=rprof_right, rail_precant_right=precant_right)
    ! --table DIR: the contact table of the pair (built, or read when DIR has it) and the
    ! scan through it (docs/theory_contact_geometry.md section 10)
    if (.not. allocated(error) .and. len(table_dir) > 0) call build_table_contact(geo, table_options, error, table_dir)
    if (.not. allocated(error)) call run_profile_scan(geo, ymax, step, yaw_per_shift, lowering, scan, error)
    if (allocated(error)) then
      write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
      return
    end if

    if (len(wheel_right_name) > 0 .or. len(rail_right_name) > 0) then
      if (len(wheel_right_name) == 0) wheel_right_name = wheel_name
      if (len(rail_right_name) == 0) rail_right_name = rail_name
      pair = 'left wheel ' // wheel_name // ', rail ' // rail_name // &
        '; right wheel ' // wheel_right_name // ', rail ' // rail_right_name
    else
      pair = 'wheel ' // wheel_name // ', rail ' // rail_name
    end if
    write (output_unit, '(a)') '# profile scan: ' // pair
    if (len(table_dir) > 0) write (output_unit, '(a)') '# through the contact table in ' // table_dir
    write (output_unit, '(a,f7.4,a,f6.3,a,f6.3,a,f6.3,a)') '# inclination ', pl%inclination, ', gauge ', pl%gauge, &
      ' m, back-to-back ', pl%back_to_back, ' m, r0 ', pl%nominal_radius, ' m'
    write (output_unit, '(a)') '#  y[mm]  roll[mrad] nL nR  rL[mm]    rR[mm]   dr[mm]  gL[rad]  gR[rad]'
    do k = 1, scan%n
      write (output_unit, '(f8.3,f10.4,2i3,2f10.3,f8.3,2f9.4)') 1000 * scan%y(k), 1000 * scan%roll(k), &
        scan%n_patches(:, k), 1000 * scan%rolling_radius(1, :, k), 1000 * scan%delta_r(k), scan%contact_angle(1, :, k)
    end do
    call scan_delta_r(scan, table, e0, error)
    do k = 1, namp
      if (allocated(error)) exit
      harmonic(k) = equivalent_conicity(scan, amps(k), error)
      if (.not. allocated(error)) call en15302_conicity(table, amps(k), pl%nominal_radius, e0, motions(k), error)
      if (allocated(error)) exit
      write (output_unit, '(a,f7.4,a,f8.4,a,f8.4,a,f8.4)') 'equivalent conicity at amplitude ', 1000 * amps(k), &
        ' mm: ', harmonic(k), ' (harmonic); EN 15302 integration', motions(k)%conicity_integration, &
        ', regression', motions(k)%conicity_regression
    end do
    if (allocated(error)) then
      write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
      return
    end if
    if (len(conicity_plot) > 0 .and. len(conicity_csv) == 0) conicity_csv = stem(conicity_plot) // '.csv'
    if (len(conicity_csv) > 0) then
      call write_conicity_csv(conicity_csv, scan, table, pl%nominal_radius, e0, error)
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a)') 'wrote ' // conicity_csv
    end if
    if (len(contact_plot) > 0) then
      curves_csv = stem(contact_plot) // '_profiles.csv'
      call write_profile_curves_csv(curves_csv, geo, scan%z((scan%n + 1) / 2), error)
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a)') 'wrote ' // curves_csv
    end if
    if (len(h5) == 0) then
      if (len(plot) > 0) then
        h5 = stem(plot) // '.h5'
      else if (len(contact_plot) > 0) then
        h5 = stem(contact_plot) // '.h5'
      end if
    end if
    if (len(h5) > 0) then
      if (len(wheel_right_name) > 0) then
        call write_profile_scan_h5(h5, scan, wheel_name, rail_name, amps(1:namp), harmonic(1:namp), &
                                   motions(1:namp), error, wheel_right_name, rail_right_name)
      else
        call write_profile_scan_h5(h5, scan, wheel_name, rail_name, amps(1:namp), harmonic(1:namp), &
                                   motions(1:namp), error)
      end if
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a)') 'wrote ' // h5
    end if
    if (len(plot) > 0) then
      if (.not. plotted('profile-scan ' // shell_quote(h5), plot)) return
    end if
    if (len(conicity_plot) > 0) then
      if (.not. plotted('conicity ' // shell_quote(conicity_csv) // ' --title ' // &
                        shell_quote('equivalent conicity: ' // pair), &
                        conicity_plot)) return
    end if
    if (len(contact_plot) > 0) then
      if (.not. plotted('contact-points ' // shell_quote(h5) // ' ' // shell_quote(curves_csv), contact_plot)) return
    end if
    if (len(csv) > 0) then
      call write_profile_scan_csv(csv, scan, error)
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a)') 'wrote ' // csv
    end if
    status = 0
  contains
    subroutine bad(msg)
      character(len=*), intent(in) :: msg
      write (error_unit, '(a)') 'raildyn profile-scan: ' // msg
      write (error_unit, '(a)') profile_scan_usage
    end subroutine bad

    !> Run `python -m raildyn.plots ARGS OUT`; .false. (and a message) when it fails.
    logical function plotted(plot_args, out)
      character(len=*), intent(in) :: plot_args, out
      call execute_command_line(python_command() // ' -m raildyn.plots ' // plot_args // ' ' // shell_quote(out), &
                                exitstat=ios)
      plotted = ios == 0
      if (plotted) then
        write (output_unit, '(a)') 'wrote ' // out
      else
        write (error_unit, '(a)') 'raildyn profile-scan: plotting ' // out // ' failed (needs Python 3 with ' // &
          'h5py and matplotlib; the data files were written)'
      end if
    end function plotted
  end subroutine run_profile_scan_command

  !> A path without its extension.
  pure function stem(path) result(s)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: s
    integer :: dot
    dot = index(path, '.', back=.true.)
    if (dot <= index(path, '/', back=.true.)) dot = len(path) + 1
    s = path(1:dot - 1)
  end function stem

  !> The scan's rolling-radius difference as a table, and half the lateral distance between
  !> the main contact points of the centred wheelset (the e0 of Klingel's formula) [m].
  subroutine scan_delta_r(scan, table, e0, error)
    type(profile_scan_t), intent(in) :: scan
    type(delta_r_table_t), intent(out) :: table
    real(wp), intent(out) :: e0
    type(error_t), allocatable, intent(out) :: error
    integer :: k0
    k0 = (scan%n + 1) / 2
    e0 = 0.5_wp * (scan%y_rail(1, 1, k0) - scan%y_rail(1, 2, k0))
    call build_delta_r_table(table, scan%y, scan%delta_r, error, origin='profile scan')
  end subroutine scan_delta_r

  !> Conicity against amplitude, one row per amplitude (every CONICITY_CSV_STEP up to the
  !> largest the scan supports by all three methods): amplitude_m, harmonic, integration,
  !> regression, wavelength_m (empty where the motion stays inside a zone with Delta r = 0).
  subroutine write_conicity_csv(path, scan, table, r0, e0, error)
    character(len=*), intent(in) :: path
    type(profile_scan_t), intent(in) :: scan
    type(delta_r_table_t), intent(in) :: table
    real(wp), intent(in) :: r0, e0
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: amplitudes(:)
    type(kinematic_motion_t) :: m
    real(wp) :: lam
    character(len=:), allocatable :: wavelength
    integer :: u, ios, k
    call default_amplitudes(table, CONICITY_CSV_STEP, amplitudes, error)
    if (allocated(error)) return
    ! the harmonic one stays inside the scan (its own test allows the same rounding)
    amplitudes = pack(amplitudes, amplitudes <= scan%y(scan%n) * (1 + 1.0e-12_wp))
    open (newunit=u, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot write ' // path)
      return
    end if
    write (u, '(a)') 'amplitude_m,harmonic,integration,regression,wavelength_m'
    do k = 1, size(amplitudes)
      lam = equivalent_conicity(scan, amplitudes(k), error)
      if (.not. allocated(error)) call en15302_conicity(table, amplitudes(k), r0, e0, m, error)
      if (allocated(error)) then
        close (u)
        return
      end if
      wavelength = ''
      if (m%oscillates) wavelength = num(m%wavelength)
      write (u, '(a)') num(amplitudes(k)) // ',' // num(lam) // ',' // num(m%conicity_integration) // ',' // &
        num(m%conicity_regression) // ',' // wavelength
    end do
    close (u)
  end subroutine write_conicity_csv

  !> One row per shift. Columns (SI): y_m, yaw_rad, z_m, roll_rad, delta_r_m, then per side
  !> (left, right): <side>_n_patches and per patch p = 1..4 (by decreasing penetration)
  !> <side>_p<p>_s_wheel_m, _u_rail_m, _y_rail_m, _rolling_radius_m, _contact_angle_rad
  !> (empty fields for absent patches).
  subroutine write_profile_scan_csv(path, scan, error)
    character(len=*), intent(in) :: path
    type(profile_scan_t), intent(in) :: scan
    type(error_t), allocatable, intent(out) :: error
    character(len=*), parameter :: side_name(2) = ['left ', 'right']
    character(len=:), allocatable :: head
    character(len=40) :: pre
    integer :: u, ios, k, s, p
    open (newunit=u, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot write ' // path)
      return
    end if
    head = 'y_m,yaw_rad,z_m,roll_rad,delta_r_m'
    do s = 1, 2
      head = head // ',' // trim(side_name(s)) // '_n_patches'
      do p = 1, MAX_PATCHES
        write (pre, '(a,"_p",i0,"_")') trim(side_name(s)), p
        head = head // ',' // trim(pre) // 's_wheel_m,' // trim(pre) // 'u_rail_m,' // trim(pre) // 'y_rail_m,' // &
          trim(pre) // 'rolling_radius_m,' // trim(pre) // 'contact_angle_rad'
      end do
    end do
    write (u, '(a)') head
    do k = 1, scan%n
      write (u, '(a)', advance='no') num(scan%y(k)) // ',' // num(scan%yaw(k)) // ',' // num(scan%z(k)) // ',' // &
        num(scan%roll(k)) // ',' // num(scan%delta_r(k))
      do s = 1, 2
        write (u, '(",",i0)', advance='no') scan%n_patches(s, k)
        do p = 1, MAX_PATCHES
          if (p <= scan%n_patches(s, k)) then
            write (u, '(a)', advance='no') ',' // num(scan%s_wheel(p, s, k)) // ',' // num(scan%u_rail(p, s, k)) // &
              ',' // num(scan%y_rail(p, s, k)) // ',' // num(scan%rolling_radius(p, s, k)) // ',' // &
              num(scan%contact_angle(p, s, k))
          else
            write (u, '(a)', advance='no') ',,,,,'
          end if
        end do
      end do
      write (u, '(a)') ''
    end do
    close (u)
  end subroutine write_profile_scan_csv

  !> A number in CSV: shortest round-trip-safe exponent form, no blanks, no negative zero.
  function num(x) result(t)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: t
    if (x == 0) then
      t = '0'
    else
      t = trim(sci_text(x, 15, 3))
    end if
  end function num

  !> The scan in the results layout (docs/output.md), with the lateral shift as the axis:
  !> series `scan/...` per shift, equivalent conicities as root attributes
  !> (equivalent_conicity_<A>mm harmonic, equivalent_conicity_integration_<A>mm and
  !> equivalent_conicity_regression_<A>mm EN 15302).
  !> With per-side profiles the right ones are the attributes wheel_profile_right and
  !> rail_profile_right.
  subroutine write_profile_scan_h5(path, scan, wheel_name, rail_name, amplitudes, harmonic, motions, error, &
                                   wheel_right_name, rail_right_name)
    character(len=*), intent(in) :: path, wheel_name, rail_name
    type(profile_scan_t), intent(in) :: scan
    real(wp), intent(in) :: amplitudes(:), harmonic(:)
    type(kinematic_motion_t), intent(in) :: motions(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: wheel_right_name, rail_right_name
    type(h5_writer_t) :: w
    integer :: id_pose, id_dr, id_n(2), id_p(MAX_PATCHES, 2), k, side, p
    character(len=5), parameter :: sides(2) = ['left ', 'right']
    character(len=16) :: tag
    real(wp) :: vals(5)
    call w%open(path, error, axis_name='y', axis_unit='m', &
                axis_description='lateral shift of the wheelset (+ left)')
    if (allocated(error)) return
    call w%set_attribute('/', 'wheel_profile', wheel_name, error); if (allocated(error)) return
    call w%set_attribute('/', 'rail_profile', rail_name, error); if (allocated(error)) return
    if (present(wheel_right_name)) then
      call w%set_attribute('/', 'wheel_profile_right', wheel_right_name, error); if (allocated(error)) return
    end if
    if (present(rail_right_name)) then
      call w%set_attribute('/', 'rail_profile_right', rail_right_name, error); if (allocated(error)) return
    end if
    do k = 1, size(amplitudes)
      write (tag, '(f0.1)') 1000 * amplitudes(k)
      call w%set_attribute('/', 'equivalent_conicity_' // trim(tag) // 'mm', harmonic(k), error)
      if (allocated(error)) return
      call w%set_attribute('/', 'equivalent_conicity_integration_' // trim(tag) // 'mm', &
                           motions(k)%conicity_integration, error)
      if (allocated(error)) return
      call w%set_attribute('/', 'equivalent_conicity_regression_' // trim(tag) // 'mm', &
                           motions(k)%conicity_regression, error)
      if (allocated(error)) return
    end do
    call w%add_series('scan/pose', 3, 'rad m rad', 'yaw, height of the wheelset centre and roll ' // &
                      'at rigid contact', id_pose, error, component_names='yaw z roll')
    if (allocated(error)) return
    call w%add_series('scan/delta_r', 1, 'm', 'rolling radius difference left - right (main patches)', &
                      id_dr, error, component_names='delta_r')
    if (allocated(error)) return
    do side = 1, 2
      call w%add_series('scan/' // trim(sides(side)) // '/n_patches', 1, '1', 'number of contact patches', &
                        id_n(side), error, component_names='n')
      if (allocated(error)) return
      do p = 1, MAX_PATCHES
        write (tag, '(i0)') p
        call w%add_series('scan/' // trim(sides(side)) // '/patch' // trim(tag), 5, 'm m m m rad', &
          'patch by decreasing penetration (zeros when absent): position on the wheel profile, ' // &
          'on the rail profile, lateral position in the track frame, rolling radius, contact angle', &
          id_p(p, side), error, component_names='s_wheel u_rail y_rail rolling_radius contact_angle')
        if (allocated(error)) return
      end do
    end do
    do k = 1, scan%n
      call w%set(id_pose, [scan%yaw(k), scan%z(k), scan%roll(k)], error); if (allocated(error)) return
      call w%set(id_dr, [scan%delta_r(k)], error); if (allocated(error)) return
      do side = 1, 2
        call w%set(id_n(side), [real(scan%n_patches(side, k), wp)], error); if (allocated(error)) return
        do p = 1, MAX_PATCHES
          vals = 0
          if (p <= scan%n_patches(side, k)) vals = [scan%s_wheel(p, side, k), scan%u_rail(p, side, k), &
            scan%y_rail(p, side, k), scan%rolling_radius(p, side, k), scan%contact_angle(p, side, k)]
          call w%set(id_p(p, side), vals, error); if (allocated(error)) return
        end do
      end do
      call w%end_step(scan%y(k), error); if (allocated(error)) return
    end do
    call w%close('completed', scan%y(scan%n), 0.0_wp, error)
  end subroutine write_profile_scan_h5
end module rd_cmd_profile_scan
