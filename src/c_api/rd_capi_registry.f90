!> The C API's table of live models: which handles are valid, and the model each names.
!>
!> A handle is an id from a counter that only goes up, never an address: a destroyed
!> handle stays invalid for the life of the process even when the next model is allocated
!> at the same address, and a stray integer is looked up, never dereferenced. Not
!> simulation state: the models themselves are independent. The table is not guarded
!> against concurrent calls (raildyn.h: a threaded host serialises its calls).
module rd_capi_registry
  use, intrinsic :: iso_c_binding, only: c_int64_t
  use rd_scene, only: scene_t
  use rd_text, only: int_text
  implicit none
  private
  public :: capi_model_t, register_model, find_model, forget_model, handle_problem

  type :: capi_model_t
    type(scene_t) :: scene
    character(len=:), allocatable :: message   !< last failure on this handle
  end type capi_model_t

  type :: live_model_t
    integer(c_int64_t) :: handle = 0
    type(capi_model_t), pointer :: model => null()
  end type live_model_t

  type(live_model_t), allocatable :: live(:)
  integer :: nlive = 0
  integer(c_int64_t) :: last_handle = 0   !< handles issued so far are 1 .. last_handle

contains

  !> A new model and its handle (never issued before).
  subroutine register_model(model, handle)
    type(capi_model_t), pointer, intent(out) :: model
    integer(c_int64_t), intent(out) :: handle
    type(live_model_t), allocatable :: grown(:)
    if (.not. allocated(live)) allocate (live(16))
    if (nlive == size(live)) then
      allocate (grown(2 * size(live)))
      grown(1:nlive) = live(1:nlive)
      call move_alloc(grown, live)
    end if
    allocate (model)
    model%message = ''
    last_handle = last_handle + 1
    handle = last_handle
    nlive = nlive + 1
    live(nlive) = live_model_t(handle, model)
  end subroutine register_model

  !> The model a live handle names; null for any other value.
  function find_model(handle) result(model)
    integer(c_int64_t), intent(in) :: handle
    type(capi_model_t), pointer :: model
    integer :: i
    model => null()
    do i = 1, nlive
      if (live(i)%handle == handle) then
        model => live(i)%model
        return
      end if
    end do
  end function find_model

  !> Remove a handle from the table (the caller frees the model).
  subroutine forget_model(handle)
    integer(c_int64_t), intent(in) :: handle
    integer :: i
    do i = 1, nlive
      if (live(i)%handle == handle) then
        live(i) = live(nlive)
        live(nlive) = live_model_t()
        nlive = nlive - 1
        return
      end if
    end do
  end subroutine forget_model

  !> Why a handle is not valid, for rd_error_message.
  function handle_problem(handle) result(text)
    integer(c_int64_t), intent(in) :: handle
    character(len=:), allocatable :: text
    if (handle >= 1 .and. handle <= last_handle) then
      text = 'raildyn handle ' // trim(int_text(handle)) // &
             ' was destroyed (rd_destroy); a destroyed handle stays invalid'
    else
      text = 'invalid raildyn handle ' // trim(int_text(handle)) // &
             ': no model was created with it (handles come from rd_create_from_file/_string)'
    end if
  end function handle_problem
end module rd_capi_registry
