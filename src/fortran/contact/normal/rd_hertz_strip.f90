!> The Hertz strip stiffness: the energy density per strip that makes a sum over
!> longitudinal strips reproduce Hertz's normal contact exactly on every Hertzian gap
!> (the distributed strip normal force, `strip_normal_force = 'distributed'`;
!> docs/theory_flange_chatter.md section 14).
!>
!> A strip at lateral position s (arc length across the patch) with normal interference
!> delta(s) stores U = c delta^2 per unit width, so the whole contact stores
!> U = int c delta_+(s)^2 ds and the force on the wheel is minus its gradient: every strip
!> pushes along its own depth gradient with 2 c delta per unit width (a Winkler bed whose
!> modulus depends on the local curvatures). For a Hertzian gap delta = delta_0 - B s^2
!> (B the lateral relative curvature, A the rolling one):
!>    int delta_+^2 ds = (16/15) delta_0^(5/2) / sqrt(B),
!> and Hertz's energy is (2/5) k_h delta_0^(5/2) (N = k_h delta_0^(3/2)), so
!>    c = (3/8) k_h sqrt(B),
!> and with k_h = E*/3 G / sqrt(4 (A + B)) (rd_hertz, G a function of B/A only)
!>    c = E* phi(ln(B/A)),   phi(x) = G(|x|) sqrt(e^x / (1 + e^x)) / 16.
!> Then sum 2 c delta = (8/3) c delta_0^(3/2) / sqrt(B) = k_h delta_0^(3/2): Hertz's force.
!> phi is 0.35 at x = 0 (B = A), 0.13 at B = A / 1000 (laterally conformal) and grows like
!> (B/A)^0.4 for narrow patches (4.0 at B = 1000 A).
!>
!> phi is tabulated once (elliptic integrals through rd_hertz) over x in [-x_max, x_max]
!> and read by the natural cubic spline through the nodes, C2, so that the force, which
!> contains delta^2 dc/d(pose), is C1 (the cubic Hermite with central-difference slopes used
!> before is C1 only: its derivative, and with it the force, kinked at every node). The strips sample the integral
!> interval by interval (interval_energy), resolving the contact edge between two strips.
module rd_hertz_strip
  use rd_kinds, only: wp
  use rd_hertz, only: hertz_params_t, hertz_patch_t, hertz_from_penetration, HERTZ_METHOD_ELLIPTIC
  use rd_natural_splines, only: natural_spline
  implicit none
  private
  public :: fill_strip_stiffness_table, strip_stiffness, interval_energy

  !> Relative curvatures are floored smoothly at this value (equivalent radius 1/(2 floor)
  !> = 20 m, the order of rd_hertz's default clamp) so that conformal and concave gaps keep
  !> a finite, smooth stiffness
  real(wp), parameter, public :: strip_curvature_floor = 0.025_wp

  integer, parameter :: nodes = 2049
  real(wp), parameter :: x_max = 16.0_wp          ! |ln(B/A)| <= 16 (ratios up to 9e6)
  real(wp), save :: table(nodes) = 0              ! phi at x_j = -x_max + (j - 1) h
  real(wp), save :: table_m(nodes) = 0            ! its spline's d2 phi / dj2 (per node step)
  logical, save :: table_filled = .false.

contains

  !> Fill the table (once per process; later calls return at once). Not pure: call it
  !> when the model is built, before any strip_stiffness.
  subroutine fill_strip_stiffness_table()
    type(hertz_params_t) :: unit
    type(hertz_patch_t) :: hp
    real(wp) :: x, b
    real(wp), allocatable :: m(:)
    integer :: j
    if (table_filled) return
    unit = hertz_params_t(e_star=1.0_wp, curvature_min=1.0e-300_wp, method=HERTZ_METHOD_ELLIPTIC)
    do j = 1, nodes
      x = -x_max + 2 * x_max * (j - 1) / (nodes - 1)
      b = exp(x)
      ! curvatures (wheel rolling, wheel lateral, rail rolling, rail lateral) with A = 1,
      ! B = e^x: rd_hertz halves the sums
      call hertz_from_penetration(unit, [2.0_wp, 2 * b, 0.0_wp, 0.0_wp], 1.0_wp, hp)
      table(j) = 0.375_wp * hp%k_hertz * sqrt(b)
    end do
    call natural_spline([(real(j, wp), j = 1, nodes)], table, m)
    table_m = m
    table_filled = .true.
  end subroutine fill_strip_stiffness_table

  !> c / E* for the rolling and lateral relative curvatures a, b [1/m] (half the sums of
  !> the two bodies' curvatures, + convex), each floored smoothly, and its partial
  !> derivatives with respect to a and b.
  pure subroutine strip_stiffness(a, b, phi, dphi_da, dphi_db)
    real(wp), intent(in) :: a, b
    real(wp), intent(out) :: phi, dphi_da, dphi_db
    real(wp), parameter :: h = 2 * x_max / (nodes - 1)
    real(wp) :: ac, bc, dac, dbc, x, t, u, dphi_dx
    logical :: clamped
    integer :: j
    call floor_curvature(a, ac, dac)
    call floor_curvature(b, bc, dbc)
    x = log(bc / ac)
    clamped = abs(x) > x_max
    x = min(max(x, -x_max), x_max)
    j = min(int((x + x_max) / h) + 1, nodes - 1)
    t = (x + x_max) / h - (j - 1)
    ! the natural cubic spline in the node index (unit steps)
    u = 1 - t
    phi = u * table(j) + t * table(j + 1) + ((u * u - 1) * u * table_m(j) + (t * t - 1) * t * table_m(j + 1)) / 6
    dphi_dx = (table(j + 1) - table(j) + (-(3 * u * u - 1) * table_m(j) + (3 * t * t - 1) * table_m(j + 1)) / 6) / h
    if (clamped) dphi_dx = 0          ! phi is held constant beyond the table
    dphi_da = -dphi_dx * dac / ac
    dphi_db = dphi_dx * dbc / bc
  end subroutine strip_stiffness

  !> The energy of one interval between neighbouring strips per unit stiffness c: with the
  !> depth interpolated linearly from a to b over the interval's width h,
  !>    q = h int_0^1 ((1 - t) a + t b)_+^2 dt
  !>      = h (a^2 + a b + b^2) / 3     (a, b > 0),   h a^3 / (3 (a - b))   (a > 0 >= b),
  !> and its derivatives by a and b (the loads of the two strips). It resolves the contact
  !> edge inside the interval, so that q is C2 in the depths where a strip comes into contact:
  !> a strip's own delta_+^2 kinked the force at each onset, and on the flange face, where the
  !> edge sweeps a strip in under a micrometre of shift, by up to 18 % of its slope
  !> (docs/theory_flange_chatter.md section 14); an onset easing over 1 um kept the kinks, one
  !> over 5 um removed them but took ~(3/8)(e/delta_0)^2 from a light patch's load. Summed over
  !> a Hertzian gap it converges to int delta_+^2 ds with the strips' spacing.
  elemental subroutine interval_energy(a, b, h, q, qa, qb)
    real(wp), intent(in) :: a, b, h
    real(wp), intent(out) :: q, qa, qb
    if (a > 0 .and. b > 0) then
      q = h * (a * a + a * b + b * b) / 3
      qa = h * (2 * a + b) / 3
      qb = h * (a + 2 * b) / 3
    else if (a > 0) then
      q = h * a**3 / (3 * (a - b))
      qa = h * a * a * (2 * a - 3 * b) / (3 * (a - b)**2)
      qb = h * a**3 / (3 * (a - b)**2)
    else if (b > 0) then
      q = h * b**3 / (3 * (b - a))
      qb = h * b * b * (2 * b - 3 * a) / (3 * (b - a)**2)
      qa = h * b**3 / (3 * (b - a)**2)
    else
      q = 0; qa = 0; qb = 0
    end if
  end subroutine interval_energy

  !> Smooth floor: 0.5 (k + sqrt(k^2 + 4 f^2)) -> k for k >> f, f at k = 0, -> f^2 / |k| for
  !> concave k << -f; and its derivative. (A softplus floor, f ln(1 + e^(k/f)), closer to k
  !> above f, sends concave curvatures to e^(k/f) f, beyond the table: phi's argument was
  !> clamped there, and the scene runs depended on the floor's shape; this one keeps
  !> ln(B/A) > -10 for |k| < 1 1/m.)
  pure subroutine floor_curvature(k, kc, dkc)
    real(wp), intent(in) :: k
    real(wp), intent(out) :: kc, dkc
    real(wp) :: root
    root = sqrt(k * k + 4 * strip_curvature_floor**2)
    kc = 0.5_wp * (k + root)
    dkc = 0.5_wp * (1 + k / root)
  end subroutine floor_curvature

end module rd_hertz_strip
