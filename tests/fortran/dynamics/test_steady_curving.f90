!> Steady curving and mirror symmetry.
!>  1. A body held by lateral and vertical springs at its CG to its track frame (rotations
!>     and x frozen) runs through a canted curve and settles at the lateral deflection
!>     y = -m (V^2/R cos(phi_t) + g sin(phi_t)) / k for a left curve (kappa = 1/R > 0,
!>     centre on +Y; phi_t < 0 raises the outer right rail; conventions.md), the textbook
!>     result of oracles.md. The test also solves the exact steady state of the body on
!>     its horizontal circle (radius R minus its horizontal offset) by fixed-point
!>     iteration, written here from the geometry alone, and requires agreement to 1e-9.
!>     Integrated with rd_integrator's CVODE BDF (the stiff method runs use).
!>  2. Mirror: a free 6-DOF body on four springs through a left and a right canted curve
!>     from mirror-symmetric initial conditions: y, psi, phi change sign, x, z, theta not.
program test_steady_curving
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_geometry_t
  use rd_speed_law, only: constant_speed
  use rd_body_spec, only: body_spec_t
  use rd_multibody, only: multibody_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_rotation, only: rot_x
  use rd_integrator, only: integrator_t, integrator_settings_t
  use rd_dynamics_test_support, only: canted_circle_t, rk4_integrate
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: m = 2000, g = 9.80665_wp, v = 40, r = 600, cant = -0.1_wp
  real(wp), parameter :: ky = 2.0e5_wp, kz = 8.0e5_wp
  real(wp) :: y_left(6), y_right(6), w(3), w_formula, sl(12), sr(12), err
  character(len=120) :: buf

  ! ---- 1. steady curving, left and right
  call settle(+1.0_wp / r, cant, y_left)
  call settle(-1.0_wp / r, -cant, y_right)
  w = exact_steady(+1.0_wp / r, cant)
  w_formula = -m * (v**2 / r * cos(cant) + g * sin(cant)) / ky
  write (buf, '(a,es14.7,a,es14.7,a,es9.2,a,es14.7)') 'y = ', y_left(2), ' exact ', w(2), ' diff ', y_left(2) - w(2), &
    ' textbook ', w_formula
  call check(abs(y_left(2) - w(2)) < 1e-9_wp, 'steady curving: y against the exact steady state', detail=trim(buf))
  call check(abs(y_left(3) - w(3)) < 1e-9_wp, 'steady curving: z against the exact steady state')
  ! the textbook formula neglects the O(y/R) change of radius and the vertical spring's tilt
  call check(abs(y_left(2) - w_formula) < 1e-3_wp * abs(w_formula), 'steady curving: textbook formula within O(y/R)')
  call check(y_left(2) < 0, 'steady curving: outward (to the right, y < 0) in a left curve with cant deficiency')
  call check(abs(y_left(2) + y_right(2)) < 1e-12_wp, 'steady curving mirror: y')
  call check(abs(y_left(3) - y_right(3)) < 1e-12_wp, 'steady curving mirror: z')

  ! ---- 2. mirror of a free body
  call free_run(+1.0_wp / 400, -0.08_wp, sl)
  call free_run(-1.0_wp / 400, +0.08_wp, sr)
  err = maxval(abs(sl([1, 3, 6, 7, 9, 12]) - sr([1, 3, 6, 7, 9, 12]))) + &
        maxval(abs(sl([2, 4, 5, 8, 10, 11]) + sr([2, 4, 5, 8, 10, 11])))
  write (buf, '(a,es9.2,a,3es10.2)') 'mirror error ', err, '; y, psi, phi = ', sl(2), sl(4), sl(5)
  call check(err < 1e-12_wp, 'mirror: left curve = mirrored right curve', detail=trim(buf))
  call check(abs(sl(2)) > 1e-4_wp .and. abs(sl(4)) > 1e-4_wp, 'mirror: the curve really moved the body')

  call test_summary('test_steady_curving')

