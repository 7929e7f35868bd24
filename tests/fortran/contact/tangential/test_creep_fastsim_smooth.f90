!> FASTSIM with the smooth clip (`fastsim_saturation_width` w > 0, rd_creep_fastsim) against
!> classic FASTSIM (w = 0) and Kalker's exact theory (kalker_exact_reference, the test's own
!> half-space solver):
!> 1. smoothness: along a creepage sweep through partial slip (xi 0..4e-3 with eta and spin,
!>    a 6 x 4 mm patch) rd_sweep_smoothness finds kinks in classic FASTSIM's Fx and Fy (one
!>    per element entering slip) and none with w = 0.2;
!> 2. accuracy: on the CONTACT rows of oracles.md in partial and full slip and on the TGV
!>    scenes' tread and flange patches (as test_creep_spin_exact), the smooth law is as close
!>    to the exact theory as classic FASTSIM, within 2 % of the exact force (the clip lowers
!>    partial-slip tractions by at most w/4 of the bound);
!> 3. outside the clip's band nothing changes: the linear range (all elements adhering) and
!>    full slip (all sliding) equal classic FASTSIM to rounding.
program test_creep_fastsim_smooth
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_creep_law
  use rd_creep_factory, only: build_creep_law
  use rd_sweep_smoothness, only: smoothness_feature_t, find_jumps_and_kinks
  use kalker_exact_reference, only: kalker_exact_forces, scene_patch_count, scene_name, scene, scene_grid, &
                                    scene_is_flange
  use rd_test_support, only: check, test_summary
  implicit none
  integer, parameter :: n_sweep = 801
  type(creep_law_options_t) :: options
  class(creep_law_t), allocatable :: classic, smooth
  type(error_t), allocatable :: error
  type(creep_patch_t) :: patch
  type(creep_force_t) :: fc, fs
  type(smoothness_feature_t), allocatable :: feat(:)
  real(wp) :: x(n_sweep), f(n_sweep, 4), fx, fy, mz, err_c, err_s
  integer :: i, k, kinks(4)
  real(wp), parameter :: contact_creep(3, 5) = reshape([ &
    1.0e-3_wp, 0.0_wp, 0.0_wp, 3.0e-3_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0e-3_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.1_wp, 1.0e-3_wp, 1.0e-3_wp, 0.1_wp], [3, 5])

  options%grid_nx = 10; options%grid_ny = 10
  call build_creep_law('fastsim', options, classic, error)
  if (allocated(error)) error stop 1
  options%saturation_width = 0.2_wp
  call build_creep_law('fastsim', options, smooth, error)
  if (allocated(error)) error stop 1
  print '(a)', 'laws: ' // classic%name() // ' | ' // smooth%name()

  ! --- 1. smoothness along a creepage sweep
  patch = creep_patch_t(a=6.0e-3_wp, b=4.0e-3_wp, normal_force=5.0e4_wp, shear_modulus=82.0e9_wp, &
                          poisson=0.28_wp, friction=0.3_wp)
  do i = 1, n_sweep
    x(i) = 4.0e-3_wp * (i - 1) / (n_sweep - 1)
    call classic%compute(patch, creepage_t(xi=x(i), eta=5.0e-4_wp, phi=0.3_wp), fc)
    call smooth%compute(patch, creepage_t(xi=x(i), eta=5.0e-4_wp, phi=0.3_wp), fs)
    f(i, :) = [fc%fx, fc%fy, fs%fx, fs%fy]
  end do
  do k = 1, 4
    call find_jumps_and_kinks(x, f(:, k), 0.3_wp * 5.0e4_wp, feat, error)
    if (allocated(error)) error stop 1
    kinks(k) = size(feat)
  end do
  print '(a,2i5,a,2i5)', 'kinks along xi: classic Fx, Fy', kinks(1:2), '; smooth Fx, Fy', kinks(3:4)
  call check(kinks(1) + kinks(2) > 0, 'classic FASTSIM kinks along the sweep (the detector sees them)')
  call check(kinks(3) + kinks(4) == 0, 'smooth FASTSIM has no kink along the sweep')

  ! --- 2. accuracy against the exact theory
  print '(a)', 'case                 exact Fx, Fy [N]        classic          smooth       err classic, smooth'
  do i = 1, 5
    call kalker_exact_forces(6.0e-3_wp, 4.0e-3_wp, 5.0e4_wp, 82.0e9_wp, 0.28_wp, 0.3_wp, contact_creep(1, i), &
                             contact_creep(2, i), contact_creep(3, i), 20, 20, fx, fy, mz)
    call classic%compute(patch, creepage_t(contact_creep(1, i), contact_creep(2, i), contact_creep(3, i)), fc)
    call smooth%compute(patch, creepage_t(contact_creep(1, i), contact_creep(2, i), contact_creep(3, i)), fs)
    call compare('CONTACT row', i)
  end do
  do i = 1, scene_patch_count
    patch = creep_patch_t(a=scene(1, i), b=scene(2, i), normal_force=scene(3, i), shear_modulus=8.4e10_wp, &
                            poisson=0.25_wp, friction=0.45_wp)
    call kalker_exact_forces(patch%a, patch%b, patch%normal_force, patch%shear_modulus, patch%poisson, &
                             patch%friction, scene(4, i), scene(5, i), scene(6, i), scene_grid(1, i), &
                             scene_grid(2, i), fx, fy, mz)
    call classic%compute(patch, creepage_t(scene(4, i), scene(5, i), scene(6, i)), fc)
    call smooth%compute(patch, creepage_t(scene(4, i), scene(5, i), scene(6, i)), fs)
    call compare('TGV scene patch', i)
  end do

  ! --- 3. unchanged outside the band: linear range and full slip
  patch = creep_patch_t(a=6.0e-3_wp, b=4.0e-3_wp, normal_force=5.0e4_wp, shear_modulus=82.0e9_wp, &
                          poisson=0.28_wp, friction=0.3_wp)
  call classic%compute(patch, creepage_t(1.0e-7_wp, 1.0e-7_wp, 0.0_wp), fc)
  call smooth%compute(patch, creepage_t(1.0e-7_wp, 1.0e-7_wp, 0.0_wp), fs)
  call check(abs(fs%fx - fc%fx) <= 1.0e-12_wp * abs(fc%fx) .and. &
             abs(fs%fy - fc%fy) <= 1.0e-12_wp * abs(fc%fy), 'linear range equal')
  call classic%compute(patch, creepage_t(0.2_wp, 0.1_wp, 0.0_wp), fc)
  call smooth%compute(patch, creepage_t(0.2_wp, 0.1_wp, 0.0_wp), fs)
  call check(abs(hypot(fs%fx, fs%fy) - hypot(fc%fx, fc%fy)) <= 1.0e-9_wp * 0.3_wp * 5.0e4_wp, 'full slip equal')

  call test_summary('test_creep_fastsim_smooth')

contains

  subroutine compare(what, i)
    character(len=*), intent(in) :: what
    integer, intent(in) :: i
    err_c = hypot(fc%fx - fx, fc%fy - fy) / hypot(fx, fy)
    err_s = hypot(fs%fx - fx, fs%fy - fy) / hypot(fx, fy)
    print '(a16,i2,2f10.0,2(2x,2f9.0),2f8.3)', what, i, fx, fy, fc%fx, fc%fy, fs%fx, fs%fy, err_c, err_s
    call check(err_s <= err_c + 0.02_wp, what // ': smooth as close to the exact theory as classic (+0.02)')
  end subroutine compare

end program test_creep_fastsim_smooth
