!> `raildyn creep`: creep forces of one contact patch by a chosen creep law, printed as one
!> JSON object {"fx": .., "fy": .., "mz": ..} (SI; forces and moment ON THE WHEEL in the
!> contact frame, docs/conventions.md).
!>
!>   raildyn creep --law linear|fastsim|polach --a A --b B --normal-force N
!>                 [--shear-modulus G] [--poisson NU] [--friction MU]
!>                 [--xi XI] [--eta ETA] [--spin PHI] [--grid N]
!>                 [--bound parabolic|elliptic] [--saturation none|shen_hedrick_elkins]
!> a, b [m], N [N], G [Pa] (default 82e9), nu (0.28), mu (0.3), spin PHI [1/m].
!> Exit status 0, or 2 with one line on stderr for bad usage.
module rd_cmd_creep
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use rd_text, only: sci_text
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_creep_law, only: creep_law_t, creep_patch_t, creepage_t, creep_force_t, creep_law_options_t, &
                          validate_patch
  use rd_creep_factory, only: build_creep_law
  implicit none
  private
  public :: run_creep_command, creep_usage

  character(len=*), parameter :: creep_usage = 'usage: raildyn creep --law linear|fastsim|polach --a A --b B ' // &
    '--normal-force N [--shear-modulus G] [--poisson NU] [--friction MU] [--xi XI] [--eta ETA] ' // &
    '[--spin PHI] [--grid N] [--bound parabolic|elliptic] [--saturation none|shen_hedrick_elkins]'

contains

  subroutine run_creep_command(args, status)
    character(len=*), intent(in) :: args(:)
    integer, intent(out) :: status
    type(creep_patch_t) :: patch
    type(creepage_t) :: creep
    type(creep_force_t) :: force
    type(creep_law_options_t) :: options
    class(creep_law_t), allocatable :: law
    type(error_t), allocatable :: error
    character(len=32) :: law_name
    real(wp) :: grid
    logical :: ok, have_a, have_b, have_n
    integer :: i

    status = 2
    if (size(args) == 0) then
      write (error_unit, '(a)') creep_usage
      return
    end if
    law_name = ''
    have_a = .false.; have_b = .false.; have_n = .false.
    i = 1
    do while (i <= size(args))
      if (trim(args(i)) == '--help' .or. trim(args(i)) == '-h') then
        write (output_unit, '(a)') creep_usage
        status = 0
        return
      end if
      if (i + 1 > size(args)) then
        call bad(trim(args(i)) // ' expects a value'); return
      end if
      ok = .true.
      select case (trim(args(i)))
      case ('--law'); law_name = args(i + 1)
      case ('--bound'); options%bound = args(i + 1)
      case ('--saturation'); options%saturation = args(i + 1)
      case ('--a'); call real_arg(i, patch%a, ok); have_a = .true.
      case ('--b'); call real_arg(i, patch%b, ok); have_b = .true.
      case ('--normal-force'); call real_arg(i, patch%normal_force, ok); have_n = .true.
      case ('--shear-modulus'); call real_arg(i, patch%shear_modulus, ok)
      case ('--poisson'); call real_arg(i, patch%poisson, ok)
      case ('--friction'); call real_arg(i, patch%friction, ok)
      case ('--xi'); call real_arg(i, creep%xi, ok)
      case ('--eta'); call real_arg(i, creep%eta, ok)
      case ('--spin'); call real_arg(i, creep%phi, ok)
      case ('--grid')
        call real_arg(i, grid, ok)
        if (ok .and. (grid /= aint(grid) .or. grid < 1.0_wp .or. grid > 100000.0_wp)) then
          call bad('--grid expects a whole number of elements between 1 and 100000'); return
        end if
        if (ok) then
          options%grid_nx = nint(grid); options%grid_ny = nint(grid)
        end if
      case default
        call bad("unknown option '" // trim(args(i)) // "'"); return
      end select
      if (.not. ok) return
      i = i + 2
    end do
    if (len_trim(law_name) == 0) then
      call bad('--law is required (linear, fastsim or polach)'); return
    end if
    if (.not. (have_a .and. have_b .and. have_n)) then
      call bad('--a, --b [m] and --normal-force [N] are required'); return
    end if
    call validate_patch(patch, creep, error)
    if (allocated(error)) then
      call bad(error%message); return
    end if
    call build_creep_law(law_name, options, law, error)
    if (allocated(error)) then
      call bad(error%message); return
    end if
    call law%compute(patch, creep, force)
    write (output_unit, '(a)') '{"fx": ' // trim(sci_text(force%fx, 16, 3)) // ', "fy": ' // trim(sci_text(force%fy, 16, 3)) // &
      ', "mz": ' // trim(sci_text(force%mz, 16, 3)) // '}'
    status = 0

  contains

    subroutine real_arg(j, value, good)
      use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
      integer, intent(in) :: j
      real(wp), intent(out) :: value
      logical, intent(out) :: good
      integer :: ios
      value = 0.0_wp
      read (args(j + 1), *, iostat=ios) value
      good = ios == 0 .and. verify(trim(args(j + 1)), '0123456789.+-eEdD') == 0
      if (good) good = ieee_is_finite(value)
      if (.not. good) call bad(trim(args(j)) // " expects a number, got '" // trim(args(j + 1)) // "'")
    end subroutine real_arg
  end subroutine run_creep_command

  subroutine bad(message)
    character(len=*), intent(in) :: message
    write (error_unit, '(a)') 'raildyn creep: ' // trim(message) // ' (see raildyn creep --help)'
  end subroutine bad
end module rd_cmd_creep
