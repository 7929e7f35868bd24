!> A state a results file holds (docs/output.md, `/state/y`): where a restarted run
!> continues (raildyn run --restart, rd_scene set_start), or the state `raildyn eigen
!> --state FILE[:ROW]` linearises about.
!>
!> The last row counts whose time and state are both finite: a killed run's file may end
!> in rows the crash left unwritten (fill value NaN, rd_hdf5_writer), and such a file is
!> still flagged open for SWMR writing, so it is reopened in SWMR read mode.
module rd_results_state
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use hdf5
  use rd_kinds, only: wp, i8
  use rd_error, only: error_t, make_error, RD_ERR_IO, RD_ERR_INPUT
  use rd_text, only: int_text
  implicit none
  private
  public :: results_state_t, read_last_state, read_state_row

  !> H5F_ACC_SWMR_READ of H5Fpublic.h (0x0040): the Fortran API of HDF5 1.10 has no
  !> constant for it and hands the access flags to H5Fopen unchanged.
  integer, parameter :: ACC_SWMR_READ = 64

  type :: results_state_t
    real(wp) :: time = 0                          !< time of the row [s]
    real(wp), allocatable :: y(:)                 !< the state of that row
    character(len=:), allocatable :: components   !< the column names of /state/y
    integer(i8) :: mean_samples = 0               !< root attribute output_mean_samples
  end type results_state_t

