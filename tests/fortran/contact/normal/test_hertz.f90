!> Hertz normal contact against closed forms and published data (oracles.md):
!> K, E at k = 1/sqrt(2) (A&S table 17.1), m and n against the elliptic-integral table,
!> the worked example (0.46 m wheel on a 300 mm crown), N ~ delta^1.5, the force <->
!> penetration round trip, the sphere closed form, the conformal fallback and no contact;
!> the tabulated elliptic path ('elliptic_table') against the elliptic path itself.
program test_hertz
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t
  use rd_elliptic_integrals, only: elliptic_ke
  use rd_hertz
  use rd_test_support, only: check, check_close, fail, test_summary
  implicit none
  type(hertz_params_t) :: params, params_table
  type(hertz_patch_t) :: patch, patch2
  type(error_t), allocatable :: error
  integer :: i
  real(wp) :: kk, ee, c, ratio, slope, e_star, r, delta_sphere, a_sphere, mt, nt
  real(wp), parameter :: theta_deg(10) = [1.0_wp, 5.0_wp, 10.0_wp, 20.0_wp, 30.0_wp, 45.0_wp, &
                                           60.0_wp, 70.0_wp, 80.0_wp, 90.0_wp]
  real(wp), parameter :: m_ref(10) = [36.932_wp, 11.238_wp, 6.6115_wp, 3.8160_wp, 2.7306_wp, &
                                      1.9265_wp, 1.4858_wp, 1.2851_wp, 1.1278_wp, 1.0_wp]
  real(wp), parameter :: n_ref(10) = [0.1313_wp, 0.2381_wp, 0.3110_wp, 0.4121_wp, 0.4931_wp, &
                                      0.6038_wp, 0.7171_wp, 0.7999_wp, 0.8927_wp, 1.0_wp]
  real(wp) :: curv(4)

  ! --- elliptic integrals: A&S table 17.1, m = k^2 = 0.5
  call elliptic_ke(sqrt(0.5_wp), kk, ee)
  call check_close(kk, 1.8540746773013719_wp, 1.0e-14_wp, 'K(1/sqrt2)')
  call check_close(ee, 1.3506438810476755_wp, 1.0e-14_wp, 'E(1/sqrt2)')
  call elliptic_ke(1.0_wp, kk, ee)
  call check_close(kk, pi / 2, 1.0e-15_wp, 'K(0)')
  call check_close(ee, pi / 2, 1.0e-15_wp, 'E(0)')

  ! --- m, n against the oracle table for every theta listed
  call build_hertz(params, error, young_wheel=210.0e9_wp, poisson_wheel=0.28_wp)
  if (allocated(error)) call fail_now(error%message)
  call build_hertz(params_table, error, young_wheel=210.0e9_wp, poisson_wheel=0.28_wp, method='table')
  if (allocated(error)) call fail_now(error%message)
  do i = 1, size(theta_deg)
    c = cos(theta_deg(i) * pi / 180.0_wp)
    ratio = (1.0_wp + c) / (1.0_wp - c)           ! B/A giving this theta
    curv = [2.0_wp, 2.0_wp * ratio, 0.0_wp, 0.0_wp]  ! A = 1, B = ratio
    call hertz_from_force(params, curv, 1.0e4_wp, patch)
    call check_close(patch%m, m_ref(i), 2.0e-4_wp, 'm(theta)')
    call check_close(patch%n, n_ref(i), 5.0e-4_wp, 'n(theta)')
    call check_close(patch%theta * 180.0_wp / pi, theta_deg(i), 1.0e-9_wp, 'theta')
    ! A < B: the major axis lies along x, so a/b = m/n
    call check_close(patch%a / patch%b, patch%m / patch%n, 1.0e-12_wp, 'a/b = m/n')
    ! printed table: agrees within its 1-2 % (oracles.md) at its tabulated angles >= 10 deg;
    ! between its 4 and 6 deg rows linear interpolation alone errs by ~3 % (see theory doc)
    call hertz_from_force(params_table, curv, 1.0e4_wp, patch2)
    if (theta_deg(i) >= 10.0_wp) then
      call check_close(patch2%m, patch%m, 0.02_wp, 'table m')
      call check_close(patch2%n, patch%n, 0.02_wp, 'table n')
      call check_close(patch2%a, patch%a, 0.02_wp, 'table a')
    end if
  end do
  ! swapping the curvatures swaps the axes: a is always along x
  call hertz_from_force(params, [2.0_wp, 6.0_wp, 0.0_wp, 0.0_wp], 1.0e4_wp, patch)
  call hertz_from_force(params, [6.0_wp, 2.0_wp, 0.0_wp, 0.0_wp], 1.0e4_wp, patch2)
  call check_close(patch%a, patch2%b, 1.0e-12_wp, 'swap a<->b')
  call check_close(patch%b, patch2%a, 1.0e-12_wp, 'swap b<->a')
  if (.not. (patch%a > patch%b)) call fail('a along the smaller curvature is the major axis')

  ! --- worked example: 0.46 m wheel (flat across), 300 mm rail crown, N = 100 kN
  curv = [1.0_wp / 0.46_wp, 0.0_wp, 0.0_wp, 1.0_wp / 0.3_wp]
  call hertz_from_force(params, curv, 1.0e5_wp, patch)
  call check_close(patch%a, 7.19e-3_wp, 0.01_wp, 'example a')
  call check_close(patch%b, 5.41e-3_wp, 0.01_wp, 'example b')
  call check_close(patch%p0, 1227.0e6_wp, 0.01_wp, 'example p0')
  call check_close(patch%approach, 105.0e-6_wp, 0.01_wp, 'example approach')
  call check_close(patch%stiffness, 1.43e9_wp, 0.01_wp, 'example stiffness')
  if (patch%warning /= 0) call fail('worked example must not warn')
  ! stiffness = dN/d delta by central difference (independent of the 1.5 N/delta formula)
  call hertz_from_penetration(params, curv, patch%approach * 1.001_wp, patch2)
  slope = patch2%normal_force
  call hertz_from_penetration(params, curv, patch%approach * 0.999_wp, patch2)
  slope = (slope - patch2%normal_force) / (0.002_wp * patch%approach)
  call check_close(patch%stiffness, slope, 1.0e-5_wp, 'dN/ddelta numeric')

  ! --- N ~ delta^1.5: log-log slope over two decades; round trip
  call hertz_from_penetration(params, curv, 1.0e-6_wp, patch)
  call hertz_from_penetration(params, curv, 1.0e-4_wp, patch2)
  slope = log(patch2%normal_force / patch%normal_force) / log(100.0_wp)
  call check_close(slope, 1.5_wp, 1.0e-12_wp, 'log-log slope')
  call hertz_from_force(params, curv, patch2%normal_force, patch)
  call check_close(patch%approach, 1.0e-4_wp, 1.0e-12_wp, 'round trip approach')
  call check_close(patch%a, patch2%a, 1.0e-12_wp, 'round trip a')

  ! --- sphere on flat (closed form, Johnson 4.22): a^3 = 3NR/(4E*), delta = a^2/R
  r = 0.02_wp
  e_star = params%e_star
  call hertz_from_force(params, [1.0_wp / r, 1.0_wp / r, 0.0_wp, 0.0_wp], 500.0_wp, patch)
  a_sphere = (3.0_wp * 500.0_wp * r / (4.0_wp * e_star))**(1.0_wp / 3.0_wp)
  delta_sphere = a_sphere**2 / r
  call check_close(patch%a, a_sphere, 1.0e-12_wp, 'sphere a')
  call check_close(patch%b, a_sphere, 1.0e-12_wp, 'sphere b')
  call check_close(patch%approach, delta_sphere, 1.0e-12_wp, 'sphere delta')
  ! nearly circular (B/A = 1 + 1e-9): continuous with the circle
  call hertz_from_force(params, [1.0_wp / r, 1.0_wp / r * (1.0_wp + 1.0e-9_wp), 0.0_wp, 0.0_wp], 500.0_wp, patch)
  call check_close(patch%a, a_sphere, 1.0e-8_wp, 'near-circle a')

  ! --- conformal / concave: wheel throat (concave, R = -14 mm) on gauge corner (R = 13 mm):
  ! relative lateral curvature negative -> clamped, flagged, finite
  curv = [1.0_wp / 0.46_wp, -1.0_wp / 0.013_wp, 0.0_wp, 1.0_wp / 0.014_wp]
  call hertz_from_force(params, curv, 2.0e4_wp, patch)
  if (iand(patch%warning, HERTZ_WARN_CLAMPED_LATERAL) == 0) call fail('conformal case must set the warning flag')
  if (.not. all_finite(patch)) call fail('conformal case must stay finite')
  if (.not. (patch%a > 0.0_wp .and. patch%b > patch%a)) call fail('conformal case: b > a > 0 expected')
  ! both directions flat (cone on flat rail): both clamped, still finite
  call hertz_from_penetration(params, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], 1.0e-5_wp, patch)
  if (iand(patch%warning, HERTZ_WARN_CLAMPED_ROLLING) == 0) call fail('flat case must flag the rolling clamp')
  if (.not. all_finite(patch)) call fail('flat case must stay finite')
  ! a very elongated ellipse is flagged (outside Kalker's a/b table)
  call hertz_from_force(params, [1.0_wp, 1000.0_wp, 0.0_wp, 0.0_wp], 1.0e4_wp, patch)
  if (iand(patch%warning, HERTZ_WARN_ELONGATED) == 0) call fail('a/b > 10 must be flagged')
  if (.not. all_finite(patch)) call fail('elongated case must stay finite')
  ! NaN input: flagged, zero patch
  curv(2) = ieee_nan()
  call hertz_from_force(params, curv, 1.0e4_wp, patch)
  if (iand(patch%warning, HERTZ_WARN_BAD_INPUT) == 0 .or. patch%a /= 0.0_wp) call fail('NaN input must be flagged')

  ! --- no contact
  call hertz_from_penetration(params, [2.0_wp, 3.0_wp, 0.0_wp, 0.0_wp], -1.0e-6_wp, patch)
  if (patch%in_contact .or. patch%normal_force /= 0.0_wp .or. patch%a /= 0.0_wp .or. patch%b /= 0.0_wp) &
    call fail('no contact must give zero patch')
  call hertz_from_penetration(params, [2.0_wp, 3.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, patch)
  if (patch%normal_force /= 0.0_wp .or. patch%p0 /= 0.0_wp) call fail('delta = 0 must give zero patch')

  ! --- damping: adds c * rate, never pulls, nothing without elastic contact
  call check_close(hertz_damped_force(1000.0_wp, 1.0e4_wp, 0.01_wp), 1100.0_wp, 1.0e-15_wp, 'damped')
  if (hertz_damped_force(1000.0_wp, 1.0e4_wp, -1.0_wp) /= 0.0_wp) call fail('damping must not pull')
  if (hertz_damped_force(0.0_wp, 1.0e4_wp, 1.0_wp) /= 0.0_wp) call fail('no damping without contact')
  ! the viscous term is bounded by the elastic force: N in [0, 2 N_el] (closed form)
  call check(hertz_damped_force(1000.0_wp, 1.0e4_wp, 1.0_wp) == 2000.0_wp, 'damping bounded by N_el when closing fast')
  call check(hertz_damped_force(1000.0_wp, 1.0e4_wp, -0.05_wp) == 500.0_wp, 'damping unbounded below N_el when opening')

  ! --- bad parameters
  call build_hertz(params, error, young_wheel=-1.0_wp)
  if (.not. allocated(error)) call fail('negative E must be refused')
  call build_hertz(params, error, method='spline')
  if (.not. allocated(error)) call fail('unknown method must be refused')
  ! default material G = 82 GPa, nu = 0.28
  call build_hertz(params, error)
  call check_close(params%shear_modulus, 82.0e9_wp, 1.0e-12_wp, 'default G')
  call check_close(params%poisson, 0.28_wp, 1.0e-12_wp, 'default nu')
  call build_hertz(params, error, shear_modulus=80.0e9_wp, poisson_wheel=0.3_wp)
  call check_close(params%e_star, 2.0_wp * 80.0e9_wp * 1.3_wp / (2.0_wp * (1.0_wp - 0.09_wp)), 1.0e-12_wp, 'G given: E*')
  call check_close(params%shear_modulus, 80.0e9_wp, 1.0e-12_wp, 'G given: G')

  call check_elliptic_table()
  call check_conformal_floor_c1()

  call test_summary('test_hertz')

contains

  !> The conformal floor is C1 (rd_hertz curvature_floor): the lateral semi-axis b at a fixed
  !> load along the relative lateral curvature B through the floor's ends B = A_min / 2,
  !> 3 A_min / 2 and through A_min: the second difference of b falls by ~4 when the step
  !> halves (C1: O(h^2); at a kink of b, O(h): ~2, what the hard max(B, A_min) gave at A_min);
  !> below A_min / 2 b is that of A_min and above 3 A_min / 2 that of B itself, and the clamp
  !> bit is set below A_min only.
  subroutine check_conformal_floor_c1()
    type(hertz_params_t) :: p, p_free
    type(hertz_patch_t) :: q, q0
    type(error_t), allocatable :: err
    real(wp) :: cmin, x, h, d2(2)
    integer :: k, m
    call build_hertz(p, err)
    if (allocated(err)) call fail_now(err%message)
    cmin = p%curvature_min
    do k = 1, 3
      x = 0.5_wp * k * cmin
      do m = 1, 2
        h = 0.01_wp * cmin / m
        d2(m) = semi_b(p, x + h) - 2.0_wp * semi_b(p, x) + semi_b(p, x - h)
      end do
      call check(abs(d2(1)) > 0 .and. abs(d2(1) / d2(2)) > 3.0_wp, 'conformal floor C1 at B = ' // &
                 achar(iachar('0') + k) // '/2 A_min')
    end do
    ! the floor's ends, against a model whose floor lies far below (R_max 1e6 m): A_min itself
    ! below A_min / 2, the curvature itself above 3 A_min / 2
    call build_hertz(p_free, err, max_equivalent_radius=1.0e6_wp)
    if (allocated(err)) call fail_now(err%message)
    call hertz_from_force(p, [1.0_wp / 0.46_wp, 2.0_wp * 0.2_wp * cmin, 0.0_wp, 0.0_wp], 2.0e4_wp, q)
    call hertz_from_force(p_free, [1.0_wp / 0.46_wp, 2.0_wp * cmin, 0.0_wp, 0.0_wp], 2.0e4_wp, q0)
    call check_close(q%b, q0%b, 1.0e-14_wp, 'conformal floor: A_min below A_min / 2')
    call check(iand(q%warning, HERTZ_WARN_CLAMPED_LATERAL) /= 0, 'conformal floor: flagged below A_min')
    call hertz_from_force(p, [1.0_wp / 0.46_wp, 2.0_wp * 1.6_wp * cmin, 0.0_wp, 0.0_wp], 2.0e4_wp, q)
    call hertz_from_force(p_free, [1.0_wp / 0.46_wp, 2.0_wp * 1.6_wp * cmin, 0.0_wp, 0.0_wp], 2.0e4_wp, q0)
    call check_close(q%b, q0%b, 1.0e-14_wp, 'conformal floor: the curvature itself above 3 A_min / 2')
    call check(iand(q%warning, HERTZ_WARN_CLAMPED_LATERAL) == 0, 'conformal floor: no flag above A_min')
  end subroutine check_conformal_floor_c1

  !> The lateral semi-axis at 20 kN for the relative lateral curvature bb (the wheel's lateral
  !> curvature 2 bb on a laterally flat rail, a 0.46 m wheel)
  real(wp) function semi_b(p, bb)
    type(hertz_params_t), intent(in) :: p
    real(wp), intent(in) :: bb
    type(hertz_patch_t) :: s
    call hertz_from_force(p, [1.0_wp / 0.46_wp, 2.0_wp * bb, 0.0_wp, 0.0_wp], 2.0e4_wp, s)
    semi_b = s%b
  end function semi_b

  !> 'elliptic_table' against 'elliptic' (the path it tabulates): N, a, b, approach and the
  !> warning bits over 20 000 ratios B/A log-uniform in [1, 1e8] (beyond ln 1e6 the table hands
  !> over to the elliptic path), both orientations, from the approach and from the force; the
  !> largest relative difference must be below 1e-9 (measured 2.3e-10 with the table's 4096 nodes
  !> and second-order end slopes; first-order end slopes gave 1.9e-7, so this fails them, and
  !> the h^4 error of a 4x coarser table, ~6e-8, too).
  subroutine check_elliptic_table()
    type(hertz_params_t) :: exact, tabulated
    type(hertz_patch_t) :: pe, pt
    real(wp) :: worst, ratio, cv(4)
    integer :: k
    call build_hertz(exact, error)
    call build_hertz(tabulated, error, method='elliptic_table')
    if (allocated(error)) call fail_now('elliptic_table refused: ' // error%message)
    worst = 0
    do k = 0, 19999
      ratio = exp(log(1.0e8_wp) * modulo(0.5_wp + k * 0.6180339887498949_wp, 1.0_wp))
      cv = [3.0_wp, 3.0_wp * ratio, 0.5_wp, 0.5_wp * ratio]          ! A along x, B = ratio A along y
      if (mod(k, 2) == 1) cv = [cv(2), cv(1), cv(4), cv(3)]          ! and the other way round
      call hertz_from_penetration(exact, cv, 7.0e-5_wp, pe)
      call hertz_from_penetration(tabulated, cv, 7.0e-5_wp, pt)
      worst = max(worst, rel(pt%normal_force, pe%normal_force), rel(pt%a, pe%a), rel(pt%b, pe%b))
      if (pt%warning /= pe%warning) call fail('elliptic_table: warning bits differ')
      call hertz_from_force(exact, cv, 9.0e4_wp, pe)
      call hertz_from_force(tabulated, cv, 9.0e4_wp, pt)
      worst = max(worst, rel(pt%approach, pe%approach), rel(pt%a, pe%a), rel(pt%b, pe%b))
    end do
    print '(a, es9.2)', 'elliptic_table against elliptic, largest relative difference: ', worst
    call check(worst < 1.0e-9_wp, 'elliptic_table within 1e-9 of the elliptic path')
  end subroutine check_elliptic_table

  pure real(wp) function rel(x, reference)
    real(wp), intent(in) :: x, reference
    rel = abs(x / reference - 1)
  end function rel

  subroutine fail_now(message)
    character(len=*), intent(in) :: message
    print '(a)', 'FAIL: ' // message
    error stop 1
  end subroutine fail_now

  logical function all_finite(p)
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    type(hertz_patch_t), intent(in) :: p
    real(wp) :: v(8)
    v = [p%a, p%b, p%normal_force, p%approach, p%p0, p%stiffness, p%m, p%n]
    all_finite = all(ieee_is_finite(v))
  end function all_finite

  function ieee_nan() result(x)
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    real(wp) :: x
    x = ieee_value(x, ieee_quiet_nan)
  end function ieee_nan
end program test_hertz
