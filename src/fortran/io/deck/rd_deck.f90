!> A scene deck: parsed, validated against the schema (rd_deck_schema),
!> defaults applied; immutable after read.
!>
!>     call read_deck_file(deck, 'scene.nml', error)
!>     n = deck%count('body')
!>     call deck%get('body', i, 'mass', mass, error)
!>     if (deck%given('segment', i, 'radius')) ...
!>     msg = deck%origin('segment', i, 'radius') // ': radius too small for ...'
!>
!> Getters return RD_ERR_INTERNAL (a programming error) for an unknown
!> group or parameter, an index out of 1..count, or a type that does not
!> match the schema; and for an optional parameter without default that the
!> user did not give (check deck%given first). User errors are all reported
!> by read_deck_file / read_deck_string as RD_ERR_INPUT with file:line.
module rd_deck
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_INTERNAL
  use rd_deck_text, only: deck_string_t, int_to_str, path_dir, append_string, in_list
  use rd_deck_schema, only: deck_schema_t, build_deck_schema, find_group, find_param, &
                            type_text, write_schema_markdown, PT_REAL, PT_INTEGER, PT_STRING, &
                            PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST
  use rd_deck_store, only: deck_entity_t, source_file_t, location_text
  use rd_deck_parser, only: parse_context_t, parse_source, read_text_file, normalize_path
  use rd_deck_resolve, only: resolve_entities
  implicit none
  private
  public :: deck_t, read_deck_file, read_deck_string, write_schema_markdown, deck_string_t

  type :: deck_t
    private
    type(deck_schema_t) :: schema
    type(source_file_t), allocatable :: sources(:)   !< 1 = the deck itself
    type(deck_entity_t), allocatable :: entities(:)
    integer :: nent = 0
    character(len=:), allocatable :: full_text
    logical :: from_file = .false.   !< sources(1) is a file (not a deck given as text)
    !> base-deck parameters an override made unread (rd_deck_resolve check_unused)
    type(deck_string_t), allocatable :: override_notes(:)
  contains
    procedure :: notes => deck_notes
    procedure :: count => deck_count
    procedure :: given => deck_given
    procedure :: origin => deck_origin
    procedure :: path => deck_path
    procedure :: text => deck_text
    procedure :: file_name => deck_file_name
    procedure :: input_files => deck_input_files
    procedure, private :: get_real, get_integer, get_logical, get_string, get_real_array, &
                          get_string_list
    generic :: get => get_real, get_integer, get_logical, get_string, get_real_array, &
                      get_string_list
  end type deck_t

