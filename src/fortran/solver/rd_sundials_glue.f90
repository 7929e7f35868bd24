!> Fortran side of sundials_glue.c: bind(C) interfaces to the glue functions and the two
!> bind(C) callbacks SUNDIALS reaches through the glue (right-hand side and Jacobian).
!>
!> The `user` pointer the callbacks receive is the c_loc of the integrator's own
!> rhs_context_t, so there is no module-global state: each integrator carries its system.
module rd_sundials_glue
  use, intrinsic :: iso_c_binding, only: c_int, c_long, c_int64_t, c_double, c_char, c_ptr, &
                                         c_null_char, c_f_pointer
  use rd_rhs_context, only: rhs_context_t
  implicit none
  private
  public :: rd_glue_create, rd_glue_destroy, rd_glue_set_tolerances, rd_glue_set_limits
  public :: rd_glue_use_jacobian, rd_glue_set_jacobian_age, rd_glue_advance, rd_glue_reinit, rd_glue_get_stats
  public :: rd_glue_flag_name, rd_glue_last_message, c_string_to_fortran
  public :: rd_solver_rhs_callback, rd_solver_jac_callback

  interface
    function rd_glue_create(method, n, t0, y0, user, msg, msglen) result(handle) &
        bind(C, name='rd_glue_create')
      import :: c_int, c_int64_t, c_double, c_ptr, c_char
      integer(c_int), value :: method
      integer(c_int64_t), value :: n
      real(c_double), value :: t0
      real(c_double), intent(in) :: y0(*)
      type(c_ptr), value :: user
      character(kind=c_char), intent(out) :: msg(*)
      integer(c_int), value :: msglen
      type(c_ptr) :: handle
    end function rd_glue_create

    subroutine rd_glue_destroy(handle) bind(C, name='rd_glue_destroy')
      import :: c_ptr
      type(c_ptr), value :: handle
    end subroutine rd_glue_destroy

    function rd_glue_set_tolerances(handle, rtol, atol, atol_vec) result(flag) &
        bind(C, name='rd_glue_set_tolerances')
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: handle
      real(c_double), value :: rtol, atol
      type(c_ptr), value :: atol_vec   ! c_null_ptr or c_loc of the per-component tolerances
      integer(c_int) :: flag
    end function rd_glue_set_tolerances

    function rd_glue_set_limits(handle, max_step, min_step, init_step, max_num_steps, &
                                max_order) result(flag) bind(C, name='rd_glue_set_limits')
      import :: c_ptr, c_double, c_long, c_int
      type(c_ptr), value :: handle
      real(c_double), value :: max_step, min_step, init_step
      integer(c_long), value :: max_num_steps
      integer(c_int), value :: max_order
      integer(c_int) :: flag
    end function rd_glue_set_limits

    function rd_glue_set_jacobian_age(handle, max_age) result(flag) bind(C, name='rd_glue_set_jacobian_age')
      import :: c_ptr, c_int, c_long
      type(c_ptr), value :: handle
      integer(c_long), value :: max_age
      integer(c_int) :: flag
    end function rd_glue_set_jacobian_age

    function rd_glue_use_jacobian(handle) result(flag) bind(C, name='rd_glue_use_jacobian')
      import :: c_ptr, c_int
      type(c_ptr), value :: handle
      integer(c_int) :: flag
    end function rd_glue_use_jacobian

    function rd_glue_advance(handle, tout, tstop, y_out, t_reached, valid) result(flag) &
        bind(C, name='rd_glue_advance')
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: handle
      real(c_double), value :: tout, tstop
      real(c_double), intent(inout) :: y_out(*)   ! unchanged when valid = 0
      real(c_double), intent(out) :: t_reached
      integer(c_int), intent(out) :: valid
      integer(c_int) :: flag
    end function rd_glue_advance

    function rd_glue_reinit(handle, t0, y0) result(flag) bind(C, name='rd_glue_reinit')
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: handle
      real(c_double), value :: t0
      real(c_double), intent(in) :: y0(*)
      integer(c_int) :: flag
    end function rd_glue_reinit

    function rd_glue_get_stats(handle, counts, reals) result(flag) &
        bind(C, name='rd_glue_get_stats')
      import :: c_ptr, c_long, c_double, c_int
      type(c_ptr), value :: handle
      integer(c_long), intent(out) :: counts(9)
      real(c_double), intent(out) :: reals(3)
      integer(c_int) :: flag
    end function rd_glue_get_stats

    subroutine rd_glue_flag_name(handle, flag, buf, buflen) bind(C, name='rd_glue_flag_name')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: handle
      integer(c_int), value :: flag
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int), value :: buflen
    end subroutine rd_glue_flag_name

    subroutine rd_glue_last_message(handle, buf, buflen) bind(C, name='rd_glue_last_message')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: handle
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int), value :: buflen
    end subroutine rd_glue_last_message
  end interface

contains

  !> SUNDIALS' RHS callback (called from the glue): ydot = f(t, y) of the system held by
  !> the rhs_context_t behind `user`. Returns 0 ok, 1 recoverable, -1 fatal.
  function rd_solver_rhs_callback(t, y, ydot, n, user) result(status) &
      bind(C, name='rd_solver_rhs_callback')
    integer(c_int64_t), value :: n
    real(c_double), value :: t
    real(c_double), intent(in) :: y(n)
    real(c_double), intent(out) :: ydot(n)
    type(c_ptr), value :: user
    integer(c_int) :: status
    type(rhs_context_t), pointer :: context

    call c_f_pointer(user, context)
    status = int(context%evaluate_rhs(t, y, ydot), c_int)
  end function rd_solver_rhs_callback

  !> CVODE's Jacobian callback: jac (n x n, column-major) = df/dy at (t, y), fy = f(t, y),
  !> by coloured difference quotients when the context holds a sparsity (with CVODE's
  !> current step h and error weights ewt; work1/work2 scratch), else by the analytic
  !> Jacobian procedure.
  function rd_solver_jac_callback(t, y, fy, jac, n, h, ewt, work1, work2, user) result(status) &
      bind(C, name='rd_solver_jac_callback')
    integer(c_int64_t), value :: n
    real(c_double), value :: t
    real(c_double), intent(in) :: y(n)
    real(c_double), intent(in) :: fy(n)
    real(c_double), intent(out) :: jac(n, n)
    real(c_double), value :: h
    real(c_double), intent(in) :: ewt(n)
    real(c_double), intent(out) :: work1(n), work2(n)
    type(c_ptr), value :: user
    integer(c_int) :: status
    type(rhs_context_t), pointer :: context

    call c_f_pointer(user, context)
    if (allocated(context%sparsity)) then
      status = int(context%evaluate_coloured_jacobian(t, y, fy, h, ewt, work1, work2, jac), c_int)
    else
      status = int(context%evaluate_jacobian(t, y, fy, jac), c_int)
    end if
  end function rd_solver_jac_callback

  !> Copy a NUL-terminated C buffer into a Fortran string.
  function c_string_to_fortran(buf) result(s)
    character(kind=c_char), intent(in) :: buf(:)
    character(len=:), allocatable :: s
    integer :: i, n
    n = 0
    do i = 1, size(buf)
      if (buf(i) == c_null_char) exit
      n = i
    end do
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = buf(i)
    end do
  end function c_string_to_fortran
end module rd_sundials_glue
