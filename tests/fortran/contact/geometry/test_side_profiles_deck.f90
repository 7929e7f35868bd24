!> Deck keys of per-side profiles (&wheelset wheel_profile_right, rail_profile_right,
!> rail_precant_right): bad input gives one line naming deck:line, group and parameter with
!> what is expected (expectations read off the deck text written here and the task's key
!> names, not from the reader's output); good input reaches the contact spec, and an
!> omitted right key keeps today's single-profile spec. The spec then builds the geometry:
!> equal names share the left surfaces, a right wheel file written here as S1002 moved by
!> 2 mm in s has its flange tip and field end 2 mm further (the per-wheel derailment checks),
!> a right precant alone gives the right rail its own surface.
program test_side_profiles_deck
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_deck, only: deck_t, read_deck_string
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry, flange_tip_coordinate, &
                                      field_end_coordinate, SIDE_LEFT, SIDE_RIGHT
  use rd_contact_geometry, only: contact_geometry_t
  use rd_profile, only: profile_t
  use rd_profile_analytic, only: s1002_profile
  use rd_scene_vehicle, only: build_wheelset_specs
  use rd_test_support, only: check, test_summary
  use test_files, only: scratch_name, delete_file
  implicit none
  type(deck_t) :: deck
  type(error_t), allocatable :: error
  type(wheelset_contact_spec_t), allocatable :: specs(:)
  character(len=:), allocatable :: dir, head, ws
  character(len=4096) :: env
  character(len=1), parameter :: nl = achar(10)
  integer :: st, u, k
  type(contact_geometry_t) :: geo
  type(profile_t) :: s1002
  real(wp) :: dtip, dend
  character(len=:), allocatable :: moved_wheel

  call get_environment_variable('RAILDYN_SOURCE_DIR', env, status=st)
  if (st /= 0) env = '.'
  dir = trim(env) // '/tests/decks'
  head = '&simulation t_end = 1.0 /' // nl // &
    "&body name = 'ws', mass = 1800.0, ixx = 1000.0, iyy = 100.0, izz = 1000.0 /" // nl
  ws = "&wheelset name = 'w', body = 'ws', wheel_profile = 's1002', rail_profile = '60e1'"

  call bad_case('missing right wheel profile file', head // ws // ',' // nl // &
    "  wheel_profile_right = 'worn_right.prw' /", &
    [character(len=48) :: "case.nml:4: &wheelset 'wheel_profile_right'", "file not found: 'worn_right.prw'     ", &
     'expected an existing file                '])
  call bad_case('missing right rail profile file', head // ws // ',' // nl // &
    "  rail_profile_right = 'high_rail.prr' /", &
    [character(len=48) :: "case.nml:4: &wheelset 'rail_profile_right' ", "file not found: 'high_rail.prr'      ", &
     'expected an existing file                '])
  call bad_case('right rail precant out of range', head // ws // ',' // nl // &
    '  rail_precant_right = 0.5 /', &
    [character(len=48) :: "case.nml:4: &wheelset 'rail_precant_right' ", 'expected a real number in [0, 0.1]   ', &
     '0.5                                      '])
  call bad_case('right wheel profile as a number', head // ws // ',' // nl // &
    '  wheel_profile_right = 3 /', &
    [character(len=48) :: "case.nml:4: &wheelset 'wheel_profile_right'", 'expected                             ', &
     '                                         '])

  ! good input: files relative to the deck, keywords, precant
  call read_deck_string(deck, head // ws // ", wheel_profile_right = 'profiles/wheel_test.prw'," // nl // &
    "  rail_profile_right = '54e1', rail_precant_right = 0.025 /", dir, 'case.nml', error)
  if (allocated(error)) error stop error%message
  call build_wheelset_specs(deck, specs, error)
  if (allocated(error)) error stop error%message
  call check(allocated(specs(1)%wheel_profile_right) .and. allocated(specs(1)%rail_profile_right), &
    'right profiles reach the contact spec')
  if (allocated(specs(1)%wheel_profile_right)) call check(index(specs(1)%wheel_profile_right, &
    'tests/decks/profiles/wheel_test.prw') > 0, 'right wheel file resolved relative to the deck')
  if (allocated(specs(1)%rail_profile_right)) call check(specs(1)%rail_profile_right == '54e1', &
    'right rail keyword kept')
  call check(specs(1)%rail_precant_right == 0.025_wp .and. specs(1)%rail_precant == 0, &
    'right rail precant read, left one unchanged')

  call read_deck_string(deck, head // ws // ' /', dir, 'case.nml', error)
  if (allocated(error)) error stop error%message
  call build_wheelset_specs(deck, specs, error)
  if (allocated(error)) error stop error%message
  call check(.not. allocated(specs(1)%wheel_profile_right) .and. .not. allocated(specs(1)%rail_profile_right) &
    .and. specs(1)%rail_precant_right < 0, 'no right keys: the right side is the left one (today''s deck unchanged)')

  ! spec -> geometry
  call build_contact_geometry(specs(1), geo, error)
  if (allocated(error)) error stop error%message
  call check(.not. (geo%own_wheel_right .or. geo%own_rail_right), 'no right keys: one surface pair')
  specs(1)%wheel_profile_right = 's1002'
  specs(1)%rail_profile_right = '60e1'
  call build_contact_geometry(specs(1), geo, error)
  if (allocated(error)) error stop error%message
  call check(.not. (geo%own_wheel_right .or. geo%own_rail_right), 'the same keywords on the right: surfaces shared')
  deallocate (specs(1)%wheel_profile_right, specs(1)%rail_profile_right)
  specs(1)%rail_precant_right = 0.01_wp
  call build_contact_geometry(specs(1), geo, error)
  if (allocated(error)) error stop error%message
  call check(geo%own_rail_right .and. .not. geo%own_wheel_right, 'a right precant alone: own right rail surface')
  specs(1)%rail_precant_right = -1

  call s1002_profile(s1002, 1.0e-4_wp, error)
  if (allocated(error)) error stop error%message
  moved_wheel = scratch_name('test_side_profiles_wheel')
  open (newunit=u, file=moved_wheel, status='replace', action='write')
  write (u, '(a)') '# S1002 moved by +2 mm in s (metres)'
  do k = 1, size(s1002%y)
    write (u, '(es24.16,1x,es24.16)') s1002%y(k) + 2.0e-3_wp, s1002%z(k)
  end do
  close (u)
  specs(1)%wheel_profile_right = moved_wheel
  call build_contact_geometry(specs(1), geo, error)
  if (allocated(error)) error stop error%message
  dtip = flange_tip_coordinate(geo, SIDE_RIGHT) - flange_tip_coordinate(geo, SIDE_LEFT)
  dend = field_end_coordinate(geo, SIDE_RIGHT) - field_end_coordinate(geo, SIDE_LEFT)
  write (*, '(a,2es12.4)') 'right wheel moved by 2 mm: flange tip and field end differ by ', dtip, dend
  call check(geo%own_wheel_right .and. abs(dtip - 2.0e-3_wp) < 1.0e-4_wp .and. abs(dend - 2.0e-3_wp) < 1.0e-9_wp, &
    'per-wheel flange tip and field end follow the right wheel''s own profile')
  specs(1)%wheel_profile_right = moved_wheel // '.missing'
  call build_contact_geometry(specs(1), geo, error)
  call check(allocated(error), 'unreadable right wheel file at geometry build: error')
  if (allocated(error)) then
    write (*, '(a)') '  -> ' // error%message
    call check(index(error%message, 'right wheel profile') > 0 .and. index(error%message, '.missing') > 0, &
      'the message says which profile and file')
  end if
  call delete_file(moved_wheel)

  call test_summary('test_side_profiles_deck')

contains

  subroutine bad_case(what, text, parts)
    character(len=*), intent(in) :: what, text
    character(len=*), intent(in) :: parts(:)
    integer :: k
    call read_deck_string(deck, text, dir, 'case.nml', error)
    if (.not. allocated(error)) then
      call check(.false., what // ': no error')
      return
    end if
    write (*, '(a)') '  ' // what // ' -> ' // error%message
    call check(error%code == RD_ERR_INPUT .and. index(error%message, nl) == 0, what // ': one-line input error')
    do k = 1, size(parts)
      if (len_trim(parts(k)) == 0) cycle
      call check(index(error%message, trim(parts(k))) > 0, what // ': message names "' // trim(parts(k)) // '"')
    end do
  end subroutine bad_case

end program test_side_profiles_deck