contains

  subroutine settle(kappa, phi_t, q)
    real(wp), intent(in) :: kappa, phi_t
    real(wp), intent(out) :: q(6)
    type(multibody_t), target :: mb
    class(track_geometry_t), pointer :: track
    type(body_spec_t) :: body(1)
    type(linear_spring_damper_t) :: spring
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:)
    logical :: ok
    type(integrator_t) :: integ
    type(integrator_settings_t) :: settings
    allocate (canted_circle_t :: track)
    select type (track)
    type is (canted_circle_t)
      track%kappa = kappa; track%cant = phi_t
    end select
    body(1)%name = 'mass'
    body(1)%mass = m
    body(1)%inertia = reshape([500.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 800.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 700.0_wp], [3, 3])
    body(1)%frozen = [.true., .false., .false., .true., .true., .true.]
    call mb%build(body, [0.0_wp], track, constant_speed(v), error)
    spring%body1 = 0; spring%body2 = 1
    spring%stiffness = [0.0_wp, ky, kz]
    spring%damping = [0.0_wp, 2 * 0.7_wp * sqrt(ky * m), 2 * 0.7_wp * sqrt(kz * m)]
    call mb%add_element(spring, error)
    allocate (y(mb%state_size()))
    call mb%initial_state(y, error)
    call check(size(y) == 4, 'frozen x and angles leave the state')
    settings%method = 'bdf'; settings%rtol = 1.0e-10_wp; settings%atol = 1.0e-13_wp
    settings%max_num_steps = 100000
    call integ%build(mb, 0.0_wp, y, settings, error)
    if (.not. allocated(error)) call integ%advance(8.0_wp, y, error)
    ok = .not. allocated(error)
    if (.not. ok) print '(a)', error%message
    call integ%destroy()
    q = 0
    q(2:3) = y(1:2)
    call check(ok .and. maxval(abs(y(3:4))) < 1e-10_wp, 'settled (rates ~ 0)')
  end subroutine settle

  !> Exact steady state: the body point P = p + A w turns with the frame at rate V kappa
  !> about the vertical axis through the curve centre C; its acceleration is
  !> -(V kappa)^2 (P - C)_horizontal. Solve K w = A^T m (g_vec - acc) by fixed point.
  function exact_steady(kappa, phi_t) result(w)
    real(wp), intent(in) :: kappa, phi_t
    real(wp) :: w(3), a(3, 3), p(3), c(3), acc(3), rel(3), f(3)
    integer :: it
    a = rot_x(phi_t)                     ! heading 0 at sigma = 0: A = Rx(phi_t)
    c = [0.0_wp, 1.0_wp / kappa, 0.0_wp]
    w = 0
    do it = 1, 200
      p = matmul(a, w)
      rel = p - c
      rel(3) = 0
      acc = -(v * kappa)**2 * rel
      f = matmul(transpose(a), m * ([0.0_wp, 0.0_wp, -g] - acc))   ! spring force needed, track axes
      w(2:3) = f(2:3) / [ky, kz]
    end do
  end function exact_steady

  subroutine free_run(kappa, phi_t, s)
    real(wp), intent(in) :: kappa, phi_t
    real(wp), intent(out) :: s(12)
    type(multibody_t), target :: mb
    class(track_geometry_t), pointer :: track
    type(body_spec_t) :: body(1)
    type(linear_spring_damper_t) :: spring
    type(error_t), allocatable :: error
    real(wp), allocatable :: y(:)
    real(wp) :: corners(3, 4)
    integer :: i
    logical :: ok
    allocate (canted_circle_t :: track)
    select type (track)
    type is (canted_circle_t)
      track%kappa = kappa; track%cant = phi_t
    end select
    body(1)%name = 'box'
    body(1)%mass = m
    ! mirror-symmetric inertia: Ixz allowed, Ixy = Iyz = 0
    body(1)%inertia = reshape([500.0_wp, 0.0_wp, 30.0_wp, 0.0_wp, 800.0_wp, 0.0_wp, 30.0_wp, 0.0_wp, 700.0_wp], [3, 3])
    body(1)%q0 = [0.01_wp, 0.0_wp, 0.02_wp, 0.0_wp, 0.0_wp, 0.01_wp]
    body(1)%qdot0 = [0.05_wp, 0.0_wp, -0.03_wp, 0.0_wp, 0.0_wp, 0.04_wp]
    call mb%build(body, [0.0_wp], track, constant_speed(v), error)
    ! front-rear asymmetric (yaw couples to the lateral load), left-right symmetric
    corners = reshape([1.0_wp, 0.9_wp, -0.4_wp, 1.0_wp, -0.9_wp, -0.4_wp, -1.5_wp, 0.9_wp, -0.4_wp, &
                       -1.5_wp, -0.9_wp, -0.4_wp], [3, 4])
    do i = 1, 4
      spring%body1 = 0; spring%body2 = 1
      spring%u1 = corners(:, i); spring%u2 = corners(:, i)
      spring%stiffness = [1.0e5_wp, 1.5e5_wp, 4.0e5_wp]
      spring%damping = [1.0e3_wp, 2.0e3_wp, 4.0e3_wp]
      spring%preload = [0.0_wp, 0.0_wp, m * g / 4]
      call mb%add_element(spring, error)
    end do
    allocate (y(mb%state_size()))
    call mb%initial_state(y, error)
    call rk4_integrate(mb, 0.0_wp, 2.0_wp, 1.0e-3_wp, y, ok)
    s = y
  end subroutine free_run
end program test_steady_curving
