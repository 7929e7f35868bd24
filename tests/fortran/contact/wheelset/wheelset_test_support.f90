!> Helpers of the wheelset contact tests, written independently of the code under test:
!> exact straight and circular test tracks, wheelset kinematics at a given pose, a light
!> lateral/yaw restraint (and vertical load) as a force provider, checks.
module wheelset_test_support
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: rot_z, skew
  use rd_track_point, only: track_point_t, track_geometry_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_force_provider, only: force_provider_t, body_load_t
  implicit none
  private
  public :: circle_track_t, pose_kinematics, restraint_t, rel_err

  !> Level circle of signed curvature kappa (> 0 left; 0 = straight along X), no cant:
  !> A = Rz(kappa sigma), w = (0, 0, kappa).
  type, extends(track_geometry_t) :: circle_track_t
    real(wp) :: kappa = 0
  contains
    procedure :: evaluate => circle_evaluate
    procedure :: length => circle_length
  end type circle_track_t

  !> Per body: lateral spring k_y and damper c_y (track Y), yaw spring k_yaw and damper
  !> c_yaw about the track Z (relative to the track frame), and a constant vertical load
  !> (track -Z) at the CG.
  type, extends(force_provider_t) :: restraint_t
    integer :: body = 1
    real(wp) :: k_y = 0, k_yaw = 0, c_y = 0, c_yaw = 0, vertical_load = 0
  contains
    procedure :: add_forces => restraint_add_forces
  end type restraint_t

contains

  pure function circle_evaluate(self, sigma) result(p)
    class(circle_track_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: p
    real(wp) :: psi, k
    k = self%kappa
    psi = k * sigma
    p%sigma = sigma
    if (abs(k) > 0) then
      p%r = [sin(psi) / k, (1 - cos(psi)) / k, 0.0_wp]
    else
      p%r = [sigma, 0.0_wp, 0.0_wp]
    end if
    p%dr = [cos(psi), sin(psi), 0.0_wp]
    p%d2r = k * [-sin(psi), cos(psi), 0.0_wp]
    p%a = rot_z(psi)
    p%omega = [0.0_wp, 0.0_wp, k]
    p%domega = 0
    p%da = matmul(p%a, skew(p%omega))
    p%d2a = matmul(p%a, matmul(skew(p%omega), skew(p%omega)))
    p%heading = psi
    p%curvature = k
  end function circle_evaluate

  pure function circle_length(self) result(total)
    class(circle_track_t), intent(in) :: self
    real(wp) :: total
    total = 1.0e9_wp
  end function circle_length

  !> Kinematics of a wheelset at pose q (x, y, z, yaw, roll, spin) with rates qdot (qdot(6):
  !> the full spin rate) in the frame at sigma of `track`, which moves at speed v.
  function pose_kinematics(track, sigma, v, q, qdot) result(kin)
    class(track_geometry_t), intent(in) :: track
    real(wp), intent(in) :: sigma, v, q(6), qdot(6)
    type(body_kinematics_t) :: kin
    call compute_body_kinematics(kin, track%evaluate(sigma), v, 0.0_wp, q, qdot, .true.)
  end function pose_kinematics

  subroutine restraint_add_forces(self, t, kin, forces, error)
    class(restraint_t), intent(inout) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin(:)
    type(body_load_t), intent(inout) :: forces(:)
    type(error_t), allocatable, intent(out) :: error
    associate (k => kin(self%body), a => kin(self%body)%track%a)
      forces(self%body)%force = forces(self%body)%force + &
        matmul(a, [0.0_wp, -self%k_y * k%q(2) - self%c_y * k%qdot(2), -self%vertical_load])
      forces(self%body)%moment_attach = forces(self%body)%moment_attach + &
        matmul(a, [0.0_wp, 0.0_wp, -self%k_yaw * k%q(4) - self%c_yaw * k%qdot(4)])
    end associate
  end subroutine restraint_add_forces

  pure real(wp) function rel_err(x, ref)
    real(wp), intent(in) :: x, ref
    rel_err = abs(x - ref) / max(abs(ref), tiny(1.0_wp))
  end function rel_err

end module wheelset_test_support
