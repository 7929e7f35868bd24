!> The interface of a suspension force element (thesis 4.8.3, eqs. 4.103-4.119).
!>
!> An element acts from body 1 on body 2 (docs/conventions.md: the force stored is the
!> force ON BODY 2); body1 = 0 means ground, i.e. the track frame body 2 is referred to.
!> It computes, from both bodies' kinematics and its own internal states, the force on
!> body 2 at a point, an optional pure couple, and where body 1's reaction acts. The
!> multibody applies the equal and opposite reaction to body 1 (Newton's third law, which
!> the thesis' separate eqs. 4.115/4.116 do not guarantee when the two bodies' frames
!> differ). Concrete elements live in src/fortran/elements.
!>
!> Elements are defined here, next to the multibody that holds them, because the
!> equations of motion must know their interface (internal states, preloads).
module rd_force_element
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_body_kinematics, only: body_kinematics_t
  implicit none
  private
  public :: force_element_t, element_result_t

  !> What an element produces at one instant.
  type :: element_result_t
    real(wp) :: point2(3) = 0          !< where the force acts on body 2 [m], fixed frame
    real(wp) :: reaction_point(3) = 0  !< where -force acts on body 1 [m], fixed frame
    real(wp) :: force(3) = 0           !< force on body 2, fixed frame [N]
    real(wp) :: moment(3) = 0          !< pure couple on body 2, fixed frame [N m] (body 1 gets -moment)
    real(wp) :: deflection(3) = 0      !< element deflection, element axes [m or rad]
    real(wp) :: force_local(3) = 0     !< force (or moment) on body 2, element axes [N or N m]
  end type element_result_t

  type, abstract :: force_element_t
    character(len=:), allocatable :: name
    integer :: body1 = 0    !< 0 = ground (track frame of body 2)
    integer :: body2 = 0
  contains
    procedure(evaluate_i), deferred :: evaluate
    procedure :: state_count => no_states
    procedure :: state_units => no_state_units
    procedure :: initial_states => no_initial_states
    procedure :: preload_count => no_preload
    procedure :: set_preload => no_set_preload
    procedure :: reset_free_length => keep_free_length
    procedure :: check_bodies
  end type force_element_t

  abstract interface
    !> Forces at time t from the kinematics of body 1 (ground: its track frame) and body 2
    !> and the element's internal states x; xdot receives their derivatives.
    pure subroutine evaluate_i(self, t, k1, k2, x, res, xdot)
      import :: force_element_t, wp, body_kinematics_t, element_result_t
      class(force_element_t), intent(in) :: self
      real(wp), intent(in) :: t
      type(body_kinematics_t), intent(in) :: k1, k2
      real(wp), intent(in) :: x(:)
      type(element_result_t), intent(out) :: res
      real(wp), intent(out) :: xdot(:)
    end subroutine evaluate_i
  end interface

contains

  pure integer function no_states(self) result(n)
    class(force_element_t), intent(in) :: self
    n = 0
  end function no_states

  !> SI unit token of each internal state (docs/output.md), for the results file's state;
  !> units has state_count() elements.
  pure subroutine no_state_units(self, units)
    class(force_element_t), intent(in) :: self
    character(len=*), intent(out) :: units(:)
  end subroutine no_state_units

  !> Internal states at the start (e.g. a relaxed series damper), from the kinematics.
  pure subroutine no_initial_states(self, k1, k2, x)
    class(force_element_t), intent(in) :: self
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(out) :: x(:)
    x = 0
  end subroutine no_initial_states

  !> Number of preload components the static-equilibrium solver may adjust.
  pure integer function no_preload(self) result(n)
    class(force_element_t), intent(in) :: self
    n = 0
  end function no_preload

  pure subroutine no_set_preload(self, p)
    class(force_element_t), intent(inout) :: self
    real(wp), intent(in) :: p(:)
  end subroutine no_set_preload

  !> Make the element unstressed at its present `deflection` (element_result_t): free length
  !> += deflection (the vehicle as built, rd_scene_startup). Without a free length: nothing.
  pure subroutine keep_free_length(self, deflection)
    class(force_element_t), intent(inout) :: self
    real(wp), intent(in) :: deflection(3)
  end subroutine keep_free_length

  !> Check the body indices against the model size.
  subroutine check_bodies(self, nbodies, error)
    class(force_element_t), intent(in) :: self
    integer, intent(in) :: nbodies
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: who
    who = 'element'
    if (allocated(self%name)) who = 'element "' // self%name // '"'
    if (self%body2 < 1 .or. self%body2 > nbodies) then
      call make_error(error, RD_ERR_INPUT, who // ': body2 must be a body index 1..number of bodies'); return
    end if
    if (self%body1 < 0 .or. self%body1 > nbodies .or. self%body1 == self%body2) then
      call make_error(error, RD_ERR_INPUT, who // ': body1 must be 0 (ground) or another body index'); return
    end if
  end subroutine check_bodies
end module rd_force_element
