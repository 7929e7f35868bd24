!> Fresnel integrals C(x), S(x) against published high-precision values and against an
!> independent quad-precision quadrature written here.
!>
!> Reference values: mpmath 1.2.1 fresnelc/fresnels at 30 significant digits (same
!> normalisation as A&S 7.3.1-7.3.2; C(1), S(1) also agree with A&S table 7.7).
program test_fresnel
  use, intrinsic :: iso_fortran_env, only: real128
  use rd_kinds, only: wp
  use rd_fresnel, only: fresnel_integrals, fresnel_aux, fresnel_phase
  use rd_test_support, only: fail, test_summary
  implicit none
  integer, parameter :: qp = real128
  integer, parameter :: n_ref = 10
  real(wp), parameter :: xs(n_ref) = [0.1_wp, 0.5_wp, 1.0_wp, 1.5_wp, 2.0_wp, 2.5_wp, 5.0_wp, &
                                      10.0_wp, 50.0_wp, 1000.0_wp]
  real(wp), parameter :: c_ref(n_ref) = [0.099997532627085073601_wp, 0.49234422587144639288_wp, &
    0.77989340037682282947_wp, 0.44526117603982153506_wp, 0.4882534060753407545_wp, &
    0.45741300964177704525_wp, 0.5636311887040122311_wp, 0.49989869420551572361_wp, &
    0.49999918943072796796_wp, 0.49999999989867881636_wp]
  real(wp), parameter :: s_ref(n_ref) = [0.00052358954761221068668_wp, 0.064732432859999277611_wp, &
    0.43825914739035476608_wp, 0.69750496008209301308_wp, 0.3434156783636982422_wp, &
    0.61918175581959293611_wp, 0.49919138191711688675_wp, 0.4681699785848822404_wp, &
    0.49363380258593874145_wp, 0.49968169011381630608_wp]
  real(wp) :: c, s, c_minus, s_minus, worst, x, err
  real(qp) :: cq, sq
  complex(wp) :: f_from_aux
  integer :: i

  worst = 0
  do i = 1, n_ref
    call fresnel_integrals(xs(i), c, s)
    err = max(abs(c - c_ref(i)) / abs(c_ref(i)), abs(s - s_ref(i)) / abs(s_ref(i)))
    worst = max(worst, err)
    if (err > 1.0e-14_wp) then
      print '(a,f8.2,2(a,es24.16),a,es9.2)', 'FAIL x=', xs(i), ' C=', c, ' S=', s, ' rel err ', err
      call fail()
    end if
    ! odd symmetry C(-x) = -C(x), S(-x) = -S(x)
    call fresnel_integrals(-xs(i), c_minus, s_minus)
    if (c_minus /= -c .or. s_minus /= -s) then
      print '(a,f8.2)', 'FAIL: odd symmetry at x=', xs(i)
      call fail()
    end if
  end do
  print '(a,es9.2)', 'Fresnel vs mpmath (10 values, 0.1..1000): worst relative error ', worst

  ! dense scan against quad-precision Gauss-Legendre quadrature, crossing the 1.5 switch
  worst = 0
  do i = 0, 160
    x = 0.05_wp * i
    call fresnel_integrals(x, c, s)
    call quad_fresnel(real(x, qp), cq, sq)
    err = max(abs(c - real(cq, wp)), abs(s - real(sq, wp)))
    worst = max(worst, err)
    ! the auxiliary function must reproduce F = (1+i)/2 - G exp(i pi x^2/2)
    f_from_aux = cmplx(0.5_wp, 0.5_wp, wp) - fresnel_aux(x) * fresnel_phase(x)
    err = max(abs(real(f_from_aux, wp) - real(cq, wp)), abs(aimag(f_from_aux) - real(sq, wp)))
    worst = max(worst, err)
  end do
  print '(a,es9.2)', 'Fresnel vs real128 quadrature on [0, 8]: worst absolute error ', worst
  if (worst > 2.0e-15_wp) then
    print '(a)', 'FAIL: Fresnel integrals differ from the quadrature'
    call fail()
  end if

  call test_summary('test_fresnel')

contains

  !> Composite 20-point Gauss-Legendre in real128 of cos/sin(pi t^2/2) on [0, x]
  !> with panels of at most 0.05.
  subroutine quad_fresnel(x, c, s)
    real(qp), intent(in) :: x
    real(qp), intent(out) :: c, s
    real(qp), save :: nodes(20), weights(20)
    logical, save :: ready = .false.
    real(qp) :: a, b, t, half_pi
    integer :: panels, p, k
    if (.not. ready) then
      call legendre_qp(nodes, weights)
      ready = .true.
    end if
    half_pi = 2 * atan(1.0_qp)
    c = 0
    s = 0
    if (x == 0) return
    panels = max(1, ceiling(x / 0.05_qp))
    do p = 1, panels
      a = x * (p - 1) / panels
      b = x * p / panels
      do k = 1, 20
        t = 0.5_qp * (a + b) + 0.5_qp * (b - a) * nodes(k)
        c = c + 0.5_qp * (b - a) * weights(k) * cos(half_pi * t * t)
        s = s + 0.5_qp * (b - a) * weights(k) * sin(half_pi * t * t)
      end do
    end do
  end subroutine quad_fresnel

  subroutine legendre_qp(x, w)
    real(qp), intent(out) :: x(20), w(20)
    real(qp) :: z, z1, p1, p2, p3, dp, pq
    integer :: i, j, n, it
    n = 20
    pq = 4 * atan(1.0_qp)
    do i = 1, n / 2
      z = cos(pq * (i - 0.25_qp) / (n + 0.5_qp))
      do it = 1, 100
        p1 = 1; p2 = 0
        do j = 1, n
          p3 = p2; p2 = p1
          p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j
        end do
        dp = n * (z * p1 - p2) / (z * z - 1)
        z1 = z
        z = z1 - p1 / dp
        if (abs(z - z1) < 1.0e-32_qp) exit
      end do
      x(i) = -z; x(n + 1 - i) = z
      w(i) = 2 / ((1 - z * z) * dp * dp); w(n + 1 - i) = w(i)
    end do
  end subroutine legendre_qp
end program test_fresnel
