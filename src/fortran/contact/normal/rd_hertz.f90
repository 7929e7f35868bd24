!> Hertz normal contact of wheel and rail: contact ellipse, normal force, approach,
!> peak pressure and normal stiffness from the principal curvatures at the contact point
!> (thesis 3.5, eqs. 3.25-3.32; derivation and corrections in docs/theory_contact_mechanics.md).
!>
!> Shape: `build_hertz` fixes the parameters (materials, method, fallback radius); the two
!> pure entry points `hertz_from_penetration` and `hertz_from_force` fill a `hertz_patch_t`
!> and allocate nothing, so they can run per contact patch in the right-hand side.
!>
!> Frames (docs/conventions.md): x is the rolling direction of the contact frame, y the
!> lateral one. `a` is ALWAYS the semi-axis along x, `b` along y; a/b may be < 1 or > 1.
!> Curvatures are signed: convex positive, concave negative (e.g. a wheel throat).
module rd_hertz
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, finite, RD_ERR_INPUT
  use rd_elliptic_integrals, only: elliptic_ke
  implicit none
  private
  public :: hertz_params_t, hertz_patch_t
  public :: build_hertz, hertz_from_penetration, hertz_from_force, hertz_damped_force
  public :: hertz_table_mn

  integer, parameter, public :: HERTZ_METHOD_ELLIPTIC = 1  !< exact: AGM elliptic integrals
  integer, parameter, public :: HERTZ_METHOD_TABLE = 2     !< classic printed m, n table (thesis App. B)
  !> the elliptic solution tabulated over ln(B/A) (cubic Hermite, within 1e-9 of it)
  integer, parameter, public :: HERTZ_METHOD_ELLIPTIC_TABLE = 3

  !> Warning bits of `hertz_patch_t%warning` (0 = clean Hertz case). Callers write the
  !> integer to their output so a conformal or degenerate patch is visible afterwards.
  integer, parameter, public :: HERTZ_WARN_CLAMPED_ROLLING = 1  !< A_x < A_min: floored (conformal / concave along x)
  integer, parameter, public :: HERTZ_WARN_CLAMPED_LATERAL = 2  !< A_y < A_min: floored (conformal / concave along y)
  integer, parameter, public :: HERTZ_WARN_ELONGATED = 4        !< a/b outside [0.1, 10] (beyond Kalker's table)
  integer, parameter, public :: HERTZ_WARN_BAD_INPUT = 8        !< NaN/Inf curvature or load: patch set to zero

  !> Parameters fixed after `build_hertz`.
  type :: hertz_params_t
    !> Combined modulus E* = 1 / (K_w + K_r), K = (1 - nu^2)/E (thesis eq. 3.27) [Pa]
    real(wp) :: e_star = 0.0_wp
    !> Combined shear modulus 1/G = (1/G_w + 1/G_r)/2 and Poisson ratio
    !> nu = G (nu_w/G_w + nu_r/G_r)/2 (Kalker 1990, 1.4), for the creep laws [Pa], [-]
    real(wp) :: shear_modulus = 0.0_wp
    real(wp) :: poisson = 0.0_wp
    !> Smallest accepted relative curvature per direction, A_min = 1/(2 R_max) [1/m]
    real(wp) :: curvature_min = 0.05_wp
    integer :: method = HERTZ_METHOD_ELLIPTIC
  end type hertz_params_t

  !> One contact patch. All zero (and `in_contact` false) when there is no contact.
  type :: hertz_patch_t
    logical :: in_contact = .false.
    real(wp) :: a = 0.0_wp              !< semi-axis along the rolling direction x [m]
    real(wp) :: b = 0.0_wp              !< semi-axis along the lateral direction y [m]
    real(wp) :: normal_force = 0.0_wp   !< elastic normal force N [N]
    real(wp) :: approach = 0.0_wp       !< approach (penetration) delta [m]
    real(wp) :: p0 = 0.0_wp             !< peak pressure 3N/(2 pi a b) [Pa]
    real(wp) :: stiffness = 0.0_wp      !< dN/d delta = 1.5 N / delta [N/m]
    real(wp) :: k_hertz = 0.0_wp        !< N = k_hertz delta^1.5 [N/m^1.5]
    real(wp) :: sum_ab = 0.0_wp         !< A + B (after any clamp) [1/m]
    real(wp) :: theta = 0.0_wp          !< cos(theta) = |B - A|/(A + B) [rad]
    real(wp) :: m = 1.0_wp              !< Hertz coefficient of the major semi-axis
    real(wp) :: n = 1.0_wp              !< Hertz coefficient of the minor semi-axis
    integer :: warning = 0              !< HERTZ_WARN_* bits
  end type hertz_patch_t

  ! Classic Hertz table of m, n against theta (deg): the table the thesis refers to
  ! (App. B, "Hertz's table"; as printed in Shabana, Zaazaa, Sugiyama 2008 and Garg &
  ! Dukkipati 1984). Kept only for comparison (hertz_method = 'table').
  integer, parameter :: n_table = 23
  real(wp), parameter :: table_theta(n_table) = [0.5_wp, 1.0_wp, 1.5_wp, 2.0_wp, 3.0_wp, 4.0_wp, &
    6.0_wp, 8.0_wp, 10.0_wp, 20.0_wp, 30.0_wp, 35.0_wp, 40.0_wp, 45.0_wp, 50.0_wp, 55.0_wp, &
    60.0_wp, 65.0_wp, 70.0_wp, 75.0_wp, 80.0_wp, 85.0_wp, 90.0_wp]
  real(wp), parameter :: table_m(n_table) = [61.4_wp, 36.89_wp, 27.48_wp, 22.26_wp, 16.50_wp, &
    13.31_wp, 9.790_wp, 7.860_wp, 6.604_wp, 3.813_wp, 2.731_wp, 2.397_wp, 2.136_wp, 1.926_wp, &
    1.754_wp, 1.611_wp, 1.486_wp, 1.378_wp, 1.284_wp, 1.202_wp, 1.128_wp, 1.061_wp, 1.0_wp]
  real(wp), parameter :: table_n(n_table) = [0.1018_wp, 0.1314_wp, 0.1522_wp, 0.1691_wp, &
    0.1964_wp, 0.2188_wp, 0.2552_wp, 0.2850_wp, 0.3112_wp, 0.4123_wp, 0.4930_wp, 0.5305_wp, &
    0.5670_wp, 0.6040_wp, 0.6407_wp, 0.6779_wp, 0.7171_wp, 0.7568_wp, 0.8000_wp, 0.8456_wp, &
    0.8927_wp, 0.9440_wp, 1.0_wp]

  real(wp), parameter :: kprime_min = 1.0e-6_wp  !< b/a >= 1e-6: beyond this the patch is a line

  ! The elliptic path tabulated (hertz_method = 'elliptic_table'). The shape of a Hertz contact
  ! depends on x = ln(B/A) only: m, n and g = (2 pi m / K(e))^1.5 (k_h = E*/3 g / sqrt(4 (A+B))).
  ! Nodes uniform in x over [0, ln 1e6], cubic Hermite with central-difference slopes
  ! (second-order one-sided at the ends): within 2.3e-10 of the elliptic path (test_hertz).
  ! Ratios beyond the range take the elliptic path.
  ! One table for every model of the process, filled by the first build_hertz that asks for
  ! it and read-only afterwards, so that the pure entry points may read it.
  integer, parameter :: shape_nodes = 4096
  real(wp), parameter :: shape_x_max = 13.815510557964274_wp   ! ln(1e6)
  real(wp), save :: shape_table(3, shape_nodes) = 0.0_wp       ! m, n, g per node
  logical, save :: shape_table_filled = .false.

contains

  !> Fix the parameters. Materials by Young's modulus and Poisson ratio of wheel and rail
  !> (same-material default G = 82 GPa, nu = 0.28 gives E = 2 G (1 + nu) = 209.92 GPa).
  !> `method` is 'elliptic' (default), 'elliptic_table' (the same, tabulated: faster) or
  !> 'table' (the printed table, for comparison); `max_equivalent_radius` [m] bounds the
  !> equivalent radius 1/(2A) per direction for conformal or concave contact (default 10 m).
  !> `shear_modulus` [Pa] instead of Young's moduli gives both bodies E = 2 G (1 + nu).
  subroutine build_hertz(params, error, young_wheel, poisson_wheel, young_rail, poisson_rail, &
                        method, max_equivalent_radius, shear_modulus)
    type(hertz_params_t), intent(out) :: params
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: young_wheel, poisson_wheel, young_rail, poisson_rail
    character(len=*), intent(in), optional :: method
    real(wp), intent(in), optional :: max_equivalent_radius
    real(wp), intent(in), optional :: shear_modulus
    real(wp) :: ew, nw, er, nr, gw, gr, rmax
    character(len=32) :: word

    nw = 0.28_wp; if (present(poisson_wheel)) nw = poisson_wheel
    nr = nw; if (present(poisson_rail)) nr = poisson_rail
    ew = 2.0_wp * 82.0e9_wp * (1.0_wp + nw); if (present(young_wheel)) ew = young_wheel
    er = ew; if (present(young_rail)) er = young_rail
    if (present(shear_modulus)) then
      if (present(young_wheel) .or. present(young_rail)) then
        call make_error(error, RD_ERR_INPUT, 'build_hertz: give Young''s moduli or the shear modulus, not both')
        return
      end if
      ew = 2.0_wp * shear_modulus * (1.0_wp + nw)
      er = 2.0_wp * shear_modulus * (1.0_wp + nr)
    end if
    rmax = 10.0_wp; if (present(max_equivalent_radius)) rmax = max_equivalent_radius
    word = 'elliptic'; if (present(method)) word = adjustl(method)

    if (.not. (ew > 0.0_wp .and. er > 0.0_wp .and. ew < 1.0e15_wp .and. er < 1.0e15_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_hertz: Young''s modulus must be > 0 Pa (finite)')
      return
    end if
    if (.not. (nw >= 0.0_wp .and. nw < 0.5_wp .and. nr >= 0.0_wp .and. nr < 0.5_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_hertz: Poisson ratio must be in [0, 0.5)')
      return
    end if
    if (.not. (rmax > 0.0_wp .and. rmax < 1.0e12_wp)) then
      call make_error(error, RD_ERR_INPUT, 'build_hertz: max_equivalent_radius must be > 0 m')
      return
    end if
    select case (trim(word))
    case ('elliptic'); params%method = HERTZ_METHOD_ELLIPTIC
    case ('table'); params%method = HERTZ_METHOD_TABLE
    case ('elliptic_table')
      params%method = HERTZ_METHOD_ELLIPTIC_TABLE
      if (.not. shape_table_filled) call fill_shape_table()
    case default
      call make_error(error, RD_ERR_INPUT, 'build_hertz: hertz_method "' // trim(word) // &
                      '" unknown; expected ''elliptic'', ''elliptic_table'' or ''table''')
      return
    end select
    params%e_star = 1.0_wp / ((1.0_wp - nw**2) / ew + (1.0_wp - nr**2) / er)
    gw = ew / (2.0_wp * (1.0_wp + nw))
    gr = er / (2.0_wp * (1.0_wp + nr))
    params%shear_modulus = 2.0_wp / (1.0_wp / gw + 1.0_wp / gr)
    params%poisson = 0.5_wp * params%shear_modulus * (nw / gw + nr / gr)
    params%curvature_min = 0.5_wp / rmax
  end subroutine build_hertz

  !> Patch from the approach delta [m] (delta <= 0: no contact, all zero).
  !> curvatures = [kappa_wheel_x, kappa_wheel_y, kappa_rail_x, kappa_rail_y] [1/m].
  !> N = k_h delta^(3/2) (thesis eq. 3.26 corrected: see the theory doc).
  pure subroutine hertz_from_penetration(params, curvatures, approach, patch)
    type(hertz_params_t), intent(in) :: params
    real(wp), intent(in) :: curvatures(4)
    real(wp), intent(in) :: approach
    type(hertz_patch_t), intent(out) :: patch
    logical :: major_is_x
    if (.not. finite(approach) .or. .not. all(finite(curvatures))) then
      patch%warning = HERTZ_WARN_BAD_INPUT
      return
    end if
    if (approach <= 0.0_wp) return
    call hertz_shape(params, curvatures, patch, major_is_x)
    patch%approach = approach
    patch%normal_force = patch%k_hertz * approach * sqrt(approach)
    call fill_size(params, patch, major_is_x)
  end subroutine hertz_from_penetration

  !> Patch from the normal force N [N] (N <= 0: no contact, all zero).
  pure subroutine hertz_from_force(params, curvatures, normal_force, patch)
    type(hertz_params_t), intent(in) :: params
    real(wp), intent(in) :: curvatures(4)
    real(wp), intent(in) :: normal_force
    type(hertz_patch_t), intent(out) :: patch
    logical :: major_is_x
    if (.not. finite(normal_force) .or. .not. all(finite(curvatures))) then
      patch%warning = HERTZ_WARN_BAD_INPUT
      return
    end if
    if (normal_force <= 0.0_wp) return
    call hertz_shape(params, curvatures, patch, major_is_x)
    patch%normal_force = normal_force
    patch%approach = (normal_force / patch%k_hertz)**(2.0_wp / 3.0_wp)
    call fill_size(params, patch, major_is_x)
  end subroutine hertz_from_force

  !> Normal force with contact damping: N_el + c_n d(delta)/dt with the viscous term bounded
  !> by the elastic force, |c_n d(delta)/dt| <= N_el, so N stays in [0, 2 N_el] (never pulls,
  !> no adhesion on separation). c_n [N s/m], approach_rate = d(delta)/dt [m/s] (> 0 when
  !> closing). The plain Kelvin-Voigt force max(0, N_el + c_n rate) jumps from 0 to c_n rate
  !> when a patch opens while approaching (10 kN for 2e5 N s/m at 5 cm/s): a discontinuous
  !> right-hand side that made the BDF Newton iteration fail. As in Hunt & Crossley (J. Appl.
  !> Mech. 42, 1975), the damping vanishes with the elastic force at first touch; unlike their
  !> N_el (1 + alpha rate) it keeps the deck's c_n wherever c_n |rate| < N_el (loaded contact).
  elemental real(wp) function hertz_damped_force(elastic_force, damping, approach_rate) result(force)
    real(wp), intent(in) :: elastic_force, damping, approach_rate
    if (elastic_force <= 0) then
      force = 0
    else
      force = elastic_force + max(-elastic_force, min(elastic_force, damping * approach_rate))
    end if
  end function hertz_damped_force

  !> m, n (major, minor coefficients) of the classic printed table at theta [deg],
  !> linear interpolation, clamped to the table's range [0.5, 90] deg.
  pure subroutine hertz_table_mn(theta_deg, m, n)
    real(wp), intent(in) :: theta_deg
    real(wp), intent(out) :: m, n
    integer :: i
    real(wp) :: t, w
    t = min(max(theta_deg, table_theta(1)), table_theta(n_table))
    do i = 1, n_table - 2
      if (t <= table_theta(i + 1)) exit
    end do
    w = (t - table_theta(i)) / (table_theta(i + 1) - table_theta(i))
    m = (1.0_wp - w) * table_m(i) + w * table_m(i + 1)
    n = (1.0_wp - w) * table_n(i) + w * table_n(i + 1)
  end subroutine hertz_table_mn

  ! ---------------------------------------------------------------------------------

  !> A relative curvature a floored at c, C1: c up to c/2, a from 3c/2 on, and between them
  !> the quadratic c + (a - c/2)^2 / (2c) that meets both with their value and slope. Every
  !> curvature above 3c/2 (equivalent radius below R_max / 1.5) is taken as it is.
  pure real(wp) function curvature_floor(a, c) result(f)
    real(wp), intent(in) :: a, c
    if (a >= 1.5_wp * c) then
      f = a
    else if (a <= 0.5_wp * c) then
      f = c
    else
      f = c + (a - 0.5_wp * c)**2 / (2.0_wp * c)
    end if
  end function curvature_floor

  !> Everything that depends on the curvatures only: A, B (thesis eq. 3.29 with the
  !> relative curvatures; A along x, B along y), theta (eq. 3.28), e, m, n and k_h.
  pure subroutine hertz_shape(params, curvatures, patch, major_is_x)
    type(hertz_params_t), intent(in) :: params
    real(wp), intent(in) :: curvatures(4)
    type(hertz_patch_t), intent(inout) :: patch
    logical, intent(out) :: major_is_x
    real(wp) :: ax, ay, small, big, kprime, k_first, e_second, theta_deg, x, g

    patch%in_contact = .true.
    ! Half the relative curvature per direction (thesis eq. 3.29 pairs kappa_1 + kappa_2
    ! as "A", but kappa_1 is the wheel's rolling and kappa_2 the rail's transverse curvature:
    ! the relative curvature must pair the two bodies in the SAME direction).
    ax = 0.5_wp * (curvatures(1) + curvatures(3))
    ay = 0.5_wp * (curvatures(2) + curvatures(4))
    ! Conformal / concave fallback: a relative curvature below A_min (equivalent radius above
    ! R_max) is floored at A_min so a and b stay finite; flagged. The floor is C1
    ! (curvature_floor): with a hard max(A, A_min) the ellipse, and the creep forces it sets,
    ! kinked where a conformal patch's curvature crossed A_min.
    if (ax < params%curvature_min) patch%warning = ior(patch%warning, HERTZ_WARN_CLAMPED_ROLLING)
    if (ay < params%curvature_min) patch%warning = ior(patch%warning, HERTZ_WARN_CLAMPED_LATERAL)
    ax = curvature_floor(ax, params%curvature_min)
    ay = curvature_floor(ay, params%curvature_min)
    patch%sum_ab = ax + ay
    small = min(ax, ay)
    big = max(ax, ay)
    ! The major semi-axis lies along the direction of the SMALLER relative curvature.
    major_is_x = ax <= ay
    patch%theta = acos(min(1.0_wp, (big - small) / (big + small)))

    if (params%method == HERTZ_METHOD_ELLIPTIC_TABLE) then
      x = log(big / small)
      if (x < shape_x_max) then
        call shape_lookup(x, patch%m, patch%n, g)
        patch%k_hertz = params%e_star / 3.0_wp * g / sqrt(4.0_wp * patch%sum_ab)
        return
      end if
    end if
    if (params%method == HERTZ_METHOD_TABLE) then
      theta_deg = patch%theta * 180.0_wp / pi
      call hertz_table_mn(theta_deg, patch%m, patch%n)
      kprime = patch%n / patch%m
      call elliptic_ke(kprime, k_first, e_second)
    else
      call solve_kprime(big / small, kprime, k_first, e_second)
      ! m = [2 E(e) / (pi (1 - e^2))]^(1/3), n = m sqrt(1 - e^2) (oracles.md; Johnson 4.2)
      patch%m = (2.0_wp * e_second / (pi * kprime**2))**(1.0_wp / 3.0_wp)
      patch%n = patch%m * kprime
    end if
    ! delta = K(e) / (2 pi m) (3N/E*)^(2/3) (4(A+B))^(1/3)  =>  N = k_h delta^(3/2)
    patch%k_hertz = params%e_star / 3.0_wp * (2.0_wp * pi * patch%m / k_first)**1.5_wp &
                    / sqrt(4.0_wp * patch%sum_ab)
  end subroutine hertz_shape

  !> The table of the elliptic path: m, n and g at the nodes x_j = (j - 1) h,
  !> h = ln(1e6) / (nodes - 1), each as hertz_shape's elliptic branch computes them.
  subroutine fill_shape_table()
    real(wp) :: kprime, k_first, e_second, m
    integer :: j
    do j = 1, shape_nodes
      call solve_kprime(exp(shape_x_max * (j - 1) / (shape_nodes - 1)), kprime, k_first, e_second)
      m = (2.0_wp * e_second / (pi * kprime**2))**(1.0_wp / 3.0_wp)
      shape_table(:, j) = [m, m * kprime, (2.0_wp * pi * m / k_first)**1.5_wp]
    end do
    shape_table_filled = .true.
  end subroutine fill_shape_table

  !> m, n, g at x in [0, ln 1e6): cubic Hermite on the node values, slopes by central
  !> differences (second-order one-sided at the ends).
  pure subroutine shape_lookup(x, m, n, g)
    real(wp), intent(in) :: x
    real(wp), intent(out) :: m, n, g
    real(wp), parameter :: h = shape_x_max / (shape_nodes - 1)
    real(wp) :: t, h00, h10, h01, h11, d0(3), d1(3), f(3)
    integer :: j
    j = min(int(x / h) + 1, shape_nodes - 1)
    t = x / h - (j - 1)
    if (j == 1) then                ! second-order one-sided differences at the ends
      d0 = 0.5_wp * (4 * shape_table(:, 2) - 3 * shape_table(:, 1) - shape_table(:, 3))
    else
      d0 = 0.5_wp * (shape_table(:, j + 1) - shape_table(:, j - 1))
    end if
    if (j + 1 == shape_nodes) then
      d1 = 0.5_wp * (3 * shape_table(:, j + 1) - 4 * shape_table(:, j) + shape_table(:, j - 1))
    else
      d1 = 0.5_wp * (shape_table(:, j + 2) - shape_table(:, j))
    end if
    h00 = (2 * t - 3) * t * t + 1
    h10 = ((t - 2) * t + 1) * t
    h01 = t * t * (3 - 2 * t)
    h11 = t * t * (t - 1)
    f = h00 * shape_table(:, j) + h10 * d0 + h01 * shape_table(:, j + 1) + h11 * d1
    m = f(1); n = f(2); g = f(3)
  end subroutine shape_lookup

  !> Semi-axes (thesis eqs. 3.31-3.32 with the cube root over the whole bracket), peak
  !> pressure and stiffness once N and delta are known.
  pure subroutine fill_size(params, patch, major_is_x)
    type(hertz_params_t), intent(in) :: params
    type(hertz_patch_t), intent(inout) :: patch
    logical, intent(in) :: major_is_x
    real(wp) :: c, ratio
    c = (0.75_wp * patch%normal_force / (params%e_star * patch%sum_ab))**(1.0_wp / 3.0_wp)
    if (major_is_x) then
      patch%a = patch%m * c
      patch%b = patch%n * c
    else
      patch%a = patch%n * c
      patch%b = patch%m * c
    end if
    patch%p0 = 1.5_wp * patch%normal_force / (pi * patch%a * patch%b)
    patch%stiffness = 1.5_wp * patch%normal_force / patch%approach
    ratio = patch%a / patch%b
    if (ratio < 0.1_wp .or. ratio > 10.0_wp) patch%warning = ior(patch%warning, HERTZ_WARN_ELONGATED)
  end subroutine fill_size

  !> Solve B/A = [E/(1-e^2) - K] / [K - E] (A <= B) for k' = sqrt(1 - e^2) = n/m.
  !> Safeguarded Newton on x = ln k' (bisection when a step leaves the bracket), started
  !> from the classic approximation k' ~ (A/B)^(2/3); analytic slope from
  !> dK/dk = E/(k k'^2) - K/k and dE/dk = (E - K)/k (A&S 17.3.43-44). 3-4 AGM evaluations.
  pure subroutine solve_kprime(ratio, kprime, k_first, e_second)
    real(wp), intent(in) :: ratio       !< B/A >= 1
    real(wp), intent(out) :: kprime, k_first, e_second
    real(wp) :: x_lo, x_hi, x, x_new, f, slope, target, k, kp2, num, den, dnum, dden
    integer :: iter
    if (ratio <= 1.0_wp + 1.0e-10_wp) then
      kprime = 1.0_wp
      k_first = 0.5_wp * pi
      e_second = 0.5_wp * pi
      return
    end if
    if (ratio >= 1.0e10_wp) then          ! beyond B/A(k'_min) ~ 7e10: a line contact; clamp
      kprime = kprime_min
      call elliptic_ke(kprime, k_first, e_second)
      return
    end if
    target = log(ratio)
    x_lo = log(kprime_min)                ! residual > 0 there (checked above)
    x_hi = 0.0_wp                         ! residual = -target < 0 (circle)
    x = max(-2.0_wp / 3.0_wp * target, x_lo)
    do iter = 1, 40
      kprime = exp(x)
      call elliptic_ke(kprime, k_first, e_second)
      kp2 = kprime * kprime
      k = sqrt((1.0_wp - kprime) * (1.0_wp + kprime))
      num = e_second / kp2 - k_first
      den = k_first - e_second
      f = log(num / den) - target
      if (f > 0.0_wp) then                ! residual falls with x: the root lies above
        x_lo = x
      else
        x_hi = x
      end if
      ! d num/dk, d den/dk, then d f/dx with dk/dx = -k'^2/k
      dnum = k_first / k * (1.0_wp - 1.0_wp / kp2) + 2.0_wp * k * e_second / kp2**2
      dden = e_second * k / kp2
      slope = (dnum / num - dden / den) * (-kp2 / k)
      x_new = x - f / slope
      if (.not. (x_new > x_lo .and. x_new < x_hi)) x_new = 0.5_wp * (x_lo + x_hi)
      if (abs(x_new - x) < 1.0e-12_wp) exit
      x = x_new
    end do
  end subroutine solve_kprime
end module rd_hertz
