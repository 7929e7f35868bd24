!> `raildyn profile-scan`: wheel-rail contact characteristics (contact table) and
!> equivalent conicity of a wheel/rail pair.
!>
!>   raildyn profile-scan [--wheel FILE|s1002] [--rail FILE|60e1|54e1|uic60]
!>                        [--wheel-right FILE|s1002] [--rail-right FILE|60e1|54e1|uic60]
!>                        [--inclination 0.025] [--rail-precant 0] [--rail-precant-right P] [--gauge 1.435]
!>                        [--back-to-back 1.360] [--radius 0.46] [--ymax 0.010]
!>                        [--step 0.0005] [--yaw-per-shift 0] [--amplitude 0.003]...
!>                        [--lowering 5e-6] [--csv OUT.csv] [--h5 OUT.h5] [--plot OUT.png]
!> Profile files: SIMPACK .prw/.prr or y-z tables (rd_profile_io). --rail-precant is the
!> inclination already contained in a rail file (e.g. 0.025 for the Manchester UIC60 v3).
!> --wheel-right / --rail-right: a different right wheel / rail (default: the same as the
!> left), given in the same profile frame as a left one (docs/conventions.md "Profiles");
!> --rail-precant-right defaults to --rail-precant.
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
  use rd_contact_geometry, only: contact_geometry_t, init_strip_contact
  use rd_contact_patch, only: MAX_PATCHES
  use rd_profile_scan, only: profile_scan_t, run_profile_scan, equivalent_conicity
  use rd_hdf5_writer, only: h5_writer_t
  use rd_build_info, only: python_command, shell_quote
  implicit none
  private
  public :: run_profile_scan_command, profile_scan_usage, write_profile_scan_csv, write_profile_scan_h5

  character(len=*), parameter :: profile_scan_usage = 'usage: raildyn profile-scan [--wheel FILE|s1002] ' // &
    '[--rail FILE|60e1|54e1|uic60] [--wheel-right FILE|s1002] [--rail-right FILE|60e1|54e1|uic60] ' // &
    '[--inclination 0.025] [--rail-precant 0] [--rail-precant-right P] [--gauge 1.435] ' // &
    '[--back-to-back 1.360] [--radius 0.46] [--ymax 0.010] [--step 0.0005] [--yaw-per-shift 0] ' // &
    '[--amplitude 0.003]... [--lowering 5e-6] [--csv OUT.csv] [--h5 OUT.h5] [--plot OUT.png]'

contains

  subroutine run_profile_scan_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    character(len=:), allocatable :: wheel_name, rail_name, csv, h5, plot, wheel_right_name, rail_right_name
    type(track_placement_t) :: pl
    type(surface_options_t) :: opt
    type(profile_t) :: wprof, rprof, wprof_right, rprof_right
    type(contact_geometry_t) :: geo
    type(profile_scan_t) :: scan
    type(error_t), allocatable :: error
    real(wp) :: ymax, step, yaw_per_shift, lowering, value, amps(32), lam, precant_right
    integer :: i, namp, k, ios
    logical :: ok

    status = 2
    wheel_name = 's1002'; rail_name = '60e1'; csv = ''; h5 = ''; plot = ''
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
      case ('--wheel', '--rail', '--wheel-right', '--rail-right', '--csv', '--h5', '--plot')
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
    if (.not. allocated(error)) call init_strip_contact(geo, wprof, rprof, pl, opt, error, &
      wheel_profile_right=wprof_right, rail_profile_right=rprof_right, rail_precant_right=precant_right)
    if (.not. allocated(error)) call run_profile_scan(geo, ymax, step, yaw_per_shift, lowering, scan, error)
    if (allocated(error)) then
      write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
      return
    end if

    if (len(wheel_right_name) > 0 .or. len(rail_right_name) > 0) then
      if (len(wheel_right_name) == 0) wheel_right_name = wheel_name
      if (len(rail_right_name) == 0) rail_right_name = rail_name
      write (output_unit, '(a)') '# profile scan: left wheel ' // wheel_name // ', rail ' // rail_name // &
        '; right wheel ' // wheel_right_name // ', rail ' // rail_right_name
    else
      write (output_unit, '(a)') '# profile scan: wheel ' // wheel_name // ', rail ' // rail_name
    end if
    write (output_unit, '(a,f7.4,a,f6.3,a,f6.3,a,f6.3,a)') '# inclination ', pl%inclination, ', gauge ', pl%gauge, &
      ' m, back-to-back ', pl%back_to_back, ' m, r0 ', pl%nominal_radius, ' m'
    write (output_unit, '(a)') '#  y[mm]  roll[mrad] nL nR  rL[mm]    rR[mm]   dr[mm]  gL[rad]  gR[rad]'
    do k = 1, scan%n
      write (output_unit, '(f8.3,f10.4,2i3,2f10.3,f8.3,2f9.4)') 1000 * scan%y(k), 1000 * scan%roll(k), &
        scan%n_patches(:, k), 1000 * scan%rolling_radius(1, :, k), 1000 * scan%delta_r(k), scan%contact_angle(1, :, k)
    end do
    do k = 1, namp
      lam = equivalent_conicity(scan, amps(k), error)
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a,f7.4,a,f8.4)') 'equivalent conicity at amplitude ', 1000 * amps(k), ' mm: ', lam
    end do
    if (len(plot) > 0 .and. len(h5) == 0) h5 = plot(1:index(plot, '.', back=.true.) - 1) // '.h5'
    if (len(h5) > 0) then
      if (len(wheel_right_name) > 0) then
        call write_profile_scan_h5(h5, scan, wheel_name, rail_name, amps(1:namp), error, &
                                   wheel_right_name, rail_right_name)
      else
        call write_profile_scan_h5(h5, scan, wheel_name, rail_name, amps(1:namp), error)
      end if
      if (allocated(error)) then
        write (error_unit, '(a)') 'raildyn profile-scan: ' // error%message
        return
      end if
      write (output_unit, '(a)') 'wrote ' // h5
    end if
    if (len(plot) > 0) then
      call execute_command_line(python_command() // ' -m raildyn.plots profile-scan ' // &
                                shell_quote(h5) // ' ' // shell_quote(plot), exitstat=ios)
      if (ios /= 0) then
        write (error_unit, '(a)') 'raildyn profile-scan: plotting ' // plot // ' failed (needs Python 3 with ' // &
          'h5py and matplotlib; the HDF5 file was written)'
        return
      end if
      write (output_unit, '(a)') 'wrote ' // plot
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
  end subroutine run_profile_scan_command

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
  !> series `scan/...` per shift, equivalent conicities as root attributes.
  !> With per-side profiles the right ones are the attributes wheel_profile_right and
  !> rail_profile_right.
  subroutine write_profile_scan_h5(path, scan, wheel_name, rail_name, amplitudes, error, &
                                   wheel_right_name, rail_right_name)
    character(len=*), intent(in) :: path, wheel_name, rail_name
    type(profile_scan_t), intent(in) :: scan
    real(wp), intent(in) :: amplitudes(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: wheel_right_name, rail_right_name
    type(h5_writer_t) :: w
    integer :: id_pose, id_dr, id_n(2), id_p(MAX_PATCHES, 2), k, side, p
    character(len=5), parameter :: sides(2) = ['left ', 'right']
    character(len=16) :: tag
    real(wp) :: lam, vals(5)
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
      lam = equivalent_conicity(scan, amplitudes(k), error)
      if (allocated(error)) return
      write (tag, '(f0.1)') 1000 * amplitudes(k)
      call w%set_attribute('/', 'equivalent_conicity_' // trim(tag) // 'mm', lam, error)
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
