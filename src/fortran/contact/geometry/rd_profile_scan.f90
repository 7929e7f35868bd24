!> Contact characteristics of a wheel/rail pair ("profile scan", contact table): for a
!> sweep of wheelset lateral shifts (yaw optionally proportional to the shift), the roll
!> and height of rigid contact of both wheels, and the contact positions, rolling radii,
!> contact angles and patch counts of each wheel; plus the equivalent conicity.
!>
!> The arrays are kept apart from any file format: the command `raildyn profile-scan`
!> writes them as CSV (runner/rd_cmd_profile_scan.f90), the integrator may write HDF5.
module rd_profile_scan
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_contact_patch, only: wheel_contact_t, MAX_PATCHES
  use rd_contact_geometry, only: contact_geometry_t
  use rd_rigid_contact, only: rigid_contact
  implicit none
  private
  public :: profile_scan_t, run_profile_scan, equivalent_conicity

  !> Per shift k (1..n) and side (1 left, 2 right); patch quantities per patch p, ordered
  !> by decreasing penetration (patch 1 is the main contact). Unused patches hold 0.
  type :: profile_scan_t
    integer :: n = 0
    real(wp), allocatable :: y(:)           !< lateral shift [m] (+ left)
    real(wp), allocatable :: yaw(:)         !< yaw [rad]
    real(wp), allocatable :: z(:)           !< height of the wheelset centre at rigid contact [m]
    real(wp), allocatable :: roll(:)        !< roll at rigid contact [rad]
    integer, allocatable :: n_patches(:, :)               !< (side, k)
    real(wp), allocatable :: s_wheel(:, :, :)             !< (p, side, k) wheel profile coordinate [m]
    real(wp), allocatable :: u_rail(:, :, :)              !< rail profile coordinate [m]
    real(wp), allocatable :: y_rail(:, :, :)              !< contact point Y, track frame [m]
    real(wp), allocatable :: rolling_radius(:, :, :)      !< [m]
    real(wp), allocatable :: contact_angle(:, :, :)       !< [rad]
    real(wp), allocatable :: delta_r(:)     !< r_left - r_right of the main patches [m]
  end type profile_scan_t

