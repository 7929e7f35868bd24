!> The deck's `&sensor` groups: measurement points on bodies (docs/input_reference.md),
!> whose motion the scene writes under /sensors/<name>/ (docs/output.md, rd_point_motion).
module rd_scene_sensors
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_deck, only: deck_t
  use rd_scene_vehicle, only: body_index
  implicit none
  private
  public :: sensor_spec_t, build_sensors

  type :: sensor_spec_t
    character(len=:), allocatable :: name
    integer :: body = 0          !< body index (deck order)
    real(wp) :: position(3) = 0  !< in the body frame (wheelset: intermediate frame) [m]
  end type sensor_spec_t

contains

  !> One spec per `&sensor`. The reader has already checked the names (unique, usable as
  !> results groups) and that `body` names a body.
  subroutine build_sensors(deck, sensors, error)
    type(deck_t), intent(in) :: deck
    type(sensor_spec_t), allocatable, intent(out) :: sensors(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: body
    real(wp), allocatable :: position(:)
    integer :: i
    allocate (sensors(deck%count('sensor')))
    do i = 1, size(sensors)
      call deck%get('sensor', i, 'name', sensors(i)%name, error); if (allocated(error)) return
      call deck%get('sensor', i, 'body', body, error); if (allocated(error)) return
      sensors(i)%body = body_index(deck, body)
      call deck%get('sensor', i, 'position', position, error); if (allocated(error)) return
      sensors(i)%position = position
    end do
  end subroutine build_sensors
end module rd_scene_sensors
