!> Results of the wheelset contact pipeline for one evaluation (thesis 5.2.3 outputs): per
!> contact patch, per wheel and per wheelset, with the plain-array channel layout the scene
!> writes (names and unit tokens below). Signs: docs/theory_wheelset.md, docs/conventions.md.
module rd_wheel_contact_result
  use rd_kinds, only: wp
  use rd_contact_patch, only: MAX_PATCHES
  implicit none
  private
  public :: patch_result_t, wheel_result_t, wheelset_result_t, MAX_PATCHES
  public :: N_PATCH_CHANNELS, N_WHEEL_CHANNELS
  public :: patch_channel_names, patch_channel_units, wheel_channel_names, wheel_channel_units
  public :: patch_channel_values, wheel_channel_values

  !> One contact patch. Contact-frame quantities: x_c rolling, y_c lateral (left), n rail -> wheel.
  type :: patch_result_t
    integer :: kind = 0                 !< rd_contact_patch PATCH_* (0: empty slot)
    real(wp) :: penetration = 0         !< virtual penetration (Hertz approach) [m]
    real(wp) :: normal_force = 0        !< N on the wheel along n, incl. damping [N]
    real(wp) :: xi = 0, eta = 0         !< longitudinal, lateral creepage [-]
    real(wp) :: spin = 0                !< spin creepage [1/m]
    real(wp) :: v_ref = 0               !< regularised reference (rolling) speed [m/s]
    real(wp) :: fx = 0, fy = 0          !< creep forces on the wheel, contact frame [N]
    real(wp) :: mz = 0                  !< spin moment on the wheel about n [N m]
    real(wp) :: s_wheel = 0             !< wheel profile coordinate of the contact [m]
    real(wp) :: u_rail = 0              !< rail profile coordinate of the contact [m]
    real(wp) :: point_wheel(3) = 0      !< contact point, wheelset intermediate frame, from the centre [m]
    real(wp) :: point_rail(3) = 0       !< contact point on the rail, track frame (x from the frame origin) [m]
    real(wp) :: contact_angle = 0       !< [rad], + when n tilts towards +Y_T
    real(wp) :: rolling_radius = 0      !< [m]
    real(wp) :: a = 0, b = 0            !< Hertz semi-axes, rolling / lateral [m]
    integer :: hertz_warning = 0        !< rd_hertz HERTZ_WARN_* bits
    ! fixed-frame vectors of the last evaluation (for checks and the generalized forces;
    ! not output channels)
    real(wp) :: force_fixed(3) = 0      !< N n + Fx x_c + Fy y_c on the wheel [N]
    real(wp) :: normal_fixed(3) = 0     !< n [-]
    real(wp) :: lever_fixed(3) = 0      !< wheel material point at the patch minus the CG [m]
  end type patch_result_t

  type :: wheel_result_t
    integer :: n_patches = 0
    type(patch_result_t) :: patch(MAX_PATCHES)
    !> resultant contact force ON THE WHEEL in track components: (longitudinal, Y, Q) [N]
    real(wp) :: force_track(3) = 0
    !> Y/Q signed so that flange contact on this wheel is positive (left: -Y/Q, right: +Y/Q);
    !> 0 when Q <= 0 (unloaded wheel) [-]
    real(wp) :: y_over_q = 0
    !> largest signed penetration [m]; < 0 is minus the smallest wheel-rail gap
    real(wp) :: max_penetration = 0
  end type wheel_result_t

  type :: wheelset_result_t
    type(wheel_result_t) :: wheel(2)        !< 1 left, 2 right
    real(wp) :: derailment_quotient = 0     !< max over both wheels of wheel%y_over_q [-]
    real(wp) :: guiding_force_sum = 0       !< Y_left + Y_right (track Y_T, on the wheelset) [N]
    real(wp) :: force(3) = 0                !< resultant on the wheelset, fixed frame [N]
    real(wp) :: moment(3) = 0               !< about its CG, fixed frame [N m]
    !> rails displaced at the wheelset (irregularities, rail bodies): dy_L dz_L dy_R dz_R, track frame [m]
    real(wp) :: rail_offsets(4) = 0
  end type wheelset_result_t

  integer, parameter :: N_PATCH_CHANNELS = 23
  character(len=*), parameter :: patch_channel_names(N_PATCH_CHANNELS) = [character(len=20) :: &
    'kind', 'penetration', 'normal_force', 'xi', 'eta', 'spin', 'creep_force_x', 'creep_force_y', &
    'spin_moment', 's_wheel', 'u_rail', 'wheel_point_x', 'wheel_point_y', 'wheel_point_z', &
    'rail_point_x', 'rail_point_y', 'rail_point_z', 'contact_angle', 'rolling_radius', &
    'semi_axis_a', 'semi_axis_b', 'hertz_warning', 'reference_speed']
  character(len=*), parameter :: patch_channel_units(N_PATCH_CHANNELS) = [character(len=4) :: &
    '1', 'm', 'N', '1', '1', '1/m', 'N', 'N', 'N*m', 'm', 'm', 'm', 'm', 'm', 'm', 'm', 'm', &
    'rad', 'm', 'm', 'm', '1', 'm/s']

  integer, parameter :: N_WHEEL_CHANNELS = 6
  character(len=*), parameter :: wheel_channel_names(N_WHEEL_CHANNELS) = [character(len=20) :: &
    'n_patches', 'force_longitudinal', 'force_lateral_Y', 'force_vertical_Q', 'Y_over_Q', 'max_penetration']
  character(len=*), parameter :: wheel_channel_units(N_WHEEL_CHANNELS) = [character(len=4) :: &
    '1', 'N', 'N', 'N', '1', 'm']

contains

  !> Channels of patch slot k (zeros when the slot is empty).
  pure subroutine patch_channel_values(wheel, k, out)
    type(wheel_result_t), intent(in) :: wheel
    integer, intent(in) :: k
    real(wp), intent(out) :: out(N_PATCH_CHANNELS)
    out = 0
    if (k < 1 .or. k > wheel%n_patches) return
    associate (p => wheel%patch(k))
      out = [real(p%kind, wp), p%penetration, p%normal_force, p%xi, p%eta, p%spin, p%fx, p%fy, p%mz, &
             p%s_wheel, p%u_rail, p%point_wheel, p%point_rail, p%contact_angle, p%rolling_radius, &
             p%a, p%b, real(p%hertz_warning, wp), p%v_ref]
    end associate
  end subroutine patch_channel_values

  pure subroutine wheel_channel_values(wheel, out)
    type(wheel_result_t), intent(in) :: wheel
    real(wp), intent(out) :: out(N_WHEEL_CHANNELS)
    out = [real(wheel%n_patches, wp), wheel%force_track, wheel%y_over_q, wheel%max_penetration]
  end subroutine wheel_channel_values


end module rd_wheel_contact_result
