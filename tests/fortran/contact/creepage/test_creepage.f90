!> Creepages against rigid-body kinematics worked by hand (thesis 3.6.1):
!> a wheel of radius r rolling at V with spin rate w has xi = (V - w r)/V; a wheelset yawed
!> by psi has eta = -sin(psi); a contact normal tilted by gamma gives phi = sin(gamma)/r.
!> Standstill: finite, and continuous across V = 0 (regularised V_ref).
program test_creepage
  use rd_kinds, only: wp
  use rd_creepage
  use rd_test_support, only: check_close, fail, test_summary
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  type(creepage_t) :: c, c_plus, c_minus
  real(wp) :: frame(3, 3), v, r, w, psi, gamma, v0, p(3)
  v0 = 0.05_wp
  frame = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])

  ! --- braking wheel: xi = (V - w r)/V_ref, V_ref = sqrt(V_roll^2 + v0^2)
  v = 30.0_wp; r = 0.46_wp; w = 0.99_wp * v / r
  p = [0.0_wp, 0.0_wp, -r]
  call creepages_from_velocities([v, 0.0_wp, 0.0_wp], [v, 0.0_wp, 0.0_wp] + cross([0.0_wp, w, 0.0_wp], p), &
                                 [0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, w, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], frame, v0, c)
  call check_close(c%xi, (v - w * r) / sqrt((0.5_wp * (v + w * r))**2 + v0**2), 1.0e-12_wp, 'xi braking')
  call check_close(c%xi, 0.01_wp, 0.01_wp, 'xi ~ 0.01')
  call check_close(c%eta, 0.0_wp, 1.0e-15_wp, 'eta none')

  ! --- yawed wheelset (axle turned by psi): eta = -sin(psi) (Wickens: eta = ydot/V - psi)
  psi = 0.01_wp; w = v / r
  call creepages_from_velocities([v, 0.0_wp, 0.0_wp], &
       [v, 0.0_wp, 0.0_wp] + cross(w * [-sin(psi), cos(psi), 0.0_wp], p), [0.0_wp, 0.0_wp, 0.0_wp], &
       w * [-sin(psi), cos(psi), 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], frame, v0, c)
  ! slip -V sin(psi); rolling speed mean of V and V cos(psi)
  call check_close(c%eta, -v * sin(psi) / sqrt((0.5_wp * v * (1.0_wp + cos(psi)))**2 + v0**2), 1.0e-12_wp, 'eta yaw')
  call check_close(c%eta, -psi, 1.0e-4_wp, 'eta ~ -psi')

  ! --- conical contact: normal tilted by gamma towards +y, phi = sin(gamma)/r
  gamma = 0.05_wp; w = v / r
  frame(:, 2) = [0.0_wp, cos(gamma), -sin(gamma)]
  frame(:, 3) = [0.0_wp, sin(gamma), cos(gamma)]
  p = -r * [0.0_wp, sin(gamma), cos(gamma)] / cos(gamma)  ! any point on the normal line below the axle
  call creepages_from_velocities([v, 0.0_wp, 0.0_wp], [v, 0.0_wp, 0.0_wp] + cross([0.0_wp, w, 0.0_wp], p), &
                                 [0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, w, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], frame, v0, c)
  call check_close(c%phi, sin(gamma) / r, 1.0e-5_wp, 'phi cone')

  ! --- standstill: finite, continuous across V = 0, equal to slip / v0 at V = 0
  call creepages_from_components([1.0e-3_wp, -2.0e-3_wp], 1.0e-3_wp, 0.0_wp, v0, c)
  if (.not. (ieee_is_finite(c%xi) .and. ieee_is_finite(c%eta) .and. ieee_is_finite(c%phi))) call fail('V = 0 must be finite')
  call check_close(c%xi, 1.0e-3_wp / v0, 1.0e-14_wp, 'xi at V=0')
  call creepages_from_components([1.0e-3_wp, -2.0e-3_wp], 1.0e-3_wp, 1.0e-7_wp, v0, c_plus)
  call creepages_from_components([1.0e-3_wp, -2.0e-3_wp], 1.0e-3_wp, -1.0e-7_wp, v0, c_minus)
  call check_close(c_plus%eta, c%eta, 1.0e-10_wp, 'continuous +')
  call check_close(c_minus%eta, c%eta, 1.0e-10_wp, 'continuous -')
  ! fast running: regularisation negligible (relative v0^2 / (2 V^2))
  call creepages_from_components([0.3_wp, 0.0_wp], 0.0_wp, 30.0_wp, v0, c)
  call check_close(c%xi, 0.01_wp, 2.0e-6_wp, 'fast xi')
  if (c%v_ref /= reference_speed(30.0_wp, v0)) call fail('v_ref reported')

  call test_summary('test_creepage')
contains
  pure function cross(x, y) result(z)
    real(wp), intent(in) :: x(3), y(3)
    real(wp) :: z(3)
    z = [x(2) * y(3) - x(3) * y(2), x(3) * y(1) - x(1) * y(3), x(1) * y(2) - x(2) * y(1)]
  end function cross
end program test_creepage
