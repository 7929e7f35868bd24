!> Builds a creep law by name. Adding a law = one module with a `*_create(options, law,
!> error)` routine + one `case` line here (and its name in `creep_law_names`).
module rd_creep_factory
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_creep_law, only: creep_law_t, creep_law_options_t
  use rd_creep_linear, only: creep_linear_build
  use rd_creep_fastsim, only: creep_fastsim_build
  use rd_creep_polach, only: creep_polach_build
  implicit none
  private
  public :: build_creep_law, creep_law_names

  character(len=*), parameter :: creep_law_names = 'linear, fastsim, polach'

contains

  subroutine build_creep_law(name, options, law, error)
    character(len=*), intent(in) :: name
    type(creep_law_options_t), intent(in) :: options
    class(creep_law_t), allocatable, intent(out) :: law
    type(error_t), allocatable, intent(out) :: error
    select case (trim(adjustl(name)))
    case ('linear'); call creep_linear_build(options, law, error)
    case ('fastsim'); call creep_fastsim_build(options, law, error)
    case ('polach'); call creep_polach_build(options, law, error)
    case default
      call make_error(error, RD_ERR_INPUT, 'creep law "' // trim(adjustl(name)) // '" unknown; valid names: ' &
                      // creep_law_names)
    end select
    call error_context(error, 'build_creep_law')
  end subroutine build_creep_law
end module rd_creep_factory
