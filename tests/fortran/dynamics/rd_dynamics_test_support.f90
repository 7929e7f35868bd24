!> Helpers for the dynamics and elements tests: exact test tracks written independently of
!> rd_track and a classical RK4 integrator.
module rd_dynamics_test_support
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: rot_x, rot_y, rot_z, skew, unskew
  use rd_ode_system, only: ode_system_t
  use rd_track_point, only: track_point_t, track_geometry_t
  implicit none
  private
  public :: straight_track_t, canted_circle_t, rk4_integrate, zxy_rotation, zxy_omega_body

  !> Level straight track along X.
  type, extends(track_geometry_t) :: straight_track_t
  contains
    procedure :: evaluate => straight_evaluate
    procedure :: length => any_length
  end type straight_track_t

  !> Circle of signed curvature kappa (> 0 left), constant cant angle phi_t, starting at the
  !> origin heading along X: psi = kappa sigma, A = Rz(psi) Rx(phi_t),
  !> w = kappa (0, sin phi_t, cos phi_t) (A^T dA/dsigma = skew(w)).
  type, extends(track_geometry_t) :: canted_circle_t
    real(wp) :: kappa = 0
    real(wp) :: cant = 0
    !> optional smooth cant variation phi_t = cant + cant_amplitude sin(sigma / cant_wavelength)
    !> (exercises the frame's roll rate w_x and dw/dsigma with no discontinuity)
    real(wp) :: cant_amplitude = 0
    real(wp) :: cant_scale = 1
  contains
    procedure :: evaluate => circle_evaluate
    procedure :: length => circle_length
  end type canted_circle_t

contains

  pure function straight_evaluate(self, sigma) result(p)
    class(straight_track_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: p
    p%sigma = sigma
    p%r = [sigma, 0.0_wp, 0.0_wp]
    p%dr = [1.0_wp, 0.0_wp, 0.0_wp]
    p%a = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
  end function straight_evaluate

  pure function any_length(self) result(total)
    class(straight_track_t), intent(in) :: self
    real(wp) :: total
    total = 1.0e9_wp
  end function any_length

  pure function circle_length(self) result(total)
    class(canted_circle_t), intent(in) :: self
    real(wp) :: total
    total = 1.0e9_wp
  end function circle_length

  pure function circle_evaluate(self, sigma) result(p)
    class(canted_circle_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    type(track_point_t) :: p
    real(wp) :: psi, k, ph, dph, d2ph
    k = self%kappa
    ph = self%cant + self%cant_amplitude * sin(sigma / self%cant_scale)
    dph = self%cant_amplitude * cos(sigma / self%cant_scale) / self%cant_scale
    d2ph = -self%cant_amplitude * sin(sigma / self%cant_scale) / self%cant_scale**2
    psi = k * sigma
    p%sigma = sigma
    if (abs(k) > 0) then
      p%r = [sin(psi) / k, (1 - cos(psi)) / k, 0.0_wp]
    else
      p%r = [sigma, 0.0_wp, 0.0_wp]
    end if
    p%dr = [cos(psi), sin(psi), 0.0_wp]
    p%d2r = k * [-sin(psi), cos(psi), 0.0_wp]
    p%a = matmul(rot_z(psi), rot_x(ph))
    ! A^T dA/dsigma = Rx^T skew(kappa e_z) Rx + skew(dph e_x)
    p%omega = [dph, k * sin(ph), k * cos(ph)]
    p%domega = [d2ph, k * cos(ph) * dph, -k * sin(ph) * dph]
    p%da = matmul(p%a, skew(p%omega))
    p%d2a = matmul(p%a, matmul(skew(p%omega), skew(p%omega)) + skew(p%domega))
    p%heading = psi
    p%cant_angle = ph
    p%curvature = k
    p%superelevation = 1.5_wp * sin(ph)
  end function circle_evaluate

  !> B = Rz(psi) Rx(phi) Ry(theta), written here from the elementary rotations.
  pure function zxy_rotation(a) result(b)
    real(wp), intent(in) :: a(3)
    real(wp) :: b(3, 3)
    b = matmul(rot_z(a(1)), matmul(rot_x(a(2)), rot_y(a(3))))
  end function zxy_rotation

  !> Angular velocity in body components from unskew(B^T dB/dt), with dB/dt by the product
  !> rule (dRz/dt = Rz skew(e_z) dpsi/dt, ...): independent of the code's H matrix.
  pure function zxy_omega_body(a, ad) result(w)
    real(wp), intent(in) :: a(3), ad(3)
    real(wp) :: w(3)
    real(wp) :: rz(3, 3), rx(3, 3), ry(3, 3), bd(3, 3)
    rz = rot_z(a(1)); rx = rot_x(a(2)); ry = rot_y(a(3))
    bd = matmul(matmul(rz, skew([0.0_wp, 0.0_wp, ad(1)])), matmul(rx, ry)) &
         + matmul(rz, matmul(matmul(rx, skew([ad(2), 0.0_wp, 0.0_wp])), ry)) &
         + matmul(rz, matmul(rx, matmul(ry, skew([0.0_wp, ad(3), 0.0_wp]))))
    w = unskew(matmul(transpose(zxy_rotation(a)), bd))
  end function zxy_omega_body

  !> Classical RK4 with fixed step h from t0 to t1 (y updated in place).
  subroutine rk4_integrate(sys, t0, t1, h, y, ok)
    class(ode_system_t), intent(inout) :: sys
    real(wp), intent(in) :: t0, t1, h
    real(wp), intent(inout) :: y(:)
    logical, intent(out) :: ok
    real(wp), allocatable :: k1(:), k2(:), k3(:), k4(:)
    type(error_t), allocatable :: error
    integer :: i, n
    real(wp) :: t, dt
    allocate (k1(size(y)), k2(size(y)), k3(size(y)), k4(size(y)))
    n = max(1, nint((t1 - t0) / h))
    dt = (t1 - t0) / n
    ok = .true.
    t = t0
    do i = 1, n
      call sys%rhs(t, y, k1, error)
      if (allocated(error)) goto 90
      call sys%rhs(t + dt / 2, y + dt / 2 * k1, k2, error)
      if (allocated(error)) goto 90
      call sys%rhs(t + dt / 2, y + dt / 2 * k2, k3, error)
      if (allocated(error)) goto 90
      call sys%rhs(t + dt, y + dt * k3, k4, error)
      if (allocated(error)) goto 90
      y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
      t = t0 + i * dt
    end do
    return
90  print '(a)', 'rk4_integrate: ' // error%message
    ok = .false.
  end subroutine rk4_integrate

end module rd_dynamics_test_support
