!> Every validation of build_track produces a clear RD_ERR_INPUT message that starts with
!> the segment's origin and says what is expected.
program test_track_errors
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_quiet_nan
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT
  use rd_track_point, only: track_point_t
  use rd_track, only: track_t, track_settings_t, segment_spec_t, build_track
  use rd_test_support, only: fail, test_summary
  implicit none
  type(track_settings_t) :: settings
  type(segment_spec_t) :: s(3)
  real(wp) :: nan

  nan = ieee_value(1.0_wp, ieee_quiet_nan)

  ! length <= 0
  s(1) = seg('straight', 0.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:12: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:12: &segment', 'length must be > 0'], 'zero length')
  s(1) = seg('clothoid', -5.0_wp, 0.01_wp, 0.0_wp, 'deck.nml:13: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:13: &segment', 'length must be > 0', '-5'], &
              'negative length')

  ! a curve whose curvature differs from the previous end curvature
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:20: &segment')
  s(2) = seg('curve', 60.0_wp, 1 / 150.0_wp, 0.0_wp, 'deck.nml:21: &segment')
  call expect(settings, s(1:2), [character(len=60) :: 'deck.nml:21: &segment', 'curvature jumps from 0', &
              'to 1/150', 'at the start of this curve', 'transition (clothoid) of non-zero length is needed'], &
              'curve after straight')
  s(2) = seg('clothoid', 30.0_wp, 1 / 300.0_wp, 0.0_wp, 'deck.nml:21: &segment')
  s(3) = seg('curve', 60.0_wp, 1 / 150.0_wp, 0.0_wp, 'deck.nml:22: &segment')
  call expect(settings, s(1:3), [character(len=60) :: 'deck.nml:22: &segment', 'curvature jumps from 1/300', &
              'to 1/150', 'transition (clothoid)'], 'compound curve without transition')
  s(3) = seg('straight', 60.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:22: &segment')
  call expect(settings, s(1:3), [character(len=60) :: 'deck.nml:22: &segment', 'curvature jumps from 1/300', &
              'this straight'], 'straight after a curved end')
  s(3) = seg('straight', 60.0_wp, 0.002_wp, 0.0_wp, 'deck.nml:22: &segment')
  call expect(settings, s(1:3), [character(len=60) :: 'deck.nml:22: &segment', 'a straight has zero curvature'], &
              'straight with curvature')

  ! cant changing on a segment that is not a clothoid
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:30: &segment')
  s(2) = seg('clothoid', 30.0_wp, 1 / 150.0_wp, -0.1_wp, 'deck.nml:31: &segment')
  s(3) = seg('curve', 60.0_wp, 1 / 150.0_wp, -0.12_wp, 'deck.nml:32: &segment')
  call expect(settings, s(1:3), [character(len=60) :: 'deck.nml:32: &segment', 'superelevation changes from -0.1', &
              'only a clothoid can ramp the cant'], 'cant change on a curve')
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.02_wp, 'deck.nml:30: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:30: &segment', 'superelevation changes from 0', &
              'only a clothoid'], 'cant change on a straight')

  ! cant larger than the gauge / cant base
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:40: &segment')
  s(2) = seg('clothoid', 30.0_wp, 1 / 150.0_wp, -1.5_wp, 'deck.nml:41: &segment')
  call expect(settings, s(1:2), [character(len=60) :: 'deck.nml:41: &segment', 'cant larger than the gauge'], &
              '|h| = cant_base')
  settings%cant_base = 2.0_wp
  s(2) = seg('clothoid', 30.0_wp, 1 / 150.0_wp, 1.5_wp, 'deck.nml:41: &segment')
  call expect(settings, s(1:2), [character(len=60) :: 'deck.nml:41: &segment', 'cant larger than the gauge'], &
              '|h| > gauge')
  settings = track_settings_t()

  ! non-finite numbers
  s(1) = seg('straight', nan, 0.0_wp, 0.0_wp, 'deck.nml:50: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:50: &segment', 'finite'], 'NaN length')
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:50: &segment')
  s(2) = seg('clothoid', 30.0_wp, 1 / 150.0_wp, nan, 'deck.nml:51: &segment')
  call expect(settings, s(1:2), [character(len=60) :: 'deck.nml:51: &segment', 'finite'], 'NaN superelevation')
  s(2) = seg('clothoid', 30.0_wp, ieee_value(1.0_wp, ieee_positive_inf), 0.0_wp, 'deck.nml:51: &segment')
  call expect(settings, s(1:2), [character(len=60) :: 'deck.nml:51: &segment', 'finite'], 'infinite curvature')

  ! unknown kind and ramp; settings
  s(1) = seg('spiral', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:60: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:60: &segment', "kind must be 'straight', 'clothoid' or", &
              "'spiral'"], 'unknown kind')
  s(1) = seg('clothoid', 50.0_wp, 0.001_wp, 0.0_wp, 'deck.nml:61: &segment')
  s(1)%cant_ramp = 'bloss'
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:61: &segment', "cant_ramp must be 'linear' or 'cosine'"], &
              'unknown ramp')
  settings%gauge = -1
  settings%origin = 'deck.nml:2: &track'
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, 'deck.nml:62: &segment')
  call expect(settings, s(1:1), [character(len=60) :: 'deck.nml:2: &track', 'gauge and cant_base must be > 0'], &
              'negative gauge')
  settings = track_settings_t()
  call no_segments_is_a_straight()

  ! without an origin the segment number is named
  s(1) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, '')
  s(2) = seg('curve', 60.0_wp, 1 / 150.0_wp, 0.0_wp, '')
  call expect(settings, s(1:2), [character(len=60) :: 'segment 2 (curve)', 'curvature jumps'], 'no origin')

  call test_summary('test_track_errors')

