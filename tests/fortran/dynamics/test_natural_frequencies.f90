!> Natural frequencies against closed forms, from the eigenvalues of the RHS Jacobian
!> (central differences) at static equilibrium, on a frame moving at 50 m/s on straight
!> track (frequencies do not depend on a uniform frame speed):
!>  A. spring-mass: springs at the CG, vertical sqrt(kz/m) and lateral sqrt(ky/m);
!>  B. a body hanging from a preloaded spring "pivot" a height l above its CG (yaw, x and
!>     pitch frozen): lateral-roll pair from det(K - w^2 M) = 0 with the linearised
!>     Lagrangian written here, M = diag(m, Ix), K = [[k, -k l], [-k l, k l^2 + m g l]]
!>     (m g l: the pendulum stiffness of the preload), and vertical sqrt(kz/m);
!>  C. a roll pendulum about a stiff pivot: as k -> large, w -> sqrt(m g l / (Ix + m l^2)).
program test_natural_frequencies
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_dynamics_test_support, only: straight_track_t
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: m = 1000, ix = 300, g = 9.80665_wp, ky = 2.0e5_wp, kz = 1.0e6_wp
  real(wp), allocatable :: w(:)
  real(wp) :: l, a2, a1, a0, lam1, lam2, expect(3)
  character(len=160) :: buf

  ! A: springs at the CG
  w = frequencies(0.0_wp, ky, [.false., .false., .false., .true., .true., .true.])
  expect = [sqrt(ky / m), sqrt(ky / m), sqrt(kz / m)]     ! x and y share the shear stiffness
  write (buf, '(a,*(f11.6))') 'computed, closed form ', w, expect
  call check(size(w) == 3 .and. &
             maxval(abs(w - expect) / expect) < 1e-6_wp, 'A: longitudinal, lateral and vertical spring-mass', detail=trim(buf))

  ! B: pivot l above the CG
  l = 0.5_wp
  w = frequencies(l, ky, [.true., .false., .false., .true., .false., .true.])
  a2 = m * ix
  a1 = -(m * (ky * l**2 + m * g * l) + ky * ix)
  a0 = ky * m * g * l
  lam1 = (-a1 - sqrt(a1**2 - 4 * a2 * a0)) / (2 * a2)
  lam2 = (-a1 + sqrt(a1**2 - 4 * a2 * a0)) / (2 * a2)
  expect = [sqrt(lam1), sqrt(lam2), sqrt(kz / m)]
  call sort(expect)
  write (buf, '(a,*(f11.6))') 'computed, closed form ', w, expect
  call check(size(w) == 3 .and. maxval(abs(w - expect) / expect) < 1e-6_wp, 'B: lateral-roll pair and vertical', detail=trim(buf))

  ! C: stiff pivot -> compound pendulum
  w = frequencies(l, 1.0e10_wp, [.true., .false., .true., .true., .false., .true.])
  expect(1) = sqrt(m * g * l / (ix + m * l**2))
  write (buf, '(a,*(f12.7))') 'pendulum mode, closed form ', w(1), expect(1)
  call check(abs(w(1) - expect(1)) / expect(1) < 1e-5_wp, 'C: compound pendulum about a stiff pivot', detail=trim(buf))

  call test_summary('test_natural_frequencies')

contains

  pure subroutine sort(x)
    real(wp), intent(inout) :: x(:)
    integer :: i, j
    real(wp) :: t
    do i = 1, size(x)
      do j = i + 1, size(x)
        if (x(j) < x(i)) then
          t = x(i); x(i) = x(j); x(j) = t
        end if
      end do
    end do
  end subroutine sort

  !> Undamped natural frequencies [rad/s] (sorted, one per free coordinate pair).
  function frequencies(lpivot, klat, frozen) result(freq)
    real(wp), intent(in) :: lpivot, klat
    logical, intent(in) :: frozen(6)
    real(wp), allocatable :: freq(:)
    type(multibody_t), target :: mb
    class(track_geometry_t), pointer :: track
    type(body_spec_t) :: body(1)
    type(linear_spring_damper_t) :: spring
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:), yp(:), ym(:), fp(:), fm(:), jac(:, :), wr(:), wi(:), work(:), vl(:, :), vr(:, :)
    integer :: n, j, info
    real(wp) :: h
    allocate (straight_track_t :: track)
    body(1)%name = 'hanging'
    body(1)%mass = m
    body(1)%inertia = reshape([ix, 0.0_wp, 0.0_wp, 0.0_wp, 500.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 400.0_wp], [3, 3])
    body(1)%frozen = frozen
    call mb%build(body, [0.0_wp], track, constant_speed(50.0_wp), error)
    spring%body1 = 0; spring%body2 = 1
    spring%u1 = [0.0_wp, 0.0_wp, lpivot]      ! on the track frame
    spring%u2 = [0.0_wp, 0.0_wp, lpivot]      ! on the body, l above its CG
    spring%stiffness = [klat, klat, kz]
    spring%preload = [0.0_wp, 0.0_wp, m * g]
    call mb%add_element(spring, error)
    n = mb%state_size()
    allocate (y(n), yp(n), ym(n), fp(n), fm(n), jac(n, n), wr(n), wi(n), work(8 * n), vl(1, 1), vr(1, 1))
    call mb%initial_state(y, error)
    do j = 1, n
      h = 1.0e-6_wp
      yp = y; yp(j) = yp(j) + h
      ym = y; ym(j) = ym(j) - h
      call mb%rhs(0.0_wp, yp, fp, error)
      call mb%rhs(0.0_wp, ym, fm, error)
      jac(:, j) = (fp - fm) / (2 * h)
    end do
    call dgeev('N', 'N', n, jac, n, wr, wi, vl, 1, vr, 1, work, size(work), info)
    ! eigenvalues +-i w: keep the non-negative imaginary parts
    freq = pack(wi, wi >= 0)
    call sort(freq)
  end function frequencies
end program test_natural_frequencies