contains

  !> Read a deck file; relative paths in it are relative to its directory.
  subroutine read_deck_file(deck, path, error)
    type(deck_t), intent(out) :: deck
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: text, problem
    call read_text_file(path, text, problem)
    if (len(problem) > 0) then
      call make_error(error, RD_ERR_INPUT, path // ': the deck ' // problem // '; expected an ' // &
        'existing readable file')
      return
    end if
    call read_deck_string(deck, text, path_dir(path), path, error)
    if (allocated(error)) return
    deck%from_file = .true.
  end subroutine read_deck_file

  !> Read a deck held in a string. `base_dir` is where its relative paths
  !> start; `name` appears in messages (and its stem names the default output).
  subroutine read_deck_string(deck, text, base_dir, name, error)
    type(deck_t), intent(out) :: deck
    character(len=*), intent(in) :: text, base_dir, name
    type(error_t), allocatable, intent(out) :: error
    type(parse_context_t) :: ctx
    character(len=:), allocatable :: expanded
    type(deck_string_t), allocatable :: notes(:)
    type(deck_entity_t), allocatable :: entities(:)
    integer :: nent
    ctx%schema = build_deck_schema()
    allocate (ctx%sources(1))
    ctx%sources(1)%name = name
    ctx%sources(1)%dir = base_dir
    ctx%nsrc = 1
    allocate (ctx%stack(1))
    ctx%stack(1)%s = normalize_path(name)
    call parse_source(ctx, text, 1, expanded, error)
    if (allocated(error)) return
    if (.not. allocated(ctx%entities)) allocate (ctx%entities(0))
    ! resolved into locals: a deck that failed to read stays empty (its
    ! getters then report RD_ERR_INTERNAL instead of half-read values)
    call resolve_entities(ctx%schema, ctx%sources(1:ctx%nsrc), ctx%entities, ctx%nent, &
                          entities, nent, error, notes)
    if (allocated(error)) return
    call move_alloc(notes, deck%override_notes)
    call move_alloc(entities, deck%entities)
    deck%nent = nent
    call move_alloc(ctx%sources, deck%sources)
    deck%schema = ctx%schema
    deck%full_text = expanded
  end subroutine read_deck_string

  !> Warnings of the reading: parameters of a base deck that an override in a later file
  !> made unread (it changed the kind that reads them), one line each.
  function deck_notes(self) result(list)
    class(deck_t), intent(in) :: self
    type(deck_string_t), allocatable :: list(:)
    if (allocated(self%override_notes)) then
      list = self%override_notes
    else
      allocate (list(0))
    end if
  end function deck_notes

  ! ------------------------------------------------------------------
  ! Queries.
  ! ------------------------------------------------------------------

  !> Number of occurrences of a group (after includes and overrides); 0 for
  !> an unknown group name.
  integer function deck_count(self, group)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group
    integer :: g
    deck_count = 0
    if (.not. allocated(self%entities)) return
    g = find_group(self%schema, group)
    if (g == 0) return
    deck_count = count(self%entities(1:self%nent)%group == g)
  end function deck_count

  !> Entity index of occurrence i of a group, and parameter index; 0 if not found.
  subroutine locate(self, group, i, param, ie, ip)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    integer, intent(out) :: ie, ip
    integer :: g, k, n
    ie = 0; ip = 0
    if (.not. allocated(self%entities)) return
    g = find_group(self%schema, group)
    if (g == 0) return
    n = 0
    do k = 1, self%nent
      if (self%entities(k)%group == g) then
        n = n + 1
        if (n == i) then
          ie = k; exit
        end if
      end if
    end do
    if (ie == 0) return
    ip = find_param(self%schema%groups(g), param)
    if (param == '') ip = -1
  end subroutine locate

  !> Check a getter's request; `error` set (RD_ERR_INTERNAL) on misuse.
  subroutine check_request(self, group, i, param, ptype, ie, ip, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i, ptype
    integer, intent(out) :: ie, ip
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: what
    integer :: actual
    what = 'deck%get(''' // group // ''', ' // int_to_str(i) // ', ''' // param // '''): '
    call locate(self, group, i, param, ie, ip)
    if (.not. allocated(self%entities)) then
      call make_error(error, RD_ERR_INTERNAL, what // 'the deck was not read successfully')
      return
    end if
    if (find_group(self%schema, group) == 0) then
      call make_error(error, RD_ERR_INTERNAL, what // 'unknown group &' // group)
      return
    end if
    if (ie == 0) then
      call make_error(error, RD_ERR_INTERNAL, what // 'occurrence out of range 1..' // &
        int_to_str(self%count(group)))
      return
    end if
    if (ip <= 0) then
      call make_error(error, RD_ERR_INTERNAL, what // 'unknown parameter of &' // group)
      return
    end if
    associate (p => self%schema%groups(self%entities(ie)%group)%params(ip), &
               v => self%entities(ie)%values(ip))
      actual = p%ptype
      if (actual /= ptype) then
        call make_error(error, RD_ERR_INTERNAL, what // 'parameter has type ' // type_text(p) // &
          ', asked with another type')
        return
      end if
      if (.not. v%given .and. .not. (allocated(v%reals) .or. allocated(v%integers) .or. &
          allocated(v%logicals) .or. allocated(v%strings))) then
        call make_error(error, RD_ERR_INTERNAL, what // 'not given and has no default; ' // &
          'check deck%given first')
      end if
    end associate
  end subroutine check_request

  subroutine get_real(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    real(wp), intent(out) :: value
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    value = 0.0_wp
    call check_request(self, group, i, param, PT_REAL, ie, ip, error)
    if (allocated(error)) return
    value = self%entities(ie)%values(ip)%reals(1)
  end subroutine get_real

  subroutine get_integer(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    integer, intent(out) :: value
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    value = 0
    call check_request(self, group, i, param, PT_INTEGER, ie, ip, error)
    if (allocated(error)) return
    value = self%entities(ie)%values(ip)%integers(1)
  end subroutine get_integer

  subroutine get_logical(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    logical, intent(out) :: value
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    value = .false.
    call check_request(self, group, i, param, PT_LOGICAL, ie, ip, error)
    if (allocated(error)) return
    value = self%entities(ie)%values(ip)%logicals(1)
  end subroutine get_logical

  !> A string as written (values with allowed choices come back in lower case;
  !> for paths this is the text as written: use deck%path for the file).
  subroutine get_string(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    character(len=:), allocatable, intent(out) :: value
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    value = ''
    call check_request(self, group, i, param, PT_STRING, ie, ip, error)
    if (allocated(error)) return
    value = self%entities(ie)%values(ip)%strings(1)%s
  end subroutine get_string

  subroutine get_real_array(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    real(wp), allocatable, intent(out) :: value(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    call check_request(self, group, i, param, PT_REAL_ARRAY, ie, ip, error)
    if (allocated(error)) then
      allocate (value(0)); return
    end if
    value = self%entities(ie)%values(ip)%reals
  end subroutine get_real_array

  subroutine get_string_list(self, group, i, param, value, error)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    type(deck_string_t), allocatable, intent(out) :: value(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: ie, ip
    call check_request(self, group, i, param, PT_STRING_LIST, ie, ip, error)
    if (allocated(error)) then
      allocate (value(0)); return
    end if
    value = self%entities(ie)%values(ip)%strings
  end subroutine get_string_list

  !> The user wrote this parameter (in any included deck), vs. a default.
  !> .false. for unknown groups, parameters or occurrences.
  logical function deck_given(self, group, i, param)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    integer :: ie, ip
    deck_given = .false.
    call locate(self, group, i, param, ie, ip)
    if (ie == 0 .or. ip <= 0) return
    deck_given = self%entities(ie)%values(ip)%given
  end function deck_given

  !> "scene.nml:12: &segment 'radius'": where a value was written, or the
  !> group's first line when it was not (param = '' gives "file:line: &group").
  !> For messages of later checks (scene building) about deck values.
  function deck_origin(self, group, i, param) result(where)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group
    integer, intent(in) :: i
    character(len=*), intent(in), optional :: param
    character(len=:), allocatable :: where
    integer :: ie, ip
    character(len=:), allocatable :: pname
    pname = ''
    if (present(param)) pname = param
    call locate(self, group, i, pname, ie, ip)
    if (ie == 0) then
      where = deck_file_name(self) // ': &' // group // ' #' // int_to_str(i)
    else
      associate (e => self%entities(ie))
        if (ip > 0) then
          if (e%values(ip)%given) then
            where = location_text(self%sources, e%values(ip)%source, e%values(ip)%line)
          else
            where = location_text(self%sources, e%source, e%line)
          end if
        else
          where = location_text(self%sources, e%source, e%line)
        end if
      end associate
      where = where // ': &' // group
    end if
    if (len(pname) > 0) where = where // " '" // pname // "'"
  end function deck_origin

  !> A path parameter resolved against the directory of the deck that names
  !> it (unchanged when absolute); analytic profile keywords ('s1002') are
  !> returned as such; '' when not given or not a path.
  function deck_path(self, group, i, param) result(path)
    class(deck_t), intent(in) :: self
    character(len=*), intent(in) :: group, param
    integer, intent(in) :: i
    character(len=:), allocatable :: path
    integer :: ie, ip
    path = ''
    call locate(self, group, i, param, ie, ip)
    if (ie == 0 .or. ip <= 0) return
    if (allocated(self%entities(ie)%values(ip)%resolved)) &
      path = self%entities(ie)%values(ip)%resolved
  end function deck_path

  !> The full deck text, included decks inserted between
  !> "! >>> begin include" / "! <<< end include" comment lines.
  function deck_text(self) result(t)
    class(deck_t), intent(in) :: self
    character(len=:), allocatable :: t
    t = ''
    if (allocated(self%full_text)) t = self%full_text
  end function deck_text

  !> Every file the deck reads, each once in reading order: the deck itself (when read from
  !> a file), every included deck (nested ones too), and every input file a parameter names
  !> (profiles, irregularity and survey files; not analytic profile keywords, not the results
  !> file). Paths as the deck resolved them. What a cache of results depends on.
  function deck_input_files(self) result(files)
    class(deck_t), intent(in) :: self
    type(deck_string_t), allocatable :: files(:)
    integer :: k, ie, ip
    allocate (files(0))
    if (.not. allocated(self%sources)) return
    do k = merge(1, 2, self%from_file), size(self%sources)
      call add(self%sources(k)%name)
    end do
    do ie = 1, self%nent
      associate (e => self%entities(ie), g => self%schema%groups(self%entities(ie)%group))
        do ip = 1, size(e%values)
          if (.not. (g%params(ip)%is_path .and. g%params(ip)%must_exist)) cycle
          if (.not. allocated(e%values(ip)%resolved)) cycle
          if (in_list(e%values(ip)%resolved, g%params(ip)%path_keywords)) cycle
          call add(e%values(ip)%resolved)
        end do
      end associate
    end do
  contains
    subroutine add(path)
      character(len=*), intent(in) :: path
      if (in_list(path, files)) return
      call append_string(files, path)
    end subroutine add
  end function deck_input_files

  function deck_file_name(self) result(name)
    class(deck_t), intent(in) :: self
    character(len=:), allocatable :: name
    name = ''
    if (allocated(self%sources)) name = self%sources(1)%name
  end function deck_file_name
end module rd_deck
