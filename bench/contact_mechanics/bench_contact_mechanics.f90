!> Cost per call of the Hertz step and of each creep law (FASTSIM at grids 5, 10, 20, 40),
!> and the error of each law against CONTACT's exact-theory rows of
!> validation/reference/oracles.md (a = 6 mm, b = 4 mm, N = 50 kN, G = 82 GPa, nu = 0.28,
!> mu = 0.3). Prints a markdown section for docs/performance.md (see run.sh).
program bench_contact_mechanics
  use, intrinsic :: iso_fortran_env, only: int64, compiler_version, compiler_options
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_hertz
  use rd_creep_law
  use rd_creep_factory, only: build_creep_law
  implicit none
  integer, parameter :: n_laws = 7
  character(len=24), parameter :: law_label(n_laws) = [character(len=24) :: 'linear', 'linear + SHE', &
    'polach', 'fastsim 5x5', 'fastsim 10x10', 'fastsim 20x20', 'fastsim 40x40']
  ! exact rows (oracles.md) in SI: creepages (xi, eta, phi[1/m]) and forces (Fx, Fy, Mz[N m])
  real(wp), parameter :: row_creep(3, 5) = reshape([1.0e-3_wp, 0.0_wp, 0.0_wp, 3.0e-3_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 1.0e-3_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.1_wp, 1.0e-3_wp, 1.0e-3_wp, 0.1_wp], [3, 5])
  real(wp), parameter :: row_force(3, 5) = reshape([-7668.0_wp, 0.0_wp, 0.0_wp, -14480.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, -7175.0_wp, 10.620_wp, 0.0_wp, -1982.0_wp, -4.172_wp, -6927.0_wp, -8196.0_wp, 3.598_wp], [3, 5])
  ! the columns of the error table: (row, component)
  integer, parameter :: n_cols = 9
  integer, parameter :: col_row(n_cols) = [1, 2, 3, 3, 4, 4, 5, 5, 5]
  integer, parameter :: col_comp(n_cols) = [1, 1, 2, 3, 2, 3, 1, 2, 3]
  class(creep_law_t), allocatable :: law
  type(creep_law_options_t) :: options
  type(error_t), allocatable :: error
  type(creep_patch_t) :: patch
  type(creep_force_t) :: force
  type(creepage_t) :: creep
  type(hertz_params_t) :: hp, hp_table
  type(hertz_patch_t) :: hpatch
  real(wp) :: ns(n_laws), err(n_cols, n_laws), got(3), checksum, t_hertz(3)
  integer :: k, j

  patch = creep_patch_t(a=6.0e-3_wp, b=4.0e-3_wp, normal_force=5.0e4_wp, shear_modulus=82.0e9_wp, &
                          poisson=0.28_wp, friction=0.3_wp)
  checksum = 0.0_wp
  do k = 1, n_laws
    call build_law(k)
    ns(k) = time_law()
    do j = 1, n_cols
      creep%xi = row_creep(1, col_row(j)); creep%eta = row_creep(2, col_row(j)); creep%phi = row_creep(3, col_row(j))
      call law%compute(patch, creep, force)
      got = [force%fx, force%fy, force%mz]
      err(j, k) = 100.0_wp * (got(col_comp(j)) / row_force(col_comp(j), col_row(j)) - 1.0_wp)
    end do
  end do
  call build_hertz(hp, error)
  call build_hertz(hp_table, error, method='table')
  t_hertz(1) = time_hertz(hp, .true.)
  t_hertz(2) = time_hertz(hp, .false.)
  t_hertz(3) = time_hertz(hp_table, .true.)

  print '(a)', '### Contact mechanics (bench/contact_mechanics)'
  print '(a)', ''
  print '(a)', 'Cost per call (one contact patch), Release build, ' // compiler_version() // '.'
  print '(a)', 'Creep laws at mixed creepage around xi = eta = 1e-3, phi = 0.1/m (partly slipping patch).'
  print '(a)', ''
  print '(a)', '| step | ns per call | relative to linear |'
  print '(a)', '|---|---:|---:|'
  print '(a,f10.1,a,f8.1,a)', '| hertz from force (elliptic, AGM) | ', t_hertz(1), ' | ', t_hertz(1) / ns(1), ' |'
  print '(a,f10.1,a,f8.1,a)', '| hertz from penetration (elliptic) | ', t_hertz(2), ' | ', t_hertz(2) / ns(1), ' |'
  print '(a,f10.1,a,f8.1,a)', '| hertz from force (table) | ', t_hertz(3), ' | ', t_hertz(3) / ns(1), ' |'
  do k = 1, n_laws
    print '(a,a,a,f10.1,a,f8.1,a)', '| ', trim(law_label(k)), ' | ', ns(k), ' | ', ns(k) / ns(1), ' |'
  end do
  print '(a)', ''
  print '(a)', 'Error [%] against CONTACT''s exact theory (oracles.md rows; a = 6 mm, b = 4 mm, N = 50 kN, mu = 0.3).'
  print '(a)', 'Columns: Fx at xi = 1e-3, 3e-3; Fy, Mz at eta = 1e-3; Fy, Mz at phi = 0.1/m; Fx, Fy, Mz at'
  print '(a)', '(xi, eta, phi) = (1e-3, 1e-3, 0.1/m). Polach''s Mz is the saturation-scaled linear Mz.'
  print '(a)', ''
  print '(a)', '| law | Fx 1e-3 | Fx 3e-3 | Fy eta | Mz eta | Fy phi | Mz phi | Fx comb | Fy comb | Mz comb |'
  print '(a)', '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|'
  do k = 1, n_laws
    print '(a,a,a,9(f7.1,a))', '| ', trim(law_label(k)), ' |', (err(j, k), ' |', j = 1, n_cols)
  end do
  if (checksum == 12345.678_wp) print *, checksum   ! keeps the timed work observable

