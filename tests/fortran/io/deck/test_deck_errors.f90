!> Every kind of deck error gives one line
!>   <file>:<line>: &<group> '<param>': <what is wrong>; expected <what is expected>
!> Each case below is a small deck written for the test; the expected file,
!> line, group, parameter and expectation are read off the deck text and the
!> task specification (ranges, allowed values), not from the reader's output.
program test_deck_errors
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_deck, only: deck_t, read_deck_string
  use rd_test_support, only: check, fail, test_summary
  implicit none
  type(deck_t) :: deck
  type(error_t), allocatable :: error
  character(len=:), allocatable :: dir, body, sim
  character(len=4096) :: env
  character(len=1), parameter :: nl = achar(10)
  integer :: ncase, st
  character(len=80), parameter :: none = ''

  ncase = 0
  call get_environment_variable('RAILDYN_SOURCE_DIR', env, status=st)
  if (st /= 0) env = '.'
  dir = trim(env) // '/tests/decks'
  sim = '&simulation t_end = 1.0 /' // nl
  body = "&body name = 'bogie1', mass = 2615.0, ixx = 1722.0, iyy = 1476.0, izz = 3067.0 /" // nl

  call case('unknown group', '&simulaton t_end = 1.0 /', &
    'case.nml:1:', '&simulaton', 'unknown group', 'did you mean &simulation?')
  call case('unknown group, no suggestion', sim // '&vehicle mass = 1.0 /', &
    'case.nml:2:', '&vehicle', 'unknown group', 'expected one of &simulation, &solver')
  call case('unknown variable', '&simulation t_end = 1.0,' // nl // ' sped = 3.0 /', &
    "case.nml:2: &simulation 'sped'", 'unknown parameter', "did you mean 'speed'?")
  call case('wrong type: string for a real', "&simulation t_end = 'ten' /", &
    "case.nml:1: &simulation 't_end'", "got a string 'ten'", 'expected a real number > 0 (s)')
  call case('wrong type: real for an integer', sim // '&solver max_num_steps = 2.5 /', &
    "case.nml:2: &solver 'max_num_steps'", 'got a real number 2.5', 'expected an integer >= 1')
  call case('wrong type: logical for a real', '&simulation t_end = .true. /', &
    "case.nml:1: &simulation 't_end'", 'got a logical .true.', 'expected a real number')
  call case('wrong type: word for a logical', sim // &
    "&body name = 'b', mass = 1, ixx = 1, iyy = 1, izz = 1 /" // nl // &
    "&wheelset name = 'w', body = 'b', contact = 'knife_edge', spin_creep = 'yes' /", &
    "case.nml:3: &wheelset 'spin_creep'", "got a string 'yes'", 'expected .true. or .false.')
  call case('unquoted string', sim // '&solver method = bdf /', &
    "case.nml:2: &solver 'method'", "'bdf' without quotes", "expected one of 'bdf'")
  call case('malformed number 1.2.3', '&simulation t_end = 1.2.3 /', &
    "case.nml:1: &simulation 't_end'", "malformed number '1.2.3'", 'expected a real number > 0')
  call case('malformed number 12OO.0 (letter O)', sim // '&track gauge = 12OO.0 /', &
    "case.nml:2: &track 'gauge'", "malformed number '12OO.0'", 'expected a real number in (0.5, 2]')
  call case('number overflows', '&simulation t_end = 1e999 /', &
    "case.nml:1: &simulation 't_end'", 'overflows', 'expected a real number')
  call case('nan is not a number', '&simulation t_end = nan /', &
    "case.nml:1: &simulation 't_end'", "got 'nan'", 'expected a real number')
  call case('too few values', sim // body(1:len(body) - 2) // ' position = 1.0, 2.0 /', &
    "case.nml:2: &body 'position'", 'too few values (2)', 'expected 3 real numbers (m)')
  call case('too many values', sim // body(1:len(body) - 2) // ' position = 1 2 3 4 /', &
    "case.nml:2: &body 'position'", 'too many values (4)', 'expected 3 real numbers (m)')
  call case('too many values for a scalar', sim // body(1:len(body) - 2) // ' frame_offset = 1, 2 /', &
    "case.nml:2: &body 'frame_offset'", 'too many values (2)', 'expected one value')
  call case('too many values from an index', sim // body(1:len(body) - 2) // &
    ' position(2) = 1, 2, 3 /', "case.nml:2: &body 'position'", &
    'too many values (3 from element 2)', 'expected 3 real numbers')
  call case('gap in a variable list', '&simulation t_end = 1.0, speed_times = 0.0, 1.0,' // nl // &
    ' speed_values = 1.0, speed_values(3) = 2.0 /', "case.nml:2: &simulation 'speed_values'", &
    'element 2 not given (list of 3)', 'expected every element from 1 on')
  call case('index out of bounds', sim // body(1:len(body) - 2) // ' position(4) = 1 /', &
    "case.nml:2: &body 'position'", 'element index 4 out of bounds', 'expected 1 to 3')
  call case('missing required parameter (line of the group start)', sim // &
    "&body name = 'ws1'," // nl // ' ixx = 1.0, iyy = 1.0, izz = 1.0 /', &
    "case.nml:2: &body 'mass'", 'missing required parameter', 'expected a real number > 0 (kg)')
  call case('missing required group', '&solver rtol = 1e-6 /', &
    'case.nml: &simulation', 'missing group', "expected a &simulation group with t_end")
  call case('negative length', sim // "&segment type = 'straight', length = -50.0 /", &
    "case.nml:2: &segment 'length'", 'value -50.0 out of range', 'expected a real number > 0 (m)')
  call case('negative mass', sim // "&body name = 'b', mass = -1.0 /", &
    "case.nml:2: &body 'mass'", 'value -1.0 out of range', 'expected a real number > 0 (kg)')
  call case('zero radius', sim // "&segment type = 'curve', length = 50.0, radius = 0.0 /", &
    "case.nml:2: &segment 'radius'", 'value 0.0 out of range', 'expected a real number >= 10 (m)')
  call case('cant above the range', sim // &
    "&segment type = 'curve', length = 50.0, radius = 300.0, side = 'left', cant = 0.35 /", &
    "case.nml:2: &segment 'cant'", 'value 0.35 out of range', &
    'expected a real number in [-0.2, 0.3] (m)')
  call case('rtol in an open interval', sim // '&solver rtol = 1.0 /', &
    "case.nml:2: &solver 'rtol'", 'out of range', 'expected a real number in (0, 1)')
  call case('integer out of range', sim // '&solver max_order = 13 /', &
    "case.nml:2: &solver 'max_order'", 'value 13 out of range', 'expected an integer in [0, 12]')
  call case('string not allowed', sim // "&solver method = 'bfd' /", &
    "case.nml:2: &solver 'method'", "'bfd' is not an allowed value", &
    "expected one of 'bdf', 'adams', 'erk', 'rk4' (did you mean 'bdf'?)")
  call case('string list value not allowed', sim // body(1:len(body) - 2) // &
    " frozen = 'x', 'spin' /", "case.nml:2: &body 'frozen'", "'spin' is not an allowed value", &
    "'yaw'")
  call case('unterminated group (next group)', '&simulation t_end = 1.0' // nl // &
    '&solver rtol = 1e-6 /', 'case.nml:1: &simulation', 'unterminated group', &
    "expected '/' or &end to close it")
  call case('unterminated group (end of file)', sim // '&solver rtol = 1e-6' // nl // nl, &
    'case.nml:2: &solver', 'unterminated group', "expected '/' or &end")
  call case('unterminated string', "&simulation title = 'MB V1, t_end = 1.0 /" // nl, &
    "case.nml:1: &simulation 'title'", 'unterminated string', "expected a closing ' on the same line")
  call case('text outside a group', sim // 'speed = 4.4' // nl, &
    'case.nml:2:', "text outside a group: 'speed'", 'expected only &group ... / blocks')
  call case('slash outside a group', sim // ' /' // nl, &
    'case.nml:2:', "'/' outside a group", 'expected it only to close a &group')
  call case('not an assignment', '&simulation t_end 1.0 /', &
    'case.nml:1: &simulation', "'t_end' is not an assignment", 'expected name = value')
  call case('duplicate name', sim // body // nl // body, &
    "case.nml:4: &body 'name'", "duplicate name 'bogie1' (already at case.nml:2)", &
    'expected a unique name')
  call case('group given twice in one file', sim // '&solver rtol = 1e-6 /' // nl // &
    '&solver atol = 1e-9 /', 'case.nml:3: &solver', 'given twice', 'expected at most one &solver')
  call case('element refers to an undefined body', sim // body // &
    "&element name = 'k', type = 'spring_damper'," // nl // " body1 = 'bogie1', body2 = 'bogie9' /", &
    "case.nml:4: &element 'body2'", "undefined body 'bogie9'", &
    "expected the name of a &body defined in the deck (did you mean 'bogie1'?)")
  call case('element body1 may be ground, nothing else', sim // body // &
    "&element name = 'k', type = 'spring_damper', body1 = 'grund', body2 = 'bogie1' /", &
    "case.nml:3: &element 'body1'", "undefined body 'grund'", "or 'ground'")
  call case('element between a body and itself', sim // body // &
    "&element name = 'k', type = 'spring_damper', body1 = 'bogie1', body2 = 'bogie1' /", &
    "case.nml:3: &element 'body2'", "body2 = body1 = 'bogie1'", 'expected two different bodies')
  call case('body sharing its own frame', sim // body(1:len(body) - 2) // " frame = 'bogie1' /", &
    "case.nml:2: &body 'frame'", "'bogie1' refers to itself", 'expected another &body')
  call case('speed_times/speed_values mismatch', '&simulation t_end = 1.0,' // nl // &
    ' speed_times = 0.0, 1.0, 2.0,' // nl // ' speed_values = 0.0, 5.0 /', &
    "case.nml:3: &simulation 'speed_values'", '2 values for 3 speed_times', &
    'expected as many speed_values as speed_times')
  call case('speed_times not increasing', '&simulation t_end = 1.0, speed_times = 0.0, 2.0, 1.0,' &
    // nl // ' speed_values = 0.0, 5.0, 5.0 /', "case.nml:1: &simulation 'speed_times'", &
    'element 3 (1) not above element 2 (2)', 'expected strictly increasing values')
  call case('speed_values without speed_times', '&simulation t_end = 1.0, speed_values = 1, 2 /', &
    "case.nml:1: &simulation 'speed_times'", 'missing, required with speed_values', &
    'expected a list of real numbers')
  call case('curve without radius', sim // "&segment type = 'curve', length = 50.0 /", &
    "case.nml:2: &segment 'radius'", "required with type = 'curve'", 'expected a real number >= 10 (m)')
  call case('radius without side', sim // "&segment type = 'curve', length = 50.0, radius = 300.0 /", &
    "case.nml:2: &segment 'side'", 'required with radius', "expected one of 'left', 'right'")
  call case('table lengths', sim // body // "&element name = 't', type = 'table', body2 = 'bogie1'," &
    // nl // " table_axis = 'z', table_deflection = -0.01 0 0.01, table_force = -1e3 1e3 /", &
    "case.nml:4: &element 'table_force'", '2 forces for 3 deflections', &
    'expected as many table_force as table_deflection values')
  call case('series spring without its stiffness', sim // body // &
    "&element name = 's', type = 'series_spring_damper', body2 = 'bogie1' /", &
    "case.nml:3: &element 'series_stiffness'", "required with type = 'series_spring_damper'", &
    'expected a real number > 0 (N/m)')
  call case('series spring without its damper', sim // body // &
    "&element name = 's', type = 'series_spring_damper', body2 = 'bogie1', series_stiffness = 1e6 /", &
    "case.nml:3: &element 'damping'", 'damps along the line joining its points', 'expected damping(1) > 0 (N s/m)')
  call case('profile contact without profiles', sim // body // &
    "&wheelset name = 'w', body = 'bogie1' /", "case.nml:3: &wheelset 'wheel_profile'", &
    "required with contact = 'profile'", "expected a quoted file name or one of: s1002, 60e1, 54e1")
  call case('missing profile file, relative to the deck', sim // body // &
    "&wheelset name = 'w', body = 'bogie1', wheel_profile = 'wheel_test.prw', rail_profile = '60e1' /", &
    "case.nml:3: &wheelset 'wheel_profile'", "file not found: 'wheel_test.prw'", &
    'expected an existing file')
  call case('survey file and segments', sim // "&track survey_file = 'profiles/rail_test.prr' /" &
    // nl // "&segment type = 'straight', length = 10.0 /", 'case.nml:3: &segment', &
    "&track 'survey_file' (case.nml:2)", 'expected either a survey file or &segment groups')
  call case('external force ending before it starts', sim // body // &
    "&external_force body = 'bogie1', t_start = 2.0, t_end = 1.0 /", &
    "case.nml:3: &external_force 't_end'", 'not after t_start', 'expected t_end > t_start')
  call case('repeat count without value', sim // body(1:len(body) - 2) // ' position = 3* /', &
    "case.nml:2: &body 'position'", "repeat count '3*' without a value", 'expected n*value')
  call case('include of a missing file, relative to the deck', sim // &
    "&include file = 'nothere.nml' /", "case.nml:2: &include 'file'", &
    "file not found: 'nothere.nml'", 'expected an existing file')

  call test_summary('test_deck_errors')

contains

  subroutine case(what, text, p1, p2, p3, p4)
    character(len=*), intent(in) :: what, text, p1, p2, p3
    character(len=*), intent(in), optional :: p4
    ncase = ncase + 1
    call read_deck_string(deck, text, dir // '/profiles/..', 'case.nml', error)
    if (.not. allocated(error)) then
      call fail()
      print '(a)', 'FAIL: ' // what // ': no error for:' // nl // text
      return
    end if
    print '(a)', '  ' // what // ' -> ' // error%message
    call check(error%code == RD_ERR_INPUT, what // ': code is not RD_ERR_INPUT')
    call check(index(error%message, nl) == 0, what // ': message spans lines')
    call check(index(error%message, '; expected ') > 0, what // ': no "; expected"')
    call part(what, p1); call part(what, p2); call part(what, p3)
    if (present(p4)) call part(what, p4)
  end subroutine case

  subroutine part(what, p)
    character(len=*), intent(in) :: what, p
    call check(index(error%message, p) > 0, what // ': message lacks "' // p // '"')
  end subroutine part

end program test_deck_errors
