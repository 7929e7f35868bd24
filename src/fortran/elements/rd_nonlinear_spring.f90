!> Three-axis spring with a force-deflection table and a clearance per axis (bump stops,
!> progressive springs), optional damping acting while engaged; the nonlinear counterpart
!> of thesis eq. 4.115 with the same geometry (rd_element_geometry).
!>
!> Per axis i, with deflection d = separation - free_length in element axes:
!>   d >  c+ : f = -F+(d - c+) - c d'      (table of the positive side)
!>   d < -c- : f = +F-(-d - c-) - c d'     (table of the negative side; F+ if none given)
!>   else    : f = 0                       (inside the clearance)
!> F(e) interpolates linearly in a table starting at e = 0 (F(0) normally 0) and extends
!> it with the last segment's slope. Body 1's reaction acts at point 2 (see
!> rd_linear_spring_damper: exact conservation with axes turning with body 1).
module rd_nonlinear_spring
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_body_kinematics, only: body_kinematics_t
  use rd_force_element, only: force_element_t, element_result_t
  use rd_element_geometry, only: point_pair_t, point_pair
  implicit none
  private
  public :: nonlinear_spring_t, force_table_t, build_force_table, table_force

  !> Force magnitude [N] against penetration beyond the clearance [m].
  type :: force_table_t
    real(wp), allocatable :: e(:)
    real(wp), allocatable :: f(:)
  end type force_table_t

  type, extends(force_element_t) :: nonlinear_spring_t
    real(wp) :: u1(3) = 0
    real(wp) :: u2(3) = 0
    real(wp) :: axes(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    real(wp) :: free_length(3) = 0
    real(wp) :: clearance_pos(3) = 0  !< c+ [m]
    real(wp) :: clearance_neg(3) = 0  !< c- [m]
    real(wp) :: damping(3) = 0        !< [N s/m], only while engaged
    type(force_table_t) :: table_pos(3)  !< unallocated: no force on that side
    type(force_table_t) :: table_neg(3)  !< unallocated: mirror of table_pos
  contains
    procedure :: evaluate => nonlinear_evaluate
    procedure :: reset_free_length => nonlinear_reset_free_length
  end type nonlinear_spring_t

contains

  !> A table from penetrations e (strictly increasing, e(1) = 0) and forces f.
  subroutine build_force_table(table, e, f, error)
    type(force_table_t), intent(out) :: table
    real(wp), intent(in) :: e(:), f(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    if (size(e) < 2 .or. size(e) /= size(f)) then
      call make_error(error, RD_ERR_INPUT, 'force table: expected at least two (penetration, force) points'); return
    end if
    if (abs(e(1)) > 0) then
      call make_error(error, RD_ERR_INPUT, 'force table: the first penetration must be 0 m'); return
    end if
    do i = 2, size(e)
      if (.not. e(i) > e(i - 1)) then
        call make_error(error, RD_ERR_INPUT, 'force table: penetrations must be strictly increasing'); return
      end if
    end do
    if (any(.not. ieee_is_finite(f))) then
      call make_error(error, RD_ERR_INPUT, 'force table: forces must be finite'); return
    end if
    table%e = e
    table%f = f
  end subroutine build_force_table

  !> F(e) for e >= 0: linear interpolation, last slope beyond the end.
  pure real(wp) function table_force(table, e) result(f)
    type(force_table_t), intent(in) :: table
    real(wp), intent(in) :: e
    integer :: i, n
    n = size(table%e)
    i = 1
    do while (i < n - 1 .and. e > table%e(i + 1))
      i = i + 1
    end do
    f = table%f(i) + (table%f(i + 1) - table%f(i)) * (e - table%e(i)) / (table%e(i + 1) - table%e(i))
  end function table_force

  pure subroutine nonlinear_evaluate(self, t, k1, k2, x, res, xdot)
    class(nonlinear_spring_t), intent(in) :: self
    real(wp), intent(in) :: t
    type(body_kinematics_t), intent(in) :: k1, k2
    real(wp), intent(in) :: x(:)
    type(element_result_t), intent(out) :: res
    real(wp), intent(out) :: xdot(:)
    type(point_pair_t) :: pp
    real(wp) :: d
    integer :: i
    pp = point_pair(k1, k2, self%u1, self%u2, self%axes)
    res%deflection = pp%d - self%free_length
    res%force_local = 0
    do i = 1, 3
      d = res%deflection(i)
      if (d > self%clearance_pos(i)) then
        if (allocated(self%table_pos(i)%e)) &
          res%force_local(i) = -table_force(self%table_pos(i), d - self%clearance_pos(i)) - self%damping(i) * pp%ddot(i)
      else if (d < -self%clearance_neg(i)) then
        if (allocated(self%table_neg(i)%e)) then
          res%force_local(i) = table_force(self%table_neg(i), -d - self%clearance_neg(i)) - self%damping(i) * pp%ddot(i)
        else if (allocated(self%table_pos(i)%e)) then
          res%force_local(i) = table_force(self%table_pos(i), -d - self%clearance_neg(i)) - self%damping(i) * pp%ddot(i)
        end if
      end if
    end do
    res%force = matmul(pp%axes, res%force_local)
    res%moment = 0
    res%point2 = pp%p2
    res%reaction_point = pp%p2
  end subroutine nonlinear_evaluate

  !> Free length += deflection (force_element_t reset_free_length).
  pure subroutine nonlinear_reset_free_length(self, deflection)
    class(nonlinear_spring_t), intent(inout) :: self
    real(wp), intent(in) :: deflection(3)
    self%free_length = self%free_length + deflection
  end subroutine nonlinear_reset_free_length
end module rd_nonlinear_spring
