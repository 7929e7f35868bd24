!> Segment track (rd_track) against independent oracles:
!> - joints: left and right limits (first-order extrapolated) agree at every joint;
!> - arcs: the closed-form circle; clothoids: a real128 Gauss-Legendre quadrature of
!>   (cos, sin) of the quadratic heading, written here;
!> - thesis track and Manchester Track Case 1: L/(2R), asin(h/1.5), 1/R, total length, and
!>   the end of the curve from the clothoid's own power series plus the circle;
!> - invariances: a right curve mirrors a left one, splitting a segment changes nothing;
!> - vertical profile: the parabola z = g0 u + (g1 - g0) u^2/(2L); tangential run-off.
program test_track_segments
  use, intrinsic :: iso_fortran_env, only: real128
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: rot_x, rot_y, rot_z
  use rd_track_point, only: track_point_t
  use rd_track, only: track_t, track_settings_t, segment_spec_t, build_track
  use rd_test_support, only: check, test_summary
  implicit none
  integer, parameter :: qp = real128

  call test_joint_continuity()
  call test_circle()
  call test_clothoids_against_quadrature()
  call test_thesis_and_manchester()
  call test_mirror()
  call test_split()
  call test_vertical_profile_and_run_off()

  call test_summary('test_track_segments')

contains

  function seg(kind, length, curvature, superelevation, ramp, gradient) result(s)
    character(len=*), intent(in) :: kind
    real(wp), intent(in) :: length, curvature, superelevation
    character(len=*), intent(in), optional :: ramp
    real(wp), intent(in), optional :: gradient
    type(segment_spec_t) :: s
    s%kind = kind
    s%length = length
    s%curvature_end = curvature
    s%superelevation_end = superelevation
    if (present(ramp)) s%cant_ramp = ramp
    if (present(gradient)) s%gradient_end = gradient
    s%origin = 'test: ' // kind
  end function seg

  subroutine build_or_fail(track, settings, specs)
    type(track_t), intent(out) :: track
    type(track_settings_t), intent(in) :: settings
    type(segment_spec_t), intent(in) :: specs(:)
    type(error_t), allocatable :: error
    call build_track(track, settings, specs, error)
    if (allocated(error)) then
      print '(a)', 'FAIL: build_track: ' // error%message
      error stop 1
    end if
  end subroutine build_or_fail

  !> The track used for continuity and derivative tests: every kind of joint, gradients,
  !> both cant ramps.
  function mixed_specs() result(specs)
    type(segment_spec_t) :: specs(9)
    ! signed superelevation: left rail over right rail, so a left curve (kappa > 0) has
    ! h < 0 (outer = right rail raised) and a right curve h > 0
    specs(1) = seg('straight', 100.0_wp, 0.0_wp, 0.0_wp, gradient=0.01_wp)
    specs(2) = seg('clothoid', 80.0_wp, 1 / 600.0_wp, -0.08_wp)                  ! entry
    specs(3) = seg('curve', 100.0_wp, 1 / 600.0_wp, -0.08_wp, gradient=-0.005_wp) ! left
    specs(4) = seg('clothoid', 60.0_wp, 1 / 300.0_wp, -0.12_wp, 'cosine')        ! compound
    specs(5) = seg('curve', 80.0_wp, 1 / 300.0_wp, -0.12_wp)
    specs(6) = seg('clothoid', 120.0_wp, -1 / 400.0_wp, 0.06_wp)                 ! reverse
    specs(7) = seg('curve', 70.0_wp, -1 / 400.0_wp, 0.06_wp, gradient=0.0_wp)    ! right
    specs(8) = seg('clothoid', 90.0_wp, 0.0_wp, 0.0_wp, 'cosine')                ! exit
    specs(9) = seg('straight', 50.0_wp, 0.0_wp, 0.0_wp)
  end function mixed_specs

  subroutine test_joint_continuity()
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(segment_spec_t) :: specs(9)
    type(track_point_t) :: left, right
    real(wp), parameter :: d = 1.0e-6_wp
    real(wp) :: joint, worst, e(6)
    integer :: j
    specs = mixed_specs()
    settings%start_position = [100.0_wp, -50.0_wp, 12.0_wp]
    settings%start_heading = 0.7_wp
    call build_or_fail(track, settings, specs)
    call check(abs(track%length() - 750.0_wp) < 1.0e-12_wp, 'mixed track length', track%length())
    worst = 0
    joint = 0
    do j = 1, size(specs) - 1
      joint = joint + specs(j)%length
      left = track%evaluate(joint - d)
      right = track%evaluate(joint + d)
      ! first-order extrapolation of each side to the joint; the remainder is O(d^2)
      e(1) = maxval(abs((left%r + d * left%dr) - (right%r - d * right%dr)))
      e(2) = abs((left%heading + d * left%curvature) - (right%heading - d * right%curvature))
      e(3) = abs((left%curvature + d * left%dcurvature) - (right%curvature - d * right%dcurvature))
      ! dphi/dsigma = omega_1 + kappa sin(theta) (omega_1 = phi' - psi' sin(theta))
      e(4) = abs((left%cant_angle + d * (left%omega(1) + left%curvature * sin(left%grade_angle))) - &
                 (right%cant_angle - d * (right%omega(1) + right%curvature * sin(right%grade_angle))))
      e(5) = abs((left%dr(3) + d * left%d2r(3)) - (right%dr(3) - d * right%d2r(3)))
      e(6) = maxval(abs(matmul(left%a, identity() + d * skew3(left%omega)) - &
                        matmul(right%a, identity() - d * skew3(right%omega))))
      worst = max(worst, maxval(e))
      if (any(e >= 1.0e-9_wp)) print '(a,6es9.2)', '  jumps (r, psi, kappa, phi, g, A): ', e
      call check(all(e < 1.0e-9_wp), 'joint continuity (r, psi, kappa, phi, g, A) at sigma=', joint)
    end do
    print '(a,es9.2)', 'joint continuity, 8 joints: worst jump ', worst
    ! finite-difference derivative check on the same track, every segment kind
    call check_derivatives(track)
  end subroutine test_joint_continuity

  !> dr, d2r, dA, d2A, omega, domega against central differences; A orthonormal, det +1;
  !> X_T along dr; Y_T lifted by sin(phi) cos(theta).
  subroutine check_derivatives(track)
    class(track_t), intent(in) :: track
    real(wp), parameter :: h = 1.0e-4_wp
    type(track_point_t) :: p, pp, pm
    real(wp) :: sigma, e(11), worst(11), ata(3, 3), w(3), t(3)
    integer :: i
    worst = 0
    do i = 0, 80
      sigma = -20.0_wp + 10.0_wp * i + 0.37_wp   ! away from joints (multiples of 10)
      p = track%evaluate(sigma)
      pp = track%evaluate(sigma + h)
      pm = track%evaluate(sigma - h)
      e(1) = maxval(abs((pp%r - pm%r) / (2 * h) - p%dr))
      e(2) = maxval(abs((pp%dr - pm%dr) / (2 * h) - p%d2r))
      e(3) = maxval(abs((pp%a - pm%a) / (2 * h) - p%da))
      e(4) = maxval(abs((pp%da - pm%da) / (2 * h) - p%d2a))
      e(5) = maxval(abs((pp%omega - pm%omega) / (2 * h) - p%domega))
      w = 0.5_wp * [ata_entry(p, 3, 2) - ata_entry(p, 2, 3), ata_entry(p, 1, 3) - ata_entry(p, 3, 1), &
                    ata_entry(p, 2, 1) - ata_entry(p, 1, 2)]
      e(6) = maxval(abs(w - p%omega))
      ata = matmul(transpose(p%a), p%a)
      e(7) = maxval(abs(ata - identity()))
      e(8) = abs(det3(p%a) - 1)
      t = p%dr / norm2(p%dr)
      e(9) = maxval(abs(p%a(:, 1) - t))
      e(10) = abs(p%a(3, 2) - cos(p%grade_angle) * p%superelevation / 1.5_wp) + &
              abs(p%grade_angle + atan(p%dr(3))) + abs(p%heading - atan2(p%dr(2), p%dr(1)))
      ! A against the product of rd_rotation's elementary rotations (thesis eq. 4.5)
      e(11) = maxval(abs(p%a - matmul(rot_z(p%heading), matmul(rot_y(p%grade_angle), rot_x(p%cant_angle)))))
      worst = max(worst, e)
    end do
    print '(a,11es9.2)', 'derivatives vs central differences (dr d2r dA d2A domega), frame checks: ', worst
    call check(worst(1) < 1.0e-8_wp, 'dr vs FD of r', worst(1))
    call check(worst(2) < 1.0e-9_wp, 'd2r vs FD of dr', worst(2))
    call check(worst(3) < 1.0e-9_wp, 'dA vs FD of A', worst(3))
    call check(worst(4) < 1.0e-9_wp, 'd2A vs FD of dA', worst(4))
    call check(worst(5) < 1.0e-9_wp, 'domega vs FD of omega', worst(5))
    call check(worst(6) < 1.0e-15_wp, 'omega vs unskew(A^T dA)', worst(6))
    call check(worst(7) < 1.0e-14_wp, 'A^T A = I', worst(7))
    call check(worst(8) < 1.0e-14_wp, 'det A = 1', worst(8))
    call check(worst(9) < 1.0e-14_wp, 'X_T along dr', worst(9))
    call check(worst(10) < 1.0e-13_wp, 'angles vs frame (cant lifts Y_T, grade, heading)', worst(10))
    call check(worst(11) < 1.0e-15_wp, 'A = R_z R_y R_x', worst(11))
  end subroutine check_derivatives

  real(wp) function ata_entry(p, i, j)
    type(track_point_t), intent(in) :: p
    integer, intent(in) :: i, j
    ata_entry = dot_product(p%a(:, i), p%da(:, j))
  end function ata_entry

  pure function identity() result(m)
    real(wp) :: m(3, 3)
    m = 0
    m(1, 1) = 1; m(2, 2) = 1; m(3, 3) = 1
  end function identity

  pure function skew3(a) result(s)
    real(wp), intent(in) :: a(3)
    real(wp) :: s(3, 3)
    s = reshape([0.0_wp, a(3), -a(2), -a(3), 0.0_wp, a(1), a(2), -a(1), 0.0_wp], [3, 3])
  end function skew3

  pure real(wp) function det3(m)
    real(wp), intent(in) :: m(3, 3)
    det3 = m(1, 1) * (m(2, 2) * m(3, 3) - m(2, 3) * m(3, 2)) &
         - m(1, 2) * (m(2, 1) * m(3, 3) - m(2, 3) * m(3, 1)) &
         + m(1, 3) * (m(2, 1) * m(3, 2) - m(2, 2) * m(3, 1))
  end function det3

  !> A single curve starting on the circle (start curvature 1/R) against the circle.
  subroutine test_circle()
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(track_point_t) :: p
    real(wp) :: radius, centre(2), angle, worst, q(2)
    integer :: side, i
    worst = 0
    do side = -1, 1, 2
      radius = 300.0_wp
      settings%start_position = [10.0_wp, 20.0_wp, 5.0_wp]
      settings%start_heading = 0.3_wp
      settings%start_curvature = side / radius
      call build_or_fail(track, settings, [seg('curve', 1500.0_wp, side / radius, 0.0_wp)])
      centre = settings%start_position(1:2) + side * radius * [-sin(0.3_wp), cos(0.3_wp)]
      do i = 0, 150
        p = track%evaluate(10.0_wp * i)
        angle = 0.3_wp + side * 10.0_wp * i / radius
        q = centre + side * radius * [sin(angle), -cos(angle)]
        worst = max(worst, maxval(abs(p%r(1:2) - q)), abs(p%r(3) - 5), abs(p%heading - angle), &
                    abs(p%curvature - side / radius))
      end do
    end do
    print '(a,es9.2)', 'circle R 300 (left and right, 1500 m) vs closed form: worst error ', worst
    call check(worst < 1.0e-9_wp, 'circle vs closed form', worst)
  end subroutine test_circle

  !> Clothoids (entry from straight, compound, reverse through zero, a nearly constant
  !> curvature one that uses the quadrature branch) against real128 quadrature.
  subroutine test_clothoids_against_quadrature()
    call one_clothoid('200 m clothoid 0 -> 1/1000', 0.0_wp, 1 / 1000.0_wp, 200.0_wp)
    call one_clothoid('30 m clothoid 0 -> 1/150', 0.0_wp, 1 / 150.0_wp, 30.0_wp)
    call one_clothoid('30 m clothoid 0 -> -1/150', 0.0_wp, -1 / 150.0_wp, 30.0_wp)
    call one_clothoid('100 m compound 1/1000 -> 1/300', 1 / 1000.0_wp, 1 / 300.0_wp, 100.0_wp)
    call one_clothoid('100 m compound -1/300 -> -1/1000', -1 / 300.0_wp, -1 / 1000.0_wp, 100.0_wp)
    call one_clothoid('150 m reverse 1/500 -> -1/400', 1 / 500.0_wp, -1 / 400.0_wp, 150.0_wp)
    call one_clothoid('150 m reverse -1/500 -> 1/400', -1 / 500.0_wp, 1 / 400.0_wp, 150.0_wp)
    call one_clothoid('20 m 1/2000 -> 1/2001 (tiny rate)', 1 / 2000.0_wp, 1 / 2001.0_wp, 20.0_wp)
    call one_clothoid('300 m 1/50 -> 1/40 (long, tight)', 1 / 50.0_wp, 1 / 40.0_wp, 300.0_wp)
    ! the continued-fraction range of G (|t| > 1.5) on both sides of the inflection and
    ! across it (unrealistic radii, chosen to exercise each branch of rd_clothoid)
    call one_clothoid('300 m 1/40 -> 1/50 (decreasing)', 1 / 40.0_wp, 1 / 50.0_wp, 300.0_wp)
    call one_clothoid('400 m 1/20 -> -1/20 (reverse, large t)', 1 / 20.0_wp, -1 / 20.0_wp, 400.0_wp)
  end subroutine test_clothoids_against_quadrature

  subroutine one_clothoid(name, k0, k1, length)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: k0, k1, length
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(track_point_t) :: p
    real(qp) :: x, y, psi0
    real(wp) :: u, worst
    integer :: i
    settings%start_position = [-3.0_wp, 7.0_wp, 0.0_wp]
    settings%start_heading = -1.1_wp
    settings%start_curvature = k0
    call build_or_fail(track, settings, [seg('clothoid', length, k1, 0.0_wp)])
    worst = 0
    psi0 = real(settings%start_heading, qp)
    do i = 0, 40
      u = length * i / 40
      call quad_clothoid(psi0, real(k0, qp), (real(k1, qp) - real(k0, qp)) / real(length, qp), &
                         real(u, qp), x, y)
      p = track%evaluate(u)
      worst = max(worst, abs(p%r(1) - real(-3.0_qp + x, wp)), abs(p%r(2) - real(7.0_qp + y, wp)))
    end do
    print '(a,a,a,es9.2,a)', 'clothoid ', name, ' vs real128 quadrature: worst ', worst, ' m'
    call check(worst < 1.0e-9_wp, 'clothoid position vs quadrature: ' // name, worst)
  end subroutine one_clothoid

  !> int_0^u (cos, sin)(psi0 + k0 v + c v^2/2) dv, composite 20-point Gauss-Legendre in
  !> real128 with panels of at most 1 m.
  subroutine quad_clothoid(psi0, k0, c, u, x, y)
    real(qp), intent(in) :: psi0, k0, c, u
    real(qp), intent(out) :: x, y
    real(qp), save :: nodes(20), weights(20)
    logical, save :: ready = .false.
    real(qp) :: a, b, v, psi
    integer :: panels, p, k
    if (.not. ready) then
      call legendre_qp(nodes, weights)
      ready = .true.
    end if
    x = 0
    y = 0
    if (u == 0) return
    panels = max(1, ceiling(u))
    do p = 1, panels
      a = u * (p - 1) / panels
      b = u * p / panels
      do k = 1, 20
        v = 0.5_qp * (a + b) + 0.5_qp * (b - a) * nodes(k)
        psi = psi0 + k0 * v + 0.5_qp * c * v * v
        x = x + 0.5_qp * (b - a) * weights(k) * cos(psi)
        y = y + 0.5_qp * (b - a) * weights(k) * sin(psi)
      end do
    end do
  end subroutine quad_clothoid

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

  !> Thesis track (1000 m straight, 200 m transition, R 1000 left, 50 mm) and Manchester
  !> Track Case 1 (50 m, 30 m, R 150, 100 mm, 60 m of curve).
  subroutine test_thesis_and_manchester()
    call canonical_track('thesis track', 1000.0_wp, 200.0_wp, 1000.0_wp, 0.05_wp, 500.0_wp)
    call canonical_track('Manchester track case 1', 50.0_wp, 30.0_wp, 150.0_wp, 0.1_wp, 60.0_wp)
  end subroutine test_thesis_and_manchester

  subroutine canonical_track(name, l1, l2, radius, cant, l3)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: l1, l2, radius, cant, l3
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(track_point_t) :: p
    real(wp) :: tau, xc, yc, term, centre(2), end_point(2), angle
    integer :: n
    call build_or_fail(track, settings, [seg('straight', l1, 0.0_wp, 0.0_wp), &
                                         seg('clothoid', l2, 1 / radius, -cant), &
                                         seg('curve', l3, 1 / radius, -cant)])
    call check(abs(track%length() - (l1 + l2 + l3)) < 1.0e-12_wp, name // ': total length', track%length())
    p = track%evaluate(l1 + l2)
    call check(abs(p%heading - l2 / (2 * radius)) < 1.0e-14_wp, name // ': heading L/(2R) at the transition end', &
               p%heading - l2 / (2 * radius))
    ! left-hand curve: the outer (right) rail is raised, phi = -asin(h/1.5) (thesis eq. 3.1)
    call check(abs(p%cant_angle + asin(cant / 1.5_wp)) < 1.0e-15_wp, name // ': cant angle -asin(h/1.5)', &
               p%cant_angle)
    call check(abs(p%curvature - 1 / radius) < 1.0e-16_wp, name // ': curvature 1/R', p%curvature)
    p = track%evaluate(l1 + l2 + 0.5_wp * l3)
    call check(abs(p%cant_angle + asin(cant / 1.5_wp)) < 1.0e-15_wp, name // ': cant angle in the curve', &
               p%cant_angle)
    call check(abs(p%superelevation + cant) < 1.0e-15_wp, name // ': superelevation in the curve', &
               p%superelevation)
    ! Clothoid end from its power series (int_0^1 exp(i tau v^2) dv = sum (i tau)^k/(k!(2k+1))),
    ! then the circle of radius R tangent there: independent of rd_clothoid.
    tau = l2 / (2 * radius)
    xc = 0; yc = 0
    term = 1
    do n = 0, 30
      if (n > 0) term = term * tau / n
      select case (modulo(n, 4))
      case (0); xc = xc + term / (2 * n + 1)
      case (1); yc = yc + term / (2 * n + 1)
      case (2); xc = xc - term / (2 * n + 1)
      case (3); yc = yc - term / (2 * n + 1)
      end select
    end do
    xc = l1 + l2 * xc
    yc = l2 * yc
    centre = [xc - radius * sin(tau), yc + radius * cos(tau)]
    angle = tau + l3 / radius
    end_point = centre + radius * [sin(angle), -cos(angle)]
    p = track%evaluate(l1 + l2 + l3)
    print '(a,a,2f14.6,a,es9.2)', name, ': curve end ', p%r(1:2), ', error vs closed form ', &
      maxval(abs(p%r(1:2) - end_point))
    call check(maxval(abs(p%r(1:2) - end_point)) < 1.0e-9_wp, name // ': end point of the curve', &
               maxval(abs(p%r(1:2) - end_point)))
    call check(abs(p%heading - angle) < 1.0e-13_wp, name // ': end heading', p%heading - angle)
  end subroutine canonical_track

  !> The same track curving right: y -> -y, heading -> -heading, cant -> -cant.
  subroutine test_mirror()
    type(track_t) :: left, right
    type(track_settings_t) :: settings
    type(segment_spec_t) :: specs(9)
    type(track_point_t) :: pl, pr
    real(wp) :: worst, sigma
    integer :: i
    specs = mixed_specs()
    call build_or_fail(left, settings, specs)
    specs%curvature_end = -specs%curvature_end
    specs%superelevation_end = -specs%superelevation_end
    call build_or_fail(right, settings, specs)
    worst = 0
    do i = -10, 800
      sigma = 1.0_wp * i + 0.25_wp
      pl = left%evaluate(sigma)
      pr = right%evaluate(sigma)
      worst = max(worst, abs(pl%r(1) - pr%r(1)), abs(pl%r(2) + pr%r(2)), abs(pl%r(3) - pr%r(3)), &
                  abs(pl%heading + pr%heading), abs(pl%cant_angle + pr%cant_angle), &
                  abs(pl%curvature + pr%curvature), abs(pl%grade_angle - pr%grade_angle))
    end do
    print '(a,es9.2)', 'mirror left/right: worst asymmetry ', worst
    call check(worst < 1.0e-12_wp, 'mirror symmetry', worst)
  end subroutine test_mirror

  !> Splitting a straight or a curve into two halves changes nothing.
  subroutine test_split()
    type(track_t) :: whole, halves
    type(track_settings_t) :: settings
    type(track_point_t) :: p, q
    real(wp) :: worst, sigma
    integer :: i
    call build_or_fail(whole, settings, [seg('straight', 100.0_wp, 0.0_wp, 0.0_wp, gradient=0.01_wp), &
                                         seg('clothoid', 50.0_wp, 1 / 500.0_wp, 0.06_wp), &
                                         seg('curve', 200.0_wp, 1 / 500.0_wp, 0.06_wp)])
    call build_or_fail(halves, settings, [seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, gradient=0.005_wp), &
                                          seg('straight', 50.0_wp, 0.0_wp, 0.0_wp, gradient=0.01_wp), &
                                          seg('clothoid', 50.0_wp, 1 / 500.0_wp, 0.06_wp), &
                                          seg('curve', 100.0_wp, 1 / 500.0_wp, 0.06_wp), &
                                          seg('curve', 100.0_wp, 1 / 500.0_wp, 0.06_wp)])
    worst = 0
    do i = -5, 360
      sigma = 1.0_wp * i + 0.125_wp
      p = whole%evaluate(sigma)
      q = halves%evaluate(sigma)
      worst = max(worst, maxval(abs(p%r - q%r)), maxval(abs(p%dr - q%dr)), maxval(abs(p%d2r - q%d2r)), &
                  maxval(abs(p%a - q%a)), maxval(abs(p%da - q%da)), maxval(abs(p%d2a - q%d2a)), &
                  maxval(abs(p%omega - q%omega)), maxval(abs(p%domega - q%domega)))
    end do
    print '(a,es9.2)', 'split straight and curve in halves: worst difference ', worst
    call check(worst < 1.0e-12_wp, 'split segments give the same track', worst)
  end subroutine test_split

  !> z follows the parabola of a linear gradient ramp; past both ends the track runs on
  !> straight with the end heading, cant and gradient.
  subroutine test_vertical_profile_and_run_off()
    type(track_t) :: track
    type(track_settings_t) :: settings
    type(track_point_t) :: p, e
    real(wp) :: worst, u
    integer :: i
    settings%start_gradient = -0.004_wp
    settings%start_position = [0.0_wp, 0.0_wp, 100.0_wp]
    call build_or_fail(track, settings, [seg('straight', 200.0_wp, 0.0_wp, 0.0_wp, gradient=0.02_wp), &
                                         seg('clothoid', 40.0_wp, -1 / 250.0_wp, 0.09_wp, 'cosine')])
    worst = 0
    do i = 0, 40
      u = 5.0_wp * i
      p = track%evaluate(u)
      worst = max(worst, abs(p%r(3) - (100 - 0.004_wp * u + 0.024_wp * u**2 / 400)), &
                  abs(p%dr(3) - (-0.004_wp + 0.024_wp * u / 200)), &
                  abs(norm2(p%dr) - sqrt(1 + p%dr(3)**2)))
    end do
    call check(worst < 1.0e-12_wp, 'vertical parabola', worst)
    e = track%evaluate(240.0_wp)
    p = track%evaluate(250.0_wp)
    worst = max(maxval(abs(p%r - (e%r + 10 * [cos(e%heading), sin(e%heading), 0.02_wp]))), &
                abs(p%heading - e%heading), abs(p%cant_angle - e%cant_angle), abs(p%curvature), &
                maxval(abs(p%omega)))
    call check(worst < 1.0e-12_wp, 'run-off past the end', worst)
    call check(abs(e%cant_angle - asin(0.09_wp / 1.5_wp)) < 1.0e-15_wp, 'cosine ramp end cant', e%cant_angle)
    e = track%evaluate(0.0_wp)
    p = track%evaluate(-10.0_wp)
    worst = max(maxval(abs(p%r - (e%r - 10 * [1.0_wp, 0.0_wp, -0.004_wp]))), abs(p%heading), &
                abs(p%grade_angle - atan(0.004_wp)))
    call check(worst < 1.0e-12_wp, 'run-off before the start', worst)
  end subroutine test_vertical_profile_and_run_off
end program test_track_segments
