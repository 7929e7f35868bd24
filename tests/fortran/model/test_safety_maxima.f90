!> rd_safety_maxima's sliding mean and median against closed forms (the completion line of
!> raildyn run builds on them): the centred 2 m mean of a constant, of a sampled step (the
!> integral of its linear interpolant written piecewise here) and of a finely, unevenly
!> sampled sine (sin(k c) sin(k L/2) / (k L/2)); which windows lie inside the covered track;
!> the median of odd and even counts with repeated values against a sorted copy.
program test_safety_maxima
  use rd_kinds, only: wp
  use rd_safety_maxima, only: centred_sliding_mean, median
  use rd_test_support, only: check, test_summary
  use rd_text, only: sci_text
  implicit none
  integer, parameter :: n = 101
  real(wp) :: s(n), y(n), mean(n)
  logical :: inside(n)
  integer :: i

  s = [(0.1_wp * (i - 1), i = 1, n)]                ! 0 .. 10 m
  y = 0.37_wp
  call centred_sliding_mean(s, y, 2.0_wp, mean, inside)
  call check(all(inside .eqv. (s >= 1 - 1e-9_wp .and. s <= 9 + 1e-9_wp)), 'windows inside [1, 9] m')
  call check(count(inside) == 81, 'window count 81')
  call check(all(abs(pack(mean, inside) - 0.37_wp) < 1e-14_wp), 'constant: mean = the constant')

  ! step: 0 up to 4.9 m, 1 from 5.0 m; the interpolant ramps over [4.9, 5.0]
  y = merge(1.0_wp, 0.0_wp, s >= 5 - 1e-9_wp)
  call centred_sliding_mean(s, y, 2.0_wp, mean, inside)
  do i = 1, n
    if (.not. inside(i)) cycle
    call check(abs(mean(i) - (step_integral(s(i) + 1) - step_integral(s(i) - 1)) / 2) < 1e-12_wp, &
               'step mean at s = ' // trim(sci_text(s(i), 4)))
  end do
  call check(abs(mean(51) - 0.525_wp) < 1e-12_wp, 'step mean at 5 m = (1 + 0.05) / 2')
  ! a window whose ends fall between samples (1.95 m): the interpolant's partial intervals
  call centred_sliding_mean(s, y, 1.95_wp, mean, inside)
  call check(count(inside) == 81, '1.95 m windows: count 81')
  do i = 1, n
    if (.not. inside(i)) cycle
    call check(abs(mean(i) - (step_integral(s(i) + 0.975_wp) - step_integral(s(i) - 0.975_wp)) / 1.95_wp) &
               < 1e-12_wp, 'step mean (1.95 m) at s = ' // trim(sci_text(s(i), 4)))
  end do

  call sine_case()

  call check(median([3.0_wp]) == 3, 'median of one value')
  call check(median([5.0_wp, 1.0_wp, 4.0_wp, 1.0_wp, 3.0_wp]) == 3, 'median odd count')
  call check(median([5.0_wp, 1.0_wp, 4.0_wp, 2.0_wp]) == 3, 'median even count: (2 + 4) / 2')
  call check(median([2.0_wp, 2.0_wp, 2.0_wp, 7.0_wp, 2.0_wp, 2.0_wp]) == 2, 'median with repeats')
  call random_medians()
  call test_summary('test_safety_maxima')

contains

  !> Integral from 0 to a of the step's linear interpolant.
  pure real(wp) function step_integral(a)
    real(wp), intent(in) :: a
    if (a <= 4.9_wp) then
      step_integral = 0
    else if (a < 5.0_wp) then
      step_integral = (a - 4.9_wp)**2 / (2 * 0.1_wp)
    else
      step_integral = 0.05_wp + (a - 5.0_wp)
    end if
  end function step_integral

  subroutine sine_case()
    integer, parameter :: m = 4001
    real(wp) :: ss(m), yy(m), mm(m), k, expected, worst
    logical :: in(m)
    integer :: j
    k = 2.3_wp
    ! uneven spacing: positions of a vehicle whose speed varies
    ss = [(20.0_wp * (j - 1) / (m - 1) + 0.05_wp * sin(0.7_wp * (j - 1) / 50.0_wp), j = 1, m)]
    yy = sin(k * ss)
    call centred_sliding_mean(ss, yy, 2.0_wp, mm, in)
    worst = 0
    do j = 1, m
      if (.not. in(j)) cycle
      expected = sin(k * ss(j)) * sin(k) / k
      worst = max(worst, abs(mm(j) - expected))
    end do
    call check(worst < 1e-5_wp, 'sine: mean = sin(k c) sin(k) / k, worst ' // trim(sci_text(worst, 4)))
  end subroutine sine_case

  subroutine random_medians()
    real(wp) :: v(37), sorted(37), t
    integer :: trial, a, b, nv
    do trial = 1, 20
      call random_number(v)
      v = anint(v * 10)                    ! repeats
      nv = 36 + mod(trial, 2)              ! even and odd counts
      sorted(1:nv) = v(1:nv)
      do a = 1, nv
        do b = a + 1, nv
          if (sorted(b) < sorted(a)) then
            t = sorted(a); sorted(a) = sorted(b); sorted(b) = t
          end if
        end do
      end do
      if (mod(nv, 2) == 1) then
        call check(median(v(1:nv)) == sorted((nv + 1) / 2), 'random median, odd')
      else
        call check(median(v(1:nv)) == 0.5_wp * (sorted(nv / 2) + sorted(nv / 2 + 1)), 'random median, even')
      end if
    end do
  end subroutine random_medians
end program test_safety_maxima
