!> Track irregularities (rd_track_irregularity): interpolation, scale and fade against
!> closed forms written here, the per-rail offsets against the definitions of the four
!> components (docs/conventions.md: gauge = dy_L - dy_R, cross-level = dz_L - dz_R,
!> alignment and level the means), and every malformed file giving path:line and what
!> is expected.
program test_track_irregularity
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_kinds, only: wp
  use test_files, only: scratch_name, write_file, delete_file
  use rd_error, only: error_t, RD_ERR_INPUT, RD_ERR_IO
  use rd_track_irregularity, only: track_irregularity_t, build_track_irregularity, read_irregularity_file
  use rd_test_support, only: check, fail, test_summary
  implicit none

  call test_interpolation()
  call test_rail_offsets()
  call test_fade_and_scale()
  call test_reader()
  call test_file_errors()
  call test_build_errors()

  call test_summary('test_track_irregularity')

contains

  !> Knots of a piecewise-linear closed form f_j(s) = |s - 12| c_j + d_j (kink at 12 m, a
  !> knot): linear interpolation reproduces it exactly at any sigma inside the range.
  subroutine test_interpolation()
    type(track_irregularity_t) :: irr
    type(error_t), allocatable :: error
    real(wp), parameter :: knots(5) = [0.0_wp, 5.0_wp, 12.0_wp, 20.5_wp, 40.0_wp]
    real(wp), parameter :: outside(3) = [-1.0e-9_wp, 40.0_wp + 1.0e-9_wp, 1.0e4_wp]
    real(wp) :: values(4, 5), s, got(4), err
    integer :: k, j
    do k = 1, 5
      values(:, k) = exact(knots(k))
    end do
    call build_track_irregularity(irr, knots, values, error)
    call require_ok(error, 'interpolation: build')
    err = 0
    do k = 0, 400
      s = 40.0_wp * k / 400
      got = irr%components(s)
      err = max(err, maxval(abs(got - exact(s))))
    end do
    call check(err <= 1.0e-17_wp, 'interpolation equals the piecewise-linear closed form', err)
    ! zero outside the record, also just outside
    err = 0
    do j = 1, 3
      err = max(err, maxval(abs(irr%components(outside(j)))))
    end do
    call check(err == 0, 'zero outside [sigma_1, sigma_n]', err)
    call check(maxval(abs(irr%components(40.0_wp) - exact(40.0_wp))) == 0, 'last point included', 0.0_wp)
    call check(maxval(abs(irr%components(0.0_wp) - exact(0.0_wp))) == 0, 'first point included', 0.0_wp)
  end subroutine test_interpolation

  pure function exact(s) result(f)
    real(wp), intent(in) :: s
    real(wp) :: f(4)
    real(wp), parameter :: c(4) = [1.0e-4_wp, -2.0e-4_wp, 5.0e-5_wp, 3.0e-5_wp]
    real(wp), parameter :: d(4) = [-1.0e-3_wp, 2.0e-3_wp, 0.0_wp, 4.0e-3_wp]
    f = abs(s - 12) * c + d
  end function exact

  !> One component at a time: the offsets of the two rails must give back the component by
  !> its definition (EN 13848-1): alignment = mean lateral, level = mean vertical, gauge =
  !> left minus right lateral (left rail at +Y), cross-level = left minus right vertical.
  subroutine test_rail_offsets()
    type(track_irregularity_t) :: irr
    type(error_t), allocatable :: error
    real(wp) :: values(4, 2), off(2, 2), comp(4)
    character(len=11), parameter :: names(4) = ['alignment  ', 'level      ', 'cross_level', 'gauge      ']
    integer :: j
    do j = 1, 4
      values = 0
      values(j, :) = 3.0e-3_wp
      call build_track_irregularity(irr, [0.0_wp, 10.0_wp], values, error)
      call require_ok(error, 'rail offsets: build')
      off = irr%rail_offsets(5.0_wp)
      comp = [0.5_wp * (off(1, 1) + off(1, 2)), 0.5_wp * (off(2, 1) + off(2, 2)), &
              off(2, 1) - off(2, 2), off(1, 1) - off(1, 2)]
      call check(maxval(abs(comp - values(:, 1))) <= 1.0e-18_wp, 'rail offsets reproduce component ' // &
                 trim(names(j)), maxval(abs(comp - values(:, 1))))
    end do
    ! signs spelled out: gauge widening moves the left rail to +Y and the right rail to -Y;
    ! cross-level + lifts the left rail
    values = 0
    values(4, :) = 2.0e-3_wp
    call build_track_irregularity(irr, [0.0_wp, 10.0_wp], values, error)
    off = irr%rail_offsets(1.0_wp)
    call check(off(1, 1) == 1.0e-3_wp .and. off(1, 2) == -1.0e-3_wp .and. all(off(2, :) == 0), &
               'gauge +2 mm: left rail +1 mm, right rail -1 mm laterally', off(1, 1))
    values = 0
    values(3, :) = 2.0e-3_wp
    call build_track_irregularity(irr, [0.0_wp, 10.0_wp], values, error)
    off = irr%rail_offsets(1.0_wp)
    call check(off(2, 1) == 1.0e-3_wp .and. off(2, 2) == -1.0e-3_wp .and. all(off(1, :) == 0), &
               'cross-level +2 mm: left rail up 1 mm, right rail down 1 mm', off(2, 1))
  end subroutine test_rail_offsets

  !> Constant record a on [0, 100] m, fade 10 m, scale 0.5: the closed form is
  !> 0.5 a min(1, s/10, (100 - s)/10).
  subroutine test_fade_and_scale()
    type(track_irregularity_t) :: irr
    type(error_t), allocatable :: error
    real(wp) :: values(4, 3), a(4), s, err, ramp
    integer :: k
    a = [1.0e-3_wp, -2.0e-3_wp, 3.0e-3_wp, 4.0e-3_wp]
    do k = 1, 3
      values(:, k) = a
    end do
    call build_track_irregularity(irr, [0.0_wp, 50.0_wp, 100.0_wp], values, error, scale=0.5_wp, fade=10.0_wp)
    call require_ok(error, 'fade: build')
    err = 0
    do k = 0, 1000
      s = -5 + 110.0_wp * k / 1000
      ramp = 0
      if (s >= 0 .and. s <= 100) ramp = min(1.0_wp, s / 10, (100 - s) / 10)
      err = max(err, maxval(abs(irr%components(s) - 0.5_wp * ramp * a)))
    end do
    call check(err <= 1.0e-17_wp, 'fade-in, fade-out and scale against the closed form', err)
    call check(maxval(abs(irr%components(2.5_wp) - 0.125_wp * a)) <= 1.0e-17_wp, 'quarter of the fade', err)
    ! no fade: full value at the first point
    call build_track_irregularity(irr, [0.0_wp, 50.0_wp, 100.0_wp], values, error)
    call check(all(irr%components(0.0_wp) == a), 'no fade: full offset from the first point', 0.0_wp)
  end subroutine test_fade_and_scale

  subroutine test_reader()
    character(len=:), allocatable :: path
    real(wp), allocatable :: sigma(:), values(:, :)
    type(error_t), allocatable :: error
    path = scratch_name('irregularity')
    call write_file(path, [character(len=80) :: '# sigma_m alignment_m level_m cross_level_m gauge_m', '', &
                    '0.0  0.001 -0.002 0.0005 0.0  # first', '2.5, 0.0015, -0.001, 0, 0.002' // char(13), &
                    '   # a comment line', '5.0' // char(9) // '0 0 0 -0.003'])
    call read_irregularity_file(path, sigma, values, error)
    call require_ok(error, 'reader: valid file')
    if (.not. allocated(error)) then
      call check(size(sigma) == 3, 'reader: 3 data lines', real(size(sigma), wp))
      call check(all(sigma == [0.0_wp, 2.5_wp, 5.0_wp]), 'reader: sigma column', 0.0_wp)
      call check(all(values(:, 1) == [0.001_wp, -0.002_wp, 0.0005_wp, 0.0_wp]) .and. &
                 all(values(:, 2) == [0.0015_wp, -0.001_wp, 0.0_wp, 0.002_wp]) .and. &
                 all(values(:, 3) == [0.0_wp, 0.0_wp, 0.0_wp, -0.003_wp]), 'reader: offset columns', 0.0_wp)
    end if
    call delete_file(path)
  end subroutine test_reader

  !> Each malformed case: RD_ERR_INPUT naming path:line and what is expected.
  subroutine test_file_errors()
    character(len=:), allocatable :: path
    character(len=*), parameter :: ok1 = '0 0 0 0 0', ok2 = '1 0 0 0 0'
    path = scratch_name('irregularity')
    call expect_file(path, [character(len=60) :: '# header', ok1, '1 0 abc 0 0', '2 0 0 0 0'], ':3:', &
                     'column 3 "abc" is not a number', 'non-numeric')
    call expect_file(path, [character(len=60) :: ok1, ok2, '2 0 0 0'], ':3:', '4 columns, expected 5', 'four columns')
    call expect_file(path, [character(len=60) :: ok1, '1 0 0 0 0 0', '2 0 0 0 0'], ':2:', '6 columns, expected 5', &
                     'six columns')
    call expect_file(path, [character(len=60) :: ok1, ok2, '# gap', '1 0 0 0 0'], ':4:', 'does not increase (line 2', &
                     'repeated sigma')
    call expect_file(path, [character(len=60) :: ok1, ok2, '0.5 0 0 0 0'], ':3:', 'strictly increasing', &
                     'decreasing sigma')
    call expect_file(path, [character(len=60) :: ok1, '1 0 NaN 0 0'], ':2:', 'column 3 is not finite', 'NaN')
    call expect_file(path, [character(len=60) :: ok1, '1 0 0 0 -Infinity'], ':2:', 'column 5 is not finite', 'Inf')
    call expect_file(path, [character(len=60) :: ok1, '1 2.5 0 0 0'], ':2:', 'in metres (millimetres given?)', &
                     'millimetres')
    call expect_file(path, [character(len=60) :: ok1, '1 0 0 0 3*0.0'], ':2:', 'is not a number', 'repeat count')
    call expect_file(path, [character(len=60) :: '# only one line', ok1], '', 'at least 2 are needed', 'one data line')
    call delete_file(path)
    block
      real(wp), allocatable :: sigma(:), values(:, :)
      type(error_t), allocatable :: error
      call read_irregularity_file(path, sigma, values, error)
      call check_message(error, RD_ERR_IO, 'missing file', path, 'cannot open irregularity file')
    end block
  end subroutine test_file_errors

  subroutine expect_file(path, lines, where, what, label)
    character(len=*), intent(in) :: path, lines(:), where, what, label
    real(wp), allocatable :: sigma(:), values(:, :)
    type(error_t), allocatable :: error
    call write_file(path, lines)
    call read_irregularity_file(path, sigma, values, error)
    call check_message(error, RD_ERR_INPUT, label, path // where, what)
  end subroutine expect_file

  subroutine test_build_errors()
    type(track_irregularity_t) :: irr
    type(error_t), allocatable :: error
    real(wp) :: values(4, 3), nan
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    values = 0
    call build_track_irregularity(irr, [0.0_wp, 1.0_wp, 1.0_wp], values, error, origin='deck.nml:3')
    call check_message(error, RD_ERR_INPUT, 'build: repeated sigma', 'deck.nml:3', 'point 3', 'strictly increasing')
    values(2, 2) = nan
    call build_track_irregularity(irr, [0.0_wp, 1.0_wp, 2.0_wp], values, error, origin='deck.nml:3')
    call check_message(error, RD_ERR_INPUT, 'build: NaN', 'deck.nml:3', 'finite')
    values = 0
    values(1, 3) = -0.2_wp
    call build_track_irregularity(irr, [0.0_wp, 1.0_wp, 2.0_wp], values, error, origin='deck.nml:3')
    call check_message(error, RD_ERR_INPUT, 'build: 0.2 m', 'point 3', 'in metres')
    values = 0
    call build_track_irregularity(irr, [0.0_wp, 1.0_wp, 2.0_wp], values, error, scale=-1.0_wp)
    call check_message(error, RD_ERR_INPUT, 'build: negative scale', 'scale', '>= 0')
    call build_track_irregularity(irr, [0.0_wp, 1.0_wp, 2.0_wp], values, error, fade=nan)
    call check_message(error, RD_ERR_INPUT, 'build: NaN fade', 'fade', '>= 0 m')
    call build_track_irregularity(irr, [0.0_wp], values(:, 1:1), error)
    call check_message(error, RD_ERR_INPUT, 'build: one point', '1 points', 'at least 2')
  end subroutine test_build_errors

  ! ------------------------------------------------------------------ helpers

  subroutine require_ok(error, label)
    type(error_t), allocatable, intent(in) :: error
    character(len=*), intent(in) :: label
    if (allocated(error)) then
      print '(a)', 'FAIL ' // label // ': ' // error%message
      call fail()
    end if
  end subroutine require_ok

  subroutine check_message(error, code, label, p1, p2, p3)
    type(error_t), allocatable, intent(in) :: error
    integer, intent(in) :: code
    character(len=*), intent(in) :: label, p1, p2
    character(len=*), intent(in), optional :: p3
    logical :: ok
    if (.not. allocated(error)) then
      print '(a)', 'FAIL ' // label // ': no error'
      call fail()
      return
    end if
    ok = error%code == code .and. index(error%message, p1) > 0 .and. index(error%message, p2) > 0
    if (present(p3)) ok = ok .and. index(error%message, p3) > 0
    ! one line
    ok = ok .and. index(error%message, new_line('a')) == 0
    if (ok) then
      print '(a)', 'ok   ' // label // ': ' // error%message
    else
      print '(a)', 'FAIL ' // label // ': ' // error%message
      call fail()
    end if
  end subroutine check_message
end program test_track_irregularity
