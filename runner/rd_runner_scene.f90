!> The start of a scene shared by the runner's commands (run, check, eigen).
module rd_runner_scene
  use, intrinsic :: iso_fortran_env, only: error_unit
  use rd_error, only: error_t
  use rd_scene, only: scene_t
  use rd_deck, only: deck_string_t
  implicit none
  private
  public :: start_scene

contains

  !> Everything run does before its first step (read, build, results path, initial state,
  !> static equilibrium, integrator set-up); check does the same without writing, so that
  !> check and run agree. Warnings go to stderr, one line each; the caller reports `error`.
  !> eigen starts from a results file's row `restart_row` (from 0; default the last
  !> complete one) and writes no results, so it skips the results path
  !> (check_results_path = .false.).
  subroutine start_scene(scene, deck, output, write_output, error, restart, restart_row, check_results_path)
    type(scene_t), intent(inout) :: scene
    character(len=*), intent(in) :: deck, output
    logical, intent(in) :: write_output
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: restart   !< results file to continue ('' none)
    integer, intent(in), optional :: restart_row
    logical, intent(in), optional :: check_results_path
    type(deck_string_t), allocatable :: warnings(:)
    integer :: i
    call scene%load_file(deck, error)
    if (.not. allocated(error) .and. len(output) > 0) call scene%set_output_file(output)
    if (.not. allocated(error)) call scene%build(error)
    if (allocated(error)) return
    ! printed before initialize: a failed initialize resets the scene to its deck
    warnings = scene%warnings()
    do i = 1, size(warnings)
      write (error_unit, '(2a)') 'raildyn: warning: ', warnings(i)%s
    end do
    if (present(restart)) then
      if (len(restart) > 0) call scene%continue_from(restart, error, restart_row)
      if (allocated(error)) return
    end if
    if (present(check_results_path)) then
      if (.not. check_results_path) then
        call scene%initialize(write_output, error)
        return
      end if
    end if
    call scene%check_output_path(error)
    if (.not. allocated(error)) call scene%initialize(write_output, error)
  end subroutine start_scene
end module rd_runner_scene
