!> Named output channels of a scene: one definition serves the HDF5 file, the C API
!> (rd_output_name / rd_get_output) and the Python package.
!>
!> A channel is a fixed-size vector per time step with a unit and component names
!> (docs/output.md). The scene registers its channels once when it is built and
!> refreshes the values whenever outputs are requested.
module rd_output_set
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: output_channel_t, output_set_t

  type :: output_channel_t
    character(len=:), allocatable :: name         !< HDF5 path, e.g. 'track/frames/1/position'
    character(len=:), allocatable :: unit
    character(len=:), allocatable :: description
    character(len=:), allocatable :: components   !< space separated column names
    real(wp), allocatable :: values(:)
    integer :: source(4) = 0   !< what fills it: the owner's table row and instance (rd_scene_output_table)
  end type output_channel_t

  type :: output_set_t
    type(output_channel_t), allocatable :: channels(:)
    integer :: n = 0
  contains
    procedure :: add => output_set_add
    procedure :: find => output_set_find
    procedure :: clear => output_set_clear
    procedure :: packed => output_set_packed
    procedure :: packed_index => output_set_packed_index
  end type output_set_t

contains

  !> Register a channel and return its index.
  subroutine output_set_add(self, name, ncomp, unit, description, components, id)
    class(output_set_t), intent(inout) :: self
    character(len=*), intent(in) :: name, unit, description, components
    integer, intent(in) :: ncomp
    integer, intent(out) :: id
    type(output_channel_t), allocatable :: grown(:)
    if (.not. allocated(self%channels)) allocate (self%channels(32))
    if (self%n == size(self%channels)) then
      allocate (grown(2 * self%n))
      grown(1:self%n) = self%channels(1:self%n)
      call move_alloc(grown, self%channels)
    end if
    self%n = self%n + 1
    id = self%n
    self%channels(id)%name = name
    self%channels(id)%unit = unit
    self%channels(id)%description = description
    self%channels(id)%components = components
    allocate (self%channels(id)%values(ncomp))
    self%channels(id)%values = 0
  end subroutine output_set_add

  !> Index of the channel called `name`, or an RD_ERR_INPUT error listing a few names.
  subroutine output_set_find(self, name, id, error)
    class(output_set_t), intent(in) :: self
    character(len=*), intent(in) :: name
    integer, intent(out) :: id
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    do i = 1, self%n
      if (self%channels(i)%name == name) then
        id = i
        return
      end if
    end do
    id = 0
    call make_error(error, RD_ERR_INPUT, "no output channel named '" // name // &
                    "' (rd_output_count/rd_output_name list them; see docs/output.md)")
  end subroutine output_set_find

  !> Every channel's values in one vector, channel after channel in registration order.
  function output_set_packed(self) result(flat)
    class(output_set_t), intent(in) :: self
    real(wp), allocatable :: flat(:)
    integer :: i, k, n
    n = 0
    do i = 1, self%n
      n = n + size(self%channels(i)%values)
    end do
    allocate (flat(n))
    k = 0
    do i = 1, self%n
      n = size(self%channels(i)%values)
      flat(k + 1:k + n) = self%channels(i)%values
      k = k + n
    end do
  end function output_set_packed

  !> Position in the packed vector (output_set_packed) of the column `component` of the
  !> channel `name`; 0 when there is no such channel or column.
  pure integer function output_set_packed_index(self, name, component) result(k)
    class(output_set_t), intent(in) :: self
    character(len=*), intent(in) :: name, component
    integer :: i, column, start, finish
    k = 0
    do i = 1, self%n
      associate (c => self%channels(i))
        if (c%name == name) then
          ! the column's number among the space-separated component names
          column = 0
          start = 1
          do while (start <= len(c%components))
            finish = index(c%components(start:) // ' ', ' ') + start - 2
            column = column + 1
            if (c%components(start:finish) == component) then
              k = k + column
              return
            end if
            start = finish + 2
          end do
          k = 0
          return
        end if
        k = k + size(c%values)
      end associate
    end do
    k = 0
  end function output_set_packed_index

  subroutine output_set_clear(self)
    class(output_set_t), intent(inout) :: self
    if (allocated(self%channels)) deallocate (self%channels)
    self%n = 0
  end subroutine output_set_clear
end module rd_output_set
