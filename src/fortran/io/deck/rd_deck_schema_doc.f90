!> Regenerates the parameter tables of the input reference from the schema:
!>     rd_deck_schema_doc docs/input_reference.md
!> replaces the text between "<!-- BEGIN schema -->" and "<!-- END schema -->"
!> (hand-written prose around the markers is kept). Without an argument the
!> tables are printed to standard output.
program rd_deck_schema_doc
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use rd_deck, only: write_schema_markdown
  implicit none
  character(len=4096) :: path, line
  character(len=*), parameter :: begin_mark = '<!-- BEGIN schema -->', end_mark = '<!-- END schema -->'
  integer :: u, scratch, ios, nargs
  character(len=:), allocatable :: before, after, tables
  logical :: in_block, found_begin, found_end

  nargs = command_argument_count()
  if (nargs == 0) then
    call write_schema_markdown(output_unit)
    stop
  end if
  call get_command_argument(1, path)
  open (newunit=u, file=trim(path), status='old', action='read', iostat=ios)
  if (ios /= 0) then
    write (error_unit, '(a)') trim(path) // ': cannot open'
    error stop 1
  end if
  before = ''; after = ''
  in_block = .false.; found_begin = .false.; found_end = .false.
  do
    read (u, '(a)', iostat=ios) line
    if (ios /= 0) exit
    if (trim(line) == begin_mark) then
      found_begin = .true.; in_block = .true.
      before = before // trim(line) // new_line('a')
    else if (trim(line) == end_mark) then
      found_end = .true.; in_block = .false.
      after = after // trim(line) // new_line('a')
    else if (.not. in_block) then
      if (found_end) then
        after = after // trim(line) // new_line('a')
      else
        before = before // trim(line) // new_line('a')
      end if
    end if
  end do
  close (u)
  if (.not. (found_begin .and. found_end)) then
    write (error_unit, '(a)') trim(path) // ': markers ' // begin_mark // ' / ' // end_mark // &
      ' not found'
    error stop 1
  end if

  open (newunit=scratch, status='scratch', action='readwrite', form='formatted')
  call write_schema_markdown(scratch)
  rewind (scratch)
  tables = ''
  do
    read (scratch, '(a)', iostat=ios) line
    if (ios /= 0) exit
    tables = tables // trim(line) // new_line('a')
  end do
  close (scratch)

  open (newunit=u, file=trim(path), status='replace', action='write', access='stream', &
        form='unformatted')
  write (u) before // tables // after
  close (u)
end program rd_deck_schema_doc
