!> The jump/kink detector of rd_sweep_smoothness against functions whose features are known
!> in closed form: a smooth function (nothing found), a step (one jump of the step's size
!> between the two samples around it), |x - x0| and a ramp's corner (one kink of the known
!> slope change at x0, on and between samples), a step on a smooth background and a
!> plateau's two corners, and bad input (errors, not a crash).
program test_sweep_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_sweep_smoothness, only: smoothness_feature_t, find_jumps_and_kinks, FEATURE_JUMP, FEATURE_KINK
  use rd_test_support, only: check, fail, test_summary
  implicit none
  integer, parameter :: n = 2001
  real(wp), parameter :: h = 1.0e-3_wp
  real(wp) :: x(n), f(n)
  type(smoothness_feature_t), allocatable :: feat(:)
  type(error_t), allocatable :: error
  integer :: i

  x = [(-1.0_wp + (i - 1) * h, i = 1, n)]

  ! smooth: a force-like curve of size 5e4 with curvature changing sign
  f = 5.0e4_wp * (sin(3 * x) + 0.3_wp * exp(x) * x**2)
  call detect('smooth function')
  call check(size(feat) == 0, 'smooth: nothing detected')

  ! step of -1234.5 between x(700) and x(701) on a smooth background
  f = 5.0e4_wp * sin(3 * x)
  f(701:) = f(701:) - 1234.5_wp
  call detect('step')
  call check(size(feat) == 1, 'step: one feature')
  if (size(feat) == 1) then
    call check(feat(1)%kind == FEATURE_JUMP, 'step: it is a jump')
    call check(abs(feat(1)%x - 0.5_wp * (x(700) + x(701))) < 1.0e-9_wp, 'step: at the middle of the interval')
    call check(abs(feat(1)%size + 1234.5_wp) < 1.2_wp, 'step: size within 0.1 %')
  end if

  ! |x - x0| with x0 on a sample: slope change +2 at x0
  f = abs(x - x(1201))
  call detect('|x - x0| on a sample')
  call check(size(feat) == 1, '|x|: one feature')
  if (size(feat) == 1) then
    call check(feat(1)%kind == FEATURE_KINK, '|x|: it is a kink')
    call check(abs(feat(1)%x - x(1201)) < 1.0e-9_wp, '|x|: at x0')
    call check(abs(feat(1)%size - 2) < 1.0e-9_wp, '|x|: slope change 2')
  end if

  ! 3 |x - x0| - 0.5 x^2 with x0 between samples (0.3 h after x(500)): slope change 6
  f = 3 * abs(x - (x(500) + 0.3_wp * h)) - 0.5_wp * x**2
  call detect('kink between samples')
  call check(size(feat) == 1, 'kink between samples: one feature')
  if (size(feat) == 1) then
    call check(feat(1)%kind == FEATURE_KINK, 'kink between samples: it is a kink')
    call check(abs(feat(1)%x - (x(500) + 0.3_wp * h)) < 1.0e-6_wp, 'kink between samples: at x0 within 1e-3 h')
    call check(abs(feat(1)%size - 6) < 6.0e-6_wp, 'kink between samples: slope change 6 within 1e-6')
  end if

  ! a ramp between two plateaus, 1e3 min(max(x, -0.2), 0.4): slope change +1e3 at -0.2, -1e3 at 0.4
  f = 1.0e3_wp * min(max(x, -0.2_wp), 0.4_wp)
  call detect('plateau corners')
  call check(size(feat) == 2, 'plateau: two features')
  if (size(feat) == 2) then
    call check(all(feat%kind == FEATURE_KINK), 'plateau: both kinks')
    call check(abs(feat(1)%size - 1.0e3_wp) < 1.0e-6_wp .and. &
               abs(feat(2)%size + 1.0e3_wp) < 1.0e-6_wp .and. abs(feat(1)%x + 0.2_wp) < 1.0e-9_wp .and. &
               abs(feat(2)%x - 0.4_wp) < 1.0e-9_wp, 'plateau: +1e3 at -0.2, -1e3 at 0.4')
  end if

  ! a step smaller than ratio x the local second differences is not reported (at this
  ! resolution it is indistinguishable from the curve): 5e4 sin(3x) has |s| = 0.45 at x = 0.5
  ! (where the curve is straight, x = 0, the same step is found: the local scale is tiny)
  f = 5.0e4_wp * sin(3 * x)
  f(1501:) = f(1501:) + 1.0_wp
  call detect('step below the threshold')
  call check(size(feat) == 0, 'step below the threshold: nothing detected')

  ! bad input: errors, no crash
  call find_jumps_and_kinks(x(1:5), f(1:5), 1.0_wp, feat, error)
  call check(allocated(error), 'too few samples: error')
  x(10) = x(10) + 0.5_wp * h
  call find_jumps_and_kinks(x, f, 1.0_wp, feat, error)
  call check(allocated(error), 'non-uniform x: error')

  call test_summary('test_sweep_smoothness')

contains

  subroutine detect(what)
    character(len=*), intent(in) :: what
    integer :: k
    call find_jumps_and_kinks(x, f, maxval(abs(f)), feat, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: ' // what // ': ' // error%message
      call fail()
      allocate (feat(0))
      return
    end if
    do k = 1, size(feat)
      print '(a,i0,a,i0,a,es14.6,a,es14.6)', what // ': feature ', k, ' kind ', feat(k)%kind, ' at ', feat(k)%x, &
        ' size ', feat(k)%size
    end do
  end subroutine detect

end program test_sweep_smoothness
