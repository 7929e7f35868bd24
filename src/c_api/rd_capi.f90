!> C API of raildyn (src/c_api/raildyn.h): opaque handles over scene objects.
!>
!> NEKO style: a handle names a heap-allocated `capi_model_t`. Handles are ids from a
!> counter that never goes back, looked up in the table of live models (rd_capi_registry):
!> a destroyed handle stays invalid even when the next model gets the same address, and
!> a stray integer is never dereferenced. No simulation state is global: any number of
!> models may live in one process. Pointer arguments are taken as C pointers and checked:
!> NULL gives RD_ERR_INPUT with a message instead of a crash.
module rd_capi
  use, intrinsic :: iso_c_binding
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_OK, RD_ERR_INPUT, RD_ERR_HANDLE
  use rd_scene, only: raildyn_version
  use rd_text, only: int_text
  use rd_scene_linearization, only: linearize_scene
  use rd_capi_registry, only: capi_model_t, register_model, find_model, forget_model, &
                              handle_problem
  implicit none
  private

  interface
    pure function c_strlen(text) bind(C, name='strlen') result(n)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: text
      integer(c_size_t) :: n
    end function c_strlen
  end interface

  character(kind=c_char, len=16), target :: version_c = c_null_char
  !> What a NULL array argument of size 0 stands for.
  real(c_double), target :: no_values(0)

