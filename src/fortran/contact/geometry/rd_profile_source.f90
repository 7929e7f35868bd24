!> A profile by name or file: 's1002' (wheel), '60e1' / 'uic60' / '54e1' (rails, uncanted)
!> from the analytic generators (0.1 mm point spacing), anything else read as a file
!> (SIMPACK .prw/.prr or y-z table, rd_profile_io). For decks and commands; `spacing` [m]
!> overrides the generators' point spacing (the wheelset contact builds them at 0.2 mm).
module rd_profile_source
  use rd_kinds, only: wp
  use rd_text, only: lower_case
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_io, only: read_profile_file
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1, RAIL_54E1
  implicit none
  private
  public :: load_wheel_profile, load_rail_profile

  real(wp), parameter :: analytic_spacing = 1.0e-4_wp

contains

  subroutine load_wheel_profile(spec, profile, error, spacing)
    character(len=*), intent(in) :: spec
    type(profile_t), intent(out) :: profile
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: spacing
    select case (lower_case(trim(adjustl(spec))))
    case ('s1002')
      call s1002_profile(profile, point_spacing(spacing), error)
    case default
      call read_profile_file(trim(spec), PROFILE_WHEEL, profile, error)
    end select
  end subroutine load_wheel_profile

  subroutine load_rail_profile(spec, profile, error, spacing)
    character(len=*), intent(in) :: spec
    type(profile_t), intent(out) :: profile
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: spacing
    select case (lower_case(trim(adjustl(spec))))
    case ('60e1', 'uic60')
      call rail_head_profile(RAIL_60E1, profile, point_spacing(spacing), error)
    case ('54e1')
      call rail_head_profile(RAIL_54E1, profile, point_spacing(spacing), error)
    case default
      call read_profile_file(trim(spec), PROFILE_RAIL, profile, error)
    end select
  end subroutine load_rail_profile

  pure real(wp) function point_spacing(spacing)
    real(wp), intent(in), optional :: spacing
    point_spacing = analytic_spacing
    if (present(spacing)) point_spacing = spacing
  end function point_spacing

end module rd_profile_source
