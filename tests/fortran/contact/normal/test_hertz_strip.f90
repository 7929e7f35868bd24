!> The Hertz strip stiffness (rd_hertz_strip) against closed forms written here:
!> 1. B = A (circular patch): K(0) = E(0) = pi/2 and m = 1, so G = (2 pi / (pi/2))^(3/2) = 8
!>    and phi = 8 sqrt(1/2) / 16 = 1 / (2 sqrt 2).
!> 2. A Hertzian gap sampled by strips: for an elliptic patch of semi-axes a >= b
!>    (eccentricity e, peak pressure p0) Johnson's Contact Mechanics (1985) eqs. 4.39-4.41
!>    give the relative curvatures A (along a) = p0 b (K - E) / (E* a^2 e^2),
!>    B (along b) = p0 b ((a/b)^2 E - K) / (E* a^2 e^2), the approach delta0 = p0 b K / E* and
!>    the load N = (2/3) pi a b p0 (K, E the complete elliptic integrals of modulus e),
!>    scaled so that the smaller curvature is 1.1 1/m (a wheel's rolling one). Strips
!>    across either axis with depths delta0 - C s^2 (C the curvature across the strips) must
!>    carry N and store (2/5) N delta0, summed interval by interval (interval_energy: the
!>    strips' loads are its derivatives), within 5e-4: the smooth curvature floor moves each
!>    curvature k by ~f^2 / k (f = 0.025 1/m: 5e-4 of 1.1 1/m) and phi by about 0.4 times
!>    that (measured 2.0e-4), the strips' sampling of the parabola adds less.
!> 3. phi's partial derivatives against central differences; phi finite, positive and
!>    continuous through conformal (B -> 0) and concave (B < 0) gaps.
!> 4. The interval energy (the strips' quadrature of int c delta_+^2 ds): against a
!>    numerical integral of the positive part of the linear depth, its derivatives against
!>    differences, and C2 where the contact edge enters the interval.
program test_hertz_strip
  use rd_kinds, only: wp, pi
  use rd_elliptic_integrals, only: elliptic_ke
  use rd_hertz_strip, only: fill_strip_stiffness_table, strip_stiffness, interval_energy
  use rd_test_support, only: check, check_close, test_summary
  implicit none
  real(wp), parameter :: e_star = 1.15e11_wp
  !> B / A of the derivative checks
  !> the second depth b of the interval-energy checks (a = 20 um): both in contact, the edge
  !> near b, b out of contact, b on the edge
  real(wp), parameter :: b_cases(6) = [3.0e-5_wp, 2.0e-5_wp, 1.0e-6_wp, -1.0e-5_wp, -4.0e-5_wp, 0.0_wp]
  real(wp), parameter :: ratios(7) = [1.0e-3_wp, 0.05_wp, 0.3_wp, 1.0_wp, 4.0_wp, 60.0_wp, 2000.0_wp]
  real(wp) :: phi, dpa, dpb, ecc(5), worst_n, worst_u, worst_d, pp, pm, h, s0, s1, ds0, ds1, t, prev
  integer :: k, across, i
  logical :: ok

  call fill_strip_stiffness_table()

  call strip_stiffness(1.3_wp, 1.3_wp, phi, dpa, dpb)
  call check_close(phi, 1 / (2 * sqrt(2.0_wp)), 1.0e-9_wp, 'circular patch: phi = 1 / (2 sqrt 2)')

  ! Hertzian gaps from Johnson's closed forms, strips across the minor and the major axis
  ecc = [0.3_wp, 0.7_wp, 0.9_wp, 0.98_wp, 0.999_wp]
  worst_n = 0; worst_u = 0
  do k = 1, size(ecc)
    do across = 1, 2
      call strip_sum(ecc(k), across == 1)
    end do
  end do
  print '(a,2es10.2)', 'Hertzian gaps: worst relative error of the strip sums (force, energy) ', worst_n, worst_u
  call check(worst_n < 5.0e-4_wp, 'strip sum of a Hertzian gap = Hertz load (Johnson 4.39-4.41), 5 shapes x 2 directions')
  call check(worst_u < 5.0e-4_wp, 'strip energy of a Hertzian gap = (2/5) N delta0')

  ! derivatives against central differences
  worst_d = 0
  do k = 1, size(ratios)
    associate (a => 1.1_wp, b => 1.1_wp * ratios(k))
      call strip_stiffness(a, b, phi, dpa, dpb)
      h = 1.0e-6_wp * a
      call strip_stiffness(a + h, b, pp, s0, s1); call strip_stiffness(a - h, b, pm, s0, s1)
      worst_d = max(worst_d, abs((pp - pm) / (2 * h) - dpa) / (abs(dpa) + 1.0e-6_wp * phi / a))
      h = 1.0e-6_wp * b
      call strip_stiffness(a, b + h, pp, s0, s1); call strip_stiffness(a, b - h, pm, s0, s1)
      worst_d = max(worst_d, abs((pp - pm) / (2 * h) - dpb) / (abs(dpb) + 1.0e-6_wp * phi / b))
    end associate
  end do
  print '(a,es10.2)', 'phi derivatives: worst relative difference to central differences ', worst_d
  call check(worst_d < 1.0e-5_wp, 'phi partial derivatives = central differences')

  ! conformal and concave gaps: finite, positive, continuous (the smooth curvature floor)
  ok = .true.
  prev = -1
  do i = 0, 400
    call strip_stiffness(1.1_wp, 0.5_wp - 1.0e-3_wp * i * 2.5_wp, phi, dpa, dpb)
    ok = ok .and. phi > 0 .and. phi < 1 .and. abs(dpa) < huge(1.0_wp) .and. abs(dpb) < huge(1.0_wp)
    if (prev > 0) ok = ok .and. abs(phi - prev) < 0.01_wp * prev
    prev = phi
  end do
  call check(ok, 'phi positive, finite and continuous from B = 0.5 to B = -0.5 1/m (A = 1.1 1/m)')

  ! the interval energy against a numerical integral of the positive part, and its
  ! continuity where the contact edge enters the interval (b through 0)
  worst_d = 0
  do i = 1, 6
    t = b_cases(i)
    call interval_energy(2.0e-5_wp, t, 2.0e-4_wp, s0, pp, pm)
    worst_d = max(worst_d, abs(s0 - positive_part_integral(2.0e-5_wp, t, 2.0e-4_wp)) / (2.0e-4_wp * 4.0e-10_wp))
    ! derivatives by central differences
    h = 1.0e-9_wp
    call interval_energy(2.0e-5_wp + h, t, 2.0e-4_wp, s1, ds0, ds1)
    call interval_energy(2.0e-5_wp - h, t, 2.0e-4_wp, prev, ds0, ds1)
    worst_d = max(worst_d, abs((s1 - prev) / (2 * h) - pp) / (2.0e-4_wp * 2.0e-5_wp))
    call interval_energy(2.0e-5_wp, t + h, 2.0e-4_wp, s1, ds0, ds1)
    call interval_energy(2.0e-5_wp, t - h, 2.0e-4_wp, prev, ds0, ds1)
    worst_d = max(worst_d, abs((s1 - prev) / (2 * h) - pm) / (2.0e-4_wp * 2.0e-5_wp))
  end do
  print '(a,es10.2)', 'interval energy: worst relative difference to the integral and its differences ', worst_d
  call check(worst_d < 1.0e-6_wp, 'interval energy = h int ((1-t) a + t b)_+^2 dt, derivatives = its differences')
  ! C2 across b = 0: q, q_a, q_b and the second derivative by b on either side
  h = 1.0e-12_wp
  call interval_energy(2.0e-5_wp, -h, 2.0e-4_wp, s0, ds0, pm)
  call interval_energy(2.0e-5_wp, h, 2.0e-4_wp, s1, ds1, pp)
  ok = abs(s1 - s0) < 1.0e-6_wp * s1 .and. abs(ds1 - ds0) < 1.0e-6_wp * ds1 .and. abs(pp - pm) < 1.0e-6_wp * pp
  call interval_energy(2.0e-5_wp, -1.0e-9_wp, 2.0e-4_wp, s0, ds0, pm)
  call interval_energy(2.0e-5_wp, -2.0e-9_wp, 2.0e-4_wp, s0, ds0, prev)
  call interval_energy(2.0e-5_wp, 1.0e-9_wp, 2.0e-4_wp, s1, ds1, pp)
  call interval_energy(2.0e-5_wp, 2.0e-9_wp, 2.0e-4_wp, s1, ds1, t)
  ok = ok .and. abs((pm - prev) / 1.0e-9_wp - (t - pp) / 1.0e-9_wp) < 1.0e-3_wp * abs((t - pp) / 1.0e-9_wp)
  call interval_energy(-1.0e-6_wp, -2.0e-6_wp, 2.0e-4_wp, s0, ds0, ds1)
  ok = ok .and. s0 == 0 .and. ds0 == 0 .and. ds1 == 0
  call check(ok, 'interval energy C2 where the contact edge enters the interval, zero out of contact')
  call test_summary('test_hertz_strip')

contains

  !> Strip sums over the Hertzian gap of eccentricity e (a = 6 mm, p0 = 1 GPa), strips
  !> across the minor axis (lateral curvature B) or the major one (A).
  subroutine strip_sum(e, across_minor)
    real(wp), intent(in) :: e
    logical, intent(in) :: across_minor
    integer, parameter :: n = 400
    real(wp), parameter :: a = 6.0e-3_wp, p0 = 1.0e9_wp
    real(wp) :: b, kk, ee, scale, ca, cb, delta0, load, c_across, c_along, half, w, s, f, u, d, sd, q, qa, qb
    integer :: j
    b = a * sqrt(1 - e * e)
    call elliptic_ke(sqrt(1 - e * e), kk, ee)     ! (its argument: the complementary modulus)
    ca = p0 * b * (kk - ee) / (e_star * a * a * e * e)
    cb = p0 * b * ((a / b)**2 * ee - kk) / (e_star * a * a * e * e)
    delta0 = p0 * b * kk / e_star
    load = 2.0_wp / 3 * pi * a * b * p0
    ! scaled (p0 with it) so that the smaller curvature is a wheel's rolling one, 1.1 1/m:
    ! all four are proportional to p0 at fixed a and b
    scale = 1.1_wp / min(ca, cb)
    ca = scale * ca; cb = scale * cb; delta0 = scale * delta0; load = scale * load
    if (across_minor) then
      c_across = cb; c_along = ca
    else
      c_across = ca; c_along = cb
    end if
    call strip_stiffness(c_along, c_across, phi, dpa, dpb)
    half = sqrt(delta0 / c_across)
    ! strips 2 half / n apart across the patch and one beyond each edge, summed interval by
    ! interval (the load: sum of the derivatives by each strip's depth)
    w = 2 * half / n
    f = 0; u = 0
    do j = 0, n
      s = -half - 0.5_wp * w + j * w
      d = delta0 - c_across * s * s
      sd = delta0 - c_across * (s + w)**2
      call interval_energy(d, sd, w, q, qa, qb)
      f = f + phi * (qa + qb) * e_star
      u = u + phi * q * e_star
    end do
    worst_n = max(worst_n, abs(f / load - 1))
    worst_u = max(worst_u, abs(u / (0.4_wp * load * delta0) - 1))
  end subroutine strip_sum

  !> h int_0^1 ((1-t) a + t b)_+^2 dt by the midpoint rule on 20 000 points
  real(wp) function positive_part_integral(a, b, h) result(q)
    real(wp), intent(in) :: a, b, h
    integer :: k
    real(wp) :: t, v
    q = 0
    do k = 1, 20000
      t = (k - 0.5_wp) / 20000
      v = max((1 - t) * a + t * b, 0.0_wp)
      q = q + v * v / 20000
    end do
    q = h * q
  end function positive_part_integral

end program test_hertz_strip
