!> The reader never crashes and never accepts garbage silently: every
!> truncation of a valid deck, and every single-character corruption of it
!> by a syntax character, either reads or fails with one RD_ERR_INPUT line
!> "case.nml[:line]: ...; expected ...". (The deck is tests/decks/mb_v1_tc1.nml
!> minus its profile file, so the test needs no files.)
program test_deck_robustness
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_deck, only: deck_t, read_deck_string
  use rd_test_support, only: fail, failure_count, test_summary
  implicit none
  character(len=1), parameter :: nl = achar(10)
  character(len=*), parameter :: specials = '/&''"=,(!*x.'
  character(len=:), allocatable :: text, mutated
  type(deck_t) :: deck
  type(error_t), allocatable :: error
  integer :: cut, pos, k, nread, nerr

  text = '! Manchester benchmark vehicle 1, track case 1' // nl // &
    '&simulation title = ''MB V1 TC1'', t_end = 30.0, speed = 4.4 /' // nl // &
    '&solver method = ''bdf'', rtol = 1e-6 /' // nl // &
    '&segment type = ''clothoid'', length = 30.0, radius = 150.0, side = ''left'', cant = 0.100 /' // nl // &
    '&body name = ''ws1'', mass = 1813.0, ixx = 1120.0, iyy = 112.0, izz = 1120.0,' // nl // &
    '      position = 0.0, 0.0, 0.46 /' // nl // &
    '&body name = ''bogie1'', mass = 2615.0, ixx = 1722.0, iyy = 1476.0, izz = 3067.0 /' // nl // &
    '&element name = ''prim1l'', type = ''spring_damper'', body1 = ''bogie1'', body2 = ''ws1'',' // nl // &
    '      point1 = 1.28, 1.0, -0.14, stiffness = 3*1e6, damping(2) = 5.0e3 /' // nl
  nread = 0; nerr = 0

  call read_deck_string(deck, text, '.', 'case.nml', error)
  if (allocated(error)) then
    print '(a)', 'FAIL: the intact deck: ' // error%message
    error stop 1
  end if

  do cut = 0, len(text) - 1
    call read_deck_string(deck, text(1:cut), '.', 'case.nml', error)
    call judge('truncated at ' // itoa(cut))
  end do
  do pos = 1, len(text)
    do k = 1, len(specials)
      if (text(pos:pos) == specials(k:k)) cycle
      mutated = text
      mutated(pos:pos) = specials(k:k)
      call read_deck_string(deck, mutated, '.', 'case.nml', error)
      call judge('char ' // itoa(pos) // ' -> "' // specials(k:k) // '"')
    end do
  end do
  print '(a,i0,a,i0,a)', 'test_deck_robustness: ', nread, ' variants read, ', nerr, &
    ' rejected with a proper message'
  call test_summary('test_deck_robustness')

contains

  subroutine judge(what)
    character(len=*), intent(in) :: what
    if (.not. allocated(error)) then
      nread = nread + 1
      return
    end if
    nerr = nerr + 1
    if (error%code /= RD_ERR_INPUT .or. index(error%message, nl) > 0 .or. &
        index(error%message, 'case.nml') /= 1 .or. index(error%message, '; expected ') == 0) then
      call fail()
      if (failure_count() <= 20) print '(a)', 'FAIL: ' // what // ': ' // error%message
    end if
    deallocate (error)
  end subroutine judge

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=12) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa
end program test_deck_robustness