contains

  !> Sweep y = -y_max ... y_max in steps `step` (yaw = yaw_per_shift * y); each pose at
  !> rigid contact lowered by `lowering` (a few um, so that touching points form patches).
  subroutine run_profile_scan(geo, y_max, step, yaw_per_shift, lowering, scan, error)
    type(contact_geometry_t), intent(in) :: geo
    real(wp), intent(in) :: y_max, step, yaw_per_shift, lowering
    type(profile_scan_t), intent(out) :: scan
    type(error_t), allocatable, intent(out) :: error
    type(wheel_contact_t) :: res(2)
    integer :: n, k, side, p, order(MAX_PATCHES)
    character(len=120) :: msg
    if (.not. (y_max > 0 .and. y_max < 0.05_wp)) then
      call make_error(error, RD_ERR_INPUT, 'profile scan: maximum shift must be in (0, 0.05) m')
      return
    end if
    if (.not. (step > 0 .and. step <= y_max)) then
      call make_error(error, RD_ERR_INPUT, 'profile scan: step must be in (0, ymax] m')
      return
    end if
    if (.not. (abs(yaw_per_shift) < 10 .and. lowering >= 0 .and. lowering < 1.0e-3_wp)) then
      call make_error(error, RD_ERR_INPUT, 'profile scan: yaw per shift must be < 10 rad/m and lowering in [0, 1 mm)')
      return
    end if
    n = 2 * nint(y_max / step) + 1
    scan%n = n
    allocate (scan%y(n), scan%yaw(n), scan%z(n), scan%roll(n), scan%n_patches(2, n), scan%delta_r(n))
    allocate (scan%s_wheel(MAX_PATCHES, 2, n), scan%u_rail(MAX_PATCHES, 2, n), scan%y_rail(MAX_PATCHES, 2, n), &
              scan%rolling_radius(MAX_PATCHES, 2, n), scan%contact_angle(MAX_PATCHES, 2, n))
    scan%s_wheel = 0; scan%u_rail = 0; scan%y_rail = 0; scan%rolling_radius = 0; scan%contact_angle = 0
    do k = 1, n
      scan%y(k) = step * (k - 1 - (n - 1) / 2)
      scan%yaw(k) = yaw_per_shift * scan%y(k)
      call rigid_contact(geo, scan%y(k), scan%yaw(k), scan%z(k), scan%roll(k), error, res(1), res(2), lowering)
      if (allocated(error)) then
        write (msg, '(a,es11.4,a)') 'profile scan at y = ', scan%y(k), ' m'
        call error_context(error, trim(msg))
        return
      end if
      do side = 1, 2
        scan%n_patches(side, k) = res(side)%n_patches
        call sort_by_penetration(res(side), order)
        do p = 1, res(side)%n_patches
          associate (c => res(side)%patch(order(p)))
            scan%s_wheel(p, side, k) = c%s_wheel
            scan%u_rail(p, side, k) = c%u_rail
            scan%y_rail(p, side, k) = c%point_rail(2)
            scan%rolling_radius(p, side, k) = c%rolling_radius
            scan%contact_angle(p, side, k) = c%contact_angle
          end associate
        end do
      end do
      scan%delta_r(k) = scan%rolling_radius(1, 1, k) - scan%rolling_radius(1, 2, k)
    end do
  end subroutine run_profile_scan

  pure subroutine sort_by_penetration(res, order)
    type(wheel_contact_t), intent(in) :: res
    integer, intent(out) :: order(MAX_PATCHES)
    integer :: i, j, t
    order = [(i, i=1, MAX_PATCHES)]
    do i = 2, res%n_patches
      j = i
      do while (j > 1)
        if (res%patch(order(j))%penetration <= res%patch(order(j - 1))%penetration) exit
        t = order(j); order(j) = order(j - 1); order(j - 1) = t
        j = j - 1
      end do
    end do
  end subroutine sort_by_penetration

  !> Equivalent conicity for a lateral amplitude A by harmonic linearisation of the
  !> rolling-radius difference (the describing-function reading of EN 15302): for
  !> y = A sin(theta), the first harmonic of delta_r(y) is
  !>   delta_r1 = (1/pi) int_0^{2 pi} delta_r(A sin(theta)) sin(theta) d theta,
  !> and lambda_e = delta_r1 / (2 A), exact (= tan gamma) for conical wheels where
  !> delta_r = 2 y tan(gamma). delta_r between scanned shifts is linear. EN 15302's
  !> regression (Klingel-integral) method gives nearly the same values for smooth
  !> delta_r; it differs where delta_r jumps (see docs/theory_contact_geometry.md).
  function equivalent_conicity(scan, amplitude, error) result(lambda)
    type(profile_scan_t), intent(in) :: scan
    real(wp), intent(in) :: amplitude
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: lambda
    integer, parameter :: m = 2000
    integer :: i, j
    real(wp) :: th, yq, w, dr, acc
    lambda = 0
    if (scan%n < 3) then
      call make_error(error, RD_ERR_INPUT, 'equivalent_conicity: no scan')
      return
    end if
    if (.not. (amplitude > 0 .and. amplitude <= scan%y(scan%n) * (1 + 1.0e-12_wp))) then
      call make_error(error, RD_ERR_INPUT, 'equivalent_conicity: amplitude must be in (0, ymax] of the scan')
      return
    end if
    acc = 0
    do i = 0, m - 1
      th = 2 * pi * (i + 0.5_wp) / m           ! midpoint rule: spectral accuracy for periodic integrands
      yq = amplitude * sin(th)
      j = min(max(1 + floor((yq - scan%y(1)) / (scan%y(2) - scan%y(1))), 1), scan%n - 1)
      w = (yq - scan%y(j)) / (scan%y(j + 1) - scan%y(j))
      dr = scan%delta_r(j) + w * (scan%delta_r(j + 1) - scan%delta_r(j))
      acc = acc + dr * sin(th)
    end do
    acc = acc * 2 * pi / m / pi
    lambda = acc / (2 * amplitude)
  end function equivalent_conicity

end module rd_profile_scan
