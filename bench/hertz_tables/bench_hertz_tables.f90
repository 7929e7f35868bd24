!> Hertz tables (issue 14, item 2): do the Hertz constants tabulated over the curvature
!> ratio pay against the elliptic-integral path of rd_hertz?
!>
!> The shape of a Hertz contact depends on the curvature ratio B/A only: the coefficients
!> m, n of the semi-axes and g = (2 pi m / K(e))^(3/2) of the normal force
!> (N = E*/3 g delta^(3/2) / sqrt(4 (A + B)), rd_hertz). They are tabulated here at nodes
!> uniform in x = ln(B/A) over [0, ln 1e4] (64, 256, 1024 nodes), from rd_hertz itself, and
!> interpolated by cubic Hermite with central-difference slopes. Measured:
!> - accuracy: largest relative error of N, a and b over 100 000 ratios log-uniform in
!>   [1, 1e4] (the elliptic path is the reference);
!> - cost per patch of the elliptic path (hertz_from_penetration) and of the same
!>   computation with the table lookup instead of the elliptic solve;
!> - for scale, the geometry per wheel: the strip search and the contact table
!>   (S1002 / 60E1 1:40, centred wheelset lowered 50 um);
!> - the same for rd_hertz's own tabulated path (hertz_method = 'elliptic_table': 4096 nodes
!>   over [0, ln 1e6], second-order end slopes), the default since it was measured here.
program bench_hertz_tables
  use, intrinsic :: iso_fortran_env, only: int64
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_hertz, only: hertz_params_t, hertz_patch_t, build_hertz, hertz_from_penetration
  use rd_profile, only: profile_t
  use rd_profile_source, only: load_wheel_profile, load_rail_profile
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, wheel_contact, SIDE_LEFT
  use rd_contact_table, only: contact_table_t, contact_table_options_t, build_contact_table, table_wheel_contact
  use rd_contact_patch, only: wheel_contact_t
  implicit none
  integer, parameter :: n_sizes = 3, n_samples = 100000
  integer, parameter :: sizes(n_sizes) = [64, 256, 1024]
  real(wp), parameter :: x_max = log(1.0e4_wp), a_curv = 1.0_wp, approach = 5.0e-5_wp
  type(hertz_params_t) :: hp, hp_table, hp_timed
  type(error_t), allocatable :: error
  real(wp), allocatable :: xs(:), fm(:), fn(:), fg(:), ratios(:)
  !> the geometry timed for scale (time_geometry)
  type(contact_geometry_t) :: geo
  type(contact_table_t) :: table
  type(wheel_contact_t) :: r
  real(wp) :: err(3, n_sizes), t_elliptic, t_table(n_sizes), checksum, t_strip, t_tab, err_rd(3), t_rd
  integer :: k, i

  call build_hertz(hp, error)
  if (allocated(error)) error stop error%message
  call build_hertz(hp_table, error, method='elliptic_table')
  if (allocated(error)) error stop error%message
  allocate (ratios(n_samples))
  do i = 1, n_samples
    ratios(i) = exp(x_max * sample(i))
  end do
  checksum = 0
  t_elliptic = time_hertz(hp)
  do k = 1, n_sizes
    call tabulate(sizes(k))
    err(:, k) = table_errors()
    t_table(k) = time_table()
  end do
  err_rd = rd_table_errors()
  t_rd = time_hertz(hp_table)
  call time_geometry(t_strip, t_tab)

  print '(a)', 'Hertz constants over the curvature ratio B/A in [1, 1e4]: elliptic integrals (rd_hertz, AGM, Newton on'
  print '(a)', 'k'') against tables uniform in ln(B/A), cubic Hermite. Errors: largest relative error over 100 000'
  print '(a)', 'log-uniform ratios; cost: ns per patch (N, a, b from the approach), Release build.'
  print '(a)', ''
  print '(a)', '| Hertz shape | max rel. error N | max rel. error a | max rel. error b | ns per patch | relative |'
  print '(a)', '|---|---:|---:|---:|---:|---:|'
  print '(a,f10.1,a)', '| elliptic integrals (reference) | 0 | 0 | 0 | ', t_elliptic, ' | 1.00 |'
  do k = 1, n_sizes
    print '(a,i0,a,3(es9.2,a),f10.1,a,f5.2,a)', '| table, ', sizes(k), ' nodes | ', err(1, k), ' | ', err(2, k), ' | ', &
      err(3, k), ' | ', t_table(k), ' | ', t_table(k) / t_elliptic, ' |'
  end do
  print '(a,3(es9.2,a),f10.1,a,f5.2,a)', '| rd_hertz elliptic_table (4096 nodes to 1e6, the default) | ', &
    err_rd(1), ' | ', err_rd(2), ' | ', err_rd(3), ' | ', t_rd, ' | ', t_rd / t_elliptic, ' |'
  print '(a)', ''
  print '(a,f9.1,a,f9.1,a)', 'For scale, the geometry of one wheel: strips (0.2 mm) ', t_strip, ' ns, contact table ', t_tab, ' ns.'
  if (checksum == 12345.678_wp) print *, checksum   ! keeps the timed work observable

