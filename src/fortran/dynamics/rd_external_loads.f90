!> External loads on bodies (thesis 5.2.1: "external forces and torques ... in the global
!> reference frame and ... in the track frame"), and the per-body override the C API sets
!> at run time. Both are force providers.
module rd_external_loads
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_provider, only: force_provider_t, body_load_t
  implicit none
  private
  public :: external_loads_t, override_loads_t, external_load_t
  public :: LOAD_FRAME_FIXED, LOAD_FRAME_TRACK, LOAD_FRAME_BODY

  integer, parameter :: LOAD_FRAME_FIXED = 1  !< components in the fixed frame
  integer, parameter :: LOAD_FRAME_TRACK = 2  !< components in the body's track frame (follow the track)
  integer, parameter :: LOAD_FRAME_BODY = 3   !< components in the body frame (follow the body)

  !> A constant force at the CG and moment, switched on in [t_on, t_off).
  type :: external_load_t
    integer :: body = 0
    integer :: frame = LOAD_FRAME_FIXED
    real(wp) :: force(3) = 0      !< [N]
    real(wp) :: moment(3) = 0     !< [N m]
    real(wp) :: t_on = -huge(1.0_wp)
    real(wp) :: t_off = huge(1.0_wp)
  end type external_load_t

  type, extends(force_provider_t) :: external_loads_t
    type(external_load_t), allocatable :: loads(:)
  contains
    procedure :: add_load
    procedure :: add_forces => external_add_forces
    procedure :: coupled_bodies => external_coupled_bodies
  end type external_loads_t

  !> Per-body force (at the CG) and moment in fixed-frame components, set at run time.
  type, extends(force_provider_t) :: override_loads_t
    real(wp), allocatable :: force(:, :)    !< (3, nbodies)
    real(wp), allocatable :: moment(:, :)   !< (3, nbodies)
  contains
    procedure :: build => override_build
    procedure :: set => override_set
    procedure :: add_forces => override_add_forces
  end type override_loads_t

contains

  subroutine add_load(self, load, nbodies, error)
    class(external_loads_t), intent(inout) :: self
    type(external_load_t), intent(in) :: load
    integer, intent(in) :: nbodies
    type(error_t), allocatable, intent(out) :: error
    if (load%body < 1 .or. load%body > nbodies) then
      call make_error(error, RD_ERR_INPUT, 'external load: body index out of range 1..number of bodies'); return
    end if
    if (load%frame < LOAD_FRAME_FIXED .or. load%frame > LOAD_FRAME_BODY) then
      call make_error(error, RD_ERR_INPUT, 'external load: frame must be fixed, track or body'); return
    end if
    if (any(.not. ieee_is_finite(load%force)) .or. any(.not. ieee_is_finite(load%moment)) .or. .not. (load%t_off >= load%t_on)) then
      call make_error(error, RD_ERR_INPUT, 'external load: expected finite force/moment and t_off >= t_on'); return
    end if
    if (.not. allocated(self%loads)) allocate (self%loads(0))
    self%loads = [self%loads, load]
  end subroutine add_load

  subroutine external_add_forces(self, t, kin, forces, error)
    class(external_loads_t), intent(inout) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin(:)
    type(body_load_t), intent(inout) :: forces(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, ib
    real(wp) :: r(3, 3)
    if (.not. allocated(self%loads)) return
    do i = 1, size(self%loads)
      associate (ld => self%loads(i))
        if (t < ld%t_on .or. t >= ld%t_off) cycle
        ib = ld%body
        select case (ld%frame)
        case (LOAD_FRAME_TRACK)
          r = kin(ib)%track%a
        case (LOAD_FRAME_BODY)
          r = kin(ib)%rot
        case default
          forces(ib)%force = forces(ib)%force + ld%force
          forces(ib)%moment = forces(ib)%moment + ld%moment
          cycle
        end select
        forces(ib)%force = forces(ib)%force + matmul(r, ld%force)
        forces(ib)%moment = forces(ib)%moment + matmul(r, ld%moment)
      end associate
    end do
  end subroutine external_add_forces

  subroutine override_build(self, nbodies)
    class(override_loads_t), intent(inout) :: self
    integer, intent(in) :: nbodies
    if (allocated(self%force)) deallocate (self%force, self%moment)
    allocate (self%force(3, nbodies), self%moment(3, nbodies))
    self%force = 0
    self%moment = 0
  end subroutine override_build

  subroutine override_set(self, body, force, moment, error)
    class(override_loads_t), intent(inout) :: self
    integer, intent(in) :: body
    real(wp), intent(in) :: force(3), moment(3)
    type(error_t), allocatable, intent(out) :: error
    if (.not. allocated(self%force)) then
      call make_error(error, RD_ERR_INPUT, 'override load: not initialised'); return
    end if
    if (body < 1 .or. body > size(self%force, 2)) then
      call make_error(error, RD_ERR_INPUT, 'override load: body index out of range 1..number of bodies'); return
    end if
    if (any(.not. ieee_is_finite(force)) .or. any(.not. ieee_is_finite(moment))) then
      call make_error(error, RD_ERR_INPUT, 'override load: NaN in force or moment'); return
    end if
    self%force(:, body) = force
    self%moment(:, body) = moment
  end subroutine override_set

  subroutine override_add_forces(self, t, kin, forces, error)
    class(override_loads_t), intent(inout) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: kin(:)
    type(body_load_t), intent(inout) :: forces(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: ib
    if (.not. allocated(self%force)) return
    do ib = 1, min(size(forces), size(self%force, 2))
      forces(ib)%force = forces(ib)%force + self%force(:, ib)
      forces(ib)%moment = forces(ib)%moment + self%moment(:, ib)
    end do
  end subroutine override_add_forces

  !> Each load acts on its body from that body's track or body frame: no coupling.
  subroutine external_coupled_bodies(self, pairs, known)
    class(external_loads_t), intent(in) :: self
    integer, allocatable, intent(out) :: pairs(:, :)
    logical, intent(out) :: known
    allocate (pairs(2, 0))
    known = .true.
  end subroutine external_coupled_bodies
end module rd_external_loads