contains

  !> The last complete row (a restart).
  subroutine read_last_state(path, state, error)
    character(len=*), intent(in) :: path
    type(results_state_t), intent(out) :: state
    type(error_t), allocatable, intent(out) :: error
    call read_state_row(path, -1, state, error)
  end subroutine read_last_state

  !> Row `row` of /time and /state/y, counted from 0 as h5py and numpy count them; -1: the
  !> last complete row. A row outside the file or with a non-finite value is an error.
  subroutine read_state_row(path, row_wanted, state, error)
    character(len=*), intent(in) :: path
    integer, intent(in) :: row_wanted
    type(results_state_t), intent(out) :: state
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: file, fapl
    integer :: hdferr
    real(wp), allocatable, target :: time(:, :), y(:, :)
    character(len=:), allocatable :: time_name
    integer :: row
    logical :: exists

    ! HDF5 1.10 answers an absent file here with a file handle whose queries say 'no such
    ! dataset': ask the file system first
    inquire (file=path, exist=exists)
    if (.not. exists) then
      call make_error(error, RD_ERR_IO, '"' // path // '": no such file; expected a raildyn results file (.h5)')
      return
    end if
    call h5open_f(hdferr)
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call h5eset_auto_f(0, hdferr)
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr, access_prp=fapl)
    if (hdferr < 0) call h5fopen_f(path, ior(H5F_ACC_RDONLY_F, ACC_SWMR_READ), file, hdferr, &
                                   access_prp=fapl)
    call h5pclose_f(fapl, hdferr)
    if (file < 0 .or. hdferr < 0) then
      call h5eset_auto_f(1, hdferr)
      call make_error(error, RD_ERR_IO, '"' // path // '": cannot open it as an HDF5 results file')
      return
    end if

    call h5lexists_f(file, 'state', exists, hdferr)
    if (exists) call h5lexists_f(file, 'state/y', exists, hdferr)
    if (.not. exists) then
      call make_error(error, RD_ERR_INPUT, 'no /state/y series (written when ' // &
                      "&output groups includes 'state', the default); a run cannot continue from it")
    end if
    if (.not. allocated(error)) call read_table(file, 'time', time, time_name, error)
    if (.not. allocated(error)) call read_table(file, 'state/y', y, state%components, error)
    if (.not. allocated(error)) call read_int_attribute(file, 'output_mean_samples', state%mean_samples, error)
    call h5fclose_f(file, hdferr)
    call h5eset_auto_f(1, hdferr)
    if (allocated(error)) then
      error%message = '"' // path // '": ' // error%message
      return
    end if

    if (row_wanted >= 0) then
      row = row_wanted + 1
      if (row > min(size(time, 2), size(y, 2))) then
        call make_error(error, RD_ERR_INPUT, '"' // path // '": no row ' // trim(int_text(row_wanted)) // &
          ' in /state/y; expected a row from 0 to ' // trim(int_text(min(size(time, 2), size(y, 2)) - 1)))
        return
      end if
      if (.not. (ieee_is_finite(time(1, row)) .and. all(ieee_is_finite(y(:, row))))) then
        call make_error(error, RD_ERR_INPUT, '"' // path // '": row ' // trim(int_text(row_wanted)) // &
          ' of /state/y is incomplete (values not finite: a killed run did not write it)')
        return
      end if
    else
      do row = min(size(time, 2), size(y, 2)), 1, -1
        if (ieee_is_finite(time(1, row)) .and. all(ieee_is_finite(y(:, row)))) exit
      end do
      if (row < 1) then
        call make_error(error, RD_ERR_INPUT, '"' // path // '": no complete row in /state/y')
        return
      end if
    end if
    state%time = time(1, row)
    state%y = y(:, row)
  end subroutine read_state_row

  !> A float64 dataset of rank 1 (n values, read as (1, n)) or 2 (h5py's rows x columns,
  !> (columns, rows) here), whole, and its 'components' attribute.
  subroutine read_table(file, name, values, components, error)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), allocatable, target, intent(out) :: values(:, :)
    character(len=:), allocatable, intent(out) :: components
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: dset, space, attr, atype
    integer(hsize_t) :: dims(2), maxdims(2), length
    integer(hsize_t), parameter :: scalar(1) = [1_hsize_t]
    integer :: hdferr, rank
    type(c_ptr) :: ptr
    components = ''
    call h5dopen_f(file, name, dset, hdferr)
    if (hdferr < 0) then
      call make_error(error, RD_ERR_INPUT, 'no dataset /' // name); return
    end if
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, rank, hdferr)
    if (rank < 1 .or. rank > 2) then
      call make_error(error, RD_ERR_INPUT, '/' // name // ' is not a series (rank 1 or 2)')
    else
      dims = 1
      call h5sget_simple_extent_dims_f(space, dims(3 - rank:2), maxdims(3 - rank:2), hdferr)
      allocate (values(dims(1), dims(2)))
      ptr = c_loc(values)
      if (size(values) > 0) call h5dread_f(dset, H5T_NATIVE_DOUBLE, ptr, hdferr)
      if (hdferr < 0) call make_error(error, RD_ERR_IO, 'cannot read /' // name)
    end if
    call h5sclose_f(space, hdferr)
    if (.not. allocated(error)) then
      call h5aopen_f(dset, 'components', attr, hdferr)
      if (hdferr < 0) then
        call make_error(error, RD_ERR_INPUT, '/' // name // ' has no components attribute')
      else
        call h5aget_type_f(attr, atype, hdferr)
        call h5tget_size_f(atype, length, hdferr)
        block
          character(len=int(length)) :: text
          call h5aread_f(attr, atype, text, scalar, hdferr)
          components = trim(text)
        end block
        call h5tclose_f(atype, hdferr)
        call h5aclose_f(attr, hdferr)
      end if
    end if
    call h5dclose_f(dset, hdferr)
  end subroutine read_table

  !> An integer root attribute (0 when absent: files written before it existed).
  subroutine read_int_attribute(file, name, value, error)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer(i8), target, intent(out) :: value
    type(error_t), allocatable, intent(out) :: error
    integer(hid_t) :: attr
    integer :: hdferr
    logical :: exists
    type(c_ptr) :: ptr
    value = 0
    call h5aexists_f(file, name, exists, hdferr)
    if (.not. exists) return
    call h5aopen_f(file, name, attr, hdferr)
    ptr = c_loc(value)
    call h5aread_f(attr, H5T_STD_I64LE, ptr, hdferr)
    if (hdferr < 0) call make_error(error, RD_ERR_INPUT, 'cannot read the root attribute ' // name)
    call h5aclose_f(attr, hdferr)
  end subroutine read_int_attribute
end module rd_results_state
