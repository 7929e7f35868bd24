!> Turns the raw group occurrences of a deck (and its includes) into the
!> final entities: merges overrides, applies defaults, enforces required
!> parameters, references between groups and the cross-parameter rules of
!> the schema. Every error names file:line, group and parameter.
!>
!> Override rules: a group that occurs once, or a repeatable group carrying
!> the `name` of an existing entity, given again in a *different* deck file
!> (e.g. the campaign deck that includes a base deck) overrides only the
!> parameters it writes. Within one file a second occurrence is a mistake
!> (duplicate name, group given twice) and is reported.
module rd_deck_resolve
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_deck_text, only: deck_string_t, single_string, int_to_str, real_to_str, path_join, path_stem, &
    append_string, in_list
  use rd_deck_schema, only: deck_schema_t, param_schema_t, find_group, &
                            find_param, suggest_name, used_text, PT_REAL, PT_INTEGER, PT_STRING, &
                            PT_LOGICAL, PT_REAL_ARRAY, PT_STRING_LIST, DEF_REQUIRED, DEF_VALUE, &
                            DEF_OPTIONAL, DEF_PREVIOUS, DEF_DECK_STEM
  use rd_deck_store, only: param_value_t, deck_entity_t, source_file_t, append_entity, &
                           location_text
  use rd_deck_parser, only: expected_text
  implicit none
  private
  public :: resolve_entities

