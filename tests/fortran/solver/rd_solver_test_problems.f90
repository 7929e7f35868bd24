!> Test problems with closed-form solutions for the integrator tests, plus systems that
!> fail on purpose. Each exact solution is written here independently of the solver.
module rd_solver_test_problems
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, retry_error, RD_ERR_PHYSICS, RD_ERR_RUNTIME
  use rd_ode_system, only: ode_system_t
  implicit none
  private
  public :: oscillator_t, decay_t, stiff_cosine_t, stiff_pair_t, failing_t
  public :: stiff_pair_jacobian, report
  public :: FAIL_FATAL, FAIL_NAN, FAIL_RECOVERABLE_ALWAYS, FAIL_RECOVERABLE_FEW

  !> x'' = -omega^2 x as y = (x, v): x(t) = x0 cos(wt) + v0/w sin(wt).
  type, extends(ode_system_t) :: oscillator_t
    real(wp) :: omega = 2.0_wp * pi
    integer :: calls = 0
  contains
    procedure :: rhs => oscillator_rhs
    procedure :: state_size => two
    procedure :: exact => oscillator_exact
  end type oscillator_t

  !> y' = -lambda y: y(t) = y0 exp(-lambda t).
  type, extends(ode_system_t) :: decay_t
    real(wp) :: lambda = 1.0_wp
  contains
    procedure :: rhs => decay_rhs
    procedure :: state_size => one_decay
  end type decay_t

  !> y' = -k (y - cos t) - sin t, y(0) = 1: y(t) = cos t for any k (stiff for k >> 1).
  type, extends(ode_system_t) :: stiff_cosine_t
    real(wp) :: k = 1000.0_wp
  contains
    procedure :: rhs => stiff_cosine_rhs
    procedure :: state_size => one_cos
  end type stiff_cosine_t

  !> y' = A y with A = V diag(-1, -1e5) V^-1, V = [1 0.5; 0.2 1] (eigenvalues -1 and
  !> -1e5, coupled, A not symmetric so a transposed Jacobian would show):
  !> y(t) = V diag(exp(-t), exp(-1e5 t)) V^-1 y0.
  type, extends(ode_system_t) :: stiff_pair_t
    real(wp) :: lambda(2) = [-1.0_wp, -1.0e5_wp]
    real(wp) :: coupling(2) = [0.2_wp, 0.5_wp]   !< V(2,1), V(1,2)
  contains
    procedure :: rhs => stiff_pair_rhs
    procedure :: state_size => two_pair
    procedure :: matrix => stiff_pair_matrix
    procedure :: exact => stiff_pair_exact
  end type stiff_pair_t

  integer, parameter :: FAIL_FATAL = 1               !< unrecoverable error for t >= t_fail
  integer, parameter :: FAIL_NAN = 2                 !< NaN derivative for t >= t_fail
  integer, parameter :: FAIL_RECOVERABLE_ALWAYS = 3  !< recoverable error on every call
  integer, parameter :: FAIL_RECOVERABLE_FEW = 4     !< recoverable error on the first 3 calls with t >= t_fail

  !> y' = -y that fails in the chosen way.
  type, extends(ode_system_t) :: failing_t
    integer :: mode = FAIL_FATAL
    real(wp) :: t_fail = 0.5_wp
    integer :: failures = 0   !< failures produced so far
  contains
    procedure :: rhs => failing_rhs
    procedure :: state_size => one_fail
  end type failing_t

