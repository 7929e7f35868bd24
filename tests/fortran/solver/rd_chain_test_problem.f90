!> A chain of m masses joined by cubic springs and dampers, ends fixed (unit masses):
!>   x_i'' = s(x_{i+1} - x_i) - s(x_i - x_{i-1}) - c v_i,   s(d) = k d + k3 d^3,
!> y = [x(1:m), v(1:m)], with its closed-form Jacobian (banded: a test problem for
!> coloured difference quotients, test_solver_coloured_jacobian).
module rd_chain_test_problem
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_ode_system, only: ode_system_t
  implicit none
  private
  public :: chain_t, chain_jacobian, spring, pos, m, n, k_lin, k_cub, c_damp

  integer, parameter :: m = 10, n = 2 * m
  real(wp), parameter :: k_lin = 4.0e4_wp, k_cub = 3.0e9_wp, c_damp = 50.0_wp

  type, extends(ode_system_t) :: chain_t
    integer :: calls = 0
  contains
    procedure :: rhs => chain_rhs
    procedure :: state_size => chain_size
  end type chain_t

contains

  subroutine chain_rhs(self, t, y, ydot, error)
    class(chain_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    self%calls = self%calls + 1
    do i = 1, m
      ydot(i) = y(m + i)
      ydot(m + i) = spring(pos(y, i + 1) - y(i)) - spring(y(i) - pos(y, i - 1)) - c_damp * y(m + i)
    end do
  end subroutine chain_rhs

  pure integer function chain_size(self)
    class(chain_t), intent(in) :: self
    chain_size = n
  end function chain_size

  pure real(wp) function pos(y, i)
    real(wp), intent(in) :: y(:)
    integer, intent(in) :: i
    pos = 0.0_wp                 ! fixed ends
    if (i >= 1 .and. i <= m) pos = y(i)
  end function pos

  pure real(wp) function spring(d)
    real(wp), intent(in) :: d
    spring = k_lin * d + k_cub * d**3
  end function spring

  pure real(wp) function spring_slope(d)
    real(wp), intent(in) :: d
    spring_slope = k_lin + 3.0_wp * k_cub * d**2
  end function spring_slope

  !> Closed-form Jacobian of the chain.
  pure function chain_jacobian(y) result(jac)
    real(wp), intent(in) :: y(:)
    real(wp) :: jac(n, n)
    real(wp) :: sr, sl
    integer :: i
    jac = 0.0_wp
    do i = 1, m
      jac(i, m + i) = 1.0_wp
      sr = spring_slope(pos(y, i + 1) - y(i))
      sl = spring_slope(y(i) - pos(y, i - 1))
      jac(m + i, i) = -sr - sl
      if (i < m) jac(m + i, i + 1) = sr
      if (i > 1) jac(m + i, i - 1) = sl
      jac(m + i, m + i) = -c_damp
    end do
  end function chain_jacobian

end module rd_chain_test_problem
