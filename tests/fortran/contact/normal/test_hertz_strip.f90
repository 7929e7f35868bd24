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
!>    carry sum w phi s'(delta_i) E* = N and store sum w phi s(delta_i) E* = (2/5) N delta0,
!>    within 5e-4: the smooth curvature floor moves each curvature k by ~f^2 / k (f = 0.025
!>    1/m: 5e-4 of 1.1 1/m) and phi by about 0.4 times that (measured 2.0e-4; without the
!>    floor 3e-6, the strips' sampling and the onset easing).
!> 3. phi's partial derivatives against central differences; phi finite, positive and
!>    continuous through conformal (B -> 0) and concave (B < 0) gaps.
!> 4. The eased onset s(delta): C2 at the onset depth, s' > 0 and s <= delta^2 below it.
program test_hertz_strip
  use rd_kinds, only: wp, pi
  use rd_elliptic_integrals, only: elliptic_ke
  use rd_hertz_strip, only: fill_strip_stiffness_table, strip_stiffness, strip_depth_energy, strip_onset_depth
  use rd_test_support, only: check, check_close, test_summary
  implicit none
  real(wp), parameter :: e_star = 1.15e11_wp
  !> B / A of the derivative checks
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

  ! the eased onset: C2 at the onset depth, monotone, below delta^2
  h = 1.0e-4_wp * strip_onset_depth
  call strip_depth_energy(strip_onset_depth - h, s0, ds0)
  call strip_depth_energy(strip_onset_depth + h, s1, ds1)
  call check(abs(s1 - s0 - 2 * strip_onset_depth * 2 * h) < 1.0e-6_wp * strip_onset_depth**2 .and. &
             abs((ds1 - ds0) / (2 * h) - 2) < 1.0e-3_wp, 'onset easing: s, s'' and s'''' continuous at the onset depth')
  ok = .true.
  do i = 1, 200
    t = i * strip_onset_depth / 200
    call strip_depth_energy(t, s0, ds0)
    call strip_depth_energy(t + h, s1, ds1)
    ok = ok .and. ds0 > 0 .and. s0 <= t * t * (1 + 1.0e-12_wp) .and. ds1 >= ds0
  end do
  call strip_depth_energy(0.0_wp, s0, ds0)
  ok = ok .and. s0 == 0 .and. ds0 == 0
  call strip_depth_energy(-1.0e-6_wp, s0, ds0)
  ok = ok .and. s0 == 0 .and. ds0 == 0
  call check(ok, 'onset easing: s'' > 0 and growing, s <= delta^2, zero out of contact')
  call test_summary('test_hertz_strip')

contains

  !> Strip sums over the Hertzian gap of eccentricity e (a = 6 mm, p0 = 1 GPa), strips
  !> across the minor axis (lateral curvature B) or the major one (A).
  subroutine strip_sum(e, across_minor)
    real(wp), intent(in) :: e
    logical, intent(in) :: across_minor
    integer, parameter :: n = 400
    real(wp), parameter :: a = 6.0e-3_wp, p0 = 1.0e9_wp
    real(wp) :: b, kk, ee, scale, ca, cb, delta0, load, c_across, c_along, half, w, s, f, u, d, sd, dsd
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
    w = 2 * half / n
    f = 0; u = 0
    do j = 1, n
      s = -half + (j - 0.5_wp) * w
      d = delta0 - c_across * s * s
      call strip_depth_energy(d, sd, dsd)
      f = f + w * phi * dsd * e_star
      u = u + w * phi * sd * e_star
    end do
    worst_n = max(worst_n, abs(f / load - 1))
    worst_u = max(worst_u, abs(u / (0.4_wp * load * delta0) - 1))
  end subroutine strip_sum

end program test_hertz_strip