contains

  !> `notes`: parameters of a base deck that an override in a later file made unread (it
  !> changed the kind that reads them: check_unused), one line each, for the warnings.
  subroutine resolve_entities(schema, sources, raw, nraw, entities, nent, error, notes)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(in) :: raw(:)
    integer, intent(in) :: nraw
    type(deck_entity_t), allocatable, intent(out) :: entities(:)
    integer, intent(out) :: nent
    type(error_t), allocatable, intent(out) :: error
    type(deck_string_t), allocatable, intent(out) :: notes(:)
    integer :: i, j
    nent = 0
    allocate (entities(max(1, nraw)), notes(0))
    do i = 1, nraw
      call merge_or_append(schema, sources, raw(i), entities, nent, error)
      if (allocated(error)) return
    end do
    ! a group that occurs once and is absent takes all its defaults, so
    ! deck%get('solver', 1, 'rtol', ...) always works; if it has required
    ! parameters its absence is an error (reported with the first of them).
    do i = 1, size(schema%groups)
      if (schema%groups(i)%repeatable) cycle
      if (any(entities(1:nent)%group == i)) cycle
      block
        type(deck_entity_t) :: implicit
        implicit%group = i; implicit%source = 1; implicit%line = 0
        implicit%contributors = [1]
        allocate (implicit%values(size(schema%groups(i)%params)))
        do j = 1, size(schema%groups(i)%params)
          if (schema%groups(i)%params(j)%default_kind == DEF_REQUIRED) then
            call make_error(error, RD_ERR_INPUT, sources(1)%name // ': &' // &
              schema%groups(i)%name // ": missing group (needed for '" // &
              schema%groups(i)%params(j)%name // "'); expected a &" // schema%groups(i)%name // &
              ' group with ' // schema%groups(i)%params(j)%name // ' = ' // &
              expected_text(schema%groups(i)%params(j)))
            return
          end if
        end do
        call append_entity(entities, nent, implicit)
      end block
    end do
    do i = 1, nent
      do j = 1, size(entities(i)%values)
        call apply_default(schema, sources, entities, i, j, error)
        if (allocated(error)) return
      end do
    end do
    call check_references(schema, sources, entities, nent, error)
    if (allocated(error)) return
    call check_rules(schema, sources, entities, nent, error, notes)
  end subroutine resolve_entities

  function where_value(schema, sources, e, j) result(t)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(in) :: e
    integer, intent(in) :: j
    character(len=:), allocatable :: t
    if (e%values(j)%given) then
      t = location_text(sources, e%values(j)%source, e%values(j)%line)
    else
      t = location_text(sources, e%source, e%line)
    end if
    t = t // ': &' // schema%groups(e%group)%name // " '" // &
        schema%groups(e%group)%params(j)%name // "': "
  end function where_value

  ! -------------------------------------------------------------------
  ! Merging.
  ! -------------------------------------------------------------------
  subroutine merge_or_append(schema, sources, e, entities, nent, error)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(in) :: e
    type(deck_entity_t), allocatable, intent(inout) :: entities(:)
    integer, intent(inout) :: nent
    type(error_t), allocatable, intent(out) :: error
    integer :: i, jname, target
    character(len=:), allocatable :: gname
    associate (g => schema%groups(e%group))
      gname = g%name
      target = 0
      jname = find_param(g, 'name')
      if (.not. g%repeatable) then
        do i = 1, nent
          if (entities(i)%group == e%group) target = i
        end do
        if (target > 0) then
          if (any(entities(target)%contributors == e%source)) then
            call make_error(error, RD_ERR_INPUT, location_text(sources, e%source, e%line) // &
              ': &' // gname // ': group given twice in one file (first at ' // &
              location_text(sources, entities(target)%source, entities(target)%line) // &
              '); expected at most one &' // gname // ' per file (a deck that includes ' // &
              'another may override it)')
            return
          end if
        end if
      else if (jname > 0) then
        if (e%values(jname)%given) then
          do i = 1, nent
            if (entities(i)%group /= e%group) cycle
            if (.not. entities(i)%values(jname)%given) cycle
            if (entities(i)%values(jname)%strings(1)%s == e%values(jname)%strings(1)%s) target = i
          end do
          if (target > 0) then
            if (any(entities(target)%contributors == e%source)) then
              call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jname) // &
                "duplicate name '" // e%values(jname)%strings(1)%s // "' (already at " // &
                location_text(sources, entities(target)%source, entities(target)%line) // &
                '); expected a unique name within a file (a deck that includes another ' // &
                'may override it)')
              return
            end if
          end if
        end if
      end if
    end associate
    if (target == 0) then
      call append_entity(entities, nent, e)
      return
    end if
    associate (t => entities(target))
      t%contributors = [t%contributors, e%source]
      call replace_speed(t, e)
      do i = 1, size(e%values)
        if (.not. e%values(i)%given) cycle
        call merge_value(t%values(i), e%values(i))
      end do
    end associate

  contains

    !> The running speed is one quantity written two ways (&simulation speed, or the law
    !> speed_times + speed_values, which exclude each other): a later file that gives one
    !> replaces the other from an earlier file, so that a campaign or critical-speed probe can
    !> run a deck with a constant speed at a speed law and the other way round.
    subroutine replace_speed(t, e)
      type(deck_entity_t), intent(inout) :: t
      type(deck_entity_t), intent(in) :: e
      integer :: js, jt, jv
      if (schema%groups(e%group)%name /= 'simulation') return
      js = find_param(schema%groups(e%group), 'speed')
      jt = find_param(schema%groups(e%group), 'speed_times')
      jv = find_param(schema%groups(e%group), 'speed_values')
      if (e%values(jt)%given .or. e%values(jv)%given) then
        t%values(js) = param_value_t()
      else if (e%values(js)%given) then
        t%values(jt) = param_value_t()
        t%values(jv) = param_value_t()
      end if
    end subroutine replace_speed
  end subroutine merge_or_append

  !> Later value over earlier: whole assignments replace, element
  !> assignments (name(k) = ...) replace only the elements they wrote.
  subroutine merge_value(old, new)
    type(param_value_t), intent(inout) :: old
    type(param_value_t), intent(in) :: new
    integer :: n, k
    type(param_value_t) :: m
    if (new%whole .or. .not. old%given) then
      old = new; return
    end if
    m = new
    n = max(size(old%set), size(new%set))
    deallocate (m%set); allocate (m%set(n)); m%set = .false.
    m%set(1:size(old%set)) = old%set
    if (allocated(new%reals)) then
      deallocate (m%reals); allocate (m%reals(n)); m%reals = 0.0_wp
      m%reals(1:size(old%reals)) = old%reals
    end if
    if (allocated(new%strings)) then
      deallocate (m%strings); allocate (m%strings(n))
      m%strings(1:size(old%strings)) = old%strings
    end if
    do k = 1, size(new%set)
      if (.not. new%set(k)) cycle
      m%set(k) = .true.
      if (allocated(new%reals)) m%reals(k) = new%reals(k)
      if (allocated(new%strings)) m%strings(k) = new%strings(k)
    end do
    m%whole = old%whole
    old = m
  end subroutine merge_value

  ! -------------------------------------------------------------------
  ! Defaults.
  ! -------------------------------------------------------------------
  subroutine apply_default(schema, sources, entities, i, j, error)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(inout) :: entities(:)
    integer, intent(in) :: i, j
    type(error_t), allocatable, intent(out) :: error
    integer :: k, prev
    associate (p => schema%groups(entities(i)%group)%params(j), v => entities(i)%values(j))
      if (v%given) then
        ! fixed-size arrays partly written with name(k) = ...: the rest keeps its default
        if (p%ptype == PT_REAL_ARRAY .and. p%size > 0) then
          if (.not. all(v%set)) then
            if (p%default_kind /= DEF_VALUE) then
              k = findloc(v%set, .false., dim=1)
              call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) &
                // 'element ' // int_to_str(k) // ' not given; expected all ' // &
                int_to_str(p%size) // ' elements')
              return
            end if
            where (.not. v%set) v%reals = p%default_reals
          end if
        end if
        ! variable lists written element by element must have no gaps
        if ((p%ptype == PT_REAL_ARRAY .or. p%ptype == PT_STRING_LIST) .and. p%size == 0) then
          if (.not. all(v%set)) then
            k = findloc(v%set, .false., dim=1)
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
              'element ' // int_to_str(k) // ' not given (list of ' // int_to_str(size(v%set)) // &
              '); expected every element from 1 on')
            return
          end if
        end if
        return
      end if
      select case (p%default_kind)
      case (DEF_REQUIRED)
        call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
          'missing required parameter; expected ' // expected_text(p))
      case (DEF_OPTIONAL)
        continue
      case (DEF_DECK_STEM)
        v%strings = single_string(file_stem(sources(1)%name) // p%default_strings(1)%s)
        v%resolved = path_join(sources(1)%dir, v%strings(1)%s)
        v%source = 1; v%line = entities(i)%line
      case (DEF_VALUE, DEF_PREVIOUS)
        prev = 0
        if (p%default_kind == DEF_PREVIOUS) then
          do k = i - 1, 1, -1
            if (entities(k)%group == entities(i)%group) then
              prev = k; exit
            end if
          end do
        end if
        if (prev > 0) then
          associate (w => entities(prev)%values(j))
            if (allocated(w%reals)) v%reals = w%reals
            if (allocated(w%integers)) v%integers = w%integers
            if (allocated(w%logicals)) v%logicals = w%logicals
            if (allocated(w%strings)) v%strings = w%strings
          end associate
          return
        end if
        call set_default(p, v)
      end select
    end associate
  end subroutine apply_default

  !> Stem of the deck name for default file names; a string deck named like
  !> '<string>' gives 'string' (no '<', '>' in file names), an empty one 'raildyn'.
  function file_stem(name) result(stem)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: stem, raw
    integer :: k
    raw = path_stem(name)
    stem = ''
    do k = 1, len(raw)
      if (index('<>:*?"|', raw(k:k)) == 0) stem = stem // raw(k:k)
    end do
    if (len(stem) == 0) stem = 'raildyn'
  end function file_stem

  subroutine set_default(p, v)
    type(param_schema_t), intent(in) :: p
    type(param_value_t), intent(inout) :: v
    select case (p%ptype)
    case (PT_REAL, PT_REAL_ARRAY); v%reals = p%default_reals
    case (PT_INTEGER); v%integers = [p%default_integer]
    case (PT_LOGICAL); v%logicals = [p%default_logical]
    case (PT_STRING, PT_STRING_LIST); v%strings = p%default_strings
    end select
  end subroutine set_default

  ! -------------------------------------------------------------------
  ! References between groups: body1 = 'bogie1' must name a &body.
  ! -------------------------------------------------------------------
  subroutine check_references(schema, sources, entities, nent, error)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(in) :: entities(:)
    integer, intent(in) :: nent
    type(error_t), allocatable, intent(out) :: error
    integer :: i, j, k, gref, jname, n
    type(deck_string_t), allocatable :: names(:)
    character(len=:), allocatable :: value, hint, keys
    logical :: found
    do i = 1, nent
      associate (g => schema%groups(entities(i)%group))
        do j = 1, size(g%params)
          associate (p => g%params(j), v => entities(i)%values(j))
            if (len(p%ref_group) == 0 .or. .not. allocated(v%strings)) cycle
            value = v%strings(1)%s
            if (any([(value == p%ref_keywords(k)%s, k=1, size(p%ref_keywords))])) cycle
            gref = find_group(schema, p%ref_group)
            jname = find_param(schema%groups(gref), 'name')
            n = 0
            if (allocated(names)) deallocate (names)
            allocate (names(nent))
            found = .false.
            do k = 1, nent
              if (entities(k)%group /= gref) cycle
              if (.not. entities(k)%values(jname)%given) cycle
              n = n + 1
              names(n)%s = entities(k)%values(jname)%strings(1)%s
              if (names(n)%s == value) found = .true.
            end do
            if (found .and. gref == entities(i)%group) then
              if (entities(i)%values(jname)%strings(1)%s == value) then
                call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) &
                  // "'" // value // "' refers to itself; expected another &" // p%ref_group)
                return
              end if
            end if
            if (found) cycle
            hint = suggest_name(value, names(1:n))
            if (len(hint) > 0) hint = " (did you mean '" // hint // "'?)"
            keys = ''
            do k = 1, size(p%ref_keywords)
              keys = keys // " or '" // p%ref_keywords(k)%s // "'"
            end do
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
              'undefined ' // p%ref_group // " '" // value // "'; expected the name of a &" // &
              p%ref_group // ' defined in the deck' // keys // hint)
            return
          end associate
        end do
      end associate
    end do
  end subroutine check_references

  ! -------------------------------------------------------------------
  ! Rules that involve several parameters or groups.
  ! -------------------------------------------------------------------
  subroutine check_rules(schema, sources, entities, nent, error, notes)
    type(deck_schema_t), intent(in) :: schema
    type(source_file_t), intent(in) :: sources(:)
    type(deck_entity_t), intent(inout) :: entities(:)
    integer, intent(in) :: nent
    type(error_t), allocatable, intent(out) :: error
    type(deck_string_t), allocatable, intent(inout) :: notes(:)
    integer :: i, j, k, prev_segment, gsim, gseg, gtrack, gelem, gws, gext, nseg
    character(len=:), allocatable :: kind
    gsim = find_group(schema, 'simulation'); gseg = find_group(schema, 'segment')
    gtrack = find_group(schema, 'track'); gelem = find_group(schema, 'element')
    gws = find_group(schema, 'wheelset'); gext = find_group(schema, 'external_force')

    ! strictly increasing lists (speed_times, table_deflection)
    do i = 1, nent
      associate (g => schema%groups(entities(i)%group))
        do j = 1, size(g%params)
          if (.not. g%params(j)%increasing) cycle
          if (.not. entities(i)%values(j)%given) cycle
          associate (x => entities(i)%values(j)%reals)
            do k = 2, size(x)
              if (x(k) <= x(k - 1)) then
                call make_error(error, RD_ERR_INPUT, &
                  where_value(schema, sources, entities(i), j) // 'element ' // &
                  int_to_str(k) // ' (' // real_to_str(x(k)) // ') not above element ' // &
                  int_to_str(k - 1) // ' (' // real_to_str(x(k - 1)) // &
                  '); expected strictly increasing values')
                return
              end if
            end do
          end associate
        end do
      end associate
    end do

    prev_segment = 0; nseg = 0
    do i = 1, nent
      if (entities(i)%group == gsim) then
        call check_speed_law(entities(i))
      else if (entities(i)%group == gseg) then
        nseg = nseg + 1
        call check_segment(entities(i), prev_segment)
        prev_segment = i
      else if (entities(i)%group == gelem) then
        call check_element(entities(i))
      else if (entities(i)%group == gws) then
        kind = sval(entities(i), 'contact')
        if (kind == 'profile') then
          call need(entities(i), 'wheel_profile', 'contact = ''profile''')
          if (allocated(error)) return
          call need(entities(i), 'rail_profile', 'contact = ''profile''')
        else if (rval(entities(i), 'flange_clearance') > 0 .and. &
                 .not. rval(entities(i), 'flange_stiffness') > 0) then
          call make_error(error, RD_ERR_INPUT, &
            where_value(schema, sources, entities(i), pidx(entities(i), 'flange_stiffness')) // &
            'a flange stop at flange_clearance = ' // real_to_str(rval(entities(i), 'flange_clearance')) // &
            ' m needs a stiffness; expected flange_stiffness > 0 (N/m)')
        end if
        if (allocated(error)) return
        ! the unsaturated linear law has no friction limit (Kalker's linear theory)
        if (has(entities(i), 'friction') .and. sval(entities(i), 'creep_law') == 'linear' .and. &
            sval(entities(i), 'creep_saturation') == 'none') then
          ! an override in a later file that switched the law: the base deck's friction is
          ! reported, not refused, as check_unused does for every kind-changing override
          j = pidx(entities(i), 'friction')
          if (overridden(entities(i), pidx(entities(i), 'creep_law'), j) .or. &
              overridden(entities(i), pidx(entities(i), 'creep_saturation'), j)) then
            notes = [notes, deck_string_t(where_value(schema, sources, entities(i), j) // &
                     "not read with creep_law = 'linear' and creep_saturation = 'none' " // &
                     "(Kalker's linear law has no friction limit), an override of the kind; ignored")]
          else
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
              "not read by creep_law = 'linear' with creep_saturation = 'none' (Kalker's linear " // &
              "law has no friction limit); expected it left out, or creep_saturation = " // &
              "'shen_hedrick_elkins', or creep_law = 'fastsim' or 'polach'")
            return
          end if
        end if
        do k = 1, i - 1
          if (allocated(error)) exit
          if (entities(k)%group /= gws) cycle
          if (sval(entities(k), 'body') == sval(entities(i), 'body')) then
            j = pidx(entities(i), 'body')
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
              "body '" // sval(entities(i), 'body') // "' already carries wheelset '" // &
              sval(entities(k), 'name') // "'; expected one &wheelset per body")
          end if
        end do
      else if (entities(i)%group == gext) then
        j = pidx(entities(i), 't_end')
        if (rval(entities(i), 't_end') <= rval(entities(i), 't_start')) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, entities(i), j) // &
            'load ends at ' // real_to_str(rval(entities(i), 't_end')) // ' s, not after ' // &
            't_start = ' // real_to_str(rval(entities(i), 't_start')) // ' s; expected t_end > t_start')
        end if
      end if
      if (allocated(error)) return
    end do

    ! a surveyed track replaces the segment list
    do i = 1, nent
      if (entities(i)%group /= gtrack) cycle
      if (.not. entities(i)%values(pidx(entities(i), 'survey_file'))%given) cycle
      do k = 1, nent
        if (entities(k)%group == gseg) then
          call make_error(error, RD_ERR_INPUT, location_text(sources, entities(k)%source, &
            entities(k)%line) // ': &segment: segments given together with &track ' // &
            "'survey_file' (" // location_text(sources, &
            entities(i)%values(pidx(entities(i), 'survey_file'))%source, &
            entities(i)%values(pidx(entities(i), 'survey_file'))%line) // &
            '); expected either a survey file or &segment groups')
          return
        end if
      end do
    end do

    ! parameters given to a kind of their group that does not read them
    do i = 1, nent
      call check_unused(entities(i))
      if (allocated(error)) return
    end do
    ! values that are study options, not fidelity levels: accepted, with a warning
    do i = 1, nent
      call note_study_values(entities(i))
    end do

  contains

    !> Every parameter of e that its kind does not read (schema used_with / used_values) is
    !> an error naming the parameter, the selector's value and where it is read; except
    !> when the selector was written by an override in a later file than the parameter (a
    !> campaign deck switching the base deck's creep_law, a scene switching its vehicle's
    !> contact model): the override replaced the kind, and the base deck's parameters of
    !> the former kind are reported in `notes` (a warning of check and run), not refused.
    subroutine check_unused(e)
      type(deck_entity_t), intent(in) :: e
      integer :: j, js
      logical :: read
      character(len=:), allocatable :: why
      associate (g => schema%groups(e%group))
        do j = 1, size(g%params)
          associate (p => g%params(j))
            if (len(p%used_with) == 0 .or. .not. e%values(j)%given) cycle
            js = find_param(g, p%used_with)
            select case (p%used_values(1)%s)
            case ('(given)')
              read = e%values(js)%given
              why = 'without ' // p%used_with
            case ('(not given)')
              read = .not. e%values(js)%given
              why = 'with ' // p%used_with // ' (' // location_text(sources, e%values(js)%source, &
                    e%values(js)%line) // ')'
            case default
              read = in_list(sval(e, p%used_with), p%used_values)
              why = 'with ' // p%used_with // " = '" // sval(e, p%used_with) // "'"
              if (e%values(js)%given) then
                why = why // ' (' // location_text(sources, e%values(js)%source, e%values(js)%line) // ')'
              else
                why = why // ' (the default)'
              end if
            end select
            if (read) cycle
            if (overridden(e, js, j)) then
              notes = [notes, deck_string_t(where_value(schema, sources, e, j) // 'not read ' // why // &
                       ', an override of the kind; ignored (' // p%name // ' is read only ' // &
                       used_text(p) // ')')]
              cycle
            end if
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, j) // &
              'not read ' // why // '; expected it left out (' // p%name // ' is read only ' // &
              used_text(p) // ')')
            return
          end associate
        end do
      end associate
    end subroutine check_unused

    !> A warning for every given value of e that its parameter marks as a study option
    !> (param_schema_t%study_values), naming where it was written.
    subroutine note_study_values(e)
      type(deck_entity_t), intent(in) :: e
      integer :: j
      associate (g => schema%groups(e%group))
        do j = 1, size(g%params)
          if (.not. allocated(g%params(j)%study_values) .or. .not. e%values(j)%given) cycle
          if (.not. allocated(e%values(j)%strings)) cycle
          associate (v => e%values(j)%strings(1)%s)
            if (in_list(v, g%params(j)%study_values)) &
              call append_string(notes, where_value(schema, sources, e, j) // "'" // v // &
                                 "' is a study option, not a fidelity level: " // g%params(j)%study_note)
          end associate
        end do
      end associate
    end subroutine note_study_values

    !> True when e's selector parameter js was given in a later file than its parameter j
    !> (an override that replaced the kind reading j).
    logical function overridden(e, js, j)
      type(deck_entity_t), intent(in) :: e
      integer, intent(in) :: js, j
      overridden = .false.
      if (e%values(js)%given .and. e%values(js)%source /= e%values(j)%source) &
        overridden = findloc(e%contributors, e%values(js)%source, dim=1) > &
                     findloc(e%contributors, e%values(j)%source, dim=1)
    end function overridden

    integer function pidx(e, name)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name
      pidx = find_param(schema%groups(e%group), name)
    end function pidx

    function sval(e, name) result(s)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: s
      s = ''
      if (allocated(e%values(pidx(e, name))%strings)) s = e%values(pidx(e, name))%strings(1)%s
    end function sval

    real(wp) function rval(e, name)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name
      rval = e%values(pidx(e, name))%reals(1)
    end function rval

    logical function has(e, name)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name
      has = e%values(pidx(e, name))%given
    end function has

    subroutine need(e, name, because)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name, because
      if (has(e, name)) return
      call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, pidx(e, name)) // &
        'missing, required with ' // because // '; expected ' // &
        expected_text(schema%groups(e%group)%params(pidx(e, name))))
    end subroutine need

    subroutine forbid(e, name, because)
      type(deck_entity_t), intent(in) :: e
      character(len=*), intent(in) :: name, because
      if (.not. has(e, name)) return
      call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, pidx(e, name)) // &
        'not allowed with ' // because // '; expected it left out')
    end subroutine forbid

    subroutine check_speed_law(e)
      type(deck_entity_t), intent(in) :: e
      integer :: jt, jv
      jt = pidx(e, 'speed_times'); jv = pidx(e, 'speed_values')
      if (has(e, 'speed_times') .or. has(e, 'speed_values')) then
        call need(e, 'speed_times', 'speed_values')
        if (allocated(error)) return
        call need(e, 'speed_values', 'speed_times')
        if (allocated(error)) return
        call forbid(e, 'speed', 'a speed law (speed_times, speed_values)')
        if (allocated(error)) return
        if (size(e%values(jt)%reals) /= size(e%values(jv)%reals)) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jv) // &
            int_to_str(size(e%values(jv)%reals)) // ' values for ' // &
            int_to_str(size(e%values(jt)%reals)) // ' speed_times; expected as many ' // &
            'speed_values as speed_times')
          return
        end if
        if (any(e%values(jv)%reals < 0.0_wp)) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jv) // &
            'negative speed; expected speeds >= 0 (m/s)')
        end if
      end if
    end subroutine check_speed_law

    subroutine check_segment(e, prev)
      type(deck_entity_t), intent(inout) :: e
      integer, intent(in) :: prev
      integer :: jc
      kind = sval(e, 'type')
      select case (kind)
      case ('curve')
        call need(e, 'radius', "type = 'curve'")
      case ('straight')
        call forbid(e, 'radius', "type = 'straight'")
      end select
      if (allocated(error)) return
      if (has(e, 'radius')) call need(e, 'side', 'radius')
      if (allocated(error)) return
      if (has(e, 'side') .and. .not. has(e, 'radius')) then
        call forbid(e, 'side', 'no radius')
        if (allocated(error)) return
      end if
      ! a curve keeps the cant reached by the transition before it
      jc = pidx(e, 'cant')
      if (kind == 'curve' .and. .not. e%values(jc)%given .and. prev > 0) then
        e%values(jc)%reals = entities(prev)%values(jc)%reals
      end if
    end subroutine check_segment

    subroutine check_element(e)
      type(deck_entity_t), intent(in) :: e
      integer :: jd, jf, k
      if (sval(e, 'body1') == sval(e, 'body2')) then
        call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, pidx(e, 'body2')) // &
          "body2 = body1 = '" // sval(e, 'body2') // "'; expected two different bodies")
        return
      end if
      kind = sval(e, 'type')
      select case (kind)
      case ('table')
        call need(e, 'table_axis', "type = 'table'")
        if (allocated(error)) return
        call need(e, 'table_deflection', "type = 'table'")
        if (allocated(error)) return
        call need(e, 'table_force', "type = 'table'")
        if (allocated(error)) return
        jd = pidx(e, 'table_deflection'); jf = pidx(e, 'table_force')
        if (size(e%values(jd)%reals) < 2) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jd) // &
            'only ' // int_to_str(size(e%values(jd)%reals)) // ' point; expected at least 2')
          return
        end if
        if (size(e%values(jf)%reals) /= size(e%values(jd)%reals)) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jf) // &
            int_to_str(size(e%values(jf)%reals)) // ' forces for ' // &
            int_to_str(size(e%values(jd)%reals)) // ' deflections; expected as many ' // &
            'table_force as table_deflection values')
          return
        end if
        ! the table acts along table_axis only: damping across it would be ignored
        jd = pidx(e, 'damping')
        if (has(e, 'damping')) then
          k = index('xyz', sval(e, 'table_axis'))
          if (any(e%values(jd)%reals /= 0 .and. [1, 2, 3] /= k)) then
            call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jd) // &
              "a table element damps along table_axis = '" // sval(e, 'table_axis') // &
              "' only; expected 0 for the other components")
            return
          end if
        end if
      case ('series_spring_damper')
        call need(e, 'series_stiffness', "type = 'series_spring_damper'")
        if (allocated(error)) return
        ! one damper along the line joining the points (damping(1) > 0): nothing across it
        jd = pidx(e, 'damping')
        if (.not. (e%values(jd)%reals(1) > 0)) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jd) // &
            'a series spring-damper damps along the line joining its points, with damping(1); ' // &
            'expected damping(1) > 0 (N s/m)')
          return
        end if
        if (any(e%values(jd)%reals(2:3) /= 0)) then
          call make_error(error, RD_ERR_INPUT, where_value(schema, sources, e, jd) // &
            'a series spring-damper damps along the line joining its points only, with ' // &
            'damping(1); expected damping(2) = damping(3) = 0')
          return
        end if
      end select
    end subroutine check_element
  end subroutine check_rules
end module rd_deck_resolve
