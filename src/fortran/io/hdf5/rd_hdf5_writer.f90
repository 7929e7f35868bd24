!> HDF5 results writer: time series of everything a scene produces on one time axis,
!> plus run metadata. The layout it writes is the contract documented in docs/output.md.
!>
!> Life cycle (one object per file, no module-global state, so two writers may live
!> in one process):
!>
!>   1. `open`          create/truncate the file (latest file format, needed for SWMR);
!>                      writes root attributes `format`, `format_version`, `created`,
!>                      the `/time` dataset and `/meta` with `status = 'running'`.
!>   2. define phase    `add_series`, `write_text`, `set_attribute` (root, any group or
!>                      dataset). New objects and attributes can only be created here.
!>   3. stepping        per output step: `set(id, values)` for every series, then
!>                      `end_step(time)`. The first `end_step` switches the file to
!>                      SWMR write mode (H5Fstart_swmr_write). Rows are buffered in
!>                      memory and appended as one hyperslab per series every
!>                      `buffer_steps` rows; every `flush_every` rows the buffers are
!>                      written and the file is flushed (H5Fflush). In SWMR mode HDF5
!>                      orders its metadata writes so that the file on disk is always
!>                      readable, so a process killed at any moment leaves a file with
!>                      at least all rows up to the last flush.
!>   4. `close`         writes what is buffered, closes the SWMR session, reopens the
!>                      file normally and writes the final run metadata (status, end
!>                      time, wall time, solver statistics) in `/meta`.
!>
!> Data layout: Fortran writes column-major buffers `(ncomp, nrows)`, which HDF5 (C order)
!> and h5py see as `(nrows, ncomp)`: one row per output step; `/time` is `(nrows,)`.
!> Every dataset carries the attributes `unit`, `description`, `components`.
!> Non-finite values are refused with an error naming the series (brief: never a NaN in
!> the output). Unwritten cells have the fill value NaN, so a row that a crash left
!> half-written cannot be mistaken for data.
module rd_hdf5_writer
  use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_bool, c_char, c_loc, c_ptr, &
                                         c_null_char
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
  use hdf5
  use rd_kinds, only: wp, i8
  use rd_text, only: int_text, sci_text
  use rd_error, only: error_t, make_error, error_context, RD_ERR_IO, RD_ERR_INPUT, &
                      RD_ERR_HANDLE
  implicit none
  private
  public :: h5_writer_t, RESULTS_FORMAT, RESULTS_FORMAT_VERSION

  character(len=*), parameter :: RESULTS_FORMAT = 'raildyn-results'
  integer, parameter :: RESULTS_FORMAT_VERSION = 1

  integer, parameter :: MODE_CLOSED = 0    !< no file
  integer, parameter :: MODE_DEFINE = 1    !< file open, objects may be created
  integer, parameter :: MODE_STEPPING = 2  !< SWMR write mode: only appending

  integer, parameter :: DEFAULT_BUFFER_STEPS = 256
  integer, parameter :: DEFAULT_FLUSH_EVERY = 256

  !> H5Fstart_swmr_write has no Fortran wrapper in HDF5 1.10; the C routine takes the
  !> same hid_t (int64_t in HDF5 >= 1.10, H5Ipublic.h) the Fortran API hands out.
  interface
    function c_h5fstart_swmr_write(file_id) bind(C, name='H5Fstart_swmr_write') result(status)
      import :: c_int, c_int64_t
      integer(c_int64_t), value :: file_id
      integer(c_int) :: status
    end function c_h5fstart_swmr_write
    !> H5Pset_file_locking (HDF5 >= 1.10.7), also without a Fortran wrapper.
    function c_h5pset_file_locking(fapl_id, use_file_locking, ignore_when_disabled) &
        bind(C, name='H5Pset_file_locking') result(status)
      import :: c_int, c_int64_t, c_bool
      integer(c_int64_t), value :: fapl_id
      logical(c_bool), value :: use_file_locking, ignore_when_disabled
      integer(c_int) :: status
    end function c_h5pset_file_locking
  end interface

  !> One registered time series (a dataset of shape (nrows, ncomp) in h5py).
  type :: series_t
    character(len=:), allocatable :: path
    integer :: ncomp = 0
    integer(hid_t) :: dataset = -1
    real(wp), allocatable :: buffer(:, :)  !< (ncomp, buffer_steps), rows not yet written
    logical :: is_set = .false.            !< set() called since the last end_step()
  end type series_t

  type :: h5_writer_t
    private
    character(len=:), allocatable :: filename
    character(len=:), allocatable :: axis_name   !< the common axis dataset ('time')
    integer(hid_t) :: file = -1
    integer(hid_t) :: time_dataset = -1
    integer :: mode = MODE_CLOSED
    integer :: buffer_steps = DEFAULT_BUFFER_STEPS
    integer :: flush_every = DEFAULT_FLUSH_EVERY
    type(series_t), allocatable :: series(:)
    integer :: nseries = 0
    real(wp), allocatable :: time_buffer(:)
    integer :: nbuffered = 0           !< rows held in the buffers
    integer(i8) :: nwritten = 0        !< rows in the file (dataset extent)
    integer(i8) :: nflushed = 0        !< rows in the file at the last flush
    integer :: steps_since_flush = 0
    real(wp) :: last_time = 0.0_wp
  contains
    procedure :: open => writer_open
    procedure :: add_series => writer_add_series
    procedure :: write_text => writer_write_text
    procedure, private :: set_attribute_text, set_attribute_real, set_attribute_int, &
                          set_attribute_int8
    generic :: set_attribute => set_attribute_text, set_attribute_real, set_attribute_int, &
                                set_attribute_int8
    procedure :: set => writer_set
    procedure :: end_step => writer_end_step
    procedure :: flush => writer_flush
    procedure :: close => writer_close
    procedure :: is_open => writer_is_open
    procedure :: steps_written => writer_steps_written
    procedure :: steps_flushed => writer_steps_flushed
    procedure :: series_count => writer_series_count
    procedure, private :: write_buffers
    procedure, private :: start_stepping
    procedure, private :: release_handles
  end type h5_writer_t

