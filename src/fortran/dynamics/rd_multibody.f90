!> The multibody system: rigid bodies in track-following frames, force elements and force
!> providers, as one ODE y' = f(t, y) for the integrators (thesis chapter 4, eqs. 4.27-4.62;
!> the equations as implemented, with the thesis' typos corrected, are in docs/theory.md).
!>
!> State layout (documented for the integrators, the outputs and the C API):
!>   y = [ q_f(1:nfree) ; nu_f(1:nfree) ; x_el(1:nel_states) ]
!> q_f are the free coordinates of all bodies, body after body, each body in the order
!> (x, y, z, psi, phi, theta) with its frozen coordinates skipped; for a wheelset the
!> pitch slot holds the spin deviation beta (theta = s(t)/r0 + beta).
!> nu_f are generalized velocities nu = qdot + c(q, Omega), c = (Omega x w_bar,
!> H^{-1} B^T Omega) (docs/theory.md section 5): on straight track nu = qdot; they stay
!> continuous where the frame's angular velocity jumps (a linear cant ramp starts, a
!> curve joins a straight), so the absolute velocities do. The wheelset spin slot holds
!> nu_theta - V/r0 (= dbeta/dt on straight track). Relative rates for output: kin(i)%qdot.
!> x_el are the elements' internal states, element after element.
!>
!> Frozen coordinates are not in the state: they keep q0 and zero rate (a wheelset's frozen
!> spin keeps beta = beta0, i.e. rolls at V/r0). Quasi-static coordinates (a wheelset's z and
!> roll on quasi-static normal contact) are not in the state either: every evaluation solves
!> them for zero relative acceleration, their inertia neglected, with zero relative rate
!> (solve_quasi_static; docs/theory.md "Quasi-static normal contact"). Each body's generalized mass matrix is
!> block-diagonal (m I, H^T J H) because the body frame sits at the CG, so the reduced
!> system is solved body by body with at most 3x3 eliminations and no allocation.
module rd_multibody
  use, intrinsic :: iso_fortran_env, only: int64
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t, make_error, error_context, retry_error, nonfinite_error, finite, RD_ERR_INPUT, &
                      RD_ERR_RUNTIME, RD_ERR_INTERNAL, RD_ERR_PHYSICS
  use rd_text, only: sci_text
  use rd_rotation, only: cross
  use rd_text, only: int_text
  use rd_ode_system, only: ode_system_t
  use rd_track_point, only: track_point_t, track_geometry_t
  use rd_speed_law, only: speed_law_t
  use rd_body_spec, only: body_spec_t, validate_body_spec, DOF_PITCH, DOF_Z, DOF_ROLL, &
                          spin_from_deviation, deviation_from_spin
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics, ground_kinematics, &
                                angle_rate_matrix, angle_rate_matrix_dot, inverse_angle_rate, &
                                frame_rate_shift, rotation_factors
  use rd_force_provider, only: force_provider_t, body_load_t
  use rd_force_element, only: force_element_t, element_result_t
  use rd_external_loads, only: override_loads_t
  implicit none
  private
  public :: multibody_t, multibody_output_t

  !> solutions of the quasi-static coordinates kept (multibody_t%qs_history): more than the
  !> distinct stage times of the attempts of one explicit step (Dormand-Prince: 5 new times
  !> an attempt, ARKODE's default limit of 7 error-test failures a step: 40), so that a
  !> restart from the last accepted step finds that step's solution
  integer, parameter :: qs_history_size = 48

  !> The outputs of one evaluation at (t, y) (calc_output). Wheelset pitch: the spin angle.
  type :: multibody_output_t
    type(body_kinematics_t), allocatable :: bodies(:)   !< kinematics and accelerations per body
    type(element_result_t), allocatable :: elements(:)  !< per force element
  end type multibody_output_t

  !> Per-call scratch of an evaluation (rhs fills it; never read as output: calc_output
  !> returns what the outputs need): the track frames, every body's kinematics and loads,
  !> every element's result.
  type :: multibody_scratch_t
    type(track_point_t), allocatable :: frames(:)
    type(body_kinematics_t), allocatable :: kin(:)
    type(body_load_t), allocatable :: loads(:)
    type(element_result_t), allocatable :: el_res(:)
  end type multibody_scratch_t

  type :: element_holder_t
    class(force_element_t), allocatable :: e
  end type element_holder_t

  type :: provider_ptr_t
    class(force_provider_t), pointer :: p => null()
  end type provider_ptr_t

  type, extends(ode_system_t) :: multibody_t
    type(body_spec_t), allocatable :: bodies(:)
    real(wp), allocatable :: frame_offset(:)   !< sigma_k = sigma0 + offset_k + s(t) [m]
    real(wp) :: sigma0 = 0                      !< vehicle's reference arc length at t = 0 [m]
    class(track_geometry_t), pointer :: track => null()
    type(speed_law_t) :: speed
    real(wp) :: gravity = standard_gravity      !< along -Z of the fixed frame [m/s^2]
    type(element_holder_t), allocatable :: elements(:)
    type(provider_ptr_t), allocatable :: providers(:)
    type(override_loads_t) :: override          !< loads set at run time (C API)
    integer :: nfree = 0
    integer :: nel_states = 0
    integer, allocatable :: free_index(:, :)    !< (6, nbodies): slot in q_f, 0 if frozen
    integer, allocatable :: el_state_start(:)   !< first slot of each element's states in x_el
    type(multibody_scratch_t) :: scratch
    !> Quasi-static coordinates: per body the chord Jacobian d(z'', roll'')/d(z, roll) of
    !> the Newton solve, kept between evaluations (the state moves little between calls)
    real(wp), allocatable :: qs_jacobian(:, :, :)
    logical, allocatable :: qs_jacobian_valid(:)
    !> the last qs_history_size solutions of the quasi-static coordinates at distinct
    !> times ((z, roll), body, slot), their times and a digest of the state they solved: a
    !> solve at a new time starts from the extrapolation of the newest two, a solve of the
    !> state of an older entry (same time, same digest) from that entry (solve_quasi_static).
    !> A ring: the newest entry is in slot qs_history_newest, the e-th newest in
    !> history_slot(e) (a new time overwrites the oldest slot instead of shifting them all)
    real(wp), allocatable :: qs_history(:, :, :)
    real(wp) :: qs_history_t(qs_history_size) = 0
    integer(int64) :: qs_history_state(qs_history_size) = 0
    integer :: qs_history_count = 0
    integer :: qs_history_newest = 1
    logical :: has_quasi_static = .false.
    !> Inside one quasi-static solve, after its first load evaluation: the force elements
    !> that touch no quasi-static body (element_moves false, set by add_element) keep their
    !> result (el_res) and their states' rates instead of being evaluated again. Exact:
    !> within a solve the time, the state and every other body stay as they are, and only
    !> the quasi-static bodies' z and roll move (solve_quasi_static).
    logical :: reuse_fixed_elements = .false.
    logical :: in_quasi_static_solve = .false.
    logical, allocatable :: element_moves(:)
    !> hold the quasi-static coordinates where they are instead of solving them (the static
    !> preload balance: the vehicle's preloads at its initial configuration, wheelsets held)
    logical :: hold_quasi_static = .false.
  contains
    procedure :: build
    procedure :: add_element
    procedure :: add_provider
    procedure :: state_size
    procedure :: body_count
    procedure :: element_count
    procedure :: initial_state
    procedure :: rhs
    procedure :: evaluate_kinematics
    procedure :: element_loads
    procedure :: free_slot
    procedure :: absolute_tolerances
    procedure :: state_layout
    procedure :: calc_output
    procedure :: set_override_load
    procedure :: quasi_static_balance
  end type multibody_t

contains

  !> Build the system from body specs, the track frames' offsets, a track and a speed law.
  subroutine build(self, bodies, frame_offsets, track, speed, error, sigma0, gravity)
    class(multibody_t), intent(inout) :: self
    type(body_spec_t), intent(in) :: bodies(:)
    real(wp), intent(in) :: frame_offsets(:)
    class(track_geometry_t), pointer, intent(in) :: track
    type(speed_law_t), intent(in) :: speed
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: sigma0, gravity
    integer :: i, j, n
    call clear(self)
    if (size(bodies) < 1) then
      call make_error(error, RD_ERR_INPUT, 'multibody: at least one body is needed'); return
    end if
    if (size(frame_offsets) < 1) then
      call make_error(error, RD_ERR_INPUT, 'multibody: at least one track frame is needed'); return
    end if
    if (.not. associated(track)) then
      call make_error(error, RD_ERR_INPUT, 'multibody: no track'); return
    end if
    if (.not. allocated(speed%t)) then
      call make_error(error, RD_ERR_INPUT, 'multibody: speed law not defined'); return
    end if
    do i = 1, size(bodies)
      call validate_body_spec(bodies(i), size(frame_offsets), error)
      if (allocated(error)) then
        call error_context(error, 'multibody'); return
      end if
    end do
    self%bodies = bodies
    self%frame_offset = frame_offsets
    self%track => track
    self%speed = speed
    if (present(sigma0)) self%sigma0 = sigma0
    if (present(gravity)) then
      if (.not. (gravity >= 0)) then
        call make_error(error, RD_ERR_INPUT, 'multibody: gravity must be >= 0 m/s^2'); return
      end if
      self%gravity = gravity
    end if
    allocate (self%free_index(6, size(bodies)))
    n = 0
    do i = 1, size(bodies)
      do j = 1, 6
        if (bodies(i)%frozen(j) .or. bodies(i)%quasi_static(j)) then
          self%free_index(j, i) = 0
        else
          n = n + 1
          self%free_index(j, i) = n
        end if
      end do
    end do
    self%nfree = n
    self%nel_states = 0
    self%has_quasi_static = any([(any(bodies(i)%quasi_static), i = 1, size(bodies))])
    allocate (self%qs_jacobian(2, 2, size(bodies)), self%qs_jacobian_valid(size(bodies)))
    self%qs_jacobian = 0
    self%qs_jacobian_valid = .false.
    allocate (self%qs_history(2, size(bodies), qs_history_size))
    self%qs_history = 0
    self%qs_history_count = 0
    self%qs_history_newest = 1
    allocate (self%elements(0), self%providers(0), self%el_state_start(0), self%scratch%el_res(0), &
              self%element_moves(0))
    allocate (self%scratch%frames(size(frame_offsets)), self%scratch%kin(size(bodies)), self%scratch%loads(size(bodies)))
    call self%override%build(size(bodies))
  end subroutine build

  !> Forget a previous model (build may be called again on the same object).
  subroutine clear(self)
    class(multibody_t), intent(inout) :: self
    if (allocated(self%bodies)) deallocate (self%bodies)
    if (allocated(self%frame_offset)) deallocate (self%frame_offset)
    if (allocated(self%elements)) deallocate (self%elements)
    if (allocated(self%providers)) deallocate (self%providers)
    if (allocated(self%free_index)) deallocate (self%free_index)
    if (allocated(self%el_state_start)) deallocate (self%el_state_start)
    if (allocated(self%element_moves)) deallocate (self%element_moves)
    self%scratch = multibody_scratch_t()
    if (allocated(self%qs_jacobian)) deallocate (self%qs_jacobian)
    if (allocated(self%qs_jacobian_valid)) deallocate (self%qs_jacobian_valid)
    if (allocated(self%qs_history)) deallocate (self%qs_history)
    self%qs_history_count = 0
    self%has_quasi_static = .false.
    self%track => null()
    self%sigma0 = 0
    self%gravity = standard_gravity
    self%nfree = 0
    self%nel_states = 0
  end subroutine clear

  !> Add a force element (copied). Its internal states are appended to the state vector.
  subroutine add_element(self, element, error)
    class(multibody_t), intent(inout) :: self
    class(force_element_t), intent(in) :: element
    type(error_t), allocatable, intent(out) :: error
    type(element_holder_t), allocatable :: tmp(:)
    type(element_result_t), allocatable :: res(:)
    integer :: n
    logical :: moves
    if (.not. allocated(self%bodies)) then
      call make_error(error, RD_ERR_INPUT, 'multibody: add_element before build'); return
    end if
    call element%check_bodies(size(self%bodies), error)
    if (allocated(error)) return
    n = size(self%elements)
    allocate (tmp(n + 1))
    tmp(1:n) = self%elements
    allocate (tmp(n + 1)%e, source=element)
    call move_alloc(tmp, self%elements)
    self%el_state_start = [self%el_state_start, self%nel_states + 1]
    ! whether the element moves with a quasi-static body's z and roll (element_loads)
    moves = any(self%bodies(element%body2)%quasi_static)
    if (element%body1 > 0) moves = moves .or. any(self%bodies(element%body1)%quasi_static)
    self%element_moves = [self%element_moves, moves]
    self%nel_states = self%nel_states + element%state_count()
    allocate (res(n + 1))
    call move_alloc(res, self%scratch%el_res)
  end subroutine add_element

  !> Register a force provider. The caller owns it; it must outlive the system.
  subroutine add_provider(self, provider)
    class(multibody_t), intent(inout) :: self
    class(force_provider_t), pointer, intent(in) :: provider
    type(provider_ptr_t), allocatable :: tmp(:)
    integer :: n
    n = size(self%providers)
    allocate (tmp(n + 1))
    tmp(1:n) = self%providers
    tmp(n + 1)%p => provider
    call move_alloc(tmp, self%providers)
  end subroutine add_provider

  pure function state_size(self) result(n)
    class(multibody_t), intent(in) :: self
    integer :: n
    n = 2 * self%nfree + self%nel_states
  end function state_size

  pure integer function body_count(self)
    class(multibody_t), intent(in) :: self
    body_count = 0
    if (allocated(self%bodies)) body_count = size(self%bodies)
  end function body_count

  pure integer function element_count(self)
    class(multibody_t), intent(in) :: self
    element_count = 0
    if (allocated(self%elements)) element_count = size(self%elements)
  end function element_count

  !> Slot of coordinate `dof` of body `ib` in q_f (0 if frozen); its rate is at nfree + slot.
  pure integer function free_slot(self, ib, dof)
    class(multibody_t), intent(in) :: self
    integer, intent(in) :: ib, dof
    free_slot = self%free_index(dof, ib)
  end function free_slot

  !> Per-component absolute tolerances of the state [q_f, nu_f, element states]: atol for the
  !> coordinates (m, rad) and the element states (m), atol_velocity for their rates (m/s,
  !> rad/s). One atol for both weighs a rate error of 1e-8 m/s like a displacement of 1e-8 m:
  !> in a motion of amplitude A at angular frequency w the rate's amplitude is w A, so
  !> atol_velocity = w_c atol asks for the same amplitude accuracy atol in both for motions at
  !> w_c, and lets the displacements' test govern every slower motion
  !> (docs/theory_solver.md "Tolerances").
  pure function absolute_tolerances(self, atol, atol_velocity) result(tol)
    class(multibody_t), intent(in) :: self
    real(wp), intent(in) :: atol, atol_velocity
    real(wp), allocatable :: tol(:)
    allocate (tol(self%state_size()), source=atol)
    tol(self%nfree + 1:2 * self%nfree) = atol_velocity
  end function absolute_tolerances

  !> Column names and SI unit tokens of the state vector, in the layout above:
  !> '<body>.<coordinate>' for q_f (a wheelset's pitch slot is its spin deviation beta),
  !> '<body>.nu_<coordinate>' for nu_f, '<element>.x<k>' for the elements' internal states.
  subroutine state_layout(self, components, units)
    class(multibody_t), intent(in) :: self
    character(len=:), allocatable, intent(out) :: components, units
    character(len=5), parameter :: dof_names(6) = ['x    ', 'y    ', 'z    ', 'yaw  ', 'roll ', 'pitch']
    character(len=5), parameter :: dof_units(6) = ['m    ', 'm    ', 'm    ', 'rad  ', 'rad  ', 'rad  ']
    character(len=5), parameter :: rate_units(6) = ['m/s  ', 'm/s  ', 'm/s  ', 'rad/s', 'rad/s', 'rad/s']
    character(len=:), allocatable :: q_names, q_units, nu_names, nu_units
    character(len=16), allocatable :: el_units(:)
    integer :: i, j, k
    q_names = ''; q_units = ''; nu_names = ''; nu_units = ''
    do i = 1, self%body_count()
      do j = 1, 6
        if (self%free_slot(i, j) == 0) cycle
        q_names = q_names // ' ' // self%bodies(i)%name // '.' // trim(dof_names(j))
        q_units = q_units // ' ' // trim(dof_units(j))
        nu_names = nu_names // ' ' // self%bodies(i)%name // '.nu_' // trim(dof_names(j))
        nu_units = nu_units // ' ' // trim(rate_units(j))
      end do
    end do
    components = q_names // nu_names
    units = q_units // nu_units
    do i = 1, self%element_count()
      if (allocated(el_units)) deallocate (el_units)
      allocate (el_units(self%elements(i)%e%state_count()))
      call self%elements(i)%e%state_units(el_units)
      do k = 1, size(el_units)
        components = components // ' ' // self%elements(i)%e%name // '.x' // trim(int_text(k))
        units = units // ' ' // trim(el_units(k))
      end do
    end do
    components = components(2:)
    units = units(2:)
  end subroutine state_layout

  !> The initial state from the bodies' q0/qdot0 and the elements' initial states.
  subroutine initial_state(self, y, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(out) :: y(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, j, k, e, n
    type(body_kinematics_t) :: kg
    real(wp) :: c(6)
    if (size(y) /= self%state_size()) then
      call make_error(error, RD_ERR_INPUT, 'multibody%initial_state: state vector has the wrong size'); return
    end if
    y = 0
    do i = 1, size(self%bodies)
      do j = 1, 6
        k = self%free_index(j, i)
        if (k > 0) y(k) = self%bodies(i)%q0(j)
      end do
    end do
    ! frames and angles at t = 0, then nu = qdot0 + c(q0, Omega(0))
    call self%evaluate_kinematics(0.0_wp, y)
    do i = 1, size(self%bodies)
      c = frame_rate_shift(self%scratch%kin(i)%q, self%scratch%kin(i)%omega_frame)
      do j = 1, 6
        k = self%free_index(j, i)
        if (k > 0) y(self%nfree + k) = self%bodies(i)%qdot0(j) + c(j)
      end do
    end do
    call self%evaluate_kinematics(0.0_wp, y)
    do e = 1, size(self%elements)
      associate (el => self%elements(e)%e)
        n = el%state_count()
        if (n == 0) cycle
        k = 2 * self%nfree + self%el_state_start(e)
        if (el%body1 == 0) then
          kg = ground_kinematics(self%scratch%kin(el%body2))
          call el%initial_states(kg, self%scratch%kin(el%body2), y(k:k + n - 1))
        else
          call el%initial_states(self%scratch%kin(el%body1), self%scratch%kin(el%body2), y(k:k + n - 1))
        end if
      end associate
    end do
  end subroutine initial_state

  !> Track frames and body kinematics at time t for state y (stored in self%scratch%kin).
  subroutine evaluate_kinematics(self, t, y)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp) :: v, vdot, s
    integer :: i, k
    v = self%speed%speed(t)
    vdot = self%speed%acceleration(t)
    s = self%speed%distance(t)
    do k = 1, size(self%scratch%frames)
      self%scratch%frames(k) = self%track%evaluate(self%sigma0 + self%frame_offset(k) + s)
    end do
    do i = 1, size(self%bodies)
      call body_kinematics(self, i, y, v, vdot, s)
    end do
  end subroutine evaluate_kinematics

  !> Kinematics of body i from the state (frames already evaluated at the time of v, s).
  subroutine body_kinematics(self, i, y, v, vdot, s)
    class(multibody_t), intent(inout) :: self
    integer, intent(in) :: i
    real(wp), intent(in) :: y(:), v, vdot, s
    real(wp) :: q(6), qdot(6), c(6), bzx(3, 3), rot(3, 3)
    integer :: j, k
      associate (b => self%bodies(i))
        q = b%q0
        do j = 1, 6
          k = self%free_index(j, i)
          if (k > 0) q(j) = y(k)
        end do
        ! theta = s/r0 + beta (docs/theory.md, spin deviation)
        if (b%is_wheelset) q(DOF_PITCH) = spin_from_deviation(q(DOF_PITCH), s, b%r0)
        ! relative rates from the generalized velocities nu = qdot + c(q, Omega)
        call rotation_factors(q(4:6), bzx, rot)
        c = frame_rate_shift(q, v * self%scratch%frames(b%frame)%omega, rot)
        qdot = 0
        do j = 1, 6
          k = self%free_index(j, i)
          if (k > 0) qdot(j) = y(self%nfree + k) - c(j)
        end do
        ! the spin slot holds nu_theta - V/r0; a frozen spin rolls (dbeta/dt = 0)
        if (b%is_wheelset) qdot(DOF_PITCH) = spin_from_deviation(qdot(DOF_PITCH), v, b%r0)
        call compute_body_kinematics(self%scratch%kin(i), self%scratch%frames(b%frame), v, vdot, q, qdot, b%is_wheelset, &
                                     bzx, rot)
      end associate
  end subroutine body_kinematics

  !> y' = f(t, y): kinematics, loads (gravity, elements, providers, override), then the
  !> equations of motion body by body (docs/theory.md eqs. T1-T3, R1-R4).
  subroutine rhs(self, t, y, ydot, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    logical :: loads_ready
    if (size(y) /= self%state_size() .or. size(ydot) /= size(y)) then
      call make_error(error, RD_ERR_INTERNAL, 'multibody%rhs: state vector has the wrong size'); return
    end if
    call self%evaluate_kinematics(t, y)
    ! Z-X-Y angles are singular at 90 deg roll (det H = cos(phi)): stop cleanly before
    do i = 1, size(self%bodies)
      if (abs(cos(self%scratch%kin(i)%q(5))) < 1.0e-3_wp) then
        call make_error(error, RD_ERR_RUNTIME, 'multibody%rhs: body "' // name_of(self, i) // &
                        '" reached 90 deg roll (singular Z-X-Y angles)')
        return
      end if
    end do
    loads_ready = .false.
    if (self%has_quasi_static .and. .not. self%hold_quasi_static) then
      self%reuse_fixed_elements = .false.
      self%in_quasi_static_solve = .true.
      call solve_quasi_static(self, t, y, ydot, loads_ready, error)
      self%in_quasi_static_solve = .false.
      self%reuse_fixed_elements = .false.
      if (allocated(error)) return
    end if
    if (.not. loads_ready) then
      call accumulate_loads(self, t, y, ydot, error)
      if (allocated(error)) return
    end if
    do i = 1, size(self%bodies)
      call body_equations(self, i, ydot)
    end do
    if (all(finite(ydot))) return
    ! name what is non-finite (rd_error's policy: recoverable, the integrator retries)
    do i = 1, size(self%elements)
      if (allocated(self%elements(i)%e%name)) call nonfinite_error(error, [self%scratch%el_res(i)%force, &
        self%scratch%el_res(i)%moment], 'force of element "' // self%elements(i)%e%name // '"')
      if (allocated(error)) return
    end do
    do i = 1, size(self%bodies)
      call nonfinite_error(error, [self%scratch%loads(i)%force, self%scratch%loads(i)%moment, self%scratch%loads(i)%moment_attach], &
                           'load on body "' // name_of(self, i) // '" (gravity, elements, contact, external loads)')
      if (allocated(error)) return
    end do
    call nonfinite_error(error, ydot, 'state derivative')
  end subroutine rhs

  !> Quasi-static coordinates (a wheelset's z and roll on quasi-static normal contact):
  !> solve them for zero relative acceleration, z'' = roll'' = 0 with the other
  !> coordinates, all rates and the time given, by a chord Newton iteration. The 2x2
  !> Jacobian per body comes from forward differences, all quasi-static bodies perturbed at
  !> once (they load each other only through bodies held fixed here, so each body's block
  !> is what a perturbation of that body alone gives); it is kept between evaluations,
  !> corrected after every step by Broyden's secant update (free), and refreshed only when
  !> the iteration stays slow (a residual that falls by less than a factor 4 twice in a
  !> row, or a damped step): the Jacobian costs two load evaluations, a chord step one. The
  !> solution stays in the body's q0, which is the next evaluation's starting point at the
  !> same time (the integrator's Newton iterations and difference quotients); at a new time
  !> the start is extrapolated linearly in time from the last two solutions at distinct
  !> times. Either way the iteration ends at the same root within its tolerance; the start
  !> only decides how many load evaluations it takes (measured on the Manchester acceptance
  !> scene: 3.1 -> 2.7 per right-hand side with the secant updates and the extrapolation,
  !> docs/performance.md "Smooth contact"). On
  !> return `loads_ready` says whether the loads held are those of the solution (the last
  !> residual was evaluated there), so that the caller need not evaluate them again. Why
  !> the coordinates are condensed at all: docs/theory_flange_chatter.md section 9 (elastic wheelset contact modes on rigid track
  !> couple into a friction flutter at a saturated flange contact).
  subroutine solve_quasi_static(self, t, y, ydot, loads_ready, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(inout) :: ydot(:)
    logical, intent(out) :: loads_ready
    type(error_t), allocatable, intent(out) :: error
    integer, parameter :: max_iterations = 200
    !> Converged when the update is below 1e-13 (m, rad): on a Hertz stiffness of ~1e9 N/m
    !> that is 1e-4 N, and ~5e-8 m/s^2 of noise between nearby evaluations, below 1e-3 of what
    !> the integrator's difference quotients see: their increments are floored at 1e-10 in
    !> scenes with quasi-static coordinates (rd_scene_jacobian; CVODE's rule alone goes down
    !> to 1e-15, where a solve at 1e-13 m made 170 Newton failures in 0.3 s of the Manchester
    !> scene).
    real(wp), parameter :: tolerance = 1.0e-13_wp, jump_scale = 1.0e-7_wp
    !> 0.01 m/s^2 (rad/s^2): ~20 N on a wheelset, 4e-4 of a Manchester wheel load
    real(wp), parameter :: stuck_residual = 1.0e-2_wp
    !> a chord step whose residual falls by less than this factor asks for a fresh Jacobian
    real(wp), parameter :: slow_contraction = 0.25_wp
    real(wp), parameter :: small_update = 1.0e-9_wp
    !> a secant update needs a step well above the forces' rounding: below ~1e-11 (m, rad) the
    !> residual's change, ~1e-5 m/s^2 on a Hertz stiffness, is not resolved to a few digits
    real(wp), parameter :: secant_floor = 1.0e-11_wp
    !> the chord Jacobian is refreshed after this many slow steps in a row (one slow step is
    !> left to the secant update to correct)
    integer, parameter :: slow_steps_for_refresh = 2
    !> the start is extrapolated at most this many of the history's time intervals ahead
    !> (further, the newest solution is the start)
    real(wp), parameter :: max_extrapolation = 5.0_wp
    !> a body not converged after this many iterations continues by pseudo-transient
    !> continuation (below)
    integer, parameter :: ptc_after = 12
    !> largest update per iteration (z [m], roll [rad]): keeps a bad start on the rail
    real(wp), parameter :: max_update(2) = [2.0e-4_wp, 2.0e-3_wp]
    real(wp) :: r(2, size(self%bodies)), dp(2, size(self%bodies)), &
                merit(size(self%bodies)), merit_new(size(self%bodies)), lambda(size(self%bodies)), &
                start(2, size(self%bodies)), kappa(size(self%bodies))
    integer :: iteration, i, halvings
    logical :: converged(size(self%bodies)), fresh, qs(size(self%bodies)), accepted(size(self%bodies)), &
               ptc(size(self%bodies)), lifting(size(self%bodies))
    !> (z, roll) and residual before a step, for the secant update
    real(wp) :: before(2, size(self%bodies)), r_before(2, size(self%bodies))
    !> consecutive slow chord steps per body
    integer :: slow_steps(size(self%bodies))
    loads_ready = .false.
    qs = [(any(self%bodies(i)%quasi_static), i = 1, size(self%bodies))]
    call extrapolate_start()
    start = quasi_static_coordinates()
    fresh = any(qs .and. .not. self%qs_jacobian_valid)
    dp = 0
    ptc = .false.
    kappa = 0
    slow_steps = 0
    call quasi_static_residual(self, t, y, ydot, r, error)
    if (allocated(error)) return
    merit = hypot(r(1, :), r(2, :))
    do iteration = 1, max_iterations
      loads_ready = .true.            ! the loads held are the residual's, at q0
      if (fresh) then
        call quasi_static_jacobian(self, t, y, ydot, r, error)
        if (allocated(error)) return
        loads_ready = .false.         ! now they are those of the last perturbed point
      end if
      converged = .not. qs
      do i = 1, size(self%bodies)
        if (.not. qs(i)) cycle
        if (.not. ptc(i) .and. iteration > ptc_after) then
          ! Pseudo-transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 35, 1998):
          ! at a fold of the balance (the tread / flange-root transition, det J ~ 0) the
          ! residual has a local minimum above zero and the root is on the other branch; a
          ! line search on |r| cannot cross, the fictitious flow z' = r(z) can. Start with a
          ! pseudo time step of a tenth of the stiffest rate.
          ptc(i) = .true.
          kappa(i) = 0.1_wp / max(maxval(abs(self%qs_jacobian(:, :, i))), 1.0_wp)
        end if
        if (ptc(i)) then
          dp(:, i) = pseudo_transient_update(self%qs_jacobian(:, :, i), r(:, i), kappa(i))
        else
          dp(:, i) = newton_update(self%qs_jacobian(:, :, i), r(:, i))
        end if
        dp(:, i) = max(-max_update, min(max_update, dp(:, i)))
        ! below the tolerance, or cycling below jump_scale after several iterations: the
        ! forces jump there by less than |J| jump_scale (the strip geometry's patch switches,
        ! ~10-100 N on a wheelset), so no exact root exists and the point reached is kept;
        ! likewise a residual below stuck_residual that the damped steps cannot reduce (a fold
        ! of the balance, det J ~ 0, met at the tread / flange-root transition). Both only
        ! where the last step did not contract the residual (slow_steps): a Newton iteration
        ! still converging is not cut short (it was, after a cold start reaching the root
        ! late, and the balance then depended on the start by 1e-8 m;
        ! test_quasi_static_history)
        converged(i) = all(abs(dp(:, i)) <= tolerance) .or. (iteration > 8 .and. slow_steps(i) > 0 .and. &
                       (all(abs(dp(:, i)) < jump_scale) .or. merit(i) < stuck_residual))
        ! a converged body stays where its residual was evaluated while the others iterate:
        ! its loads are then those of the point kept (the wheelset contact's result cache
        ! returns them without evaluating the pipeline again), and it is not counted slow
        if (converged(i)) then
          dp(:, i) = 0
          slow_steps(i) = 0
        end if
      end do
      ! converged: q0 stays where the residual was evaluated (the update left, at most the
      ! tolerance, is below what the forces resolve), so its loads can be used as they are
      if (all(converged)) then
        call remember_solution()
        return
      end if
      ! damped Newton: halve a body's update while its residual does not fall (the residual
      ! is only piecewise smooth: contact onset, patch splits, the creep law's saturation)
      lambda = 1
      ! a small update is taken as it is: at 1e-9 (m, rad), 1e-5 of a Hertz approach, the
      ! linearisation is exact to rounding and a residual that does not fall there is the
      ! forces' noise, which halvings cannot reduce (each costs a load evaluation)
      accepted = .not. qs .or. ptc .or. [(all(abs(dp(:, i)) <= small_update), i = 1, size(self%bodies))]
      before = quasi_static_coordinates()
      r_before = r
      call shift_quasi_static(dp)
      do halvings = 0, 10
        call quasi_static_residual(self, t, y, ydot, r, error)
        if (allocated(error)) return
        merit_new = hypot(r(1, :), r(2, :))
        do i = 1, size(self%bodies)
          if (accepted(i)) cycle
          if (merit_new(i) <= (1 - 1.0e-4_wp * lambda(i)) * merit(i) .or. halvings == 10) then
            accepted(i) = .true.
          end if
        end do
        if (all(accepted)) exit
        do i = 1, size(self%bodies)
          if (accepted(i)) then
            dp(:, i) = 0
          else
            lambda(i) = 0.5_wp * lambda(i)
            dp(:, i) = -0.5_wp * dp(:, i)     ! back by half of what was applied
          end if
        end do
        call shift_quasi_static(dp)
        do i = 1, size(self%bodies)
          if (.not. accepted(i)) dp(:, i) = -dp(:, i)
        end do
      end do
      call secant_update()
      where (merit_new > slow_contraction * merit .and. .not. converged)
        slow_steps = slow_steps + 1
      elsewhere
        slow_steps = 0
      end where
      fresh = any(lambda < 1) .or. any(qs .and. slow_steps >= slow_steps_for_refresh) .or. any(ptc)
      ! pseudo time step by switched evolution relaxation: it grows as the residual falls
      ! (towards Newton's step at the root) and shrinks where the flow climbs over the fold
      where (ptc) kappa = kappa * min(10.0_wp, merit / max(merit_new, tiny(1.0_wp)))
      merit = merit_new
    end do
    ! not converged. Where a wheel of a wheelset left unbalanced carries no load at the point
    ! reached, the contact holds that wheelset on one wheel only and its balance, if any, lies
    ! with that wheel lifted further (a roll moment beyond 2 b Q; flange climb): follow it.
    lifting = qs .and. .not. converged
    do i = 1, size(self%bodies)
      if (lifting(i)) lifting(i) = wheel_unloaded(i)
    end do
    ! Where none is unloaded, the same step-limited Newton iteration (fresh Jacobian every
    ! step) is the last resort for every body left unbalanced: a wheelset about to tip over
    ! its flange contact (Y/Q near y_c / r_c, the other wheel still lightly loaded) has a
    ! nearly singular balance whose root lies with that wheel lifted, and the damped
    ! iteration and the pseudo-transient continuation can stall short of it on a kink of
    ! the classic strip forces (bench/extremes, Manchester at 100 m/s on rigid track, strips
    ! with strip_normal_force = 'potential': a residual of 0.5 m/s^2 left with the other
    ! wheel at 9 um of approach, Newton's step 37 um and -48 urad towards its lift; before,
    ! a solver failure at 0.456 s). Reached only where the iteration above failed, so no
    ! balance it finds changes.
    if (.not. any(lifting)) lifting = qs .and. .not. converged
    if (any(lifting)) then
      call follow_lift(error)
      if (allocated(error)) then
        if (error%code == RD_ERR_PHYSICS) then
          ! the documented physics stop (exit 3), final: no smaller step removes a balance
          ! that does not exist short of the lift-off limit
          call error_context(error, 'quasi-static normal contact: no balance short of the limit')
          return
        end if
        deallocate (error)
      else if (all(converged .or. lifting)) then
        call remember_solution()
        return
      end if
    end if
    ! not converged: back to where this evaluation started (a retry starts from there too)
    loads_ready = .false.
    call shift_quasi_static(start - quasi_static_coordinates())
    call retry_error(error, 'quasi-static normal contact did not converge at t = ' // trim(sci_text(t, 5)) // &
                    ' s (a wheelset near lift-off or derailment)')

  contains

    logical function wheel_unloaded(ib)
      integer, intent(in) :: ib
      integer :: k
      wheel_unloaded = .false.
      do k = 1, size(self%providers)
        if (self%providers(k)%p%wheel_unloaded(ib)) wheel_unloaded = .true.
      end do
    end function wheel_unloaded

    !> The balance of the `lifting` bodies (one wheel unloaded, or about to tip over a flange
    !> contact: the caller), by Newton's method with
    !> a fresh Jacobian every step (one wheel's contact and the suspension: nearly linear,
    !> but J is close to singular, det J / (|J11 J22| + |J12 J21|) ~ the suspension's share
    !> ~1e-3, so a step may be long): each step scaled as a whole to at most follow_step, so
    !> that it keeps its direction (the roll about the loaded wheel's contact) and the gap
    !> opens by less than a millimetre a step. On return without error: every lifting body
    !> is balanced (update below jump_scale), q0 holds that balance and loads_ready is false.
    !> A physics error of the loads (rd_wheelset_contact: a gap beyond max_wheel_lift, a
    !> derailment) says the balance lies beyond the limit; any other error or no balance
    !> within follow_iterations: `error` set, q0 where it stopped (the caller restores it).
    subroutine follow_lift(error)
      type(error_t), allocatable, intent(out) :: error
      integer, parameter :: follow_iterations = 60
      !> (z [m], roll [rad]): 0.4 mm of a Manchester wheel's gap per step at b = 0.75 m
      real(wp), parameter :: follow_step(2) = [5.0e-4_wp, 5.0e-4_wp]
      integer :: k, it
      real(wp) :: d(2)
      loads_ready = .false.
      do it = 1, follow_iterations
        call quasi_static_jacobian(self, t, y, ydot, r, error)
        if (allocated(error)) return
        dp = 0
        do k = 1, size(self%bodies)
          if (.not. lifting(k)) cycle
          d = newton_update(self%qs_jacobian(:, :, k), r(:, k))
          dp(:, k) = d * minval([1.0_wp, follow_step / max(abs(d), tiny(1.0_wp))])
        end do
        if (all(abs(dp) < jump_scale)) return
        call shift_quasi_static(dp)
        call quasi_static_residual(self, t, y, ydot, r, error)
        if (allocated(error)) return
      end do
      call make_error(error, RD_ERR_RUNTIME, 'no balance with a wheel unloaded')
    end subroutine follow_lift

    !> (z, roll) of every body, (2, body)
    function quasi_static_coordinates() result(p)
      real(wp) :: p(2, size(self%bodies))
      integer :: k
      do k = 1, size(self%bodies)
        p(:, k) = self%bodies(k)%q0([DOF_Z, DOF_ROLL])
      end do
    end function quasi_static_coordinates

    !> At a new time, start from the linear extrapolation in time of the last two solutions
    !> at distinct times (within max_extrapolation of their interval), else from the newest
    !> solution; at the time of the newest solution, from where the last evaluation left q0;
    !> for the very state (t, y) an older entry solved, from that entry's solution. The last
    !> case is an explicit integrator's restart from its last accepted step after a failed
    !> stage (sundials_glue.c, erk_evolve): the accepted step's last stage solved this very
    !> state, while the newest solutions belong to the failed step's stages, ahead in time and
    !> off the solution; near a wheel's lift-off their extrapolation can start the iteration
    !> where it does not converge (bench/extremes, Manchester flange climb with erk). Only the
    !> same state: CVODE comes back to an earlier time with another state (a step retried
    !> after a failure, then two shorter ones), and the solution of the failed attempt's
    !> state is no better a start than the extrapolation.
    subroutine extrapolate_start()
      real(wp) :: f
      integer(int64) :: digest
      integer :: k, e
      integer :: newest, second, slot
      if (self%qs_history_count < 1) return
      newest = history_slot(1)
      if (t == self%qs_history_t(newest)) return
      ! the state's digest only where an older entry has this time (Fortran's .or. need not
      ! short-circuit: a digest per entry and call was hashing y up to 47 times); the slots
      ! of the entries 2 .. count are all but the newest one's
      if (count(self%qs_history_t(:self%qs_history_count) == t) > 0) then
        digest = state_digest(y)
        do e = 2, self%qs_history_count
          slot = history_slot(e)
          if (self%qs_history_t(slot) /= t) cycle
          if (self%qs_history_state(slot) /= digest) cycle
          do k = 1, size(self%bodies)
            if (qs(k)) self%bodies(k)%q0([DOF_Z, DOF_ROLL]) = self%qs_history(:, k, slot)
          end do
          call update_quasi_static_kinematics(self, t, y)
          return
        end do
      end if
      f = 0
      second = newest
      if (self%qs_history_count >= 2) then
        second = history_slot(2)
        f = (t - self%qs_history_t(newest)) / (self%qs_history_t(newest) - self%qs_history_t(second))
        if (abs(f) > max_extrapolation) f = 0
      end if
      do k = 1, size(self%bodies)
        if (.not. qs(k)) cycle
        self%bodies(k)%q0([DOF_Z, DOF_ROLL]) = self%qs_history(:, k, newest) &
                                               + f * (self%qs_history(:, k, newest) - self%qs_history(:, k, second))
      end do
      call update_quasi_static_kinematics(self, t, y)
    end subroutine extrapolate_start

    !> Keep the solution at t as the newest of the history (replacing one at the same t,
    !> the oldest dropped).
    subroutine remember_solution()
      integer :: newest
      newest = self%qs_history_newest
      if (self%qs_history_count == 0) then
        self%qs_history_count = 1
      else if (t /= self%qs_history_t(newest)) then
        newest = mod(newest, qs_history_size) + 1     ! the oldest slot once the ring is full
        self%qs_history_newest = newest
        self%qs_history_count = min(qs_history_size, self%qs_history_count + 1)
      end if
      self%qs_history_t(newest) = t
      self%qs_history_state(newest) = state_digest(y)
      self%qs_history(:, :, newest) = quasi_static_coordinates()
    end subroutine remember_solution

    !> The ring slot of the e-th newest entry of the history (e = 1: the newest).
    pure integer function history_slot(e)
      integer, intent(in) :: e
      history_slot = modulo(self%qs_history_newest - e, qs_history_size) + 1
    end function history_slot

    !> Broyden's update of each body's chord Jacobian with the step s just taken and the
    !> change y of its residual (Broyden's "good" update: C. G. Broyden, A class of methods
    !> for solving nonlinear simultaneous equations, Math. Comp. 19, 577-593, 1965):
    !> J <- J + (y - J s) s^T / (s^T s), so that J s = y; it costs no load evaluation.
    subroutine secant_update()
      real(wp) :: s(2), dr(2)
      integer :: k
      do k = 1, size(self%bodies)
        if (.not. qs(k) .or. ptc(k)) cycle
        s = self%bodies(k)%q0([DOF_Z, DOF_ROLL]) - before(:, k)
        if (maxval(abs(s)) <= secant_floor) cycle
        dr = r(:, k) - r_before(:, k) - matmul(self%qs_jacobian(:, :, k), s)
        self%qs_jacobian(:, :, k) = self%qs_jacobian(:, :, k) &
                                    + spread(dr, 2, 2) * spread(s, 1, 2) / dot_product(s, s)
      end do
    end subroutine secant_update

    !> Move every quasi-static body's (z, roll) by d and update their kinematics.
    subroutine shift_quasi_static(d)
      real(wp), intent(in) :: d(:, :)
      integer :: k
      do k = 1, size(self%bodies)
        if (.not. qs(k)) cycle
        self%bodies(k)%q0(DOF_Z) = self%bodies(k)%q0(DOF_Z) + d(1, k)
        self%bodies(k)%q0(DOF_ROLL) = self%bodies(k)%q0(DOF_ROLL) + d(2, k)
      end do
      call update_quasi_static_kinematics(self, t, y)
    end subroutine shift_quasi_static

    !> Newton update -J^-1 r where the contact holds the wheelset (a lower wheelset is pushed
    !> up harder: dz''/dz below -1e4 1/s^2, far above what the suspension alone gives, ~-1e3;
    !> J need not be definite: at the tread / flange-root transition of S1002 on 60E1 the
    !> contact's z-roll stiffness is indefinite); elsewhere (off the rail) a full step of the
    !> height along its acceleration, i.e. towards the rail, roll kept.
    pure function newton_update(jq, res) result(d)
      real(wp), intent(in) :: jq(2, 2), res(2)
      real(wp) :: d(2), det
      det = jq(1, 1) * jq(2, 2) - jq(1, 2) * jq(2, 1)
      if (jq(1, 1) < -1.0e4_wp .and. abs(det) > 1.0e-8_wp * (abs(jq(1, 1) * jq(2, 2)) + abs(jq(1, 2) * jq(2, 1)))) then
        d = -[jq(2, 2) * res(1) - jq(1, 2) * res(2), jq(1, 1) * res(2) - jq(2, 1) * res(1)] / det
      else
        d = 0
        if (res(1) /= 0) d(1) = sign(max_update(1), res(1))
      end if
    end function newton_update

    !> Backward-Euler step of the fictitious flow z' = r(z) with pseudo time step kappa,
    !> (I / kappa - J) d = r: a step along the accelerations for a small kappa, Newton's
    !> step -J^-1 r for a large one. Where I / kappa - J is not positive (kappa beyond an
    !> unstable direction of J), the explicit step kappa r.
    pure function pseudo_transient_update(jq, res, kap) result(d)
      real(wp), intent(in) :: jq(2, 2), res(2), kap
      real(wp) :: d(2), a(2, 2), det
      a = -jq
      a(1, 1) = a(1, 1) + 1 / kap
      a(2, 2) = a(2, 2) + 1 / kap
      det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
      if (a(1, 1) > 0 .and. a(2, 2) > 0 .and. det > 1.0e-8_wp * abs(a(1, 1) * a(2, 2))) then
        d = [a(2, 2) * res(1) - a(1, 2) * res(2), a(1, 1) * res(2) - a(2, 1) * res(1)] / det
      else
        d = kap * res
      end if
    end function pseudo_transient_update
  end subroutine solve_quasi_static

  !> A digest of a state vector's bits (rotate and exclusive-or of its 64-bit words): equal
  !> states give equal digests; two different states of one run giving the same one is
  !> as good as impossible, and would only choose the quasi-static solve's start
  !> (solve_quasi_static, extrapolate_start).
  pure function state_digest(y) result(h)
    real(wp), intent(in) :: y(:)
    integer(int64) :: h
    integer(int64) :: words(size(y))
    integer :: i
    words = transfer(y, words)
    h = int(size(y), int64)
    do i = 1, size(y)
      h = ieor(ishftc(h, 23), words(i))
    end do
  end function state_digest

  !> z'' and roll'' (relative) of every quasi-static body at the current kinematics.
  subroutine quasi_static_residual(self, t, y, ydot, r, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(inout) :: ydot(:)
    real(wp), intent(out) :: r(:, :)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    r = 0
    call accumulate_loads(self, t, y, ydot, error)
    if (allocated(error)) return
    ! inside a solve (not a static balance, whose state changes between calls): the fixed
    ! elements have now been evaluated at this solve's time and state
    if (self%in_quasi_static_solve) self%reuse_fixed_elements = .true.
    do i = 1, size(self%bodies)
      if (.not. any(self%bodies(i)%quasi_static)) cycle
      call body_equations(self, i, ydot, quasi_static_free=.true.)
      r(:, i) = [self%scratch%kin(i)%qddot(DOF_Z), self%scratch%kin(i)%qddot(DOF_ROLL)]
    end do
  end subroutine quasi_static_residual

  !> Forward-difference chord Jacobian of the residual, one column (z, then roll) for all
  !> quasi-static bodies at once.
  subroutine quasi_static_jacobian(self, t, y, ydot, r, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:), r(:, :)
    real(wp), intent(inout) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    !> steps: 1e-8 m and 1e-8 rad, ~1e-4 of a Hertz approach, far above the geometry's noise
    real(wp), parameter :: step = 1.0e-8_wp
    integer, parameter :: dofs(2) = [DOF_Z, DOF_ROLL]
    real(wp) :: rp(2, size(self%bodies))
    integer :: c, i
    do c = 1, 2
      do i = 1, size(self%bodies)
        if (any(self%bodies(i)%quasi_static)) self%bodies(i)%q0(dofs(c)) = self%bodies(i)%q0(dofs(c)) + step
      end do
      call update_quasi_static_kinematics(self, t, y)
      call quasi_static_residual(self, t, y, ydot, rp, error)
      do i = 1, size(self%bodies)
        if (.not. any(self%bodies(i)%quasi_static)) cycle
        self%bodies(i)%q0(dofs(c)) = self%bodies(i)%q0(dofs(c)) - step
        self%qs_jacobian(:, c, i) = (rp(:, i) - r(:, i)) / step
        self%qs_jacobian_valid(i) = .true.
      end do
      call update_quasi_static_kinematics(self, t, y)
      if (allocated(error)) return
    end do
  end subroutine quasi_static_jacobian

  !> Kinematics of the quasi-static bodies after their q0 changed.
  subroutine update_quasi_static_kinematics(self, t, y)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    integer :: i
    do i = 1, size(self%bodies)
      if (any(self%bodies(i)%quasi_static)) &
        call body_kinematics(self, i, y, self%speed%speed(t), self%speed%acceleration(t), self%speed%distance(t))
    end do
  end subroutine update_quasi_static_kinematics

  !> Loads on every body at the current kinematics: gravity and force elements
  !> (element_loads), providers and the run-time override.
  subroutine accumulate_loads(self, t, y, ydot, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(inout) :: ydot(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    call self%element_loads(t, y, ydot)
    do i = 1, size(self%providers)
      call self%providers(i)%p%add_forces(t, self%scratch%kin, self%scratch%loads, error)
      if (allocated(error)) then
        call error_context(error, 'multibody%rhs')
        return
      end if
    end do
    call self%override%add_forces(t, self%scratch%kin, self%scratch%loads, error)
    if (allocated(error)) return
  end subroutine accumulate_loads

  !> Gravity and the force elements at the current kinematics (evaluate_kinematics): the
  !> bodies' loads so far, the element results el_res and the elements' internal states'
  !> rates in ydot. Cannot fail; also what the free lengths are taken from (rd_scene_startup).
  subroutine element_loads(self, t, y, ydot)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(inout) :: ydot(:)
    integer :: i, e, k, n, b1, b2
    logical :: reuse
    type(body_kinematics_t) :: kg
    ! gravity (fixed frame, -Z)
    do i = 1, size(self%bodies)
      self%scratch%loads(i)%force = [0.0_wp, 0.0_wp, -self%bodies(i)%mass * self%gravity]
      self%scratch%loads(i)%moment = 0
      self%scratch%loads(i)%moment_attach = 0
    end do
    ! force elements: force on body 2 at point2, reaction on body 1 at reaction_point
    do e = 1, size(self%elements)
      associate (el => self%elements(e)%e, res => self%scratch%el_res(e))
        b1 = el%body1; b2 = el%body2
        n = el%state_count()
        k = 2 * self%nfree + self%el_state_start(e)
        ! (a fixed element inside a quasi-static solve: res and ydot(k:k + n - 1) hold its
        ! evaluation at this solve's state)
        reuse = self%reuse_fixed_elements
        if (reuse) reuse = .not. self%element_moves(e)
        if (reuse) then
          continue
        else if (b1 == 0) then
          kg = ground_kinematics(self%scratch%kin(b2))
          call el%evaluate(t, kg, self%scratch%kin(b2), y(k:k + n - 1), res, ydot(k:k + n - 1))
        else
          call el%evaluate(t, self%scratch%kin(b1), self%scratch%kin(b2), y(k:k + n - 1), res, ydot(k:k + n - 1))
        end if
        self%scratch%loads(b2)%force = self%scratch%loads(b2)%force + res%force
        self%scratch%loads(b2)%moment_attach = self%scratch%loads(b2)%moment_attach &
                                       + cross(res%point2 - self%scratch%kin(b2)%r, res%force) + res%moment
        if (b1 > 0) then
          self%scratch%loads(b1)%force = self%scratch%loads(b1)%force - res%force
          self%scratch%loads(b1)%moment_attach = self%scratch%loads(b1)%moment_attach &
                                         - cross(res%reaction_point - self%scratch%kin(b1)%r, res%force) - res%moment
        end if
      end associate
    end do
  end subroutine element_loads

  function name_of(self, i) result(name)
    class(multibody_t), intent(in) :: self
    integer, intent(in) :: i
    character(len=:), allocatable :: name
    if (allocated(self%bodies(i)%name)) then
      name = self%bodies(i)%name
    else
      name = '?'
    end if
  end function name_of

  !> Equations of motion of body i (docs/theory.md):
  !>  T: m (w'' + A^T p'' + 2 Om x w' + Om' x w + Om x (Om x w)) = A^T F     (eq. 4.61)
  !>  R: (H^T J H) a'' = H^T [M_b - om x J om - J (B^T Om' - om_rel x B^T Om + H' a')]
  !>                     + H_att^T M_att,b                                   (eq. 4.62 corrected)
  !> solved for the free coordinates with the frozen ones' accelerations prescribed (zero
  !> relative acceleration); quasi-static ones are prescribed too (their balance has been
  !> solved), unless `quasi_static_free`, which gives their acceleration: the residual of
  !> that balance.
  subroutine body_equations(self, i, ydot, quasi_static_free)
    class(multibody_t), intent(inout) :: self
    integer, intent(in) :: i
    real(wp), intent(inout) :: ydot(:)
    logical, intent(in), optional :: quasi_static_free
    real(wp) :: a(3, 3), om(3), al(3), a0(3), w(3), wd(3), wdd(3), f(3)
    real(wp) :: h(3, 3), hd(3, 3), hatt(3, 3), jm(3, 3), mgen(3, 3), g(3), mb(3), mab(3)
    real(wp) :: omb(3), omrel(3), btom(3), angd(3), angdd(3), acc_pres(3), cdot(6), ca(3)
    logical :: free_ang(3), held(6)
    integer :: j, k
    held = self%bodies(i)%frozen .or. self%bodies(i)%quasi_static
    if (present(quasi_static_free)) then
      if (quasi_static_free) held = self%bodies(i)%frozen
    end if
    associate (b => self%bodies(i), kin => self%scratch%kin(i), ld => self%scratch%loads(i))
      a = kin%track%a
      om = kin%omega_frame
      al = kin%alpha_frame
      ! origin acceleration p'' = V^2 d2p/dsigma2 + dV/dt dp/dsigma, in track components
      a0 = matmul(kin%speed**2 * kin%track%d2r + kin%accel * kin%track%dr, a)
      w = kin%q(1:3)
      wd = kin%qdot(1:3)
      f = matmul(ld%force, a)
      ! eq. 4.61: relative acceleration in track components (frozen translations: 0)
      wdd = f / b%mass - a0 - 2 * cross(om, wd) - cross(al, w) - cross(om, cross(om, w))
      do j = 1, 3
        if (held(j)) wdd(j) = 0
      end do
      kin%acc = matmul(a, a0 + wdd + 2 * cross(om, wd) + cross(al, w) + cross(om, cross(om, w)))
      ! rotation: Euler's equation in body components projected on the angles with H^T
      angd = kin%qdot(4:6)
      h = angle_rate_matrix(kin%q(5), kin%q(6))
      hd = angle_rate_matrix_dot(kin%q(5), kin%q(6), angd(2), angd(3))
      jm = b%inertia
      omb = kin%omega_body
      omrel = matmul(h, angd)
      btom = matmul(om, kin%b)
      mb = matmul(ld%moment, kin%rot)
      mab = matmul(ld%moment_attach, kin%rot)
      g = mb - cross(omb, matmul(jm, omb)) &
          - matmul(jm, matmul(al, kin%b) - cross(omrel, btom) + matmul(hd, angd))
      g = matmul(g, h)
      hatt = h
      if (b%is_wheelset) hatt(:, 3) = 0   ! axle-box loads do no work on the spin
      g = g + matmul(mab, hatt)
      mgen = matmul(transpose(h), matmul(jm, h))
      free_ang = .not. held(4:6)
      ! prescribed accelerations of frozen angles: 0; a wheelset's frozen spin rolls: dV/dt / r0
      acc_pres = 0
      if (b%is_wheelset) acc_pres(3) = spin_from_deviation(0.0_wp, kin%accel, b%r0)
      call solve_subset(mgen, g, free_ang, acc_pres, angdd)
      kin%qddot(1:3) = wdd
      kin%qddot(4:6) = angdd
      ! d/dt of the shift c: (Omega' x w + Omega x w', H^{-1} (g' - H' c_a)), g = B^T Omega
      cdot(1:3) = cross(al, w) + cross(om, wd)
      ca = inverse_angle_rate(kin%q(5), kin%q(6), btom)
      cdot(4:6) = inverse_angle_rate(kin%q(5), kin%q(6), &
                  -cross(omrel, btom) + matmul(al, kin%b) - matmul(hd, ca))
      do j = 1, 6
        k = self%free_index(j, i)
        if (k == 0) cycle
        if (j == DOF_PITCH .and. b%is_wheelset) then
          ydot(k) = deviation_from_spin(kin%qdot(j), kin%speed, b%r0)        ! dbeta/dt
          ydot(self%nfree + k) = deviation_from_spin(kin%qddot(j) + cdot(j), kin%accel, b%r0)
        else
          ydot(k) = kin%qdot(j)
          ydot(self%nfree + k) = kin%qddot(j) + cdot(j)
        end if
      end do
    end associate
  end subroutine body_equations

  !> Solve M x = g for the entries with free(i), the others prescribed (x(i) = xp(i)):
  !> M_ff x_f = g_f - M_fc x_c. At most 3x3, Gaussian elimination with partial pivoting.
  pure subroutine solve_subset(m, g, free, xp, x)
    real(wp), intent(in) :: m(3, 3), g(3), xp(3)
    logical, intent(in) :: free(3)
    real(wp), intent(out) :: x(3)
    real(wp) :: a(3, 3), r(3), tmp(3), piv, fac, t
    integer :: idx(3), n, i, j, k, p
    x = xp
    n = 0
    do i = 1, 3
      if (free(i)) then
        n = n + 1
        idx(n) = i
      end if
    end do
    if (n == 0) return
    do i = 1, n
      r(i) = g(idx(i))
      do j = 1, 3
        if (.not. free(j)) r(i) = r(i) - m(idx(i), j) * xp(j)
      end do
      do j = 1, n
        a(i, j) = m(idx(i), idx(j))
      end do
    end do
    do k = 1, n
      p = k
      piv = abs(a(k, k))
      do i = k + 1, n
        if (abs(a(i, k)) > piv) then
          p = i; piv = abs(a(i, k))
        end if
      end do
      if (p /= k) then
        tmp(1:n) = a(k, 1:n); a(k, 1:n) = a(p, 1:n); a(p, 1:n) = tmp(1:n)
        t = r(k); r(k) = r(p); r(p) = t
      end if
      do i = k + 1, n
        fac = a(i, k) / a(k, k)
        a(i, k:n) = a(i, k:n) - fac * a(k, k:n)
        r(i) = r(i) - fac * r(k)
      end do
    end do
    do i = n, 1, -1
      t = r(i)
      do j = i + 1, n
        t = t - a(i, j) * x(idx(j))
      end do
      x(idx(i)) = t / a(i, i)
    end do
  end subroutine solve_subset

  !> OpenFAST's "calc output" step: the outputs at (t, y), by one evaluation of the equations
  !> of motion there (the integrator's last evaluation may be at another state): every body's
  !> kinematics with its accelerations, every element's result. The providers' own outputs
  !> (e.g. wheelset_contact_t%results) are those of this evaluation too.
  subroutine calc_output(self, t, y, out, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    type(multibody_output_t), intent(out) :: out
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: ydot(size(y))
    call self%rhs(t, y, ydot, error)
    if (allocated(error)) return
    out%bodies = self%scratch%kin
    out%elements = self%scratch%el_res
  end subroutine calc_output

  !> Run-time load on body ib (force at the CG and moment, fixed frame), replacing the
  !> previous one (C API input).
  subroutine set_override_load(self, ib, force, moment, error)
    class(multibody_t), intent(inout) :: self
    integer, intent(in) :: ib
    real(wp), intent(in) :: force(3), moment(3)
    type(error_t), allocatable, intent(out) :: error
    call self%override%set(ib, force, moment, error)
    if (allocated(error)) call error_context(error, 'multibody%set_override_load')
  end subroutine set_override_load

  !> The quasi-static balance's residual (z'', roll'' of every quasi-static body, relative,
  !> rates zero) with the quasi-static coordinates at `zr(:, i)` = (z, roll) of body i
  !> (bodies without quasi-static coordinates: ignored) and everything else from (t, y):
  !> what solve_quasi_static drives to zero, at a pose of the caller's choosing (studies of
  !> the balance, tests). The bodies' q0 keep zr afterwards; the next rhs starts from there.
  subroutine quasi_static_balance(self, t, y, zr, r, error)
    class(multibody_t), intent(inout) :: self
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:), zr(:, :)
    real(wp), intent(out) :: r(:, :)
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: ydot(size(y))
    integer :: i
    if (size(y) /= self%state_size() .or. size(zr, 2) /= size(self%bodies) .or. size(r, 2) /= size(self%bodies)) then
      call make_error(error, RD_ERR_INTERNAL, 'multibody%quasi_static_balance: wrong array sizes'); return
    end if
    call self%evaluate_kinematics(t, y)
    do i = 1, size(self%bodies)
      if (.not. any(self%bodies(i)%quasi_static)) cycle
      self%bodies(i)%q0(DOF_Z) = zr(1, i)
      self%bodies(i)%q0(DOF_ROLL) = zr(2, i)
    end do
    call update_quasi_static_kinematics(self, t, y)
    ydot = 0
    call quasi_static_residual(self, t, y, ydot, r, error)
  end subroutine quasi_static_balance
end module rd_multibody
