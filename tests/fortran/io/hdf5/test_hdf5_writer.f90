!> Tests of rd_hdf5_writer. The oracle is the HDF5 library's own reader (the Fortran API,
!> independent of the writer's buffering and hyperslab logic) and the closed-form values
!> the test itself feeds in: shapes as h5py sees them (rows = steps), exact values, units,
!> components, metadata; refusal of NaN/Inf naming the series; an unwritable path;
!> two writers alive in one process; call-order errors; an empty run.
!> Reals are compared exactly on purpose: storage must be bit-exact.
program test_hdf5_writer
  use test_files, only: delete_file
  use, intrinsic :: iso_c_binding, only: c_char, c_loc, c_ptr
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
  use hdf5
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, RD_ERR_IO, RD_ERR_INPUT, RD_ERR_HANDLE
  use rd_hdf5_writer, only: h5_writer_t
  use rd_test_support, only: check, test_summary
  implicit none

  character(len=512) :: tmpdir

  call get_environment_variable('TMPDIR', tmpdir)
  if (len_trim(tmpdir) == 0) tmpdir = '/tmp'

  call test_round_trip()
  call test_refuses_non_finite()
  call test_unwritable_path()
  call test_two_writers()
  call test_call_order()
  call test_empty_run()
  call test_other_axis()

  call test_summary('test_hdf5_writer')

