!> C API of raildyn (src/c_api/raildyn.h): opaque handles over scene objects.
!>
!> NEKO style: a handle is the address of a heap-allocated `capi_model_t`; the
!> only module-level data is the list of live handles, used to reject stale or
!> foreign handles before they are dereferenced. No simulation state is global:
!> any number of models may live in one process.
module rd_capi
  use, intrinsic :: iso_c_binding
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_OK, RD_ERR_HANDLE
  use rd_scene, only: scene_t, raildyn_version
  implicit none
  private

  integer(c_int64_t), parameter :: magic = int(z'7261696C64796E', c_int64_t)  ! "raildyn"

  type :: capi_model_t
    integer(c_int64_t) :: magic = 0
    type(scene_t) :: scene
    character(len=:), allocatable :: message   !< last failure on this handle
  end type capi_model_t

  !> Live handles (addresses). Not simulation state: only which handles are valid.
  integer(c_int64_t), allocatable :: live(:)
  integer :: nlive = 0

  character(kind=c_char, len=16), target :: version_c = c_null_char

contains

  ! ------------------------------------------------------------------ helpers
  function c_to_f_string(cstr) result(fstr)
    character(kind=c_char), intent(in) :: cstr(*)
    character(len=:), allocatable :: fstr
    integer :: n
    n = 0
    do while (cstr(n + 1) /= c_null_char)
      n = n + 1
    end do
    allocate (character(len=n) :: fstr)
    fstr = transfer(cstr(1:n), fstr)
  end function c_to_f_string

  subroutine f_to_c_string(fstr, cstr, clen)
    character(len=*), intent(in) :: fstr
    integer(c_int), intent(in) :: clen
    character(kind=c_char), intent(out) :: cstr(*)
    integer :: i, n
    if (clen <= 0) return
    n = min(len(fstr), int(clen) - 1)
    do i = 1, n
      cstr(i) = fstr(i:i)
    end do
    cstr(n + 1) = c_null_char
  end subroutine f_to_c_string

  !> Resolve a handle to its model, or fail with RD_ERR_HANDLE.
  subroutine lookup(handle, model, status)
    integer(c_int64_t), intent(in) :: handle
    type(capi_model_t), pointer, intent(out) :: model
    integer(c_int), intent(out) :: status
    type(c_ptr) :: p
    model => null()
    status = RD_ERR_HANDLE
    if (handle == 0 .or. nlive == 0) return
    if (.not. any(live(1:nlive) == handle)) return
    p = transfer(handle, p)
    call c_f_pointer(p, model)
    if (model%magic /= magic) then
      model => null()
      return
    end if
    status = RD_OK
  end subroutine lookup

  !> Record the outcome of a call on the handle and return its status.
  function conclude(model, error) result(status)
    type(capi_model_t), intent(inout) :: model
    type(error_t), allocatable, intent(in) :: error
    integer(c_int) :: status
    if (allocated(error)) then
      model%message = error%message
      status = int(error%code, c_int)
    else
      status = RD_OK
    end if
  end function conclude

  function new_handle(model) result(handle)
    type(capi_model_t), pointer, intent(in) :: model
    integer(c_int64_t) :: handle
    integer(c_int64_t), allocatable :: grown(:)
    model%magic = magic
    model%message = ''
    handle = transfer(c_loc(model), handle)
    if (.not. allocated(live)) allocate (live(16))
    if (nlive == size(live)) then
      allocate (grown(2 * size(live)))
      grown(1:nlive) = live(1:nlive)
      call move_alloc(grown, live)
    end if
    nlive = nlive + 1
    live(nlive) = handle
  end function new_handle

  ! ------------------------------------------------------------------ API
  function rd_version() result(p) bind(C, name='rd_version')
    type(c_ptr) :: p
    character(len=:), allocatable :: v
    v = raildyn_version // c_null_char
    version_c = v
    p = c_loc(version_c)
  end function rd_version

  function rd_create_from_file(path, handle) result(status) bind(C, name='rd_create_from_file')
    character(kind=c_char), intent(in) :: path(*)
    integer(c_int64_t), intent(out) :: handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    allocate (model)
    handle = new_handle(model)
    call model%scene%load_file(c_to_f_string(path), error)
    status = conclude(model, error)
  end function rd_create_from_file

  function rd_create_from_string(text, base_dir, handle) result(status) &
      bind(C, name='rd_create_from_string')
    character(kind=c_char), intent(in) :: text(*)
    type(c_ptr), value :: base_dir
    integer(c_int64_t), intent(out) :: handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    character(kind=c_char), pointer :: dir(:)
    character(len=:), allocatable :: fdir
    fdir = '.'
    if (c_associated(base_dir)) then
      call c_f_pointer(base_dir, dir, [4096])
      fdir = c_to_f_string(dir)
      if (len(fdir) == 0) fdir = '.'
    end if
    allocate (model)
    handle = new_handle(model)
    call model%scene%load_string(c_to_f_string(text), fdir, error)
    status = conclude(model, error)
  end function rd_create_from_string

  function rd_initialize(handle, write_output) result(status) bind(C, name='rd_initialize')
    integer(c_int64_t), value :: handle
    integer(c_int), value :: write_output
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%initialize(write_output /= 0, error)
    status = conclude(model, error)
  end function rd_initialize

  function rd_advance(handle, t_target) result(status) bind(C, name='rd_advance')
    integer(c_int64_t), value :: handle
    real(c_double), value :: t_target
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%advance(real(t_target, wp), error)
    status = conclude(model, error)
  end function rd_advance

  function rd_get_time(handle, time) result(status) bind(C, name='rd_get_time')
    integer(c_int64_t), value :: handle
    real(c_double), intent(out) :: time
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    time = 0
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    time = model%scene%time()
  end function rd_get_time

  function rd_get_state_size(handle, n) result(status) bind(C, name='rd_get_state_size')
    integer(c_int64_t), value :: handle
    integer(c_int), intent(out) :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    n = 0
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    n = int(model%scene%state_size(), c_int)
  end function rd_get_state_size

  function rd_get_state(handle, state, n) result(status) bind(C, name='rd_get_state')
    integer(c_int64_t), value :: handle
    integer(c_int), value :: n
    real(c_double), intent(out) :: state(n)
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%get_state(state, error)
    status = conclude(model, error)
  end function rd_get_state

  function rd_output_count(handle, count) result(status) bind(C, name='rd_output_count')
    integer(c_int64_t), value :: handle
    integer(c_int), intent(out) :: count
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    count = 0
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    count = int(model%scene%output_count(), c_int)
  end function rd_output_count

  function rd_output_name(handle, index, name, name_len) result(status) bind(C, name='rd_output_name')
    integer(c_int64_t), value :: handle
    integer(c_int), value :: index, name_len
    character(kind=c_char), intent(out) :: name(*)
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    character(len=:), allocatable :: fname
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%output_name(int(index), fname, error)
    status = conclude(model, error)
    if (status == RD_OK) call f_to_c_string(fname, name, name_len)
  end function rd_output_name

  function rd_output_size(handle, name, n) result(status) bind(C, name='rd_output_size')
    integer(c_int64_t), value :: handle
    character(kind=c_char), intent(in) :: name(*)
    integer(c_int), intent(out) :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    integer :: fn
    n = 0
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%output_size(c_to_f_string(name), fn, error)
    status = conclude(model, error)
    n = int(fn, c_int)
  end function rd_output_size

  function rd_get_output(handle, name, values, n) result(status) bind(C, name='rd_get_output')
    integer(c_int64_t), value :: handle
    character(kind=c_char), intent(in) :: name(*)
    integer(c_int), value :: n
    real(c_double), intent(out) :: values(n)
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%get_output(c_to_f_string(name), values, error)
    status = conclude(model, error)
  end function rd_get_output

  function rd_set_input(handle, name, values, n) result(status) bind(C, name='rd_set_input')
    integer(c_int64_t), value :: handle
    character(kind=c_char), intent(in) :: name(*)
    integer(c_int), value :: n
    real(c_double), intent(in) :: values(n)
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%set_input(c_to_f_string(name), values, error)
    status = conclude(model, error)
  end function rd_set_input

  function rd_finalize(handle) result(status) bind(C, name='rd_finalize')
    integer(c_int64_t), value :: handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%finalize(error)
    status = conclude(model, error)
  end function rd_finalize

  function rd_error_message(handle, message, message_len) result(status) &
      bind(C, name='rd_error_message')
    integer(c_int64_t), value :: handle
    character(kind=c_char), intent(out) :: message(*)
    integer(c_int), value :: message_len
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    call lookup(handle, model, status)
    if (status /= RD_OK) then
      call f_to_c_string('invalid raildyn handle', message, message_len)
      return
    end if
    call f_to_c_string(model%message, message, message_len)
  end function rd_error_message

  function rd_run_notes(handle, notes, notes_len) result(status) bind(C, name='rd_run_notes')
    integer(c_int64_t), value :: handle
    character(kind=c_char), intent(out) :: notes(*)
    integer(c_int), value :: notes_len
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call f_to_c_string(model%scene%run_notes(), notes, notes_len)
  end function rd_run_notes

  function rd_destroy(handle) result(status) bind(C, name='rd_destroy')
    integer(c_int64_t), value :: handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    integer :: i
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%finalize(error)   ! closes the output if still open; errors are moot now
    call model%scene%destroy()
    model%magic = 0
    deallocate (model)
    do i = 1, nlive
      if (live(i) == handle) then
        live(i) = live(nlive)
        nlive = nlive - 1
        exit
      end if
    end do
  end function rd_destroy
end module rd_capi