contains

  subroutine oscillator_rhs(self, t, y, ydot, error)
    class(oscillator_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    self%calls = self%calls + 1
    ydot(1) = y(2)
    ydot(2) = -self%omega**2 * y(1)
  end subroutine oscillator_rhs

  pure function oscillator_exact(self, t, y0) result(y)
    class(oscillator_t), intent(in) :: self
    real(wp), intent(in) :: t, y0(2)
    real(wp) :: y(2)
    real(wp) :: w
    w = self%omega
    y(1) = y0(1) * cos(w * t) + y0(2) / w * sin(w * t)
    y(2) = -y0(1) * w * sin(w * t) + y0(2) * cos(w * t)
  end function oscillator_exact

  pure integer function two(self)
    class(oscillator_t), intent(in) :: self
    two = 2
  end function two

  subroutine decay_rhs(self, t, y, ydot, error)
    class(decay_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    ydot(1) = -self%lambda * y(1)
  end subroutine decay_rhs

  pure integer function one_decay(self)
    class(decay_t), intent(in) :: self
    one_decay = 1
  end function one_decay

  subroutine stiff_cosine_rhs(self, t, y, ydot, error)
    class(stiff_cosine_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    ydot(1) = -self%k * (y(1) - cos(t)) - sin(t)
  end subroutine stiff_cosine_rhs

  pure integer function one_cos(self)
    class(stiff_cosine_t), intent(in) :: self
    one_cos = 1
  end function one_cos

  !> Eigenvector matrix V (columns) and its inverse, written out (2x2 closed form).
  pure subroutine stiff_pair_modes(self, v, v_inv)
    class(stiff_pair_t), intent(in) :: self
    real(wp), intent(out) :: v(2, 2), v_inv(2, 2)
    real(wp) :: det
    v = reshape([1.0_wp, self%coupling(1), self%coupling(2), 1.0_wp], [2, 2])
    det = v(1, 1) * v(2, 2) - v(1, 2) * v(2, 1)
    v_inv = reshape([v(2, 2), -v(2, 1), -v(1, 2), v(1, 1)], [2, 2]) / det
  end subroutine stiff_pair_modes

  pure function stiff_pair_matrix(self) result(a)
    class(stiff_pair_t), intent(in) :: self
    real(wp) :: a(2, 2), v(2, 2), v_inv(2, 2), d(2, 2)
    call stiff_pair_modes(self, v, v_inv)
    d = 0.0_wp
    d(1, 1) = self%lambda(1)
    d(2, 2) = self%lambda(2)
    a = matmul(v, matmul(d, v_inv))
  end function stiff_pair_matrix

  pure function stiff_pair_exact(self, t, y0) result(y)
    class(stiff_pair_t), intent(in) :: self
    real(wp), intent(in) :: t, y0(2)
    real(wp) :: y(2), v(2, 2), v_inv(2, 2), z(2)
    call stiff_pair_modes(self, v, v_inv)
    z = matmul(v_inv, y0)                     ! modal coordinates
    z = z * exp(self%lambda * t)
    y = matmul(v, z)
  end function stiff_pair_exact

  subroutine stiff_pair_rhs(self, t, y, ydot, error)
    class(stiff_pair_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    ydot = matmul(self%matrix(), y)
  end subroutine stiff_pair_rhs

  pure integer function two_pair(self)
    class(stiff_pair_t), intent(in) :: self
    two_pair = 2
  end function two_pair

  !> Analytic Jacobian of stiff_pair_t (matches rd_rhs_context's jacobian_i).
  subroutine stiff_pair_jacobian(system, t, y, ydot, jac, error)
    class(ode_system_t), intent(inout) :: system
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(in) :: ydot(:)
    real(wp), intent(out) :: jac(:, :)
    type(error_t), allocatable, intent(out) :: error
    select type (system)
    class is (stiff_pair_t)
      jac = system%matrix()
    class default
      call make_error(error, RD_ERR_RUNTIME, 'stiff_pair_jacobian: wrong system type')
    end select
  end subroutine stiff_pair_jacobian

  subroutine failing_rhs(self, t, y, ydot, error)
    class(failing_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    ydot(1) = -y(1)
    select case (self%mode)
    case (FAIL_FATAL)
      if (t >= self%t_fail) call make_error(error, RD_ERR_PHYSICS, &
                                            'wheelset 1 derailed (test message)')
    case (FAIL_NAN)
      if (t >= self%t_fail) ydot(1) = ieee_value(1.0_wp, ieee_quiet_nan)
    case (FAIL_RECOVERABLE_ALWAYS)
      self%failures = self%failures + 1
      call retry_error(error, 'contact search out of range (test message)')
    case (FAIL_RECOVERABLE_FEW)
      if (t >= self%t_fail .and. self%failures < 3) then
        self%failures = self%failures + 1
        call retry_error(error, 'contact search out of range (test message)')
      end if
    end select
  end subroutine failing_rhs

  pure integer function one_fail(self)
    class(failing_t), intent(in) :: self
    one_fail = 1
  end function one_fail

  !> Print one measured figure (shown by ctest --output-on-failure / -V).
  subroutine report(label, value)
    character(len=*), intent(in) :: label
    real(wp), intent(in) :: value
    write (*, '(a, t52, es12.4)') label, value
  end subroutine report
end module rd_solver_test_problems