contains

  !> Not an error: a track without segments is the straight through the start.
  subroutine no_segments_is_a_straight()
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(error_t), allocatable :: error
    type(track_point_t) :: p
    real(wp) :: worst
    integer :: i
    settings%start_position = [1.0_wp, 2.0_wp, 3.0_wp]
    settings%start_heading = 0.4_wp
    settings%start_superelevation = 0.01_wp
    call build_track(track, settings, s(1:0), error)
    if (allocated(error)) then
      call fail()
      print '(a)', 'FAIL: no segments: ' // error%message
      return
    end if
    worst = abs(track%length())
    do i = -2, 2
      p = track%evaluate(10.0_wp * i)
      worst = max(worst, maxval(abs(p%r - ([1.0_wp, 2.0_wp, 3.0_wp] + 10.0_wp * i * [cos(0.4_wp), sin(0.4_wp), &
                  0.0_wp]))), abs(p%heading - 0.4_wp), abs(p%cant_angle - asin(0.01_wp / 1.5_wp)), abs(p%curvature))
    end do
    if (worst > 1.0e-13_wp) then
      call fail()
      print '(a,es10.3)', 'FAIL: no segments is not the straight through the start ', worst
    end if
  end subroutine no_segments_is_a_straight

  function seg(kind, length, curvature, superelevation, origin) result(s)
    character(len=*), intent(in) :: kind, origin
    real(wp), intent(in) :: length, curvature, superelevation
    type(segment_spec_t) :: s
    s%kind = kind
    s%length = length
    s%curvature_end = curvature
    s%superelevation_end = superelevation
    s%origin = origin
  end function seg

  subroutine expect(settings, specs, fragments, what)
    type(track_settings_t), intent(in) :: settings
    type(segment_spec_t), intent(in) :: specs(:)
    character(len=*), intent(in) :: fragments(:), what
    type(track_t) :: track
    type(error_t), allocatable :: error
    integer :: k
    call build_track(track, settings, specs, error)
    if (.not. allocated(error)) then
      call fail()
      print '(a)', 'FAIL: no error for ' // what
      return
    end if
    print '(a)', what // ' -> ' // error%message
    if (error%code /= RD_ERR_INPUT) then
      call fail()
      print '(a)', 'FAIL: error code is not RD_ERR_INPUT for ' // what
    end if
    do k = 1, size(fragments)
      if (index(error%message, trim(fragments(k))) == 0) then
        call fail()
        print '(a)', 'FAIL: message for ' // what // ' lacks "' // trim(fragments(k)) // '"'
      end if
    end do
    if (index(error%message, trim(fragments(1))) /= 1) then
      call fail()
      print '(a)', 'FAIL: message for ' // what // ' does not start with its origin'
    end if
  end subroutine expect
end program test_track_errors
