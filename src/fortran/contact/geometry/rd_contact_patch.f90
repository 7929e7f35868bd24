!> The result of the contact geometry for one wheel: up to MAX_PATCHES contact patches,
!> each with what the normal (Hertz) and tangential (creep) models need. Frames and signs:
!> docs/conventions.md ("Wheel-rail contact", "Profiles").
module rd_contact_patch
  use rd_kinds, only: wp
  implicit none
  private
  public :: patch_geometry_t, patch_potential_t, strip_normal_t, wheel_contact_t, MAX_PATCHES
  public :: PATCH_TREAD, PATCH_FLANGE, PATCH_FLANGE_BACK, PATCH_FLANGE_SPRING
  public :: mirror_wheel_contact

  integer, parameter :: MAX_PATCHES = 4

  integer, parameter :: PATCH_TREAD = 1        !< |contact angle| < 0.3 rad
  integer, parameter :: PATCH_FLANGE = 2       !< flange face, |contact angle| >= 0.3 rad
  integer, parameter :: PATCH_FLANGE_BACK = 3  !< back of the flange (radius growing to the field side)
  !> knife-edge model only: lateral flange stop; `penetration` is the lateral overlap
  !> beyond the clearance, to be used with a lateral stiffness, curvatures are zero.
  integer, parameter :: PATCH_FLANGE_SPRING = 4

  !> One patch as the contact geometry finds it. Its path: Hertz gives its ellipse and load
  !> (rd_hertz hertz_patch_t), a creep law reads creep_patch_t (rd_creep_law), and the
  !> results file gets patch_result_t (rd_wheel_contact_result).
  type :: patch_geometry_t
    integer :: kind = PATCH_TREAD
    real(wp) :: penetration = 0       !< [m] > 0 in contact, normal to the wheel surface
    real(wp) :: point_rail(3) = 0     !< contact point on the rail, track frame [m]
    real(wp) :: point_wheel(3) = 0    !< contact point on the wheel, wheelset intermediate
                                      !< frame (yaw and roll, no spin), origin at the wheelset centre [m]
    real(wp) :: s_wheel = 0           !< wheel profile coordinate (from the tape circle, + field) [m]
    real(wp) :: u_rail = 0            !< rail profile coordinate (profile input frame, + field) [m]
    real(wp) :: normal(3) = [0.0_wp, 0.0_wp, 1.0_wp]  !< unit normal, rail -> wheel, track frame
    real(wp) :: contact_angle = 0     !< [rad] rotation of the normal from Z_T, + towards +Y
    real(wp) :: rolling_radius = 0    !< wheel radius at the contact point [m]
    real(wp) :: curv_wheel_roll = 0   !< wheel principal curvature, rolling direction [1/m] (+ convex)
    real(wp) :: curv_wheel_lat = 0    !< wheel profile curvature, lateral direction [1/m] (+ convex)
    real(wp) :: curv_rail_roll = 0    !< rail curvature, rolling direction [1/m] (0: straight)
    real(wp) :: curv_rail_lat = 0     !< rail profile curvature, lateral [1/m] (+ convex)
    real(wp) :: u_rail_min = 0        !< patch extent: range of the interpenetration strips
    real(wp) :: u_rail_max = 0        !< on the rail profile coordinate [m]
    real(wp) :: strip_length = 0      !< length of the deepest strip (thesis eq. 4.72) [m]
    !> Share of a blended bump description (rd_strip_contact split_run): the patch carries
    !> this fraction of the forces of the bump it describes; its penetration is
    !> share^(2/3) times the bump's (so that Hertz gives share times the bump's normal force).
    real(wp) :: share = 1
    !> The distributed strip force's patches (rd_strip_contact): the approach that places the
    !> patch's material point (half of it inside the wheel, rd_wheelset_contact
    !> patch_frame_and_point), share^(2/3) times the smooth peak of the strips' depths; the
    !> penetration above, the refined peak of the cones' depths, kinks where the deepest strip
    !> changes (it stays the patches' rank and output) [m]
    real(wp) :: point_depth = 0
  end type patch_geometry_t

  !> What the energy-consistent strip normal force (rd_strip_potential, `strip_normal_force =
  !> 'potential'`) adds to a patch: the normal force acts along `force_dir` (track frame,
  !> |force_dir| ~ 1, minus the gradient of the effective penetration with respect to the
  !> wheel's displacement) on its own line of action instead of along `normal` at the
  !> patch point; the contact frame of the creep forces stays `normal`. Kept apart from
  !> patch_geometry_t so that the other contact models do not carry (and copy) it.
  type :: patch_potential_t
    real(wp) :: force_dir(3) = [0.0_wp, 0.0_wp, 1.0_wp]
    !> its moment about the wheelset centre per unit normal force, sum c_i p_i x g_i
    !> (intermediate frame)
    real(wp) :: force_moment(3) = 0
    !> gradients of the Hertz curvatures (wheel rolling, wheel lateral, rail lateral) with
    !> respect to the wheel's translation (1:3, track frame) and rotation (4:6, intermediate
    !> frame): the Hertz constant's part of the potential's gradient
    real(wp) :: curv_grad(6, 3) = 0
    !> gradient of the patch's `share` (same frames): a blended patch's potential is share
    !> times its bump's, whose gradient has the term U_bump grad(share)
    real(wp) :: share_grad(6) = 0
  end type patch_potential_t

  !> The distributed strip normal force of one wheel (`strip_normal_force = 'distributed'`,
  !> rd_hertz_strip): the elastic energy U = sum_i w_i c_i delta_i^2 of every penetrating
  !> strip and minus its gradient, all per unit E* (c_i = E* phi_i).
  type :: strip_normal_t
    real(wp) :: force(3) = 0     !< on the wheel, track frame [m^2 per unit E*: N / Pa]
    real(wp) :: moment(3) = 0    !< about the wheelset centre, intermediate frame [m^3]
    real(wp) :: energy = 0       !< U / E* [m^3]
    !> each patch's share of the normal load, |force| per unit E* of its strips (slot by slot
    !> with `patch`): the load its creep law and Hertz ellipse take
    real(wp) :: patch_load(MAX_PATCHES) = 0
  end type strip_normal_t

  type :: wheel_contact_t
    integer :: n_patches = 0
    type(patch_geometry_t) :: patch(MAX_PATCHES)
    !> allocated (MAX_PATCHES, slot by slot with `patch`) only by the energy-consistent
    !> strip force
    type(patch_potential_t), allocatable :: potential(:)
    !> allocated only by the distributed strip normal force, which replaces the patches'
    !> normal forces (they carry the creep forces only)
    type(strip_normal_t), allocatable :: distributed
    !> largest signed penetration over all strips [m]: < 0 is minus the smallest gap
    !> (used by the rigid-contact search); equals the deepest patch's penetration in contact.
    real(wp) :: max_penetration = -huge(1.0_wp)
  end type wheel_contact_t

