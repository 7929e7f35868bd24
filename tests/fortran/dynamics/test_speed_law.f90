!> Speed law: distance s(t) against the exact integral of a piecewise-linear speed
!> (closed form per segment, written here), acceleration, and the run-time override.
program test_speed_law
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_speed_law, only: speed_law_t, constant_speed, table_speed
  use rd_test_support, only: check, test_summary
  implicit none
  type(speed_law_t) :: law
  type(error_t), allocatable :: error
  real(wp) :: t, s_exact, err
  integer :: i
  character(len=80) :: buf

  law = constant_speed(25.0_wp)
  call check(abs(law%distance(3.0_wp) - 75.0_wp) < 1e-12_wp, 'constant: s = V t')
  call check(law%acceleration(3.0_wp) == 0, 'constant: a = 0')

  ! V: 10 m/s until t = 1, ramps to 40 m/s at t = 4, then constant
  call table_speed(law, [1.0_wp, 4.0_wp], [10.0_wp, 40.0_wp], error)
  call check(.not. allocated(error), 'table accepted')
  err = 0
  do i = 0, 60
    t = 0.1_wp * i
    if (t <= 1) then
      s_exact = 10 * t
    else if (t <= 4) then
      s_exact = 10 + 10 * (t - 1) + 0.5_wp * 10 * (t - 1)**2
    else
      s_exact = 10 + 30 + 45 + 40 * (t - 4)
    end if
    err = max(err, abs(law%distance(t) - s_exact))
  end do
  write (buf, '(a,es9.2)') 'max error ', err
  call check(err < 1e-12_wp, 'table: s(t) exact for a ramp', detail=trim(buf))
  call check(abs(law%speed(2.5_wp) - 25.0_wp) < 1e-12_wp, 'table: V mid-ramp')
  call check(abs(law%acceleration(2.0_wp) - 10.0_wp) < 1e-12_wp, 'table: a on the ramp')
  call check(law%acceleration(5.0_wp) == 0, 'table: a after')

  call table_speed(law, [1.0_wp, 1.0_wp], [10.0_wp, 40.0_wp], error)
  call check(allocated(error), 'table: repeated times rejected')

  ! override at t = 2 (V = 20, s = 10 + 10 + 5 = 25): step to 30 m/s
  call table_speed(law, [1.0_wp, 4.0_wp], [10.0_wp, 40.0_wp], error)
  call law%override(2.0_wp, 30.0_wp, error=error)
  call check(.not. allocated(error), 'override accepted')
  call check(abs(law%distance(1.5_wp) - (10 + 5 + 1.25_wp)) < 1e-12_wp, 'override: past unchanged')
  call check(abs(law%speed(2.5_wp) - 30.0_wp) < 1e-12_wp, 'override: step speed')
  call check(abs(law%distance(3.0_wp) - (25 + 30)) < 1e-12_wp, 'override: s continuous and linear after')
  ! ramp override at t = 3 from 30 to 0 in 2 s
  call law%override(3.0_wp, 0.0_wp, 2.0_wp, error)
  call check(abs(law%distance(6.0_wp) - (55 + 30)) < 1e-12_wp, 'ramp override: s')
  call check(abs(law%acceleration(4.0_wp) + 15.0_wp) < 1e-12_wp, 'ramp override: a')
  call law%override(3.0_wp, 0.0_wp, -1.0_wp, error)
  call check(allocated(error), 'negative ramp rejected')

  call test_summary('test_speed_law')
end program test_speed_law