contains

  ! ------------------------------------------------------------------ helpers
  !> The NUL-terminated C string at `text` (not NULL).
  function c_string(text) result(fstr)
    type(c_ptr), intent(in) :: text
    character(len=:), allocatable :: fstr
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    n = int(c_strlen(text))
    call c_f_pointer(text, chars, [n])
    allocate (character(len=n) :: fstr)
    do i = 1, n
      fstr(i:i) = chars(i)
    end do
  end function c_string

  !> Copy `fstr` into the C buffer `buffer` of `clen` bytes, NUL-terminated and truncated.
  subroutine copy_to_c(fstr, buffer, clen)
    character(len=*), intent(in) :: fstr
    type(c_ptr), intent(in) :: buffer
    integer(c_int), intent(in) :: clen
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    call c_f_pointer(buffer, chars, [clen])
    n = min(len(fstr), int(clen) - 1)
    do i = 1, n
      chars(i) = fstr(i:i)
    end do
    chars(n + 1) = c_null_char
  end subroutine copy_to_c

  !> Resolve a handle to its model, or fail with RD_ERR_HANDLE.
  subroutine lookup(handle, model, status)
    integer(c_int64_t), intent(in) :: handle
    type(capi_model_t), pointer, intent(out) :: model
    integer(c_int), intent(out) :: status
    model => find_model(handle)
    status = RD_OK
    if (.not. associated(model)) status = RD_ERR_HANDLE
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

  !> Refuse a call's arguments: the message is kept on the handle.
  function refuse(model, call_name, problem) result(status)
    type(capi_model_t), intent(inout) :: model
    character(len=*), intent(in) :: call_name, problem
    integer(c_int) :: status
    model%message = call_name // ': ' // problem
    status = RD_ERR_INPUT
  end function refuse

  !> Fortran view of a C array argument of n doubles; NULL is accepted for n = 0 only.
  !> `problem` is '' when the argument is usable.
  subroutine c_doubles(values, n, name, view, problem)
    type(c_ptr), intent(in) :: values
    integer(c_int), intent(in) :: n
    character(len=*), intent(in) :: name
    real(c_double), pointer, intent(out) :: view(:)
    character(len=:), allocatable, intent(out) :: problem
    problem = ''
    view => no_values
    if (n < 0) then
      problem = 'size must be >= 0'
    else if (.not. c_associated(values)) then
      if (n > 0) problem = name // ' is NULL; expected an array of ' // trim(int_text(n)) // ' doubles'
    else
      call c_f_pointer(values, view, [n])
    end if
  end subroutine c_doubles

  !> The model of a call: status RD_OK, or its refusal: an unknown handle, or `problem` with
  !> its arguments ('' when none), recorded on the handle.
  subroutine checked_call(handle, call_name, problem, model, status)
    integer(c_int64_t), intent(in) :: handle
    character(len=*), intent(in) :: call_name, problem
    type(capi_model_t), pointer, intent(out) :: model
    integer(c_int), intent(out) :: status
    call lookup(handle, model, status)
    if (status == RD_OK .and. len(problem) > 0) status = refuse(model, call_name, problem)
  end subroutine checked_call

  !> What is wrong with the pointer argument `name`: '' when given, else NULL and `expected`.
  function null_problem(pointer, name, expected) result(problem)
    type(c_ptr), intent(in) :: pointer
    character(len=*), intent(in) :: name, expected
    character(len=:), allocatable :: problem
    problem = ''
    if (.not. c_associated(pointer)) problem = name // ' is NULL; expected ' // expected
  end function null_problem

  !> The model and the array of a call (handle, array, n): status RD_OK, or the refusal
  !> (unknown handle, NULL array, negative size), recorded on the handle. `array_name`:
  !> the array's name in raildyn.h.
  subroutine state_call(handle, state, n, call_name, model, values, status, array_name)
    integer(c_int64_t), intent(in) :: handle
    type(c_ptr), intent(in) :: state
    integer(c_int), intent(in) :: n
    character(len=*), intent(in) :: call_name, array_name
    type(capi_model_t), pointer, intent(out) :: model
    real(c_double), pointer, intent(out) :: values(:)
    integer(c_int), intent(out) :: status
    character(len=:), allocatable :: problem
    call c_doubles(state, n, array_name, values, problem)
    call checked_call(handle, call_name, problem, model, status)
  end subroutine state_call

  !> A C output buffer argument must be a pointer to at least one byte (the NUL).
  function buffer_problem(buffer, buffer_len, name) result(problem)
    type(c_ptr), intent(in) :: buffer
    integer(c_int), intent(in) :: buffer_len
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: problem
    problem = ''
    if (.not. c_associated(buffer)) then
      problem = name // ' is NULL; expected a buffer'
    else if (buffer_len < 1) then
      problem = name // '_len is ' // trim(int_text(buffer_len)) // '; expected >= 1'
    end if
  end function buffer_problem

  !> Common part of the two create calls: a new model (and handle) unless `handle` is NULL.
  function create(handle_out, call_name, text, what, model) result(status)
    type(c_ptr), intent(in) :: handle_out, text
    character(len=*), intent(in) :: call_name, what
    type(capi_model_t), pointer, intent(out) :: model
    integer(c_int) :: status
    integer(c_int64_t), pointer :: handle
    model => null()
    if (.not. c_associated(handle_out)) then
      status = RD_ERR_INPUT          ! nowhere to put a handle: nothing is created
      return
    end if
    call c_f_pointer(handle_out, handle)
    call register_model(model, handle)
    status = RD_OK
    if (.not. c_associated(text)) status = refuse(model, call_name, what // ' is NULL; expected a string')
  end function create

  ! ------------------------------------------------------------------ API
  function rd_version() result(p) bind(C, name='rd_version')
    type(c_ptr) :: p
    character(len=:), allocatable :: v
    v = raildyn_version // c_null_char
    version_c = v
    p = c_loc(version_c)
  end function rd_version

  function rd_create_from_file(path, handle) result(status) bind(C, name='rd_create_from_file')
    type(c_ptr), value :: path, handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    status = create(handle, 'rd_create_from_file', path, 'deck_path', model)
    if (status /= RD_OK) return
    call model%scene%load_file(c_string(path), error)
    status = conclude(model, error)
  end function rd_create_from_file

  function rd_create_from_string(text, base_dir, handle) result(status) &
      bind(C, name='rd_create_from_string')
    type(c_ptr), value :: text, base_dir, handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    character(len=:), allocatable :: fdir
    status = create(handle, 'rd_create_from_string', text, 'deck_text', model)
    if (status /= RD_OK) return
    fdir = '.'
    if (c_associated(base_dir)) fdir = c_string(base_dir)
    if (len(fdir) == 0) fdir = '.'
    call model%scene%load_string(c_string(text), fdir, error)
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
    ! Every input (rd_set_input, rd_set_state, rd_set_start) restarts the integrator at the
    ! scene's time, so between them the integrator may step on towards the run's end and
    ! interpolate each target: chunked advances cost no steps (scene_advance's horizon).
    call model%scene%advance(real(t_target, wp), error, max(real(t_target, wp), model%scene%end_time()))
    status = conclude(model, error)
  end function rd_advance

  function rd_get_time(handle, time) result(status) bind(C, name='rd_get_time')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: time
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    real(c_double), pointer :: t
    call checked_call(handle, 'rd_get_time', null_problem(time, 'time', 'a pointer to a double'), model, status)
    if (status /= RD_OK) return
    call c_f_pointer(time, t)
    t = model%scene%time()
  end function rd_get_time

  function rd_get_state_size(handle, size) result(status) bind(C, name='rd_get_state_size')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: size
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    integer(c_int), pointer :: n
    call checked_call(handle, 'rd_get_state_size', null_problem(size, 'size', 'a pointer to an int'), model, status)
    if (status /= RD_OK) return
    call c_f_pointer(size, n)
    n = int(model%scene%state_size(), c_int)
  end function rd_get_state_size

  function rd_get_state(handle, state, n) result(status) bind(C, name='rd_get_state')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: state
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: values(:)
    call state_call(handle, state, n, 'rd_get_state', model, values, status, 'state')
    if (status /= RD_OK) return
    call model%scene%get_state(values, error)
    status = conclude(model, error)
  end function rd_get_state

  function rd_set_state(handle, state, n) result(status) bind(C, name='rd_set_state')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: state
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: values(:)
    call state_call(handle, state, n, 'rd_set_state', model, values, status, 'state')
    if (status /= RD_OK) return
    call model%scene%set_state(values, error)
    status = conclude(model, error)
  end function rd_set_state

  function rd_set_start(handle, time, state, n) result(status) bind(C, name='rd_set_start')
    integer(c_int64_t), value :: handle
    real(c_double), value :: time
    type(c_ptr), value :: state
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: values(:)
    call state_call(handle, state, n, 'rd_set_start', model, values, status, 'state')
    if (status /= RD_OK) return
    call model%scene%set_start(time, values, error)
    status = conclude(model, error)
  end function rd_set_start

  !> The linearised system matrix, row-major n x n (raildyn.h).
  function rd_linearize(handle, matrix, n) result(status) bind(C, name='rd_linearize')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: matrix
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: values(:)
    real(wp), allocatable :: a(:, :)
    integer :: states
    call state_call(handle, matrix, n, 'rd_linearize', model, values, status, 'matrix')
    if (status /= RD_OK) return
    states = model%scene%state_size()
    if (states > 0 .and. n /= states * states) then
      status = refuse(model, 'rd_linearize', 'size is ' // trim(int_text(n)) // '; expected the state size ' // &
                      'squared, ' // trim(int_text(states)) // ' x ' // trim(int_text(states)) // ' = ' // &
                      trim(int_text(states * states)))
      return
    end if
    call linearize_scene(model%scene, a, error)
    status = conclude(model, error)
    ! Fortran stores a(i, j) column by column: its transpose's columns are a's rows
    if (status == RD_OK) values = reshape(transpose(a), [n])
  end function rd_linearize

  function rd_output_count(handle, count) result(status) bind(C, name='rd_output_count')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: count
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    integer(c_int), pointer :: n
    call checked_call(handle, 'rd_output_count', null_problem(count, 'count', 'a pointer to an int'), model, status)
    if (status /= RD_OK) return
    call c_f_pointer(count, n)
    n = int(model%scene%output_count(), c_int)
  end function rd_output_count

  function rd_output_name(handle, index, name, name_len) result(status) bind(C, name='rd_output_name')
    integer(c_int64_t), value :: handle
    integer(c_int), value :: index, name_len
    type(c_ptr), value :: name
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    character(len=:), allocatable :: fname
    call checked_call(handle, 'rd_output_name', buffer_problem(name, name_len, 'name'), model, status)
    if (status /= RD_OK) return
    call model%scene%output_name(int(index), fname, error)
    status = conclude(model, error)
    if (status == RD_OK) call copy_to_c(fname, name, name_len)
  end function rd_output_name

  function rd_output_size(handle, name, size) result(status) bind(C, name='rd_output_size')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: name, size
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    integer(c_int), pointer :: n
    integer :: fn
    character(len=:), allocatable :: problem
    problem = null_problem(name, 'name', 'an output name')
    if (len(problem) == 0) problem = null_problem(size, 'size', 'a pointer to an int')
    call checked_call(handle, 'rd_output_size', problem, model, status)
    if (status /= RD_OK) return
    call c_f_pointer(size, n)
    call model%scene%output_size(c_string(name), fn, error)
    status = conclude(model, error)
    n = int(fn, c_int)
  end function rd_output_size

  function rd_get_output(handle, name, values, n) result(status) bind(C, name='rd_get_output')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: name, values
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: view(:)
    character(len=:), allocatable :: problem
    call c_doubles(values, n, 'values', view, problem)
    if (.not. c_associated(name)) problem = null_problem(name, 'name', 'an output name')
    call checked_call(handle, 'rd_get_output', problem, model, status)
    if (status /= RD_OK) return
    call model%scene%get_output(c_string(name), view, error)
    status = conclude(model, error)
  end function rd_get_output

  function rd_set_input(handle, name, values, n) result(status) bind(C, name='rd_set_input')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: name, values
    integer(c_int), value :: n
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    real(c_double), pointer :: view(:)
    character(len=:), allocatable :: problem
    call c_doubles(values, n, 'values', view, problem)
    if (.not. c_associated(name)) problem = null_problem(name, 'name', 'an input name')
    call checked_call(handle, 'rd_set_input', problem, model, status)
    if (status /= RD_OK) return
    call model%scene%set_input(c_string(name), real(view, wp), error)
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

  !> Does not touch the handle's message (reading it must not replace it).
  function rd_error_message(handle, message, message_len) result(status) &
      bind(C, name='rd_error_message')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: message
    integer(c_int), value :: message_len
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    if (len(buffer_problem(message, message_len, 'message')) > 0) then
      status = RD_ERR_INPUT
      return
    end if
    call lookup(handle, model, status)
    if (status /= RD_OK) then
      call copy_to_c(handle_problem(handle), message, message_len)
      return
    end if
    call copy_to_c(model%message, message, message_len)
  end function rd_error_message

  function rd_run_notes(handle, notes, notes_len) result(status) bind(C, name='rd_run_notes')
    integer(c_int64_t), value :: handle
    type(c_ptr), value :: notes
    integer(c_int), value :: notes_len
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    call checked_call(handle, 'rd_run_notes', buffer_problem(notes, notes_len, 'notes'), model, status)
    if (status /= RD_OK) return
    call copy_to_c(model%scene%run_notes(), notes, notes_len)
  end function rd_run_notes

  function rd_destroy(handle) result(status) bind(C, name='rd_destroy')
    integer(c_int64_t), value :: handle
    integer(c_int) :: status
    type(capi_model_t), pointer :: model
    type(error_t), allocatable :: error
    call lookup(handle, model, status)
    if (status /= RD_OK) return
    call model%scene%stop(error)   ! closes the output if still open; errors are moot now
    call model%scene%destroy()
    call forget_model(handle)
    deallocate (model)
  end function rd_destroy
end module rd_capi