contains

  !> Mirror a left-wheel result into the right wheel (reflection Y -> -Y of track and
  !> wheelset frames); profile coordinates are side independent and stay.
  pure subroutine mirror_wheel_contact(res)
    type(wheel_contact_t), intent(inout) :: res
    integer :: i
    do i = 1, res%n_patches
      res%patch(i)%point_rail(2) = -res%patch(i)%point_rail(2)
      res%patch(i)%point_wheel(2) = -res%patch(i)%point_wheel(2)
      res%patch(i)%normal(2) = -res%patch(i)%normal(2)
      if (allocated(res%potential)) then
        associate (q => res%potential(i))
          q%force_dir(2) = -q%force_dir(2)
          ! a moment is a pseudo-vector: under Y -> -Y it maps to (-Mx, My, -Mz)
          q%force_moment(1) = -q%force_moment(1)
          q%force_moment(3) = -q%force_moment(3)
          q%curv_grad(2, :) = -q%curv_grad(2, :)
          q%curv_grad(4, :) = -q%curv_grad(4, :)
          q%curv_grad(6, :) = -q%curv_grad(6, :)
          q%share_grad(2) = -q%share_grad(2)
          q%share_grad(4) = -q%share_grad(4)
          q%share_grad(6) = -q%share_grad(6)
        end associate
      end if
      res%patch(i)%contact_angle = -res%patch(i)%contact_angle
    end do
    if (allocated(res%distributed)) then
      ! force (Fx, -Fy, Fz), moment (-Mx, My, -Mz)
      res%distributed%force(2) = -res%distributed%force(2)
      res%distributed%moment(1) = -res%distributed%moment(1)
      res%distributed%moment(3) = -res%distributed%moment(3)
    end if
  end subroutine mirror_wheel_contact

end module rd_contact_patch
