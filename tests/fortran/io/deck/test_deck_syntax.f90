!> The namelist syntax the reader accepts, checked value by value against the
!> numbers written in the deck text below (number forms, strings with
!> escapes, logicals, lists, repeat counts, element assignment, &end,
!> comments, case folding), the defaults of the specification, and misuse of
!> the getters (RD_ERR_INTERNAL, never a crash).
program test_deck_syntax
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INTERNAL
  use rd_deck, only: deck_t, read_deck_string, deck_string_t
  use rd_deck_text, only: edit_distance, real_to_str, is_real_text
  use rd_test_support, only: check, fail, test_summary
  implicit none
  type(deck_t) :: deck, unread, never_read
  type(error_t), allocatable :: error
  character(len=1), parameter :: nl = achar(10)
  character(len=:), allocatable :: text, s
  real(wp) :: x
  real(wp), allocatable :: v(:)
  integer :: n
  logical :: b
  type(deck_string_t), allocatable :: list(:)

  text = &
    '! a deck exercising the syntax' // nl // &
    '   ' // nl // &
    '&SIMULATION T_END = 2.0, Title = ''it''''s a "test"'' ! trailing comment' // nl // &
    '   ! a comment line inside a group' // nl // &
    '/' // nl // &
    '&Solver Method = ''BDF'', max_num_steps = +500 rtol=1e-5 / &track gauge = 1.0d0 &end' // nl // &
    '&output file = "say ""hi"" ! not a comment.h5" /' // nl // &
    '&segment type = ''straight'', length = 10, gradient = 0.01 /' // nl // &
    '&segment type = ''straight'', length = 2.5E+1 /' // nl // &
    '&body name = ''b1'', mass = 1.0e3, ixx = 1, iyy = 2, izz = 3,' // nl // &
    '      position = 3*0.5  ! repeat count' // nl // &
    '      position(2) = 0.25, frozen = ''Yaw'' ''roll'', velocity = 1 2 3 /' // nl // &
    '&body name = ''b2'', mass = 1, ixx = 1, iyy = 1, izz = 1, frame = ''b1'',' // nl // &
    '      stop = 1 /' // nl
  ! 'stop' above is not a parameter: replaced below to keep the deck valid
  text = text(1:index(text, '      stop = 1 /') - 1) // '      orientation = 2*0.0 .5 /' // nl // &
    '&element name = ''t'', type = ''table'', body1 = ''b1'', body2 = ''b2'', table_axis = ''z'',' // nl // &
    '   table_deflection = -2.5E+3, -1, 1.0d-3, 1e-2, .5, 3., 7' // nl // &
    '   table_force = 1, 1.0, 1e-6, 1.0d-3, -2.5E+3, .5, 3.' // nl // &
    '   table_deflection(8) = 8.0 table_force(8) = -0.0 /' // nl // &
    '&wheelset name = ''w'', body = ''b1'', contact = ''knife_edge'',' // nl // &
    '   spin_creep = F' // nl // &
    '/' // nl

  call read_deck_string(deck, text, '.', 'syntax.nml', error)
  if (allocated(error)) then
    print '(a)', 'FAIL: read: ' // error%message
    error stop 1
  end if
  call deck%get('simulation', 1, 't_end', x, error); call ok('t_end')
  call check(x == 2.0_wp, 'upper-case names')
  call deck%get('simulation', 1, 'title', s, error); call ok('title')
  call check(s == 'it''s a "test"', 'doubled quote escape, other quote inside: ' // s)
  call deck%get('wheelset', 1, 'spin_creep', b, error); call ok('logical')
  call check(.not. b, 'logical F')
  call deck%get('solver', 1, 'method', s, error); call ok('method')
  call check(s == 'bdf', 'allowed value folded to lower case')
  call deck%get('solver', 1, 'max_num_steps', n, error); call ok('max_num_steps')
  call check(n == 500, 'signed integer')
  call deck%get('solver', 1, 'rtol', x, error)
  call check(x == 1.0e-5_wp, 'blank-separated assignments')
  call deck%get('track', 1, 'gauge', x, error)
  call check(x == 1.0_wp, '&end terminator, two groups on a line, d exponent')
  call deck%get('output', 1, 'file', s, error)
  call check(s == 'say "hi" ! not a comment.h5', 'double-quoted string with ! inside: ' // s)
  call deck%get('segment', 2, 'length', x, error)
  call check(x == 25.0_wp, '2.5E+1')
  call deck%get('segment', 2, 'gradient', x, error)
  call check(x == 0.01_wp, 'gradient default = previous segment''s')
  call check(.not. deck%given('segment', 2, 'gradient') .and. deck%given('segment', 1, 'gradient'), &
             'given flags')
  call deck%get('body', 1, 'position', v, error)
  call check(all(v == [0.5_wp, 0.25_wp, 0.5_wp]), 'repeat count then element assignment')
  call deck%get('body', 1, 'velocity', v, error)
  call check(all(v == [1.0_wp, 2.0_wp, 3.0_wp]), 'blank-separated list')
  call deck%get('body', 2, 'orientation', v, error)
  call check(all(v == [0.0_wp, 0.0_wp, 0.5_wp]), 'repeat count and .5')
  call deck%get('body', 1, 'frozen', list, error); call ok('frozen')
  call check(size(list) == 2, 'string list size')
  if (size(list) == 2) call check(list(1)%s == 'yaw' .and. list(2)%s == 'roll', 'string list')
  call deck%get('body', 2, 'frozen', list, error); call ok('frozen default')
  call check(size(list) == 0, 'string list default empty')
  call deck%get('body', 2, 'frame', s, error)
  call check(s == 'b1', 'frame shared with b1')
  call deck%get('body', 1, 'frame', s, error)
  call check(s == 'own', 'frame default own')
  call deck%get('element', 1, 'table_force', v, error); call ok('table_force')
  call check(size(v) == 8, 'variable list extended by element assignment')
  if (size(v) == 8) call check(all(v == [1.0_wp, 1.0_wp, 1.0e-6_wp, 1.0e-3_wp, -2500.0_wp, &
                                         0.5_wp, 3.0_wp, 0.0_wp]), 'all real forms')
  call deck%get('element', 1, 'table_deflection', v, error)
  if (size(v) == 8) call check(v(1) == -2500.0_wp .and. v(8) == 8.0_wp, 'table_deflection')
  call check(deck%origin('body', 1, 'frozen') == "syntax.nml:12: &body 'frozen'", &
             'origin ' // deck%origin('body', 1, 'frozen'))
  call check(deck%origin('body', 2) == 'syntax.nml:13: &body', 'origin of a group')
  call check(deck%origin('solver', 1, 'atol') == "syntax.nml:6: &solver 'atol'", &
             'origin of a default')
  call check(deck%text() == text, 'text() of a deck without includes is the deck')
  call read_deck_string(unread, '&simulation t_end = 1.0 /', 'decks_dir', '<string>', error)
  call ok('string deck')
  call check(unread%path('output', 1, 'file') == 'decks_dir/string.h5', &
             'default output of a string deck: ' // unread%path('output', 1, 'file'))
  call check(deck%count('wheelset') == 1 .and. deck%count('nonsense') == 0, 'counts')

  ! --- getter misuse: RD_ERR_INTERNAL, never a crash ---------------------
  call deck%get('bogie', 1, 'mass', x, error); call internal('unknown group')
  call deck%get('body', 3, 'mass', x, error); call internal('occurrence out of range')
  call deck%get('body', 1, 'weight', x, error); call internal('unknown parameter')
  call deck%get('body', 1, 'name', x, error); call internal('real asked of a string')
  call deck%get('solver', 1, 'max_num_steps', x, error); call internal('real asked of an integer')
  call deck%get('segment', 1, 'radius', x, error); call internal('optional parameter not given')
  call never_read%get('body', 1, 'mass', x, error); call internal('deck never read')
  call check(.not. deck%given('bogie', 1, 'mass'), 'given of an unknown group')
  call read_deck_string(never_read, '&simulation t_end = 1.0 /' // nl // &
    '&body name = ''b'', mass = 1.0, ixx = 1, iyy = 1, izz = 1, frame = ''nobody'' /', '.', &
    'bad.nml', error)
  call check(allocated(error), 'a deck with an undefined reference fails')
  if (allocated(error)) deallocate (error)
  call check(never_read%count('body') == 0, 'a deck that failed to read is empty')
  call never_read%get('simulation', 1, 't_end', x, error)
  call internal('get from a deck that failed to read')
  call check(deck%path('body', 1, 'mass') == '', 'path of a non-path parameter')

  ! --- text helpers, against hand-computed values -------------------------
  call check(edit_distance('kitten', 'sitting') == 3, 'Levenshtein kitten/sitting = 3')
  call check(edit_distance('simulaton', 'simulation') == 1, 'one deletion')
  call check(edit_distance('', 'abc') == 3, 'empty string')
  call check(real_to_str(9.80665_wp) == '9.80665', 'format 9.80665: ' // real_to_str(9.80665_wp))
  call check(real_to_str(82.0e9_wp) == '8.2e10', 'format 82e9: ' // real_to_str(82.0e9_wp))
  call check(real_to_str(1.0e-6_wp) == '1e-6', 'format 1e-6: ' // real_to_str(1.0e-6_wp))
  call check(real_to_str(-0.07_wp) == '-0.07', 'format -0.07: ' // real_to_str(-0.07_wp))
  call check(real_to_str(100000.0_wp) == '100000', 'format 1e5: ' // real_to_str(100000.0_wp))
  call check(real_to_str(0.025_wp) == '0.025', 'format 0.025: ' // real_to_str(0.025_wp))
  call check(is_real_text('1.') .and. is_real_text('-.5e3') .and. .not. is_real_text('.') .and. &
             .not. is_real_text('1e') .and. .not. is_real_text('e5') .and. &
             .not. is_real_text('1.0.0') .and. .not. is_real_text('+'), 'number grammar')

  call test_summary('test_deck_syntax')

contains

  subroutine ok(what)
    character(len=*), intent(in) :: what
    if (allocated(error)) then
      call fail()
      print '(a)', 'FAIL: ' // what // ': ' // error%message
      deallocate (error)
    end if
  end subroutine ok

  subroutine internal(what)
    character(len=*), intent(in) :: what
    if (.not. allocated(error)) then
      call fail()
      print '(a)', 'FAIL: ' // what // ': no error'
      return
    end if
    print '(a)', '  ' // what // ' -> ' // error%message
    call check(error%code == RD_ERR_INTERNAL, what // ': not RD_ERR_INTERNAL')
    deallocate (error)
  end subroutine internal
end program test_deck_syntax