contains

  ! ---------------------------------------------------------------------------------
  ! Opening and defining
  ! ---------------------------------------------------------------------------------

  !> Create (or truncate) the results file `path`.
  !> buffer_steps: rows kept in memory per series before one hyperslab write (>= 1);
  !> flush_every: rows between two flushes to disk (>= 1); a killed run keeps all rows
  !> up to its last flush. axis_name/axis_unit/axis_description: the common axis of all
  !> series, default '/time' in s; another strictly increasing axis (e.g. 'sigma' in m
  !> for a track export) is named in the root attribute `axis`.
  subroutine writer_open(self, path, error, buffer_steps, flush_every, axis_name, axis_unit, &
                         axis_description)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(out) :: error
    integer, intent(in), optional :: buffer_steps, flush_every
    character(len=*), intent(in), optional :: axis_name, axis_unit, axis_description
    character(len=:), allocatable :: unit, description
    integer :: hdferr
    integer(hid_t) :: fapl, group

    if (self%mode /= MODE_CLOSED) then
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%open: writer already has file "' // &
                      self%filename // '" open; close it first')
      return
    end if
    if (len_trim(path) == 0) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%open: empty file name; expected a path')
      return
    end if
    self%buffer_steps = DEFAULT_BUFFER_STEPS
    self%flush_every = DEFAULT_FLUSH_EVERY
    if (present(buffer_steps)) self%buffer_steps = buffer_steps
    if (present(flush_every)) self%flush_every = flush_every
    if (self%buffer_steps < 1 .or. self%flush_every < 1) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%open("' // trim(path) // &
                      '"): buffer_steps and flush_every must be >= 1')
      return
    end if

    self%axis_name = 'time'
    unit = 's'
    description = 'simulated time of each output step'
    if (present(axis_name)) self%axis_name = strip_slashes(axis_name)
    if (present(axis_unit)) unit = trim(adjustl(axis_unit))
    if (present(axis_description)) description = trim(axis_description)
    if (len(self%axis_name) == 0 .or. index(self%axis_name, '/') > 0 .or. &
        index(self%axis_name, ' ') > 0 .or. self%axis_name == 'meta' .or. &
        count_words(unit) /= 1) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%open("' // trim(path) // '"): axis_name ' // &
                      'must be one word at the root (not "meta") and axis_unit one unit')
      return
    end if

    self%filename = trim(path)
    self%nseries = 0
    self%nbuffered = 0
    self%nwritten = 0
    self%nflushed = 0
    self%steps_since_flush = 0
    self%last_time = 0.0_wp
    if (allocated(self%series)) deallocate (self%series)
    allocate (self%series(8))
    if (allocated(self%time_buffer)) deallocate (self%time_buffer)
    allocate (self%time_buffer(self%buffer_steps))

    call h5open_f(hdferr)   ! idempotent: initialises the Fortran type constants
    if (hdferr < 0) then
      call io_error(error, self%filename, 'cannot initialise the HDF5 library')
      return
    end if

    ! SWMR needs the latest file format (checksummed metadata, superblock v3).
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call h5pset_libver_bounds_f(fapl, H5F_LIBVER_LATEST_F, H5F_LIBVER_LATEST_F, hdferr)
    call quiet_hdf5(.true.)
    call h5fcreate_f(self%filename, H5F_ACC_TRUNC_F, self%file, hdferr, access_prp=fapl)
    call quiet_hdf5(.false.)
    call h5pclose_f(fapl, hdferr)
    if (self%file < 0) then
      self%file = -1
      call io_error(error, self%filename, 'cannot create the file (does the directory ' // &
                    'exist and is it writable?)')
      return
    end if
    self%mode = MODE_DEFINE

    call create_group(self%file, 'meta', group, error)
    if (.not. allocated(error)) call h5gclose_f(group, hdferr)
    if (.not. allocated(error)) call create_group(self%file, 'meta/solver', group, error)
    if (.not. allocated(error)) call h5gclose_f(group, hdferr)
    if (.not. allocated(error)) call create_axis_dataset(self, unit, description, error)
    if (.not. allocated(error)) call self%set_attribute('/', 'format', RESULTS_FORMAT, error)
    if (.not. allocated(error)) &
      call self%set_attribute('/', 'format_version', RESULTS_FORMAT_VERSION, error)
    if (.not. allocated(error)) call self%set_attribute('/', 'created', iso_timestamp(), error)
    if (.not. allocated(error)) call self%set_attribute('/', 'axis', self%axis_name, error)
    if (.not. allocated(error)) call self%set_attribute('meta', 'status', 'running', error)
    if (allocated(error)) then
      call self%release_handles()
      call error_context(error, 'h5_writer%open')
    end if
  end subroutine writer_open

  !> Register a series `path` (e.g. 'bodies/ws1/position_track') with `ncomp` columns.
  !> `unit`: one SI unit for all columns or one per column, space separated, no spaces
  !> inside a unit ('m m m rad rad rad', 'N*m'). `component_names`: space-separated column
  !> names ('x y z yaw roll pitch'); default 'c1 c2 ...' (or the last path segment if
  !> ncomp = 1). Returns the series `id` used by `set`. Only before the first end_step.
  subroutine writer_add_series(self, path, ncomp, unit, description, id, error, component_names)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(in) :: ncomp
    character(len=*), intent(in) :: unit
    character(len=*), intent(in) :: description
    integer, intent(out) :: id
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: component_names
    character(len=:), allocatable :: names, name
    type(series_t), allocatable :: grown(:)
    integer(hid_t) :: space, dcpl, lcpl, dataset
    integer(hsize_t) :: dims(2), maxdims(2), chunk(2)
    integer :: hdferr, k, nunit
    real(wp), target :: fill

    id = 0
    name = strip_slashes(path)
    call check_define(self, 'add_series("' // name // '")', error)
    if (allocated(error)) return
    if (len(name) == 0 .or. name == self%axis_name) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%add_series: invalid series path "' // &
                      trim(path) // '"; expected a name like "bodies/ws1/position_track"')
      return
    end if
    if (ncomp < 1) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%add_series("' // name // &
                      '"): ncomp must be >= 1')
      return
    end if
    nunit = count_words(unit)
    if (nunit /= 1 .and. nunit /= ncomp) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%add_series("' // name // '"): unit "' // &
                      trim(unit) // '" must be one unit or ' // trim(int_text(ncomp)) // &
                      ' space-separated units')
      return
    end if
    if (present(component_names)) then
      names = trim(adjustl(component_names))
      if (count_words(names) /= ncomp) then
        call make_error(error, RD_ERR_INPUT, 'h5_writer%add_series("' // name // &
                        '"): component_names "' // names // '" must have ' // trim(int_text(ncomp)) // &
                        ' space-separated names')
        return
      end if
    else if (ncomp == 1) then
      names = name(index(name, '/', back=.true.) + 1:)
    else
      names = 'c1'
      do k = 2, ncomp
        names = names // ' c' // trim(int_text(k))
      end do
    end if
    do k = 1, self%nseries
      if (self%series(k)%path == name) then
        call make_error(error, RD_ERR_INPUT, 'h5_writer%add_series: series "' // name // &
                        '" registered twice')
        return
      end if
    end do

    ! Chunked, unlimited in time. Fortran dims (ncomp, rows) = h5py shape (rows, ncomp).
    dims = [int(ncomp, hsize_t), 0_hsize_t]
    maxdims = [int(ncomp, hsize_t), H5S_UNLIMITED_F]
    chunk = [int(ncomp, hsize_t), int(self%buffer_steps, hsize_t)]
    fill = ieee_value(fill, ieee_quiet_nan)
    call h5screate_simple_f(2, dims, space, hdferr, maxdims)
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, hdferr)
    call h5pset_chunk_f(dcpl, 2, chunk, hdferr)
    call h5pset_fill_value_f(dcpl, H5T_NATIVE_DOUBLE, c_loc(fill), hdferr)
    call h5pcreate_f(H5P_LINK_CREATE_F, lcpl, hdferr)
    call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    call quiet_hdf5(.true.)
    call h5dcreate_f(self%file, name, H5T_NATIVE_DOUBLE, space, dataset, hdferr, &
                     dcpl_id=dcpl, lcpl_id=lcpl)
    call quiet_hdf5(.false.)
    call h5pclose_f(lcpl, hdferr)
    call h5pclose_f(dcpl, hdferr)
    call h5sclose_f(space, hdferr)
    if (dataset < 0) then
      call io_error(error, self%filename, 'cannot create dataset "' // name // &
                    '" (does an object of that name exist already?)')
      return
    end if
    call write_string_attribute(dataset, 'unit', trim(adjustl(unit)), error)
    if (.not. allocated(error)) call write_string_attribute(dataset, 'description', &
                                                            trim(description), error)
    if (.not. allocated(error)) call write_string_attribute(dataset, 'components', names, error)
    if (allocated(error)) then
      call h5dclose_f(dataset, hdferr)
      call error_context(error, 'h5_writer%add_series("' // name // '") in "' // &
                         self%filename // '"')
      return
    end if

    if (self%nseries == size(self%series)) then
      allocate (grown(2*size(self%series)))
      grown(1:self%nseries) = self%series(1:self%nseries)
      call move_alloc(grown, self%series)
    end if
    self%nseries = self%nseries + 1
    id = self%nseries
    self%series(id)%path = name
    self%series(id)%ncomp = ncomp
    self%series(id)%dataset = dataset
    self%series(id)%is_set = .false.
    allocate (self%series(id)%buffer(ncomp, self%buffer_steps))
  end subroutine writer_add_series

  !> Write a text (e.g. 'meta/deck_text', the full deck) as a scalar string dataset;
  !> groups are created as needed. Only before the first end_step.
  subroutine writer_write_text(self, path, text, error)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: text
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: name
    character(kind=c_char), allocatable, target :: chars(:)
    integer(hid_t) :: strtype, space, lcpl, dataset
    integer :: hdferr

    name = strip_slashes(path)
    call check_define(self, 'write_text("' // name // '")', error)
    if (allocated(error)) return
    call string_type(len(text), strtype)
    call to_chars(text, chars)
    call h5screate_f(H5S_SCALAR_F, space, hdferr)
    call h5pcreate_f(H5P_LINK_CREATE_F, lcpl, hdferr)
    call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    call quiet_hdf5(.true.)
    call h5dcreate_f(self%file, name, strtype, space, dataset, hdferr, lcpl_id=lcpl)
    call quiet_hdf5(.false.)
    if (dataset >= 0) call h5dwrite_f(dataset, strtype, c_loc(chars), hdferr)
    call h5pclose_f(lcpl, hdferr)
    call h5sclose_f(space, hdferr)
    call h5tclose_f(strtype, hdferr)
    if (dataset < 0 .or. hdferr < 0) then
      call io_error(error, self%filename, 'cannot write text dataset "' // name // &
                    '" (does an object of that name exist already?)')
    end if
    if (dataset >= 0) call h5dclose_f(dataset, hdferr)
  end subroutine writer_write_text

  !> String attribute `name` on the object `path` ('/' = root; a missing group is created).
  subroutine set_attribute_text(self, path, name, value, error)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path, name, value
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: obj
    integer :: hdferr
    call open_attribute_owner(self, path, name, obj, error)
    if (allocated(error)) return
    call write_string_attribute(obj, name, value, error)
    call h5oclose_f(obj, hdferr)
    if (allocated(error)) call error_context(error, 'h5_writer%set_attribute("' // path // &
                                             '", "' // name // '") in "' // self%filename // '"')
  end subroutine set_attribute_text

  !> Real attribute (SI unit documented in docs/output.md); refuses non-finite values.
  subroutine set_attribute_real(self, path, name, value, error)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path, name
    real(wp), intent(in) :: value
    type(error_t), allocatable, intent(out) :: error
    real(wp), target :: buffer
    integer(hid_t) :: obj
    integer :: hdferr
    if (.not. ieee_is_finite(value)) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%set_attribute("' // path // '", "' // &
                      name // '"): value is not finite')
      return
    end if
    call open_attribute_owner(self, path, name, obj, error)
    if (allocated(error)) return
    buffer = value
    call write_scalar_attribute(obj, name, H5T_NATIVE_DOUBLE, c_loc(buffer), error)
    call h5oclose_f(obj, hdferr)
    if (allocated(error)) call error_context(error, 'h5_writer%set_attribute("' // path // &
                                             '", "' // name // '") in "' // self%filename // '"')
  end subroutine set_attribute_real

  !> Integer attribute (stored as a 64-bit integer).
  subroutine set_attribute_int(self, path, name, value, error)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path, name
    integer, intent(in) :: value
    type(error_t), allocatable, intent(out) :: error
    call set_attribute_int8(self, path, name, int(value, i8), error)
  end subroutine set_attribute_int

  subroutine set_attribute_int8(self, path, name, value, error)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path, name
    integer(i8), intent(in) :: value
    type(error_t), allocatable, intent(out) :: error
    integer(i8), target :: buffer
    integer(hid_t) :: obj
    integer :: hdferr
    call open_attribute_owner(self, path, name, obj, error)
    if (allocated(error)) return
    buffer = value
    call write_scalar_attribute(obj, name, H5T_STD_I64LE, c_loc(buffer), error)
    call h5oclose_f(obj, hdferr)
    if (allocated(error)) call error_context(error, 'h5_writer%set_attribute("' // path // &
                                             '", "' // name // '") in "' // self%filename // '"')
  end subroutine set_attribute_int8

  ! ---------------------------------------------------------------------------------
  ! Stepping
  ! ---------------------------------------------------------------------------------

  !> Values of series `id` at the current step (size = its ncomp). Refuses non-finite
  !> values with an error naming the series and the column.
  subroutine writer_set(self, id, values, error)
    class(h5_writer_t), intent(inout) :: self
    integer, intent(in) :: id
    real(wp), intent(in) :: values(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: k

    if (self%mode == MODE_CLOSED) then
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%set: no file open')
      return
    end if
    if (id < 1 .or. id > self%nseries) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%set: invalid series id ' // trim(int_text(id)) // &
                      ' for "' // self%filename // '"')
      return
    end if
    associate (s => self%series(id))
      if (size(values) /= s%ncomp) then
        call make_error(error, RD_ERR_INPUT, 'h5_writer%set("' // s%path // '"): got ' // &
                        trim(int_text(size(values))) // ' values, expected ' // trim(int_text(s%ncomp)))
        return
      end if
      do k = 1, s%ncomp
        if (.not. ieee_is_finite(values(k))) then
          call make_error(error, RD_ERR_INPUT, 'h5_writer%set: non-finite value in series "' // &
                          s%path // '" component ' // trim(int_text(k)) // ' at output step ' // &
                          trim(int_text(self%nwritten + self%nbuffered + 1)) // ' of "' // &
                          self%filename // '"')
          return
        end if
      end do
      s%buffer(:, self%nbuffered + 1) = values
      s%is_set = .true.
    end associate
  end subroutine writer_set

  !> Close the current step at simulated `time` [s] (or the value of the axis chosen at
  !> open; finite, strictly increasing): every series must have been set. Writes the
  !> buffers when full and flushes every `flush_every` steps.
  subroutine writer_end_step(self, time, error)
    class(h5_writer_t), intent(inout) :: self
    real(wp), intent(in) :: time
    type(error_t), allocatable, intent(out) :: error
    integer :: k
    integer(i8) :: nrows

    if (self%mode == MODE_CLOSED) then
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%end_step: no file open')
      return
    end if
    nrows = self%nwritten + self%nbuffered
    if (.not. ieee_is_finite(time)) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%end_step: non-finite time at output step ' // &
                      trim(int_text(nrows + 1)) // ' of "' // self%filename // '"')
      return
    end if
    if (nrows > 0 .and. .not. (time > self%last_time)) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%end_step: time must increase (got ' // &
                      trim(sci_text(time, 9)) // ' s after ' // trim(sci_text(self%last_time, 9)) // ' s) in "' // &
                      self%filename // '"')
      return
    end if
    do k = 1, self%nseries
      if (.not. self%series(k)%is_set) then
        call make_error(error, RD_ERR_INPUT, 'h5_writer%end_step: series "' // &
                        self%series(k)%path // '" was not set at t = ' // trim(sci_text(time, 9)) // &
                        ' s in "' // self%filename // '"')
        return
      end if
    end do
    if (self%mode == MODE_DEFINE) then
      call self%start_stepping(error)
      if (allocated(error)) return
    end if

    self%nbuffered = self%nbuffered + 1
    self%time_buffer(self%nbuffered) = time
    self%last_time = time
    do k = 1, self%nseries
      self%series(k)%is_set = .false.
    end do
    self%steps_since_flush = self%steps_since_flush + 1
    if (self%steps_since_flush >= self%flush_every) then
      call self%flush(error)
    else if (self%nbuffered == self%buffer_steps) then
      call self%write_buffers(error)
    end if
    if (allocated(error)) call error_context(error, 'h5_writer%end_step')
  end subroutine writer_end_step

  !> Write the buffered rows and flush the file, so that a crash from now on keeps them.
  subroutine writer_flush(self, error)
    class(h5_writer_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    integer :: hdferr
    if (self%mode == MODE_CLOSED) then
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%flush: no file open')
      return
    end if
    call self%write_buffers(error)
    if (allocated(error)) return
    call h5fflush_f(self%file, H5F_SCOPE_GLOBAL_F, hdferr)
    if (hdferr < 0) then
      call io_error(error, self%filename, 'flush failed')
      return
    end if
    self%nflushed = self%nwritten
    self%steps_since_flush = 0
  end subroutine writer_flush

  !> Finish the file: write the buffered rows, end SWMR, and record the run's outcome in
  !> `/meta`: `status` ('completed', 'failed: <message>', 'stopped'), `end_time` [s]
  !> (simulated), `wall_time` [s], `n_steps`, and solver statistics as attributes of
  !> `/meta/solver` (integer and real lists of names and values). The writer is closed
  !> afterwards even when an error is returned.
  subroutine writer_close(self, status, end_time, wall_time, error, int_stat_names, &
                          int_stat_values, real_stat_names, real_stat_values, notes)
    class(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: status
    real(wp), intent(in) :: end_time, wall_time
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in), optional :: int_stat_names(:), real_stat_names(:)
    !> the run's notes for readers (one per line; '' = none, no attribute), e.g. wheels that
    !> lost contact: so that results read later still say what the run printed
    character(len=*), intent(in), optional :: notes
    integer(i8), intent(in), optional :: int_stat_values(:)
    real(wp), intent(in), optional :: real_stat_values(:)
    type(error_t), allocatable :: write_error
    integer(hid_t) :: fapl
    integer :: hdferr, k

    if (self%mode == MODE_CLOSED) then
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%close: no file open')
      return
    end if
    if (present(int_stat_names) .neqv. present(int_stat_values)) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%close: int_stat_names and ' // &
                      'int_stat_values must be given together')
    else if (present(real_stat_names) .neqv. present(real_stat_values)) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%close: real_stat_names and ' // &
                      'real_stat_values must be given together')
    end if
    if (.not. allocated(error) .and. present(int_stat_names)) then
      if (size(int_stat_names) /= size(int_stat_values)) &
        call make_error(error, RD_ERR_INPUT, 'h5_writer%close: int_stat_names and ' // &
                        'int_stat_values differ in size')
    end if
    if (.not. allocated(error) .and. present(real_stat_names)) then
      if (size(real_stat_names) /= size(real_stat_values)) &
        call make_error(error, RD_ERR_INPUT, 'h5_writer%close: real_stat_names and ' // &
                        'real_stat_values differ in size')
    end if

    ! Rows first: they matter more than the metadata if something fails below.
    call self%write_buffers(write_error)
    call self%release_handles()
    if (allocated(write_error)) then
      call move_alloc(write_error, error)
      call error_context(error, 'h5_writer%close')
      return
    end if
    if (allocated(error)) return

    ! SWMR sessions allow no new attributes: reopen normally for the final metadata.
    call quiet_hdf5(.true.)
    call h5fopen_f(self%filename, H5F_ACC_RDWR_F, self%file, hdferr)
    if (hdferr < 0) then
      ! A reader following the run (SWMR read, e.g. a monitoring script) holds a shared
      ! lock. The rows are complete and flushed; take the file without the lock for the
      ! final attributes rather than leave a finished run marked 'running'.
      call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
      if (c_h5pset_file_locking(fapl, .false._c_bool, .true._c_bool) >= 0) &
        call h5fopen_f(self%filename, H5F_ACC_RDWR_F, self%file, hdferr, access_prp=fapl)
      call h5pclose_f(fapl, k)
    end if
    call quiet_hdf5(.false.)
    if (self%file < 0 .or. hdferr < 0) then
      self%file = -1
      call io_error(error, self%filename, 'cannot reopen the file to write the run metadata')
      return
    end if
    self%mode = MODE_DEFINE
    call self%set_attribute('meta', 'status', status, error)
    if (.not. allocated(error)) call self%set_attribute('meta', 'end_time', end_time, error)
    if (.not. allocated(error)) call self%set_attribute('meta', 'wall_time', wall_time, error)
    if (.not. allocated(error)) call self%set_attribute('meta', 'n_steps', self%nwritten, error)
    if (present(notes)) then
      if (.not. allocated(error) .and. len(notes) > 0) call self%set_attribute('meta', 'notes', notes, error)
    end if
    if (present(int_stat_names)) then
      do k = 1, size(int_stat_names)
        if (allocated(error)) exit
        call self%set_attribute('meta/solver', trim(int_stat_names(k)), int_stat_values(k), error)
      end do
    end if
    if (present(real_stat_names)) then
      do k = 1, size(real_stat_names)
        if (allocated(error)) exit
        call self%set_attribute('meta/solver', trim(real_stat_names(k)), real_stat_values(k), error)
      end do
    end if
    call self%release_handles()
    if (allocated(error)) call error_context(error, 'h5_writer%close')
  end subroutine writer_close

  ! ---------------------------------------------------------------------------------
  ! Queries
  ! ---------------------------------------------------------------------------------

  pure logical function writer_is_open(self)
    class(h5_writer_t), intent(in) :: self
    writer_is_open = self%mode /= MODE_CLOSED
  end function writer_is_open

  !> Rows accepted so far (written to the file or buffered).
  pure integer(i8) function writer_steps_written(self)
    class(h5_writer_t), intent(in) :: self
    writer_steps_written = self%nwritten + self%nbuffered
  end function writer_steps_written

  !> Rows on disk at the last flush: a crash from now on keeps at least these.
  pure integer(i8) function writer_steps_flushed(self)
    class(h5_writer_t), intent(in) :: self
    writer_steps_flushed = self%nflushed
  end function writer_steps_flushed

  pure integer function writer_series_count(self)
    class(h5_writer_t), intent(in) :: self
    writer_series_count = self%nseries
  end function writer_series_count

  ! ---------------------------------------------------------------------------------
  ! Private helpers
  ! ---------------------------------------------------------------------------------

  !> Append the buffered rows to every series and to /time as one hyperslab each.
  !> /time is extended last, so its extent never exceeds that of a series.
  subroutine write_buffers(self, error)
    class(h5_writer_t), intent(inout), target :: self
    type(error_t), allocatable, intent(out) :: error
    integer :: k, hdferr
    integer(hsize_t) :: nnew

    if (self%nbuffered == 0 .or. self%file < 0) return
    nnew = int(self%nbuffered, hsize_t)
    do k = 1, self%nseries
      associate (s => self%series(k))
        call append_rows(s%dataset, int(s%ncomp, hsize_t), int(self%nwritten, hsize_t), nnew, &
                         c_loc(s%buffer), hdferr)
        if (hdferr < 0) then
          call io_error(error, self%filename, 'cannot append to series "' // s%path // '"')
          return
        end if
      end associate
    end do
    call append_rows(self%time_dataset, 0_hsize_t, int(self%nwritten, hsize_t), nnew, &
                     c_loc(self%time_buffer), hdferr)
    if (hdferr < 0) then
      call io_error(error, self%filename, 'cannot append to "/' // self%axis_name // '"')
      return
    end if
    self%nwritten = self%nwritten + self%nbuffered
    self%nbuffered = 0
  end subroutine write_buffers

  !> Extend `dataset` by `nnew` rows after row `offset` and write them from `data`.
  !> ncomp = 0 means a rank-1 dataset (/time).
  subroutine append_rows(dataset, ncomp, offset, nnew, data, hdferr)
    integer(hid_t), intent(in) :: dataset
    integer(hsize_t), intent(in) :: ncomp, offset, nnew
    type(c_ptr), intent(in) :: data
    integer, intent(out) :: hdferr
    integer(hid_t) :: filespace, memspace
    integer(hsize_t) :: extent(2), start(2), count(2)
    integer :: rank, closeerr

    if (ncomp == 0) then
      rank = 1
      extent(1) = offset + nnew
      start(1) = offset
      count(1) = nnew
    else
      rank = 2
      extent = [ncomp, offset + nnew]
      start = [0_hsize_t, offset]
      count = [ncomp, nnew]
    end if
    call h5dset_extent_f(dataset, extent(1:rank), hdferr)
    if (hdferr < 0) return
    call h5dget_space_f(dataset, filespace, hdferr)
    if (hdferr < 0) return
    call h5sselect_hyperslab_f(filespace, H5S_SELECT_SET_F, start(1:rank), count(1:rank), hdferr)
    call h5screate_simple_f(rank, count(1:rank), memspace, hdferr)
    if (hdferr >= 0) then
      call h5dwrite_f(dataset, H5T_NATIVE_DOUBLE, data, hdferr, mem_space_id=memspace, &
                      file_space_id=filespace)
      call h5sclose_f(memspace, closeerr)   ! keeps the write status in hdferr
    end if
    call h5sclose_f(filespace, closeerr)
  end subroutine append_rows

  !> First end_step: no more objects will be created; switch to SWMR write mode so that
  !> the file stays readable whatever happens to the process from now on.
  subroutine start_stepping(self, error)
    class(h5_writer_t), intent(inout) :: self
    type(error_t), allocatable, intent(out) :: error
    if (hid_t /= c_int64_t) then   ! the C binding above assumes hid_t = int64_t
      call io_error(error, self%filename, 'HDF5 hid_t is not 64-bit; SWMR binding unusable')
      return
    end if
    if (c_h5fstart_swmr_write(self%file) < 0) then
      call io_error(error, self%filename, 'cannot start SWMR write mode')
      return
    end if
    self%mode = MODE_STEPPING
  end subroutine start_stepping

  !> Close every HDF5 id the writer holds; the writer is closed afterwards.
  subroutine release_handles(self)
    class(h5_writer_t), intent(inout) :: self
    integer :: k, hdferr
    do k = 1, self%nseries
      if (self%series(k)%dataset >= 0) call h5dclose_f(self%series(k)%dataset, hdferr)
      self%series(k)%dataset = -1
    end do
    if (self%time_dataset >= 0) call h5dclose_f(self%time_dataset, hdferr)
    self%time_dataset = -1
    if (self%file >= 0) call h5fclose_f(self%file, hdferr)
    self%file = -1
    self%nbuffered = 0
    self%mode = MODE_CLOSED
  end subroutine release_handles

  subroutine create_axis_dataset(self, unit, description, error)
    type(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: unit, description
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: space, dcpl
    integer(hsize_t) :: dims(1), maxdims(1), chunk(1)
    integer :: hdferr
    real(wp), target :: fill

    dims = 0
    maxdims = H5S_UNLIMITED_F
    chunk = max(self%buffer_steps, 64)
    fill = ieee_value(fill, ieee_quiet_nan)
    call h5screate_simple_f(1, dims, space, hdferr, maxdims)
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, hdferr)
    call h5pset_chunk_f(dcpl, 1, chunk, hdferr)
    call h5pset_fill_value_f(dcpl, H5T_NATIVE_DOUBLE, c_loc(fill), hdferr)
    call h5dcreate_f(self%file, self%axis_name, H5T_NATIVE_DOUBLE, space, self%time_dataset, &
                     hdferr, dcpl_id=dcpl)
    call h5pclose_f(dcpl, hdferr)
    call h5sclose_f(space, hdferr)
    if (self%time_dataset < 0) then
      self%time_dataset = -1
      call io_error(error, self%filename, 'cannot create "/' // self%axis_name // '"')
      return
    end if
    call write_string_attribute(self%time_dataset, 'unit', unit, error)
    if (.not. allocated(error)) call write_string_attribute(self%time_dataset, 'description', &
                                                            description, error)
    if (.not. allocated(error)) call write_string_attribute(self%time_dataset, 'components', &
                                                            self%axis_name, error)
  end subroutine create_axis_dataset

  subroutine check_define(self, what, error)
    type(h5_writer_t), intent(in) :: self
    character(len=*), intent(in) :: what
    type(error_t), allocatable, intent(out) :: error
    select case (self%mode)
    case (MODE_CLOSED)
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%' // what // ': no file open')
    case (MODE_STEPPING)
      call make_error(error, RD_ERR_HANDLE, 'h5_writer%' // what // ': "' // self%filename // &
                      '" is already stepping; objects and attributes must be defined before ' // &
                      'the first end_step')
    end select
  end subroutine check_define

  !> Open the object an attribute goes on; a missing group is created.
  subroutine open_attribute_owner(self, path, name, obj, error)
    type(h5_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: path, name
    integer(hid_t), intent(out) :: obj
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: object
    logical :: exists
    integer :: hdferr

    obj = -1
    call check_define(self, 'set_attribute("' // trim(path) // '", "' // trim(name) // '")', error)
    if (allocated(error)) return
    if (len_trim(name) == 0) then
      call make_error(error, RD_ERR_INPUT, 'h5_writer%set_attribute: empty attribute name')
      return
    end if
    object = strip_slashes(path)
    if (len(object) == 0) then
      object = '/'
      exists = .true.
    else
      call link_exists(self%file, object, exists)
    end if
    if (exists) then
      call quiet_hdf5(.true.)
      call h5oopen_f(self%file, object, obj, hdferr)
      call quiet_hdf5(.false.)
    else
      call create_group(self%file, object, obj, error)
      if (allocated(error)) return
    end if
    if (obj < 0) then
      obj = -1
      call io_error(error, self%filename, 'cannot open object "' // object // '"')
    end if
  end subroutine open_attribute_owner

  !> True if every component of `path` exists (h5lexists_f fails on a missing parent).
  subroutine link_exists(file, path, exists)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    logical, intent(out) :: exists
    integer :: pos, hdferr
    pos = 0
    exists = .true.
    do
      pos = index(path(pos + 1:), '/') + pos
      if (pos == 0 .or. pos == len(path)) exit
      call h5lexists_f(file, path(1:pos - 1), exists, hdferr)
      if (.not. exists .or. hdferr < 0) then
        exists = .false.
        return
      end if
      if (index(path(pos + 1:), '/') == 0) exit
    end do
    call h5lexists_f(file, path, exists, hdferr)
    if (hdferr < 0) exists = .false.
  end subroutine link_exists

  subroutine create_group(file, path, group, error)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    integer(hid_t), intent(out) :: group
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: lcpl
    integer :: hdferr
    call h5pcreate_f(H5P_LINK_CREATE_F, lcpl, hdferr)
    call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    call quiet_hdf5(.true.)
    call h5gcreate_f(file, path, group, hdferr, lcpl_id=lcpl)
    call quiet_hdf5(.false.)
    call h5pclose_f(lcpl, hdferr)
    if (group < 0 .or. hdferr < 0) then
      group = -1
      call make_error(error, RD_ERR_IO, 'cannot create group "' // path // '"')
    end if
  end subroutine create_group

  !> Scalar attribute of the given type from `data`; replaces an existing one.
  subroutine write_scalar_attribute(obj, name, dtype, data, error)
    integer(hid_t), intent(in) :: obj, dtype
    character(len=*), intent(in) :: name
    type(c_ptr), intent(in) :: data
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: space, attr
    logical :: exists
    integer :: hdferr, status

    call h5aexists_f(obj, name, exists, hdferr)
    if (exists) call h5adelete_f(obj, name, hdferr)
    call h5screate_f(H5S_SCALAR_F, space, hdferr)
    call quiet_hdf5(.true.)
    call h5acreate_f(obj, name, dtype, space, attr, status)
    call quiet_hdf5(.false.)
    if (status >= 0) then
      call h5awrite_f(attr, dtype, data, status)
      call h5aclose_f(attr, hdferr)
    end if
    call h5sclose_f(space, hdferr)
    if (status < 0) call make_error(error, RD_ERR_IO, 'cannot write attribute "' // name // '"')
  end subroutine write_scalar_attribute

  subroutine write_string_attribute(obj, name, value, error)
    integer(hid_t), intent(in) :: obj
    character(len=*), intent(in) :: name, value
    type(error_t), allocatable, intent(out) :: error
    character(kind=c_char), allocatable, target :: chars(:)
    integer(hid_t) :: strtype
    integer :: hdferr
    call string_type(len(value), strtype)
    call to_chars(value, chars)
    call write_scalar_attribute(obj, name, strtype, c_loc(chars), error)
    call h5tclose_f(strtype, hdferr)
  end subroutine write_string_attribute

  !> Fixed-length, NUL-padded ASCII string type of `n` characters (at least 1: HDF5
  !> refuses size 0; an empty string is one NUL, which h5py reads as b'').
  subroutine string_type(n, strtype)
    integer, intent(in) :: n
    integer(hid_t), intent(out) :: strtype
    integer :: hdferr
    call h5tcopy_f(H5T_FORTRAN_S1, strtype, hdferr)
    call h5tset_size_f(strtype, int(max(n, 1), size_t), hdferr)
    call h5tset_strpad_f(strtype, H5T_STR_NULLPAD_F, hdferr)
  end subroutine string_type

  pure subroutine to_chars(text, chars)
    character(len=*), intent(in) :: text
    character(kind=c_char), allocatable, intent(out) :: chars(:)
    integer :: k
    allocate (chars(max(len(text), 1)))
    chars(1) = c_null_char
    do k = 1, len(text)
      chars(k) = text(k:k)
    end do
  end subroutine to_chars

  !> Silence HDF5's own error-stack printing around calls whose failure we report
  !> ourselves as one clear line (the stack is noise for a user).
  subroutine quiet_hdf5(quiet)
    logical, intent(in) :: quiet
    integer :: hdferr
    if (quiet) then
      call h5eset_auto_f(0, hdferr)
    else
      call h5eset_auto_f(1, hdferr)
    end if
  end subroutine quiet_hdf5

  subroutine io_error(error, filename, message)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), intent(in) :: filename, message
    call make_error(error, RD_ERR_IO, '"' // filename // '": ' // message)
  end subroutine io_error

  pure function strip_slashes(path) result(name)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: name
    integer :: first, last
    first = verify(path, '/ ')
    last = verify(path, '/ ', back=.true.)
    if (first == 0) then
      name = ''
    else
      name = path(first:last)
    end if
  end function strip_slashes

  pure integer function count_words(text)
    character(len=*), intent(in) :: text
    integer :: k
    logical :: in_word
    count_words = 0
    in_word = .false.
    do k = 1, len(text)
      if (text(k:k) /= ' ') then
        if (.not. in_word) count_words = count_words + 1
        in_word = .true.
      else
        in_word = .false.
      end if
    end do
  end function count_words



  !> Creation time as ISO 8601 with the local offset, e.g. 2026-11-21T06:08:51+00:00.
  function iso_timestamp() result(text)
    character(len=:), allocatable :: text
    character(len=8) :: date
    character(len=10) :: time
    character(len=5) :: zone
    call date_and_time(date, time, zone)
    text = date(1:4) // '-' // date(5:6) // '-' // date(7:8) // 'T' // time(1:2) // ':' // &
           time(3:4) // ':' // time(5:6) // zone(1:3) // ':' // zone(4:5)
  end function iso_timestamp
end module rd_hdf5_writer
