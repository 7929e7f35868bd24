!> The jump/kink detector of rd_sweep_smoothness against functions whose features are known
!> in closed form: a smooth function (nothing found), a step (one jump of the step's size
!> between the two samples around it), |x - x0| and a ramp's corner (one kink of the known
!> slope change at x0, on and between samples), a step on a smooth background and a
!> plateau's two corners, and bad input (errors, not a crash).
program test_sweep_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_sweep_smoothness, only: smoothness_feature_t, find_jumps_and_kinks, FEATURE_JUMP, FEATURE_KINK
  implicit none
  integer, parameter :: n = 2001
  real(wp), parameter :: h = 1.0e-3_wp
  real(wp) :: x(n), f(n)
  type(smoothness_feature_t), allocatable :: feat(:)
  type(error_t), allocatable :: error
  integer :: i, nfail = 0

  x = [(-1.0_wp + (i - 1) * h, i = 1, n)]

  ! smooth: a force-like curve of size 5e4 with curvature changing sign
  f = 5.0e4_wp * (sin(3 * x) + 0.3_wp * exp(x) * x**2)
  call detect('smooth function')
  call check('smooth: nothing detected', size(feat) == 0)

  ! step of -1234.5 between x(700) and x(701) on a smooth background
  f = 5.0e4_wp * sin(3 * x)
  f(701:) = f(701:) - 1234.5_wp
  call detect('step')
  call check('step: one feature', size(feat) == 1)
  if (size(feat) == 1) then
    call check('step: it is a jump', feat(1)%kind == FEATURE_JUMP)
    call check('step: at the middle of the interval', abs(feat(1)%x - 0.5_wp * (x(700) + x(701))) < 1.0e-9_wp)
    call check('step: size within 0.1 %', abs(feat(1)%size + 1234.5_wp) < 1.2_wp)
  end if

  ! |x - x0| with x0 on a sample: slope change +2 at x0
  f = abs(x - x(1201))
  call detect('|x - x0| on a sample')
  call check('|x|: one feature', size(feat) == 1)
  if (size(feat) == 1) then
    call check('|x|: it is a kink', feat(1)%kind == FEATURE_KINK)
    call check('|x|: at x0', abs(feat(1)%x - x(1201)) < 1.0e-9_wp)
    call check('|x|: slope change 2', abs(feat(1)%size - 2) < 1.0e-9_wp)
  end if

  ! 3 |x - x0| - 0.5 x^2 with x0 between samples (0.3 h after x(500)): slope change 6
  f = 3 * abs(x - (x(500) + 0.3_wp * h)) - 0.5_wp * x**2
  call detect('kink between samples')
  call check('kink between samples: one feature', size(feat) == 1)
  if (size(feat) == 1) then
    call check('kink between samples: it is a kink', feat(1)%kind == FEATURE_KINK)
    call check('kink between samples: at x0 within 1e-3 h', abs(feat(1)%x - (x(500) + 0.3_wp * h)) < 1.0e-6_wp)
    call check('kink between samples: slope change 6 within 1e-6', abs(feat(1)%size - 6) < 6.0e-6_wp)
  end if

  ! a ramp between two plateaus, 1e3 min(max(x, -0.2), 0.4): slope change +1e3 at -0.2, -1e3 at 0.4
  f = 1.0e3_wp * min(max(x, -0.2_wp), 0.4_wp)
  call detect('plateau corners')
  call check('plateau: two features', size(feat) == 2)
  if (size(feat) == 2) then
    call check('plateau: both kinks', all(feat%kind == FEATURE_KINK))
    call check('plateau: +1e3 at -0.2, -1e3 at 0.4', abs(feat(1)%size - 1.0e3_wp) < 1.0e-6_wp .and. &
               abs(feat(2)%size + 1.0e3_wp) < 1.0e-6_wp .and. abs(feat(1)%x + 0.2_wp) < 1.0e-9_wp .and. &
               abs(feat(2)%x - 0.4_wp) < 1.0e-9_wp)
  end if

  ! a step smaller than ratio x the local second differences is not reported (at this
  ! resolution it is indistinguishable from the curve): 5e4 sin(3x) has |s| = 0.45 at x = 0.5
  ! (where the curve is straight, x = 0, the same step is found: the local scale is tiny)
  f = 5.0e4_wp * sin(3 * x)
  f(1501:) = f(1501:) + 1.0_wp
  call detect('step below the threshold')
  call check('step below the threshold: nothing detected', size(feat) == 0)

  ! bad input: errors, no crash
  call find_jumps_and_kinks(x(1:5), f(1:5), 1.0_wp, feat, error)
  call check('too few samples: error', allocated(error))
  x(10) = x(10) + 0.5_wp * h
  call find_jumps_and_kinks(x, f, 1.0_wp, feat, error)
  call check('non-uniform x: error', allocated(error))

  if (nfail > 0) then
    print '(i0,a)', nfail, ' check(s) failed'
    error stop 1
  end if
  print '(a)', 'test_sweep_smoothness: all checks passed'

contains

  subroutine detect(what)
    character(len=*), intent(in) :: what
    integer :: k
    call find_jumps_and_kinks(x, f, maxval(abs(f)), feat, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // what // ': ' // error%message
      nfail = nfail + 1
      allocate (feat(0))
      return
    end if
    do k = 1, size(feat)
      print '(a,i0,a,i0,a,es14.6,a,es14.6)', what // ': feature ', k, ' kind ', feat(k)%kind, ' at ', feat(k)%x, &
        ' size ', feat(k)%size
    end do
  end subroutine detect

  subroutine check(name, ok)
    character(len=*), intent(in) :: name
    logical, intent(in) :: ok
    if (.not. ok) then
      nfail = nfail + 1
      print '(2a)', 'FAIL: ', name
    else
      print '(2a)', 'ok    ', name
    end if
  end subroutine check
end program test_sweep_smoothness
