!> `raildyn hertz`: the Hertz contact patch for given curvatures (or radii), material and
!> normal force or penetration, printed as one JSON object in SI units.
!>
!>   raildyn hertz (--curvatures KXW KYW KXR KYR | --wheel-radius R
!>                  [--wheel-transverse-radius RT] [--rail-radius RR]
!>                  [--rail-longitudinal-radius RL])
!>                 (--normal-force N | --penetration D)
!>                 [--young E --poisson NU | --shear-modulus G --poisson NU]
!>                 [--method elliptic|elliptic_table|table] [--max-radius RMAX]
!> Radii in m, signed (convex > 0, concave < 0), 'inf' for flat; curvatures in 1/m.
!> Exit status 0, or 2 with one line on stderr for bad usage.
module rd_cmd_hertz
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use rd_text, only: int_text, sci_text
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_hertz, only: hertz_params_t, hertz_patch_t, build_hertz, hertz_from_force, hertz_from_penetration
  implicit none
  private
  public :: run_hertz_command, hertz_usage

  character(len=*), parameter :: hertz_usage = 'usage: raildyn hertz (--curvatures KXW KYW KXR KYR | ' // &
    '--wheel-radius R [--wheel-transverse-radius RT] [--rail-radius RR] [--rail-longitudinal-radius RL]) ' // &
    '(--normal-force N | --penetration D) [--young E | --shear-modulus G] [--poisson NU] ' // &
    '[--method elliptic|elliptic_table|table] [--max-radius RMAX]'

