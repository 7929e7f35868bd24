!> What the flange-chatter studies share: a scene from a deck, built and initialised without
!> output, and the stop on an error (study programs, not library code: they may stop).
module study_support
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  implicit none
  private
  public :: start_scene, stop_on

contains

  !> Load, build and initialise (no results file) the scene of `deck`.
  subroutine start_scene(deck, scene)
    character(len=*), intent(in) :: deck
    type(scene_t), intent(inout) :: scene
    type(error_t), allocatable :: error
    call scene%load_file(deck, error); call stop_on(error)
    call scene%build(error); call stop_on(error)
    call scene%initialize(.false., error); call stop_on(error)
  end subroutine start_scene

  !> Print the error and stop with status 1 when there is one.
  subroutine stop_on(error)
    type(error_t), allocatable, intent(in) :: error
    if (allocated(error)) then
      print '(a)', 'error: ' // error%message
      stop 1
    end if
  end subroutine stop_on
end module study_support
