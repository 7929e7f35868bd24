!> The wheel and rail profiles of a contact geometry as curves in the track frame, for
!> drawings (the contact-point diagram of `raildyn profile-scan --contact-plot`): one CSV row
!> per profile point, `side,surface,profile_coordinate_m,y_m,z_m` (side left|right, surface
!> wheel|rail; profile coordinate s on the wheel, u on the rail; Y, Z in the track frame with
!> the wheelset centred at height z_centre, its roll neglected: at most a few 1e-4 rad for
!> differing left and right profiles).
module rd_profile_curves_csv
  use rd_kinds, only: wp
  use rd_text, only: sci_text
  use rd_error, only: error_t, make_error, RD_ERR_IO, RD_ERR_INPUT
  use rd_contact_geometry, only: contact_geometry_t
  use rd_contact_surfaces, only: wheel_surface_t, rail_surface_t
  implicit none
  private
  public :: write_profile_curves_csv

contains

  subroutine write_profile_curves_csv(path, geo, z_centre, error)
    character(len=*), intent(in) :: path
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: z_centre   !< height of the wheelset centre, centred [m]
    type(error_t), allocatable, intent(out) :: error
    integer :: u, ios
    if (.not. allocated(geo%wheel%s) .or. .not. allocated(geo%rail%u)) then
      call make_error(error, RD_ERR_INPUT, 'profile curves: the contact geometry has no profiles (knife edges?)')
      return
    end if
    open (newunit=u, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot write ' // path)
      return
    end if
    write (u, '(a)') 'side,surface,profile_coordinate_m,y_m,z_m'
    ! the right side's surfaces are kept in the mirrored frame (rd_contact_geometry): Y -> -Y
    call wheel_rows('left', geo%wheel, 1.0_wp)
    if (geo%own_wheel_right) then
      call wheel_rows('right', geo%wheel_right, -1.0_wp)
    else
      call wheel_rows('right', geo%wheel, -1.0_wp)
    end if
    call rail_rows('left', geo%rail, 1.0_wp)
    if (geo%own_rail_right) then
      call rail_rows('right', geo%rail_right, -1.0_wp)
    else
      call rail_rows('right', geo%rail, -1.0_wp)
    end if
    close (u)
  contains
    subroutine wheel_rows(side, w, mirror)
      character(len=*), intent(in) :: side
      type(wheel_surface_t), intent(in) :: w
      real(wp), intent(in) :: mirror
      integer :: i
      do i = 1, size(w%s)
        write (u, '(a)') side // ',wheel,' // num(w%s(i)) // ',' // num(mirror * w%y(i)) // ',' // num(z_centre - w%r(i))
      end do
    end subroutine wheel_rows
    subroutine rail_rows(side, r, mirror)
      character(len=*), intent(in) :: side
      type(rail_surface_t), intent(in) :: r
      real(wp), intent(in) :: mirror
      integer :: i
      do i = 1, size(r%u)
        write (u, '(a)') side // ',rail,' // num(r%u(i)) // ',' // num(mirror * r%y(i)) // ',' // num(r%z(i))
      end do
    end subroutine rail_rows
  end subroutine write_profile_curves_csv

  function num(x) result(t)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: t
    t = trim(sci_text(x, 15, 3))
  end function num
end module rd_profile_curves_csv
