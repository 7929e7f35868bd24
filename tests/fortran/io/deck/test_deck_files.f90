!> Deck files on disk: the example deck, includes with overrides and paths
!> relative to each deck's own directory, and file errors (missing include,
!> missing profile, include cycle) reported with file:line.
!> Expected values are the numbers written in the deck files (tests/decks)
!> and the defaults the task specification states, typed here independently.
program test_deck_files
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_deck, only: deck_t, read_deck_file
  use rd_test_support, only: check, fail, test_summary
  implicit none
  type(deck_t) :: deck
  type(error_t), allocatable :: error
  character(len=:), allocatable :: dir, s
  character(len=4096) :: env
  real(wp) :: x
  real(wp), allocatable :: v(:)
  integer :: n, i
  logical :: b

  call get_environment_variable('RAILDYN_SOURCE_DIR', env, status=i)
  if (i /= 0) env = '.'
  dir = trim(env) // '/tests/decks/'

  ! --- the example deck ---------------------------------------------------
  call read_deck_file(deck, dir // 'mb_v1_tc1.nml', error)
  call expect_ok('read mb_v1_tc1.nml')
  call check(deck%file_name() == dir // 'mb_v1_tc1.nml', 'file_name')
  call check(deck%count('body') == 2 .and. deck%count('segment') == 3 .and. &
             deck%count('element') == 1 .and. deck%count('wheelset') == 1, 'counts')
  call check(deck%count('solver') == 1 .and. deck%count('output') == 1, 'once-groups present')
  call deck%get('body', 2, 'mass', x, error); call expect_ok('ws1 mass')
  call check(x == 1813.0_wp, 'ws1 mass = 1813')
  call deck%get('body', 2, 'position', v, error); call expect_ok('ws1 position')
  call check(size(v) == 3, 'position size')
  if (size(v) == 3) call check(all(v == [0.0_wp, 0.0_wp, 0.46_wp]), 'ws1 position')
  call deck%get('element', 1, 'stiffness', v, error); call expect_ok('stiffness')
  if (size(v) == 3) call check(all(v == [31.391e6_wp, 3.884e6_wp, 1.220e6_wp]), 'stiffness')
  call deck%get('element', 1, 'damping', v, error); call expect_ok('damping default')
  if (size(v) == 3) call check(all(v == 0.0_wp), 'damping default 0 0 0')
  call deck%get('simulation', 1, 'gravity', x, error); call expect_ok('gravity')
  call check(x == 9.80665_wp, 'gravity default (standard gravity, CGPM 1901)')
  call deck%get('simulation', 1, 'speed', x, error)
  call check(x == 4.4_wp, 'speed')
  call deck%get('solver', 1, 'max_num_steps', n, error); call expect_ok('max_num_steps')
  call check(n == 100000, 'max_num_steps default')
  ! a curve keeps the cant its transition reached; a straight defaults to 0
  call deck%get('segment', 3, 'cant', x, error); call expect_ok('curve cant')
  call check(x == 0.100_wp, 'curve cant = previous clothoid end cant')
  call check(.not. deck%given('segment', 3, 'cant'), 'curve cant not given')
  call deck%get('segment', 1, 'cant', x, error)
  call check(x == 0.0_wp, 'straight cant default 0')
  call deck%get('segment', 2, 'side', s, error)
  call check(s == 'left', 'side')
  call check(deck%path('wheelset', 1, 'wheel_profile') == dir // 'profiles/wheel_test.prw', &
             'profile path relative to the deck: ' // deck%path('wheelset', 1, 'wheel_profile'))
  call check(deck%path('wheelset', 1, 'rail_profile') == '60e1', 'profile keyword (case folded)')
  call check(deck%path('output', 1, 'file') == dir // 'mb_v1_tc1.h5', &
             'default output next to the deck: ' // deck%path('output', 1, 'file'))
  call check(deck%origin('body', 2, 'mass') == dir // "mb_v1_tc1.nml:10: &body 'mass'", &
             'origin of a given value: ' // deck%origin('body', 2, 'mass'))
  call check(deck%origin('element', 1, 'point1') == dir // "mb_v1_tc1.nml:15: &element 'point1'", &
             'origin on a continuation line: ' // deck%origin('element', 1, 'point1'))
  call check(deck%origin('segment', 3, 'cant') == dir // "mb_v1_tc1.nml:7: &segment 'cant'", &
             'origin of a default = group line: ' // deck%origin('segment', 3, 'cant'))

  ! --- includes and overrides ---------------------------------------------
  call read_deck_file(deck, dir // 'include/campaign.nml', error)
  call expect_ok('read campaign.nml')
  call check(deck%count('body') == 2 .and. deck%count('element') == 3 .and. &
             deck%count('simulation') == 1 .and. deck%count('include') == 2, 'merged counts')
  call deck%get('simulation', 1, 'speed', x, error)
  call check(x == 35.0_wp, 'speed overridden')
  call deck%get('simulation', 1, 't_end', x, error)
  call check(x == 10.0_wp, 't_end kept from base')
  call deck%get('body', 1, 'mass', x, error)
  call check(x == 32000.0_wp, 'car mass overridden')
  call deck%get('body', 1, 'ixx', x, error)
  call check(x == 5.0e4_wp, 'car ixx kept')
  call deck%get('body', 1, 'position', v, error)
  if (size(v) == 3) call check(all(v == [0.0_wp, 0.0_wp, 1.6_wp]), 'position(3) override')
  call deck%get('element', 1, 'stiffness', v, error)
  if (size(v) == 3) call check(all(v == [1.0e6_wp, 2.0e6_wp, 1.0e6_wp]), &
                               'repeat count + element override')
  call deck%get('element', 1, 'body1', s, error)
  call check(s == 'ground', 'body1 default ground')
  call deck%get('element', 3, 'body1', s, error)
  call check(s == 'ws', 'element referring to an included body')
  call deck%get('element', 2, 'table_force', v, error)
  call check(size(v) == 3, 'table_force length after element override')
  if (size(v) == 3) call check(all(v == [-4.0e4_wp, 0.0_wp, 5.0e4_wp]), &
                               'table_force(3) overridden, elements 1-2 kept')
  call check(deck%path('wheelset', 1, 'wheel_profile') == &
             dir // 'include/sub/profiles/sub_wheel.prw', 'path relative to the included deck: ' &
             // deck%path('wheelset', 1, 'wheel_profile'))
  call check(deck%origin('body', 1, 'mass') == dir // "include/campaign.nml:4: &body 'mass'", &
             'origin of an override: ' // deck%origin('body', 1, 'mass'))
  call check(deck%origin('body', 1, 'ixx') == dir // "include/base.nml:3: &body 'ixx'", &
             'origin of a base value: ' // deck%origin('body', 1, 'ixx'))
  call check(deck%path('output', 1, 'file') == dir // 'include/campaign.h5', &
             'output named after the top deck')
  s = deck%text()
  call check(index(s, "! >>> begin include '" // dir // "include/base.nml'") > 0 .and. &
             index(s, "! >>> begin include '" // dir // "include/sub/wheelset.nml'") > 0 .and. &
             index(s, "&body name = 'ws'") > 0 .and. index(s, '! <<< end include') > 0, &
             'text() has the included decks between markers')
  call check(index(s, "&include file = 'base.nml' /") < index(s, "&simulation t_end = 10.0"), &
             'included text follows its &include line')

  ! --- file errors --------------------------------------------------------
  call read_deck_file(deck, dir // 'bad/missing_include.nml', error)
  call expect_error('missing include', [character(len=60) :: 'bad/missing_include.nml:3:', &
    "&include 'file'", 'no_such_deck.nml', 'expected an existing file'])
  call read_deck_file(deck, dir // 'bad/missing_profile.nml', error)
  call expect_error('missing profile', [character(len=60) :: 'bad/missing_profile.nml:4:', &
    "&wheelset 'wheel_profile'", 'bad/profiles/wheel_test.prw', 'expected an existing file'])
  call read_deck_file(deck, dir // 'bad/cycle_a.nml', error)
  call expect_error('include cycle', [character(len=60) :: 'bad/cycle_b.nml:2:', &
    "&include 'file'", 'include cycle', 'cycle_a.nml', 'expected a deck that does not include'])
  call read_deck_file(deck, dir // 'bad/no_such_deck.nml', error)
  call expect_error('missing deck', [character(len=60) :: 'no_such_deck.nml', 'expected an existing'])

  call test_summary('test_deck_files')

contains

  subroutine expect_ok(what)
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      call fail()
      print '(a)', 'FAIL: ' // what // ': ' // error%message
      deallocate (error)
    end if
  end subroutine expect_ok

  subroutine expect_error(what, parts)
    character(len=*), intent(in) :: what
    character(len=*), intent(in) :: parts(:)
    integer :: k
    if (.not. allocated(error)) then
      call fail()
      print '(a)', 'FAIL: ' // what // ': no error'
      return
    end if
    print '(a)', '  ' // what // ' -> ' // error%message
    call check(error%code == RD_ERR_INPUT, what // ': code RD_ERR_INPUT')
    call check(index(error%message, achar(10)) == 0, what // ': one line')
    do k = 1, size(parts)
      call check(index(error%message, trim(parts(k))) > 0, what // ': message lacks "' // &
                 trim(parts(k)) // '"')
    end do
    deallocate (error)
  end subroutine expect_error
end program test_deck_files
