!> A profile by name or file: 's1002' (wheel), '60e1' / 'uic60' / '54e1' (rails, uncanted)
!> from the analytic generators (0.1 mm point spacing), anything else read as a file
!> (SIMPACK .prw/.prr or y-z table, rd_profile_io). For decks and commands.
module rd_profile_source
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL
  use rd_profile_io, only: read_profile_file
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1, RAIL_54E1
  implicit none
  private
  public :: load_wheel_profile, load_rail_profile

  real(wp), parameter :: analytic_spacing = 1.0e-4_wp

contains

  subroutine load_wheel_profile(spec, profile, error)
    character(len=*), intent(in) :: spec
    type(profile_t), intent(out) :: profile
    type(error_t), allocatable, intent(out) :: error
    select case (lower(trim(spec)))
    case ('s1002')
      call s1002_profile(profile, analytic_spacing, error)
    case default
      call read_profile_file(trim(spec), PROFILE_WHEEL, profile, error)
    end select
  end subroutine load_wheel_profile

  subroutine load_rail_profile(spec, profile, error)
    character(len=*), intent(in) :: spec
    type(profile_t), intent(out) :: profile
    type(error_t), allocatable, intent(out) :: error
    select case (lower(trim(spec)))
    case ('60e1', 'uic60')
      call rail_head_profile(RAIL_60E1, profile, analytic_spacing, error)
    case ('54e1')
      call rail_head_profile(RAIL_54E1, profile, analytic_spacing, error)
    case default
      call read_profile_file(trim(spec), PROFILE_RAIL, profile, error)
    end select
  end subroutine load_rail_profile

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower

end module rd_profile_source
