!> Storage of a read deck: one entity per group occurrence, one value per
!> schema parameter of its group, and the table of source files (the deck
!> and every included deck) that values and groups point into for messages.
module rd_deck_store
  use rd_kinds, only: wp
  use rd_deck_text, only: deck_string_t, int_to_str
  implicit none
  private
  public :: param_value_t, deck_entity_t, source_file_t, append_entity, location_text

  !> The value of one parameter in one group occurrence. Only the component
  !> matching the schema type is used (scalars are arrays of length 1).
  type :: param_value_t
    logical :: given = .false.      !< the user wrote it (some element of it, for arrays)
    integer :: source = 0           !< source file of the (last) assignment
    integer :: line = 0             !< line of the (last) assignment
    logical :: whole = .false.      !< last assignment set the whole array (no index)
    logical, allocatable :: set(:)  !< which elements were written (arrays)
    real(wp), allocatable :: reals(:)
    integer, allocatable :: integers(:)
    logical, allocatable :: logicals(:)
    type(deck_string_t), allocatable :: strings(:)
    character(len=:), allocatable :: resolved  !< path resolved against its deck's directory
  end type param_value_t

  type :: deck_entity_t
    integer :: group = 0            !< index in the schema
    integer :: source = 0           !< file of the group start
    integer :: line = 0             !< line of the group start
    integer, allocatable :: contributors(:)  !< sources whose groups were merged into it
    type(param_value_t), allocatable :: values(:)
  end type deck_entity_t

  type :: source_file_t
    character(len=:), allocatable :: name   !< as shown in messages (path as given)
    character(len=:), allocatable :: dir    !< directory that relative paths start from
  end type source_file_t

contains

  subroutine append_entity(list, n, item)
    type(deck_entity_t), allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: n
    type(deck_entity_t), intent(in) :: item
    type(deck_entity_t), allocatable :: grown(:)
    if (.not. allocated(list)) allocate (list(16))
    if (n == size(list)) then
      allocate (grown(2 * n))
      grown(1:n) = list(1:n)
      call move_alloc(grown, list)
    end if
    n = n + 1
    list(n) = item
  end subroutine append_entity

  !> "file:line"
  function location_text(sources, source, line) result(t)
    type(source_file_t), intent(in) :: sources(:)
    integer, intent(in) :: source, line
    character(len=:), allocatable :: t
    if (source >= 1 .and. source <= size(sources)) then
      t = sources(source)%name
    else
      t = '<deck>'
    end if
    if (line > 0) t = t // ':' // int_to_str(line)   ! line 0: a group the deck left out
  end function location_text
end module rd_deck_store