contains

  !> Deterministic sample in [0, 1) (golden-ratio sequence: no seed to report).
  pure real(wp) function sample(i)
    integer, intent(in) :: i
    sample = modulo(0.5_wp + i * 0.6180339887498949_wp, 1.0_wp)
  end function sample

  !> Curvatures with A = a_curv along x and B = ratio A along y.
  pure function curvatures(ratio) result(c)
    real(wp), intent(in) :: ratio
    real(wp) :: c(4)
    c = [2 * a_curv, 2 * a_curv * ratio, 0.0_wp, 0.0_wp]
  end function curvatures

  subroutine tabulate(n)
    integer, intent(in) :: n
    type(hertz_patch_t) :: p
    integer :: j
    if (allocated(xs)) deallocate (xs, fm, fn, fg)
    allocate (xs(n), fm(n), fn(n), fg(n))
    do j = 1, n
      xs(j) = x_max * (j - 1) / (n - 1)
      call hertz_from_penetration(hp, curvatures(exp(xs(j))), approach, p)
      fm(j) = p%m
      fn(j) = p%n
      fg(j) = 3 * p%k_hertz * sqrt(4 * p%sum_ab) / hp%e_star
    end do
  end subroutine tabulate

  !> Cubic Hermite of f at x (uniform nodes xs, central-difference slopes).
  pure real(wp) function lookup(f, x) result(v)
    real(wp), intent(in) :: f(:), x
    real(wp) :: h, t, d0, d1
    integer :: n, j
    n = size(f)
    h = xs(2) - xs(1)
    j = min(max(int(x / h) + 1, 1), n - 1)
    t = x / h - (j - 1)
    d0 = 0.5_wp * (f(min(j + 1, n)) - f(max(j - 1, 1))) * merge(2.0_wp, 1.0_wp, j == 1)
    d1 = 0.5_wp * (f(min(j + 2, n)) - f(j)) * merge(2.0_wp, 1.0_wp, j + 1 == n)
    v = ((2 * t - 3) * t * t + 1) * f(j) + t * t * (3 - 2 * t) * f(j + 1) + ((t - 2) * t + 1) * t * d0 + &
        t * t * (t - 1) * d1
  end function lookup

  !> N, a, b with the table: the same steps as hertz_from_penetration without the elliptic solve.
  pure subroutine table_patch(curv, delta, nf, a, b)
    real(wp), intent(in) :: curv(4), delta
    real(wp), intent(out) :: nf, a, b
    real(wp) :: ax, ay, x, m, n, g, c
    ax = max(0.5_wp * (curv(1) + curv(3)), hp%curvature_min)
    ay = max(0.5_wp * (curv(2) + curv(4)), hp%curvature_min)
    x = abs(log(ay / ax))
    m = lookup(fm, x); n = lookup(fn, x); g = lookup(fg, x)
    nf = hp%e_star / 3 * g / sqrt(4 * (ax + ay)) * delta * sqrt(delta)
    c = (0.75_wp * nf / (hp%e_star * (ax + ay)))**(1.0_wp / 3.0_wp)
    if (ax <= ay) then
      a = m * c; b = n * c
    else
      a = n * c; b = m * c
    end if
  end subroutine table_patch

  function table_errors() result(e)
    real(wp) :: e(3)
    type(hertz_patch_t) :: p
    real(wp) :: nf, a, b
    integer :: i
    e = 0
    do i = 1, n_samples
      call hertz_from_penetration(hp, curvatures(ratios(i)), approach, p)
      call table_patch(curvatures(ratios(i)), approach, nf, a, b)
      e = max(e, abs([nf / p%normal_force, a / p%a, b / p%b] - 1))
    end do
  end function table_errors

  !> rd_hertz's elliptic_table against its elliptic path over the same ratios.
  function rd_table_errors() result(e)
    real(wp) :: e(3)
    type(hertz_patch_t) :: p, q
    integer :: i
    e = 0
    do i = 1, n_samples
      call hertz_from_penetration(hp, curvatures(ratios(i)), approach, p)
      call hertz_from_penetration(hp_table, curvatures(ratios(i)), approach, q)
      e = max(e, abs([q%normal_force / p%normal_force, q%a / p%a, q%b / p%b] - 1))
    end do
  end function rd_table_errors

  !> ns per call of work(i), repeating until at least 0.3 s has elapsed.
  real(wp) function time_per_call(work) result(ns)
    interface
      subroutine work(i)
        import :: int64
        integer(int64), intent(in) :: i
      end subroutine work
    end interface
    integer(int64) :: t0, t1, rate, calls, i
    calls = 256
    do
      call system_clock(t0, rate)
      do i = 1, calls
        call work(i)
      end do
      call system_clock(t1)
      if (real(t1 - t0, wp) / rate > 0.3_wp) exit
      calls = calls * 2
    end do
    ns = 1.0e9_wp * real(t1 - t0, wp) / rate / calls
  end function time_per_call

  !> ns per patch of rd_hertz with the given parameters (its method).
  real(wp) function time_hertz(params) result(ns)
    type(hertz_params_t), intent(in) :: params
    hp_timed = params
    ns = time_per_call(one_hertz)
  end function time_hertz

  real(wp) function time_table() result(ns)
    ns = time_per_call(one_table)
  end function time_table

  subroutine one_hertz(i)
    integer(int64), intent(in) :: i
    type(hertz_patch_t) :: p
    call hertz_from_penetration(hp_timed, curvatures(ratios(int(mod(i, int(n_samples, int64))) + 1)), approach, p)
    checksum = checksum + p%a
  end subroutine one_hertz

  subroutine one_table(i)
    integer(int64), intent(in) :: i
    real(wp) :: nf, a, b
    call table_patch(curvatures(ratios(int(mod(i, int(n_samples, int64))) + 1)), approach, nf, a, b)
    checksum = checksum + a
  end subroutine one_table

  !> ns per wheel of the strip search and of the contact table near the centred pose.
  subroutine time_geometry(ns_strip, ns_table)
    real(wp), intent(out) :: ns_strip, ns_table
    type(profile_t) :: wheel, rail
    type(track_placement_t) :: pl
    type(surface_options_t) :: opt
    type(contact_table_options_t) :: topt
    call load_wheel_profile('s1002', wheel, error, 2.0e-4_wp)
    if (allocated(error)) error stop error%message
    call load_rail_profile('60e1', rail, error, 2.0e-4_wp)
    if (allocated(error)) error stop error%message
    call build_strip_contact(geo, wheel, rail, pl, opt, error)
    if (allocated(error)) error stop error%message
    call build_contact_table(geo%wheel, geo%rail, topt, table, error)
    if (allocated(error)) error stop error%message
    ns_strip = time_per_call(one_strip)
    ns_table = time_per_call(one_table_wheel)
  end subroutine time_geometry

  subroutine one_strip(i)
    integer(int64), intent(in) :: i
    call wheel_contact(geo, SIDE_LEFT, 1.0e-3_wp * sample(int(i)), 0.46_wp - 5.0e-5_wp, 0.0_wp, 1.0e-3_wp, r)
    checksum = checksum + r%max_penetration
  end subroutine one_strip

  subroutine one_table_wheel(i)
    integer(int64), intent(in) :: i
    call table_wheel_contact(table, 1.0e-3_wp * sample(int(i)), 0.46_wp - 5.0e-5_wp, 0.0_wp, 1.0e-3_wp, r)
    checksum = checksum + r%max_penetration
  end subroutine one_table_wheel
end program bench_hertz_tables
