!> Test helper (not a ctest by itself): writes output steps slowly, for ever or for
!> max_steps, through rd_hdf5_writer, and prints "flushed <n>" (flushed to stdout at
!> once) each time the writer has flushed n rows to disk. tests/python/test_hdf5_kill.py
!> SIGKILLs it half-way and checks that the file holds at least those n rows.
!>
!> Usage: hdf5_writer_demo <file.h5> <flush_every> [buffer_steps=4] [sleep_ms=2] [max_steps=0]
!> (max_steps = 0: never stop). Row k (k = 0, 1, ...) holds
!>   /time                          0.01 k                      [s]
!>   /bodies/demo/position          (k, sin(0.1 k), -2 k)       [m]
!>   /wheelsets/ws1/left/normal_force  1000 + k                 [N]
program hdf5_writer_demo
  use, intrinsic :: iso_c_binding, only: c_int
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t
  use rd_hdf5_writer, only: h5_writer_t
  implicit none

  interface
    function usleep(microseconds) bind(C, name='usleep') result(status)
      import :: c_int
      integer(c_int), value :: microseconds
      integer(c_int) :: status
    end function usleep
  end interface

  type(h5_writer_t) :: writer
  type(error_t), allocatable :: error
  character(len=1024) :: path, arg
  integer :: flush_every, buffer_steps, sleep_ms, position_id, force_id
  integer(i8) :: k, max_steps, last_reported
  real(wp) :: x

  if (command_argument_count() < 2) then
    write (error_unit, '(a)') 'usage: hdf5_writer_demo <file.h5> <flush_every> ' // &
      '[buffer_steps=4] [sleep_ms=2] [max_steps=0]'
    error stop 2
  end if
  call get_command_argument(1, path)
  call get_command_argument(2, arg); read (arg, *) flush_every
  buffer_steps = 4; sleep_ms = 2; max_steps = 0
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg); read (arg, *) buffer_steps
  end if
  if (command_argument_count() >= 4) then
    call get_command_argument(4, arg); read (arg, *) sleep_ms
  end if
  if (command_argument_count() >= 5) then
    call get_command_argument(5, arg); read (arg, *) max_steps
  end if

  call writer%open(trim(path), error, buffer_steps=buffer_steps, flush_every=flush_every)
  if (.not. allocated(error)) call writer%set_attribute('/', 'title', 'hdf5_writer_demo', error)
  if (.not. allocated(error)) call writer%write_text('meta/deck_text', '&run t_end = 1 /', error)
  if (.not. allocated(error)) &
    call writer%add_series('bodies/demo/position', 3, 'm', 'demo position', position_id, error, &
                           component_names='x y z')
  if (.not. allocated(error)) &
    call writer%add_series('wheelsets/ws1/left/normal_force', 1, 'N', 'demo force', force_id, &
                           error, component_names='N')
  call check()

  last_reported = 0
  k = 0
  do while (max_steps == 0 .or. k < max_steps)
    x = real(k, wp)
    call writer%set(position_id, [x, sin(0.1_wp*x), -2.0_wp*x], error); call check()
    call writer%set(force_id, [1000.0_wp + x], error); call check()
    call writer%end_step(0.01_wp*x, error); call check()
    if (writer%steps_flushed() /= last_reported) then
      last_reported = writer%steps_flushed()
      write (output_unit, '(a, i0)') 'flushed ', last_reported
      flush (output_unit)
    end if
    if (sleep_ms > 0) then
      if (usleep(int(1000*sleep_ms, c_int)) /= 0) continue
    end if
    k = k + 1
  end do
  call writer%close('completed', 0.01_wp*real(max_steps - 1, wp), 0.0_wp, error)
  call check()
  write (output_unit, '(a, i0)') 'closed ', max_steps

contains

  subroutine check()
    if (allocated(error)) then
      write (error_unit, '(a)') 'hdf5_writer_demo: ' // error%message
      error stop 1
    end if
  end subroutine check
end program hdf5_writer_demo