contains

  subroutine run_hertz_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    real(wp) :: curv(4), young, shear, poisson, force, penetration, rmax
    logical :: have_curv, have_radius, have_force, have_pen, have_young, have_shear, ok
    character(len=16) :: method
    type(hertz_params_t) :: params
    type(hertz_patch_t) :: patch
    type(error_t), allocatable :: error
    integer :: i, k

    status = 2
    curv = 0.0_wp
    have_curv = .false.; have_radius = .false.; have_force = .false.; have_pen = .false.
    have_young = .false.; have_shear = .false.
    poisson = 0.28_wp; young = 0.0_wp; shear = 82.0e9_wp; rmax = 10.0_wp; method = 'elliptic'
    if (size(args) == 0) then
      write (error_unit, '(a)') hertz_usage
      return
    end if
    i = 1
    do while (i <= size(args))
      select case (trim(args(i)))
      case ('--help', '-h')
        write (output_unit, '(a)') hertz_usage
        status = 0
        return
      case ('--curvatures')
        if (i + 4 > size(args)) then
          call bad('--curvatures expects four curvatures KXW KYW KXR KYR [1/m]'); return
        end if
        do k = 1, 4
          call real_arg(args(i + k), '--curvatures', curv(k), ok)
          if (.not. ok) return
        end do
        have_curv = .true.
        i = i + 5
        cycle
      case ('--wheel-radius')
        call radius_arg(i, curv(1), ok); if (.not. ok) return
        have_radius = .true.
      case ('--wheel-transverse-radius')
        call radius_arg(i, curv(2), ok); if (.not. ok) return
      case ('--rail-radius')
        call radius_arg(i, curv(4), ok); if (.not. ok) return
      case ('--rail-longitudinal-radius')
        call radius_arg(i, curv(3), ok); if (.not. ok) return
      case ('--normal-force')
        call value_arg(i, force, ok); if (.not. ok) return
        have_force = .true.
      case ('--penetration')
        call value_arg(i, penetration, ok); if (.not. ok) return
        have_pen = .true.
      case ('--young')
        call value_arg(i, young, ok); if (.not. ok) return
        have_young = .true.
      case ('--shear-modulus')
        call value_arg(i, shear, ok); if (.not. ok) return
        have_shear = .true.
      case ('--poisson')
        call value_arg(i, poisson, ok); if (.not. ok) return
      case ('--max-radius')
        call value_arg(i, rmax, ok); if (.not. ok) return
      case ('--method')
        if (i + 1 > size(args)) then
          call bad('--method expects elliptic, elliptic_table or table'); return
        end if
        method = args(i + 1)
      case default
        call bad("unknown option '" // trim(args(i)) // "'"); return
      end select
      i = i + 2
    end do

    if (have_curv .eqv. have_radius) then
      call bad('give either --curvatures or --wheel-radius (with the other radii)'); return
    end if
    if (have_force .eqv. have_pen) then
      call bad('give exactly one of --normal-force N [N] or --penetration D [m]'); return
    end if
    if (have_young .and. have_shear) then
      call bad('give --young or --shear-modulus, not both'); return
    end if
    if (.not. have_young) young = 2.0_wp * shear * (1.0_wp + poisson)
    if (have_force .and. .not. (force > 0.0_wp)) then
      call bad('--normal-force must be > 0 N'); return
    end if
    call build_hertz(params, error, young_wheel=young, poisson_wheel=poisson, method=method, &
                    max_equivalent_radius=rmax)
    if (allocated(error)) then
      call bad(error%message); return
    end if
    if (have_force) then
      call hertz_from_force(params, curv, force, patch)
    else
      call hertz_from_penetration(params, curv, penetration, patch)
    end if
    write (output_unit, '(a)') '{"a": ' // trim(sci_text(patch%a, 16, 3)) // ', "b": ' // trim(sci_text(patch%b, 16, 3)) // &
      ', "normal_force": ' // trim(sci_text(patch%normal_force, 16, 3)) // ', "p0": ' // trim(sci_text(patch%p0, 16, 3)) // &
      ', "approach": ' // trim(sci_text(patch%approach, 16, 3)) // ', "stiffness": ' // trim(sci_text(patch%stiffness, 16, 3)) // &
      ', "m": ' // trim(sci_text(patch%m, 16, 3)) // ', "n": ' // trim(sci_text(patch%n, 16, 3)) // &
      ', "theta": ' // trim(sci_text(patch%theta, 16, 3)) // &
      ', "warning": ' // trim(int_text(patch%warning)) // '}'
    status = 0

  contains

    subroutine value_arg(j, value, good)
      integer, intent(in) :: j
      real(wp), intent(out) :: value
      logical, intent(out) :: good
      good = .false.
      value = 0.0_wp
      if (j + 1 > size(args)) then
        call bad(trim(args(j)) // ' expects a number'); return
      end if
      call real_arg(args(j + 1), trim(args(j)), value, good)
    end subroutine value_arg

    !> A radius [m] (signed, or 'inf' for flat) stored as its curvature 1/R.
    subroutine radius_arg(j, curvature, good)
      integer, intent(in) :: j
      real(wp), intent(out) :: curvature
      logical, intent(out) :: good
      real(wp) :: radius
      good = .false.
      curvature = 0.0_wp
      if (j + 1 > size(args)) then
        call bad(trim(args(j)) // ' expects a radius in m (or inf)'); return
      end if
      select case (trim(args(j + 1)))
      case ('inf', 'Inf', 'infinity', '-inf')
        good = .true.
        return
      end select
      call real_arg(args(j + 1), trim(args(j)), radius, good)
      if (.not. good) return
      if (radius == 0.0_wp) then
        call bad(trim(args(j)) // ' must be a non-zero radius in m (or inf)')
        good = .false.
        return
      end if
      curvature = 1.0_wp / radius
    end subroutine radius_arg
  end subroutine run_hertz_command

  subroutine real_arg(text, option, value, good)
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    character(len=*), intent(in) :: text, option
    real(wp), intent(out) :: value
    logical, intent(out) :: good
    integer :: ios
    value = 0.0_wp
    read (text, *, iostat=ios) value
    good = ios == 0 .and. len_trim(text) > 0 .and. verify(trim(text), '0123456789.+-eEdD') == 0
    if (good) good = ieee_is_finite(value)
    if (.not. good) call bad(option // " expects a number, got '" // trim(text) // "'")
  end subroutine real_arg

  subroutine bad(message)
    character(len=*), intent(in) :: message
    write (error_unit, '(a)') 'raildyn hertz: ' // trim(message) // ' (see raildyn hertz --help)'
  end subroutine bad
end module rd_cmd_hertz
