!> The natural splines of rd_natural_splines (the smooth wheel of the distributed strip force
!> and the curvature / stiffness tables). Oracle: the smoothness each spline promises, checked
!> at every interior point from the two neighbouring pieces' own polynomials (written out
!> here from the piece formulas, not taken from the library): the cubic's S' and S''
!> continuous, the quintic's S', S'' , S''' and S'''' continuous; both through every point;
!> and, on f = sin(3 x) + 0.3 x^2 sampled at uneven points, the interpolation error in the
!> middle of the range (away from the natural ends' M = P = 0, which f does not satisfy) far
!> below the cubic's, as a higher order should give.
program test_natural_splines
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_natural_splines, only: natural_spline, natural_quintic_spline
  use rd_test_support, only: check_within, test_summary
  implicit none
  integer, parameter :: n = 41
  real(wp) :: x(n), f(n), jump(4), jump3(2), err5, err3, scale, d4(4)
  real(wp), allocatable :: m(:), p(:), mc(:)
  real(wp) :: zero_p(n) = 0
  type(error_t), allocatable :: error
  integer :: i, k
  do i = 1, n
    ! uneven spacing: 0.05 +- 40 %
    x(i) = 0.05_wp * (i - 1) + 0.02_wp * sin(2.3_wp * i)
  end do
  f = sin(3 * x) + 0.3_wp * x**2
  call natural_quintic_spline(x, f, m, p, error)
  if (allocated(error)) error stop error%message
  call natural_spline(x, f, mc)
  call check_within('quintic: natural ends (M = P = 0), relative', &
                    (abs(m(1)) + abs(m(n))) / maxval(abs(m)) + (abs(p(1)) + abs(p(n))) / maxval(abs(p)), 1.0e-12_wp)

  ! continuity at the interior points: left piece at t = 1 against right piece at t = 0
  jump = 0; jump3 = 0
  do i = 2, n - 1
    jump = max(jump, abs(derivs5(i - 1, 1.0_wp, 4) - derivs5(i, 0.0_wp, 4)))
    jump3 = max(jump3, abs(derivs3(i - 1, 1.0_wp) - derivs3(i, 0.0_wp)))
  end do
  do k = 1, 4
    ! relative to the derivative's largest value at the points
    scale = 0
    do i = 1, n - 1
      d4 = derivs5(i, 0.0_wp, 4)
      scale = max(scale, abs(d4(k)))
    end do
    call check_within('quintic: jump of derivative ' // achar(48 + k) // ' at the points, relative', &
                      jump(k) / scale, 1.0e-9_wp)
  end do
  call check_within('cubic: jump of S'' at the points, relative', jump3(1) / 3, 1.0e-12_wp)
  call check_within('cubic: jump of S'''' at the points, relative', jump3(2) / maxval(abs(mc)), 1.0e-12_wp)

  ! through every point, and the interpolation error in the middle of the range
  do i = 1, n - 1
    call check_within('quintic through the points', abs(spline_value(i, 0.0_wp, m, p) - f(i)), 1.0e-14_wp)
  end do
  err5 = 0; err3 = 0
  do i = 11, n - 11
    do k = 1, 9
      err5 = max(err5, abs(spline_value(i, k / 10.0_wp, m, p) - truth(i, k / 10.0_wp)))
      err3 = max(err3, abs(spline_value(i, k / 10.0_wp, mc, zero_p) - truth(i, k / 10.0_wp)))
    end do
  end do
  print '(a,es10.3,a,es10.3)', '      interpolation error in the middle: quintic ', err5, ', cubic ', err3
  call check_within('quintic: error in the middle of the range, relative to the cubic''s', err5 / err3, 0.05_wp)
  call test_summary('test_natural_splines')

contains

  !> the quintic's derivatives 1..nd (S', S'', S''', S'''') on piece i at t
  function derivs5(i, t, nd) result(d)
    integer, intent(in) :: i, nd
    real(wp), intent(in) :: t
    real(wp) :: d(nd), h, u
    h = x(i + 1) - x(i); u = 1 - t
    d(1) = (f(i + 1) - f(i)) / h + h / 6 * (-(3 * u**2 - 1) * m(i) + (3 * t**2 - 1) * m(i + 1)) &
           + h**3 * (-(u**4 / 24 - u**2 / 12 + 7.0_wp / 360) * p(i) + (t**4 / 24 - t**2 / 12 + 7.0_wp / 360) * p(i + 1))
    if (nd >= 2) d(2) = u * m(i) + t * m(i + 1) + h**2 / 6 * ((u**3 - u) * p(i) + (t**3 - t) * p(i + 1))
    if (nd >= 3) d(3) = (m(i + 1) - m(i)) / h + h / 6 * (-(3 * u**2 - 1) * p(i) + (3 * t**2 - 1) * p(i + 1))
    if (nd >= 4) d(4) = u * p(i) + t * p(i + 1)
  end function derivs5

  !> the spline's value on piece i at t from its second and fourth derivatives mm, pp at the
  !> points (the cubic: pp = 0)
  real(wp) function spline_value(i, t, mm, pp)
    integer, intent(in) :: i
    real(wp), intent(in) :: t, mm(:), pp(:)
    real(wp) :: h, u
    h = x(i + 1) - x(i); u = 1 - t
    spline_value = u * f(i) + t * f(i + 1) + h**2 / 6 * ((u**3 - u) * mm(i) + (t**3 - t) * mm(i + 1)) &
                   + h**4 * ((u**5 / 120 - u**3 / 36 + 7 * u / 360) * pp(i) + (t**5 / 120 - t**3 / 36 + 7 * t / 360) * pp(i + 1))
  end function spline_value

  !> the cubic's S', S'' on piece i at t
  function derivs3(i, t) result(d)
    integer, intent(in) :: i
    real(wp), intent(in) :: t
    real(wp) :: d(2), h, u
    h = x(i + 1) - x(i); u = 1 - t
    d(1) = (f(i + 1) - f(i)) / h + h / 6 * (-(3 * u**2 - 1) * mc(i) + (3 * t**2 - 1) * mc(i + 1))
    d(2) = u * mc(i) + t * mc(i + 1)
  end function derivs3


  real(wp) function truth(i, t)
    integer, intent(in) :: i
    real(wp), intent(in) :: t
    real(wp) :: xx
    xx = x(i) + t * (x(i + 1) - x(i))
    truth = sin(3 * xx) + 0.3_wp * xx**2
  end function truth

end program test_natural_splines