contains

  subroutine build_law(k)
    integer, intent(in) :: k
    integer, parameter :: grids(4) = [5, 10, 20, 40]
    options = creep_law_options_t()
    select case (k)
    case (1); call build_creep_law('linear', options, law, error)
    case (2); options%saturation = 'shen_hedrick_elkins'; call build_creep_law('linear', options, law, error)
    case (3); call build_creep_law('polach', options, law, error)
    case default
      options%grid_nx = grids(k - 3); options%grid_ny = grids(k - 3)
      call build_creep_law('fastsim', options, law, error)
    end select
    if (allocated(error)) error stop 1
  end subroutine build_law

  !> ns per call, repeating until at least 0.2 s has elapsed.
  real(wp) function time_law() result(ns_per_call)
    integer(int64) :: t0, t1, rate, calls, i
    calls = 256
    do
      call system_clock(t0, rate)
      do i = 1, calls
        creep%xi = 1.0e-3_wp * (1.0_wp + 1.0e-3_wp * mod(i, 7_int64))
        creep%eta = -1.0e-3_wp * (1.0_wp + 1.0e-3_wp * mod(i, 5_int64))
        creep%phi = 0.1_wp
        call law%compute(patch, creep, force)
        checksum = checksum + force%fx
      end do
      call system_clock(t1)
      if (real(t1 - t0, wp) / rate > 0.2_wp) exit
      calls = calls * 2
    end do
    ns_per_call = 1.0e9_wp * real(t1 - t0, wp) / rate / calls
  end function time_law

  real(wp) function time_hertz(params, by_force) result(ns_per_call)
    type(hertz_params_t), intent(in) :: params
    logical, intent(in) :: by_force
    integer(int64) :: t0, t1, rate, calls, i
    real(wp) :: curv(4)
    calls = 256
    do
      call system_clock(t0, rate)
      do i = 1, calls
        curv = [2.17_wp, -1.0_wp + 0.01_wp * mod(i, 11_int64), 0.0_wp, 3.33_wp]
        if (by_force) then
          call hertz_from_force(params, curv, 1.0e5_wp, hpatch)
        else
          call hertz_from_penetration(params, curv, 1.0e-4_wp, hpatch)
        end if
        checksum = checksum + hpatch%a
      end do
      call system_clock(t1)
      if (real(t1 - t0, wp) / rate > 0.2_wp) exit
      calls = calls * 2
    end do
    ns_per_call = 1.0e9_wp * real(t1 - t0, wp) / rate / calls
  end function time_hertz
end program bench_contact_mechanics
