!> The distributed strip normal force and its patches along fine pose sweeps (issue "smooth
!> wheel-rail forces", item 2; docs/theory_flange_chatter.md section 14). The check is on the
!> second differences d2 against the largest first difference d1 of the same quantity over
!> 1001 samples: a jump shows as d2 ~ d1, a kink as d2 ~ (slope change) x step, a C1 path as
!> d2 ~ d1 x step / (the length over which the slope changes), halving with the step.
!>
!> - Flange (yaw 0, 6.338-6.348 mm, the line between two poses of bench/contact_smoothness's
!>   wheel-load path, their height and roll): the lateral force. With the cubic Hermite wheel
!>   (C1: its r'' jumped at every profile point) the depth gradient's curvature term made it
!>   jump by 60-260 N every few micrometres: d2 / d1 = 1.03 (main db5be3d). With the natural
!>   spline wheel (C2) 0.007: kinks of 0.05 N at 10 nm steps are left (d2 / d1 does not halve
!>   with the step: the spline's third derivative jumps at the points), so this sweep shows the
!>   jumps gone, not C1.
!> - Flange face at yaw 15 mrad (7.540-7.548 mm, the same path's poses): the lateral force.
!>   With the deepest points on the cones (pinned at profile points on a yawed line, then
!>   leaving them) it jumped by ~26 N every micrometre: d2 / d1 = 1.0 (main c87b9f8); with the
!>   deepest point found on the smooth wheel (rd_strip_potential smooth_line_depth) 5e-4.
!> - Tread (yaw 0, 2.0-3.0 mm, 30 um below the line between rigid contact at the ends): the
!>   patch's contact point, normal and Hertz curvature means, which the creep law sees.
!>   Interpolated linearly between neighbouring strips, point and normal kinked every ~0.19 mm
!>   (d2 / d1 0.019), and the curvature means (weights delta - thr on the cones' depths, the
!>   wheel's curvature linear between the points, the threshold from the cones' refined peak)
!>   kinked wherever a strip crossed the threshold or a point (0.26). Now 3.4e-4, 3.4e-4 and
!>   2.4e-3, halving with the step (2001 samples: 1.7e-4, 1.7e-4, 1.2e-3), which is checked.
!> - Where the flange root's contact region merges with the tread's (yaw 0: 4.80-5.10 mm,
!>   yaw 15 mrad: 4.95-5.15 mm, lines between poses of the same path; the split's blend
!>   fraction lambda between 0 and 1 all along): the patches' load-weighted lateral point,
!>   approach and lateral Hertz curvature. With lambda from the lowest strip's and the
!>   highest strips' depths and each strip's box split at the valley's refined position (main
!>   c385985) they kinked wherever those strips changed or the position crossed a strip's
!>   edge: the ratio at half the step / at the step 0.82-1.40. With the valley and peaks on a
!>   C1 interpolant of the depths, the split position on a C2 B-spline and the strips' parts
!>   smoothed (rd_strip_contact cubic_minimum, strip_part): 0.50-0.52; checked below 0.6.
program test_distributed_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use rd_test_support, only: check, check_within, test_summary
  use strip_force_test_support, only: manchester_geometry
  use rd_text, only: int_text
  implicit none
  integer, parameter :: n = 1001
  type(contact_geometry_t) :: geo
  type(error_t), allocatable :: error
  !> two poses (y, z, roll) of the wheel-load path, 2026-11-29 (the sweep's line between them)
  real(wp), parameter :: flange_a(3) = [6.338e-3_wp, 4.602722731856760e-01_wp, 7.935877691041501e-04_wp]
  real(wp), parameter :: flange_b(3) = [6.348e-3_wp, 4.602830372683690e-01_wp, 8.078696511862200e-04_wp]
  !> the same at yaw 15 mrad on the flange face (7.540-7.548 mm)
  real(wp), parameter :: yawed_a(3) = [7.540e-3_wp, 4.654071353644950e-01_wp, 7.547871874250970e-03_wp]
  real(wp), parameter :: yawed_b(3) = [7.548e-3_wp, 4.654204600062230e-01_wp, 7.565426351360790e-03_wp]
  !> the same where the tread's and the flange root's contact regions merge (4.80-5.10 mm;
  !> at yaw 15 mrad 4.95-5.15 mm)
  real(wp), parameter :: merge_a(3) = [4.800e-3_wp, 4.5992828312187761e-01_wp, 3.2129054137784127e-04_wp]
  real(wp), parameter :: merge_b(3) = [5.100e-3_wp, 4.5995751864662521e-01_wp, 3.6375722952886080e-04_wp]
  real(wp), parameter :: yawed_merge_a(3) = [4.950e-3_wp, 4.5993549594416716e-01_wp, 3.3405459509647738e-04_wp]
  real(wp), parameter :: yawed_merge_b(3) = [5.150e-3_wp, 4.5995565517983905e-01_wp, 3.6321161864230590e-04_wp]
  character(len=*), parameter :: merge_name(3) = [character(len=24) :: 'load-weighted point y', &
                                                    'load-weighted approach', 'load-weighted curvature']
  character(len=*), parameter :: tread_name(3) = [character(len=24) :: 'contact point y', 'normal y component', &
                                                    'lateral Hertz curvature']
  real(wp) :: z0, phi0, z1, phi1, ratio1(3), ratio2(3)
  integer :: k

  call manchester_geometry('distributed', geo)
  call check_flange_path('flange path', flange_a, flange_b, 0.0_wp)
  call check_flange_path('yawed flange path', yawed_a, yawed_b, 0.015_wp)
  call check_merge_path('tread and flange root merging', merge_a, merge_b, 0.0_wp)
  call check_merge_path('tread and flange root merging, yaw 15 mrad', yawed_merge_a, yawed_merge_b, 0.015_wp)

  ! the line between rigid contact lowered by 30 um at both ends; at n and 2n - 1 samples
  call rigid_contact(geo, 2.0e-3_wp, 0.0_wp, z0, phi0, error)
  if (allocated(error)) error stop error%message
  call rigid_contact(geo, 3.0e-3_wp, 0.0_wp, z1, phi1, error)
  if (allocated(error)) error stop error%message
  call tread_ratios(n, ratio1)
  call tread_ratios(2 * n - 1, ratio2)
  do k = 1, 3
    call check_within('tread: ' // trim(tread_name(k)) // ': max |d2| / max |d1|', ratio1(k), &
                      merge(2.0e-3_wp, 1.0e-2_wp, k < 3))
    ! C1: half the step, half the ratio (a kink keeps it)
    call check_within('tread: ' // trim(tread_name(k)) // ': the ratio at half the step / at the step', &
                      ratio2(k) / ratio1(k), 0.6_wp)
  end do
  call test_summary('test_distributed_smoothness')

contains

  !> the lateral force along the line from pose a to pose b (y, z, roll) at yaw psi: no jump
  !> (d2 / d1 small) and C1 (d2 / d1 halves with the step)
  subroutine check_flange_path(what, a, b, psi)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: a(3), b(3), psi
    real(wp) :: r1, r2
    r1 = flange_ratio(what, a, b, psi, n)
    r2 = flange_ratio(what, a, b, psi, 2 * n - 1)
    call check_within(what // ': lateral force: max |d2| / max |d1|', r1, 0.05_wp)
    call check_within(what // ': lateral force: the ratio at half the step / at the step', r2 / r1, 0.6_wp)
  end subroutine check_flange_path

  !> max |d2| / max |d1| of the lateral force over m samples of the line
  real(wp) function flange_ratio(what, a, b, psi, m) result(ratio)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: a(3), b(3), psi
    integer, intent(in) :: m
    real(wp) :: yf(m), q(3)
    type(wheel_contact_t) :: rp
    integer :: i
    do i = 1, m
      q = a + real(i - 1, wp) / (m - 1) * (b - a)
      call wheel_contact(geo, SIDE_LEFT, q(1), q(2), q(3), psi, rp)
      yf(i) = rp%distributed%force(2)
    end do
    ratio = d2_over_d1(what // ' (' // trim(int_text(m)) // ' samples): lateral force', yf)
  end function flange_ratio

  !> Where the flange root's contact region merges with the tread's (the line between two
  !> poses a, b (y, z, roll) of the wheel-load path at yaw psi): the patches' load-weighted
  !> lateral point, approach and lateral Hertz curvature, the creep law's inputs that the
  !> split fraction lambda moves between the merged patch and the two separate ones; C1:
  !> their d2 / d1 halves with the step.
  subroutine check_merge_path(what, a, b, psi)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: a(3), b(3), psi
    real(wp) :: r1(3), r2(3)
    integer :: k, blended
    call merge_ratios(what, a, b, psi, n, r1, blended)
    call merge_ratios(what, a, b, psi, 2 * n - 1, r2, blended)
    ! the sweep must cross the blend (some patch with a share strictly between 0 and 1)
    call check(blended > 10, what // ': the line crosses the blend of the split (a patch share in (0, 1))')
    do k = 1, 3
      call check_within(what // ': ' // trim(merge_name(k)) // ': the ratio at half the step / at the step', &
                        r2(k) / r1(k), 0.6_wp)
    end do
  end subroutine check_merge_path

  !> the merge path's d2 / d1 over m samples and the samples with a blended patch
  subroutine merge_ratios(what, a, b, psi, m, ratio, blended)
      character(len=*), intent(in) :: what
      real(wp), intent(in) :: a(3), b(3), psi
      integer, intent(in) :: m
      real(wp), intent(out) :: ratio(3)
      integer, intent(out) :: blended
      real(wp) :: v(m, 3), q(3), load, nw
      type(wheel_contact_t) :: rm
      integer :: i, p
      blended = 0
      do i = 1, m
        q = a + real(i - 1, wp) / (m - 1) * (b - a)
        call wheel_contact(geo, SIDE_LEFT, q(1), q(2), q(3), psi, rm)
        load = sum(rm%distributed%patch_load(1:rm%n_patches))
        v(i, :) = 0
        do p = 1, rm%n_patches
          nw = rm%distributed%patch_load(p) / load
          v(i, :) = v(i, :) + nw * [rm%patch(p)%point_rail(2), rm%patch(p)%point_depth, &
                                    rm%patch(p)%curv_wheel_lat + rm%patch(p)%curv_rail_lat]
        end do
        if (any(rm%patch(1:rm%n_patches)%share < 1 .and. rm%patch(1:rm%n_patches)%share > 0)) blended = blended + 1
      end do
      do i = 1, 3
        ratio(i) = d2_over_d1(what // ' (' // trim(int_text(m)) // ' samples): ' // trim(merge_name(i)), v(:, i))
      end do
  end subroutine merge_ratios

  !> max |d2| / max |d1| of the tread patch's point, normal and curvature means over m samples
  subroutine tread_ratios(m, ratio)
    integer, intent(in) :: m
    real(wp), intent(out) :: ratio(3)
    real(wp) :: v(m, 3), tt
    type(wheel_contact_t) :: rt
    integer :: i
    do i = 1, m
      tt = real(i - 1, wp) / (m - 1)
      call wheel_contact(geo, SIDE_LEFT, 2.0e-3_wp + 1.0e-3_wp * tt, z0 + tt * (z1 - z0) - 3.0e-5_wp, &
                         phi0 + tt * (phi1 - phi0), 0.0_wp, rt)
      if (rt%n_patches /= 1) error stop 'test_distributed_smoothness: expected one tread patch'
      v(i, :) = [rt%patch(1)%point_rail(2), rt%patch(1)%normal(2), rt%patch(1)%curv_wheel_lat + rt%patch(1)%curv_rail_lat]
    end do
    do i = 1, 3
      ratio(i) = d2_over_d1('tread (' // trim(int_text(m)) // ' samples): ' // trim(tread_name(i)), v(:, i))
    end do
  end subroutine tread_ratios

  !> max |d2| / max |d1| of the samples v (printed)
  real(wp) function d2_over_d1(what, v) result(ratio)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: v(:)
    real(wp) :: d1, d2
    integer :: k
    d1 = maxval(abs(v(2:) - v(:size(v) - 1)))
    d2 = 0
    do k = 2, size(v) - 1
      d2 = max(d2, abs(v(k + 1) - 2 * v(k) + v(k - 1)))
    end do
    write (*, '(a,es11.3,a,es11.3)') '      ' // what // ': max |d2| ', d2, ', max |d1| ', d1
    ratio = d2 / d1
  end function d2_over_d1

end program test_distributed_smoothness