contains

  function tmpfile(name) result(path)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: path
    character(len=16) :: pid
    ! Process id (GNU extension) keeps parallel ctest runs (Release, Debug) apart.
    write (pid, '(i0)') getpid()
    path = trim(tmpdir) // '/rd_test_hdf5_' // trim(pid) // '_' // name
  end function tmpfile

  subroutine require_ok(error, what)
    type(error_t), allocatable, intent(in) :: error
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      print '(a)', 'FAILED (unexpected error) ' // what // ': ' // error%message
      error stop 1
    end if
  end subroutine require_ok

  !> Closed-form contents of the round-trip file.
  pure function pose(k) result(q)
    integer, intent(in) :: k
    real(wp) :: q(6)
    q = [1.5_wp*k, -0.25_wp*k, 0.5_wp + k, 1.0e-3_wp*k, -2.0e-3_wp*k, 0.125_wp*k*k]
  end function pose

  subroutine test_round_trip()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=:), allocatable :: path, deck
    integer :: id_pose, id_sigma, k
    integer, parameter :: nsteps = 11
    real(wp), allocatable :: data(:, :), time(:)
    integer(hid_t) :: file
    integer :: hdferr

    path = tmpfile('round_trip.h5')
    deck = '&track name = ''straight'' /' // new_line('a') // '&run t_end = 0.1 /'
    ! buffer 3 and flush every 5: 11 steps exercise full buffers, flushes and a partial tail.
    call w%open(path, error, buffer_steps=3, flush_every=5); call require_ok(error, 'open')
    call w%set_attribute('/', 'title', 'round trip', error); call require_ok(error, 'title')
    call w%set_attribute('/', 'raildyn_version', '0.1.0', error); call require_ok(error, 'version')
    call w%set_attribute('meta', 'output_interval', 0.01_wp, error); call require_ok(error, 'real attr')
    call w%set_attribute('track/frames/1', 'body_count', 2, error); call require_ok(error, 'int attr on new group')
    call w%write_text('meta/deck_text', deck, error); call require_ok(error, 'deck text')
    call w%add_series('/bodies/car/position_track/', 6, 'm m m rad rad rad', 'car pose in its track frame', &
                      id_pose, error, component_names='x y z yaw roll pitch')
    call require_ok(error, 'add pose')
    call w%add_series('track/frames/1/sigma', 1, 'm', 'arc length', id_sigma, error)
    call require_ok(error, 'add sigma')
    call check(w%series_count() == 2, 'series_count = 2')
    do k = 0, nsteps - 1
      call w%set(id_pose, pose(k), error); call require_ok(error, 'set pose')
      call w%set(id_sigma, [2.0_wp*k], error); call require_ok(error, 'set sigma')
      call w%end_step(0.01_wp*k, error); call require_ok(error, 'end_step')
      if (k == 4) call check(w%steps_flushed() == 5, 'flushed 5 rows after step 5')
    end do
    call check(w%steps_written() == nsteps, 'steps_written = 11')
    call check(w%steps_flushed() == 10, 'flushed 10 rows after step 11')
    call w%flush(error); call require_ok(error, 'explicit flush')
    call check(w%steps_flushed() == nsteps, 'explicit flush writes the partial buffer')
    call w%close('completed', 0.105_wp, 1.25_wp, error, &
                 int_stat_names=[character(len=8) :: 'n_rhs', 'n_jac'], int_stat_values=[12345_i8, 67_i8], &
                 real_stat_names=['h_last'], real_stat_values=[2.5e-4_wp])
    call require_ok(error, 'close')
    call check(.not. w%is_open(), 'closed after close')

    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
    call check(hdferr == 0, 'reopen with HDF5')
    call read_1d(file, 'time', time)
    call check(size(time) == nsteps, 'time has 11 rows')
    call check(all(time == [(0.01_wp*k, k = 0, nsteps - 1)]), 'time values')
    call read_2d(file, 'bodies/car/position_track', data)
    ! Fortran (6, 11) is h5py's (11, 6): one row per step.
    call check(size(data, 1) == 6 .and. size(data, 2) == nsteps, 'pose shape (6, 11) = h5py (11, 6)')
    if (size(data, 2) == nsteps) then
      do k = 0, nsteps - 1
        call check(all(data(:, k + 1) == pose(k)), 'pose row values')
      end do
    end if
    call read_2d(file, 'track/frames/1/sigma', data)
    call check(size(data, 1) == 1 .and. size(data, 2) == nsteps, 'sigma shape (1, 11)')
    if (size(data, 2) == nsteps) call check(all(data(1, :) == [(2.0_wp*k, k = 0, nsteps - 1)]), 'sigma values')
    call check(string_attr(file, 'bodies/car/position_track', 'unit') == 'm m m rad rad rad', 'pose unit')
    call check(string_attr(file, 'bodies/car/position_track', 'components') == 'x y z yaw roll pitch', 'pose components')
    call check(string_attr(file, 'bodies/car/position_track', 'description') == 'car pose in its track frame', &
               'pose description')
    call check(string_attr(file, 'track/frames/1/sigma', 'components') == 'sigma', 'default scalar component name')
    call check(string_attr(file, 'time', 'unit') == 's', 'time unit')
    call check(string_attr(file, '/', 'axis') == 'time', 'default axis is time')
    call check(string_attr(file, '/', 'format') == 'raildyn-results', 'format attribute')
    call check(string_attr(file, '/', 'title') == 'round trip', 'title attribute')
    call check(len(string_attr(file, '/', 'created')) == 25, 'created is ISO 8601 with offset')
    call check(string_attr(file, 'meta', 'status') == 'completed', 'status completed')
    call check(real_attr(file, 'meta', 'end_time') == 0.105_wp, 'end_time')
    call check(real_attr(file, 'meta', 'wall_time') == 1.25_wp, 'wall_time')
    call check(real_attr(file, 'meta', 'output_interval') == 0.01_wp, 'real attribute')
    call check(int_attr(file, 'meta', 'n_steps') == nsteps, 'n_steps')
    call check(int_attr(file, 'track/frames/1', 'body_count') == 2, 'int attribute on created group')
    call check(int_attr(file, 'meta/solver', 'n_rhs') == 12345, 'solver stat n_rhs')
    call check(int_attr(file, 'meta/solver', 'n_jac') == 67, 'solver stat n_jac')
    call check(real_attr(file, 'meta/solver', 'h_last') == 2.5e-4_wp, 'solver stat h_last')
    call check(string_dataset(file, 'meta/deck_text') == deck, 'deck text round trip')
    call h5fclose_f(file, hdferr)
    call delete_file(path)
  end subroutine test_round_trip

  subroutine test_refuses_non_finite()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=:), allocatable :: path
    integer :: id_a, id_b
    real(wp) :: nan, inf
    real(wp), allocatable :: data(:, :)
    integer(hid_t) :: file
    integer :: hdferr

    nan = ieee_value(nan, ieee_quiet_nan)
    inf = ieee_value(inf, ieee_positive_inf)
    path = tmpfile('nan.h5')
    call w%open(path, error, buffer_steps=2, flush_every=2); call require_ok(error, 'open nan')
    call w%add_series('elements/spring1/force', 3, 'N', 'force', id_a, error); call require_ok(error, 'add a')
    call w%add_series('bodies/b/velocity', 2, 'm/s', 'v', id_b, error); call require_ok(error, 'add b')
    call w%set(id_a, [1.0_wp, 2.0_wp, 3.0_wp], error); call require_ok(error, 'set a')
    call w%set(id_b, [1.0_wp, 2.0_wp], error); call require_ok(error, 'set b')
    call w%end_step(0.0_wp, error); call require_ok(error, 'step 1')

    call w%set(id_a, [1.0_wp, nan, 3.0_wp], error)
    call check(allocated(error), 'NaN refused')
    if (allocated(error)) then
      call check(index(error%message, 'elements/spring1/force') > 0, 'NaN message names the series')
      call check(index(error%message, 'component 2') > 0, 'NaN message names the component')
      call check(error%code == RD_ERR_INPUT, 'NaN error code')
    end if
    call w%set(id_b, [inf, 0.0_wp], error)
    call check(allocated(error), 'Inf refused')
    if (allocated(error)) call check(index(error%message, 'bodies/b/velocity') > 0, 'Inf message names the series')
    call w%end_step(0.01_wp, error)
    call check(allocated(error), 'end_step refuses a step whose series were not set')
    call w%set(id_a, [4.0_wp, 5.0_wp, 6.0_wp], error); call require_ok(error, 'set a again')
    call w%set(id_b, [7.0_wp, 8.0_wp], error); call require_ok(error, 'set b again')
    call w%end_step(nan, error)
    call check(allocated(error), 'NaN time refused')
    call w%end_step(0.01_wp, error); call require_ok(error, 'step 2')
    call w%close('failed: test', 0.01_wp, 0.0_wp, error); call require_ok(error, 'close nan')

    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
    call read_2d(file, 'elements/spring1/force', data)
    call check(size(data, 2) == 2, 'two rows after refused values')
    if (size(data, 2) == 2) call check(all(data(:, 2) == [4.0_wp, 5.0_wp, 6.0_wp]), 'row 2 is the valid one')
    call check(string_attr(file, 'meta', 'status') == 'failed: test', 'status failed')
    call h5fclose_f(file, hdferr)
    call delete_file(path)
  end subroutine test_refuses_non_finite

  subroutine test_unwritable_path()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=*), parameter :: bad = '/nonexistent-raildyn-dir/sub/out.h5'
    call w%open(bad, error)
    call check(allocated(error), 'unwritable path is an error')
    if (allocated(error)) then
      call check(error%code == RD_ERR_IO, 'unwritable path: RD_ERR_IO')
      call check(index(error%message, bad) > 0, 'unwritable path: message names the file')
    end if
    call check(.not. w%is_open(), 'writer closed after failed open')
    call w%end_step(0.0_wp, error)
    call check(allocated(error), 'end_step on a closed writer is an error')
    if (allocated(error)) call check(error%code == RD_ERR_HANDLE, 'closed writer: RD_ERR_HANDLE')
  end subroutine test_unwritable_path

  !> No module-global state: two writers interleaved, different buffering.
  subroutine test_two_writers()
    type(h5_writer_t) :: w1, w2
    type(error_t), allocatable :: error
    character(len=:), allocatable :: p1, p2
    integer :: i1, i2, k
    real(wp), allocatable :: d1(:, :), d2(:, :), t1(:), t2(:)
    integer(hid_t) :: file
    integer :: hdferr

    p1 = tmpfile('w1.h5'); p2 = tmpfile('w2.h5')
    call w1%open(p1, error, buffer_steps=4, flush_every=7); call require_ok(error, 'open w1')
    call w2%open(p2, error, buffer_steps=1, flush_every=3); call require_ok(error, 'open w2')
    call w1%add_series('bodies/a/x', 2, 'm', 'a', i1, error); call require_ok(error, 'add w1')
    call w2%add_series('bodies/b/x', 1, 'rad', 'b', i2, error); call require_ok(error, 'add w2')
    do k = 1, 20
      call w1%set(i1, [real(k, wp), -real(k, wp)], error); call require_ok(error, 'set w1')
      call w1%end_step(real(k, wp), error); call require_ok(error, 'step w1')
      if (mod(k, 2) == 0) then
        call w2%set(i2, [100.0_wp + k], error); call require_ok(error, 'set w2')
        call w2%end_step(0.5_wp*k, error); call require_ok(error, 'step w2')
      end if
    end do
    call w2%close('stopped', 10.0_wp, 0.0_wp, error); call require_ok(error, 'close w2')
    call w1%close('completed', 20.0_wp, 0.0_wp, error); call require_ok(error, 'close w1')

    call h5fopen_f(p1, H5F_ACC_RDONLY_F, file, hdferr)
    call read_1d(file, 'time', t1)
    call read_2d(file, 'bodies/a/x', d1)
    call check(string_attr(file, 'meta', 'status') == 'completed', 'w1 status')
    call h5fclose_f(file, hdferr)
    call h5fopen_f(p2, H5F_ACC_RDONLY_F, file, hdferr)
    call read_1d(file, 'time', t2)
    call read_2d(file, 'bodies/b/x', d2)
    call check(string_attr(file, 'meta', 'status') == 'stopped', 'w2 status')
    call h5fclose_f(file, hdferr)
    call check(size(t1) == 20 .and. size(t2) == 10, 'two writers: row counts 20 and 10')
    if (size(t1) == 20 .and. size(d1, 2) == 20) then
      call check(all(t1 == [(real(k, wp), k = 1, 20)]), 'w1 time')
      call check(all(d1(1, :) == [(real(k, wp), k = 1, 20)]) .and. all(d1(2, :) == -d1(1, :)), 'w1 values')
    end if
    if (size(t2) == 10 .and. size(d2, 2) == 10) then
      call check(all(t2 == [(real(k, wp), k = 1, 10)]), 'w2 time')
      call check(all(d2(1, :) == [(100.0_wp + 2*k, k = 1, 10)]), 'w2 values')
    end if
    call delete_file(p1); call delete_file(p2)
  end subroutine test_two_writers

  subroutine test_call_order()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=:), allocatable :: path
    integer :: id, id2

    path = tmpfile('order.h5')
    call w%open(path, error); call require_ok(error, 'open order')
    call w%open(path, error)
    call check(allocated(error), 'open twice is an error')
    call w%add_series('x', 0, 'm', 'zero columns', id, error)
    call check(allocated(error), 'ncomp = 0 refused')
    call w%add_series('x', 3, 'm s', 'two units for three columns', id, error)
    call check(allocated(error), 'unit count mismatch refused')
    call w%add_series('x', 2, 'm', 'names', id, error, component_names='a b c')
    call check(allocated(error), 'component name count mismatch refused')
    call w%add_series('time', 1, 's', 'clash with /time', id, error)
    call check(allocated(error), 'series named time refused')
    call w%add_series('bodies/a/x', 2, 'm', 'ok', id, error); call require_ok(error, 'add ok')
    call w%add_series('bodies/a/x', 2, 'm', 'again', id2, error)
    call check(allocated(error), 'duplicate series refused')
    call w%set(id, [1.0_wp], error)
    call check(allocated(error), 'wrong number of values refused')
    call w%set(id + 1, [1.0_wp, 2.0_wp], error)
    call check(allocated(error), 'invalid id refused')
    call w%set(id, [1.0_wp, 2.0_wp], error); call require_ok(error, 'set')
    call w%end_step(1.0_wp, error); call require_ok(error, 'step')
    call w%set(id, [1.0_wp, 2.0_wp], error); call require_ok(error, 'set')
    call w%end_step(1.0_wp, error)
    call check(allocated(error), 'non-increasing time refused')
    call w%add_series('bodies/a/y', 1, 'm', 'late', id2, error)
    call check(allocated(error), 'add_series after the first step refused')
    if (allocated(error)) call check(error%code == RD_ERR_HANDLE, 'late add_series: RD_ERR_HANDLE')
    call w%set_attribute('/', 'late', 1.0_wp, error)
    call check(allocated(error), 'attribute after the first step refused')
    call w%close('completed', 1.0_wp, 0.0_wp, error); call require_ok(error, 'close order')
    call w%close('completed', 1.0_wp, 0.0_wp, error)
    call check(allocated(error), 'close twice is an error')
    call delete_file(path)
  end subroutine test_call_order

  subroutine test_empty_run()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=:), allocatable :: path
    integer :: id
    real(wp), allocatable :: data(:, :), time(:)
    integer(hid_t) :: file
    integer :: hdferr

    path = tmpfile('empty.h5')
    call w%open(path, error); call require_ok(error, 'open empty')
    call w%add_series('bodies/a/x', 4, 'm', 'never written', id, error); call require_ok(error, 'add')
    call w%write_text('meta/deck_text', '', error); call require_ok(error, 'empty text')
    call w%close('failed: initial state is not finite', 0.0_wp, 0.0_wp, error); call require_ok(error, 'close')
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
    call read_1d(file, 'time', time)
    call read_2d(file, 'bodies/a/x', data)
    call check(size(time) == 0 .and. size(data, 1) == 4 .and. size(data, 2) == 0, 'empty run shapes')
    call check(string_dataset(file, 'meta/deck_text') == '', 'empty text reads empty')
    call check(int_attr(file, 'meta', 'n_steps') == 0, 'empty run n_steps')
    call h5fclose_f(file, hdferr)
    call delete_file(path)
  end subroutine test_empty_run

  !> A track export samples along sigma [m] instead of time: the axis dataset is named
  !> by the caller and recorded in the root attribute `axis`.
  subroutine test_other_axis()
    type(h5_writer_t) :: w
    type(error_t), allocatable :: error
    character(len=:), allocatable :: path
    integer :: id, k
    real(wp), allocatable :: sigma(:), data(:, :)
    integer(hid_t) :: file
    integer :: hdferr
    logical :: has_time

    path = tmpfile('axis.h5')
    call w%open(path, error, axis_name='bad name', axis_unit='m')
    call check(allocated(error), 'axis name with a space refused')
    call w%open(path, error, axis_name='sigma', axis_unit='m m')
    call check(allocated(error), 'axis with two units refused')
    call w%open(path, error, axis_name='sigma', axis_unit='m', axis_description='arc length')
    call require_ok(error, 'open with axis sigma')
    call w%add_series('sigma', 1, 'm', 'clash', id, error)
    call check(allocated(error), 'series named like the axis refused')
    call w%add_series('track/curvature', 1, '1/m', 'curvature', id, error, component_names='kappa')
    call require_ok(error, 'add curvature')
    do k = 1, 5
      call w%set(id, [1.0_wp/(100.0_wp*k)], error); call require_ok(error, 'set curvature')
      call w%end_step(10.0_wp*k, error); call require_ok(error, 'step sigma')
    end do
    call w%close('completed', 50.0_wp, 0.0_wp, error); call require_ok(error, 'close axis')
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
    call read_1d(file, 'sigma', sigma)
    call check(size(sigma) == 5, 'sigma axis has 5 rows')
    if (size(sigma) == 5) call check(all(sigma == [(10.0_wp*k, k = 1, 5)]), 'sigma axis values')
    call read_2d(file, 'track/curvature', data)
    call check(size(data, 2) == 5, 'curvature rows')
    call check(string_attr(file, 'sigma', 'unit') == 'm', 'axis unit')
    call check(string_attr(file, 'sigma', 'description') == 'arc length', 'axis description')
    call check(string_attr(file, '/', 'axis') == 'sigma', 'root attribute axis')
    call h5lexists_f(file, 'time', has_time, hdferr)
    call check(.not. has_time, 'no /time when another axis is chosen')
    call h5fclose_f(file, hdferr)
    call delete_file(path)
  end subroutine test_other_axis

  ! ----- reading with the HDF5 Fortran API (the oracle) -----

  subroutine read_1d(file, path, data)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    real(wp), allocatable, target, intent(out) :: data(:)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxdims(1)
    integer :: hdferr, rank
    type(c_ptr) :: ptr
    call h5dopen_f(file, path, dset, hdferr)
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, rank, hdferr)
    call check(rank == 1, path // ' has rank 1')
    call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
    allocate (data(dims(1)))
    if (dims(1) > 0) then
      ptr = c_loc(data)
      call h5dread_f(dset, H5T_NATIVE_DOUBLE, ptr, hdferr)
    end if
    call h5sclose_f(space, hdferr)
    call h5dclose_f(dset, hdferr)
  end subroutine read_1d

  subroutine read_2d(file, path, data)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    real(wp), allocatable, target, intent(out) :: data(:, :)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(2), maxdims(2)
    integer :: hdferr, rank
    type(c_ptr) :: ptr
    call h5dopen_f(file, path, dset, hdferr)
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, rank, hdferr)
    call check(rank == 2, path // ' has rank 2')
    call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
    allocate (data(dims(1), dims(2)))
    if (dims(2) > 0) then
      ptr = c_loc(data)
      call h5dread_f(dset, H5T_NATIVE_DOUBLE, ptr, hdferr)
    end if
    call h5sclose_f(space, hdferr)
    call h5dclose_f(dset, hdferr)
  end subroutine read_2d

  function string_attr(file, object, name) result(text)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: object, name
    character(len=:), allocatable :: text
    integer(hid_t) :: attr, atype
    integer(size_t) :: n
    character(kind=c_char), allocatable, target :: chars(:)
    integer :: hdferr
    type(c_ptr) :: ptr
    call h5aopen_by_name_f(file, object, name, attr, hdferr)
    if (hdferr < 0) then
      text = '<missing attribute ' // name // '>'
      return
    end if
    call h5aget_type_f(attr, atype, hdferr)
    call h5tget_size_f(atype, n, hdferr)
    allocate (chars(n))
    ptr = c_loc(chars); call h5aread_f(attr, atype, ptr, hdferr)
    call h5tclose_f(atype, hdferr)
    call h5aclose_f(attr, hdferr)
    text = from_chars(chars)
  end function string_attr

  function string_dataset(file, path) result(text)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: text
    integer(hid_t) :: dset, dtype
    integer(size_t) :: n
    character(kind=c_char), allocatable, target :: chars(:)
    integer :: hdferr
    type(c_ptr) :: ptr
    call h5dopen_f(file, path, dset, hdferr)
    call h5dget_type_f(dset, dtype, hdferr)
    call h5tget_size_f(dtype, n, hdferr)
    allocate (chars(n))
    ptr = c_loc(chars); call h5dread_f(dset, dtype, ptr, hdferr)
    call h5tclose_f(dtype, hdferr)
    call h5dclose_f(dset, hdferr)
    text = from_chars(chars)
  end function string_dataset

  function from_chars(chars) result(text)
    character(kind=c_char), intent(in) :: chars(:)
    character(len=:), allocatable :: text
    integer :: k, n
    n = size(chars)
    do k = 1, size(chars)
      if (chars(k) == achar(0)) then
        n = k - 1
        exit
      end if
    end do
    allocate (character(len=n) :: text)
    do k = 1, n
      text(k:k) = chars(k)
    end do
  end function from_chars

  real(wp) function real_attr(file, object, name)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: object, name
    real(wp), target :: value
    integer(hid_t) :: attr
    integer :: hdferr
    type(c_ptr) :: ptr
    value = -huge(value)
    call h5aopen_by_name_f(file, object, name, attr, hdferr)
    if (hdferr >= 0) then
      ptr = c_loc(value); call h5aread_f(attr, H5T_NATIVE_DOUBLE, ptr, hdferr)
      call h5aclose_f(attr, hdferr)
    end if
    real_attr = value
  end function real_attr

  integer(i8) function int_attr(file, object, name)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: object, name
    integer(i8), target :: value
    integer(hid_t) :: attr
    integer :: hdferr
    type(c_ptr) :: ptr
    value = -huge(value)
    call h5aopen_by_name_f(file, object, name, attr, hdferr)
    if (hdferr >= 0) then
      ptr = c_loc(value); call h5aread_f(attr, H5T_STD_I64LE, ptr, hdferr)
      call h5aclose_f(attr, hdferr)
    end if
    int_attr = value
  end function int_attr

end program test_hdf5_writer
