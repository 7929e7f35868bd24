!> Anything that applies forces to the bodies from their kinematics: external loads, the
!> run-time override of the C API, and later the wheel-rail contact.
!>
!> A provider ADDS to `forces` (it never resets it): per body a force at the CG and a
!> moment about the CG, both in fixed-frame components. The equations of motion project
!> them on the generalized coordinates (thesis eqs. 4.51-4.59, docs/theory.md).
module rd_force_provider
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  implicit none
  private
  public :: force_provider_t, body_load_t

  !> Accumulated load on one body, fixed-frame components.
  type :: body_load_t
    real(wp) :: force(3) = 0    !< force at the CG [N]
    real(wp) :: moment(3) = 0   !< moment about the CG [N m]
    !> Moment about the CG of forces applied at the attachment frame of a wheelset (axle
    !> boxes): it does no work on the spin (a bearing), see docs/theory.md. For other
    !> bodies it acts exactly like `moment`.
    real(wp) :: moment_attach(3) = 0
  end type body_load_t

  type, abstract :: force_provider_t
  contains
    procedure(add_forces_i), deferred :: add_forces
    procedure :: coupled_bodies => unknown_coupling
    procedure :: wheel_unloaded => no_wheel
  end type force_provider_t

  abstract interface
    subroutine add_forces_i(self, t, kin, forces, error)
      import :: force_provider_t, wp, body_kinematics_t, body_load_t, error_t
      class(force_provider_t), intent(inout) :: self
      real(wp), intent(in) :: t
      type(body_kinematics_t), intent(in) :: kin(:)
      type(body_load_t), intent(inout) :: forces(:)
      type(error_t), allocatable, intent(out) :: error
    end subroutine add_forces_i
  end interface

contains

  !> The pairs of bodies whose motion this provider's forces couple (`pairs(:, k)`), for the
  !> sparsity of the Jacobian (rd_scene_jacobian); `known` false: the provider does not say.
  subroutine unknown_coupling(self, pairs, known)
    class(force_provider_t), intent(in) :: self
    integer, allocatable, intent(out) :: pairs(:, :)
    logical, intent(out) :: known
    allocate (pairs(2, 0))
    known = .false.
  end subroutine unknown_coupling

  !> Whether body `body` has a wheel that carried no normal load at this provider's last
  !> evaluation (its contact open): the quasi-static normal contact's test for a wheelset
  !> held by one wheel only (rd_multibody solve_quasi_static). A provider without wheels: no.
  logical function no_wheel(self, body)
    class(force_provider_t), intent(in) :: self
    integer, intent(in) :: body
    no_wheel = .false.
  end function no_wheel
end module rd_force_provider
