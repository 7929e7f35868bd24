!> Element preloads that put a vehicle in static equilibrium at its initial configuration
!> (thesis 5.2.1 d: "the preload for the suspensions are predefined by calculating the
!> amount of the normal load carried by each spring ... in the pre-processing stage").
!>
!> The accelerations of the free coordinates are affine in the adjustable preload
!> components p: a(p) = a0 + G p (the mass matrix is fixed at a given configuration).
!> G is built column by column from unit preloads (exact up to rounding: the map is
!> affine) and the minimum-norm least-squares solution of G p = -a0 is taken (LAPACK
!> dgelsd), so redundant supports share the load evenly and unloaded directions get no
!> preload. Preloads are a property of the vehicle, not of the place it starts: with
!> `level_track` they are found with every body frame on straight level track (the bodies'
!> coordinates relative to their frames unchanged), so a start inside a canted curve does
!> not hang the lateral component of the weight on lateral spring preloads that would
!> then stay for the whole run; the static position solve carries it by deflection.
!>
!> Alternatively `solve_static_positions` keeps the preloads and moves the bodies: Newton
!> on the free accelerations with zero velocities and frozen time (the frames do not
!> move), Jacobian by central differences, minimum-norm steps (dgelsd) so that neutral
!> directions (an unrestrained spin or longitudinal position) stay where they are.
!> Unknowns and equations:
!>  - the free coordinates that are not `held`, with their accelerations;
!>  - the elements' internal states, with their rates: a series spring-damper is in static
!>    equilibrium when its damper has stopped (dx_d/dt = T/c = 0), i.e. it carries no static
!>    force; holding x_d at its initial value would turn it into a spring that the bodies'
!>    settling loads.
!> Held coordinates keep their value in y and their equations are left out, i.e. whatever
!> generalized force holds them is not modelled. The scene (rd_scene) holds the lateral
!> position and the spin of bodies in wheel-rail contact: rolling, their creep forces keep
!> them on the track (lateral creep force ~ f22 (dy/dt) / V); at V = 0 the creepages and
!> the creep forces vanish, so nothing balances the component m g sin(phi_t) of the weight
!> along Y_T inside a canted curve, and an unheld Newton iteration slid the wheelsets onto
!> the flange and off the rail. The spin is a neutral coordinate at rest (no moment about
!> the axle without creep forces); in a curve the rounding of the contact geometry leaves
!> ~1e-8 rad/s^2 on it that no step can remove, so it is held too. Their vertical position,
!> roll and yaw (the primary suspension aligns a wheelset with its bogie; holding the yaw
!> radial in a tight curve would load the primaries with the curve's angle between the
!> frames: ~0.3 MN per spring on the Manchester vehicle in R = 150 m) and all coordinates
!> of the other bodies are solved; the dynamics, started from this state, find the
!> quasi-static curving position with the creep forces.
!>
!> Seating (`seated` bodies, the scene's wheelsets): a body built at its reference height
!> touches the rails at zero approach, where the Hertz force k delta^(3/2) has no stiffness,
!> so the first Jacobians have none in the vertical and Newton's minimum-norm steps wander
!> (the TGV profile vehicle on contact tables in an uncanted R 80 m: the residual of the
!> wheelset yaws, 1.8e3 rad/s^2, stalled and a wheel reached the lift-off limit). Before
!> Newton each seated body's vertical position alone is solved (everything else fixed): its
!> vertical acceleration is monotone in its height (more approach, more normal force), so
!> a bracket found by doubling steps towards the acceleration and a safeguarded secant on it
!> converge, and Newton then starts with the contact stiffness of the static load.
!>
!> Newton safeguards: coordinates move at most `max_step` per iteration, the step is halved
!> while the residual norm grows or the pose cannot be evaluated (first Jacobian without
!> contact stiffness: the profiles touch at a small gap), and an update below 1e-12 of
!> the unknowns with a residual below 1e-8 of the initial one is converged (the rounding
!> floor of the kinematics far along the track).
module rd_static_preload
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_multibody, only: multibody_t
  use rd_body_spec, only: DOF_Z, DOF_PITCH, deviation_from_spin
  use rd_speed_law, only: speed_law_t, constant_speed
  use rd_track_point, only: track_geometry_t
  use rd_level_straight_track, only: level_straight_track_t
  use rd_text, only: int_text, real_text
  use rd_lapack_interfaces, only: dgelsd
  implicit none
  private
  public :: solve_static_preloads, solve_static_positions

contains

  !> Set the preloads of all elements with adjustable components so that the free
  !> accelerations vanish at (t, y). `residual` is max |qddot| afterwards [m/s^2, rad/s^2].
  !> `supported(ib)`: body ib is held by something that is not an element (wheel-rail
  !> contact): its equations are left out of the balance, its residual is for the contact
  !> to carry (a static position solve follows).
  !> `level_track` (default false): balance with the body frames on straight level track
  !> (see the module header); the multibody's track is restored on return.
  subroutine solve_static_preloads(mb, t, y, residual, error, supported, level_track)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: residual
    type(error_t), allocatable, intent(out) :: error
    logical, intent(in), optional :: supported(:)
    logical, intent(in), optional :: level_track
    type(level_straight_track_t), target :: level
    class(track_geometry_t), pointer :: actual
    real(wp), allocatable :: y_level(:)
    logical :: on_level
    integer :: ib, j, k
    on_level = .false.
    if (present(level_track)) on_level = level_track
    if (.not. on_level) then
      call balance_preloads(mb, t, y, residual, error, supported)
      return
    end if
    ! the generalized velocities hold the rates relative to the frames plus the frames'
    ! rotation (rd_multibody); on level track the frames do not turn, so the same relative
    ! rates are the generalized velocities there
    call mb%evaluate_kinematics(t, y)
    y_level = y
    do ib = 1, mb%body_count()
      do j = 1, 6
        k = mb%free_index(j, ib)
        if (k == 0) cycle
        y_level(mb%nfree + k) = mb%scratch%kin(ib)%qdot(j)
        if (j == DOF_PITCH .and. mb%bodies(ib)%is_wheelset) &
          y_level(mb%nfree + k) = deviation_from_spin(mb%scratch%kin(ib)%qdot(j), mb%scratch%kin(ib)%speed, mb%bodies(ib)%r0)
      end do
    end do
    actual => mb%track
    mb%track => level
    ! quasi-static coordinates (wheelset height and roll) stay at their initial values, like the
    ! supported bodies' other coordinates: the balance is then affine in the preloads
    mb%hold_quasi_static = .true.
    call balance_preloads(mb, t, y_level, residual, error, supported)
    mb%hold_quasi_static = .false.
    mb%track => actual
    if (allocated(error)) call error_context(error, 'on level track')
  end subroutine solve_static_preloads

  subroutine balance_preloads(mb, t, y, residual, error, supported)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: residual
    type(error_t), allocatable, intent(out) :: error
    logical, intent(in), optional :: supported(:)
    integer :: np, ne, e, j, k, n, rank, info, lwork, nb, ib
    integer, allocatable :: first(:), iwork(:)
    logical, allocatable :: row(:)
    real(wp), allocatable :: ydot(:), a0(:), g(:, :), b(:), s(:), work(:), p(:)
    real(wp) :: wq(1)
    integer :: iwq(1)
    residual = huge(1.0_wp)
    ne = mb%nfree
    allocate (first(mb%element_count()))
    np = 0
    do e = 1, mb%element_count()
      first(e) = np + 1
      np = np + mb%elements(e)%e%preload_count()
    end do
    if (np == 0 .or. ne == 0) then
      call make_error(error, RD_ERR_INPUT, 'static preloads: no adjustable preload or no free coordinate'); return
    end if
    ! rows of the balance: free coordinates of bodies not supported otherwise
    allocate (row(ne))
    row = .true.
    if (present(supported)) then
      do ib = 1, size(supported)
        if (.not. supported(ib)) cycle
        do j = 1, 6
          if (mb%free_index(j, ib) > 0) row(mb%free_index(j, ib)) = .false.
        end do
      end do
    end if
    allocate (ydot(size(y)), p(np), g(ne, np))
    p = 0
    call apply(p)
    call mb%rhs(t, y, ydot, error)
    if (allocated(error)) then
      call error_context(error, 'static preloads'); return
    end if
    a0 = ydot(ne + 1:2 * ne)
    do j = 1, np
      p = 0
      p(j) = 1
      call apply(p)
      call mb%rhs(t, y, ydot, error)
      if (allocated(error)) then
        call error_context(error, 'static preloads'); return
      end if
      g(:, j) = ydot(ne + 1:2 * ne) - a0
    end do
    ! excluded rows enter with zero weight
    do j = 1, ne
      if (.not. row(j)) then
        g(j, :) = 0
        a0(j) = 0
      end if
    end do
    nb = max(ne, np)
    allocate (b(nb), s(min(ne, np)))
    b = 0
    b(1:ne) = -a0
    call dgelsd(ne, np, 1, g, ne, b, nb, s, -1.0_wp, rank, wq, -1, iwq, info)
    lwork = int(wq(1))
    allocate (work(lwork), iwork(max(1, iwq(1))))
    ! rcond: singular values below 1e-12 of the largest are treated as zero (null directions)
    call dgelsd(ne, np, 1, g, ne, b, nb, s, 1.0e-12_wp, rank, work, lwork, iwork, info)
    if (info /= 0) then
      call make_error(error, RD_ERR_RUNTIME, 'static preloads: least-squares solver (dgelsd) did not converge'); return
    end if
    p = b(1:np)
    call apply(p)
    call mb%rhs(t, y, ydot, error)
    if (allocated(error)) then
      call error_context(error, 'static preloads'); return
    end if
    residual = maxval(abs(ydot(ne + 1:2 * ne)), mask=row)
    if (residual > 1.0e-6_wp * max(1.0_wp, maxval(abs(a0)))) then
      call make_error(error, RD_ERR_INPUT, 'static preloads: the elements'' preloads cannot balance the loads '// &
                      '(a body or direction has no preloadable support)')
      return
    end if
  contains
    subroutine apply(pv)
      real(wp), intent(in) :: pv(:)
      do k = 1, mb%element_count()
        n = mb%elements(k)%e%preload_count()
        if (n > 0) call mb%elements(k)%e%set_preload(pv(first(k):first(k) + n - 1))
      end do
    end subroutine apply
  end subroutine balance_preloads

  !> Move the free coordinates of y (rates set to zero) and the elements' internal states to
  !> the static equilibrium at time t with the speed taken as zero. `held(dof, ib)`: that
  !> coordinate keeps its value in y and its equation is left out (see the module header).
  !> `residual` is max |qddot| of the solved coordinates at the solution [m/s^2, rad/s^2];
  !> convergence also requires the internal states' rates to vanish. `seated(ib)`: body ib
  !> rests on the rails; its height is solved alone first (module header).
  subroutine solve_static_positions(mb, t, y, residual, error, max_iterations, held, seated)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: t
    real(wp), intent(inout) :: y(:)
    real(wp), intent(out) :: residual
    type(error_t), allocatable, intent(out) :: error
    integer, intent(in), optional :: max_iterations
    logical, intent(in), optional :: held(:, :)
    logical, intent(in), optional :: seated(:)
    type(speed_law_t) :: saved
    real(wp), allocatable :: r(:), rp(:), rm(:), jac(:, :), b(:), s(:), work(:), yp(:)
    integer, allocatable :: iwork(:), unknown(:), equation(:)
    real(wp), allocatable :: y0(:)
    real(wp) :: h, wq(1), scale, rnorm, step, r0
    integer :: n, m, it, i, j, k, ib, rank, info, iwq(1), itmax, tries
    logical :: converged
    !> largest change of a coordinate in one Newton iteration [m, rad]
    real(wp), parameter :: max_step = 0.1_wp
    itmax = 100
    if (present(max_iterations)) itmax = max_iterations
    residual = huge(1.0_wp)
    n = mb%nfree
    if (n == 0) then
      call make_error(error, RD_ERR_INPUT, 'no free coordinate'); return
    end if
    if (present(held)) then
      if (size(held, 1) /= 6 .or. size(held, 2) /= mb%body_count()) then
        call make_error(error, RD_ERR_INPUT, 'held must be (6, number of bodies)'); return
      end if
    end if
    ! unknown(i): state index of unknown i (a free coordinate not held, or an element's
    ! internal state); equation(i): the entry of ydot that must vanish for it (the
    ! coordinate's acceleration at n + k, the internal state's own rate)
    allocate (unknown(n + mb%nel_states), equation(n + mb%nel_states))
    m = 0
    do ib = 1, mb%body_count()
      do j = 1, 6
        k = mb%free_index(j, ib)
        if (k == 0) cycle
        if (present(held)) then
          if (held(j, ib)) cycle
        end if
        m = m + 1
        unknown(m) = k
        equation(m) = n + k
      end do
    end do
    do k = 2 * n + 1, 2 * n + mb%nel_states
      m = m + 1
      unknown(m) = k
      equation(m) = k
    end do
    if (m == 0) then
      call make_error(error, RD_ERR_INPUT, 'every free coordinate is held'); return
    end if
    unknown = unknown(1:m)
    equation = equation(1:m)
    saved = mb%speed
    ! frozen time: speed 0, frames kept where they are at t
    mb%speed = constant_speed(0.0_wp)
    mb%speed%s = saved%distance(t)
    y(n + 1:2 * n) = 0
    allocate (r(m), rp(m), rm(m), jac(m, m), b(m), s(m), yp(size(y)))
    if (present(seated)) then
      do ib = 1, min(size(seated), mb%body_count())
        if (.not. seated(ib)) cycle
        k = mb%free_index(DOF_Z, ib)
        if (k == 0) cycle
        call seat_body(k)
        if (allocated(error)) goto 90
      end do
    end if
    call static_residual(y, r)
    if (allocated(error)) goto 90
    scale = max(1.0_wp, maxval(abs(r)))
    converged = .false.
    do it = 1, itmax
      rnorm = maxval(abs(r))
      if (rnorm <= 1.0e-10_wp * scale) then
        converged = .true.
        exit
      end if
      do i = 1, m
        k = unknown(i)
        h = 1.0e-7_wp * max(1.0_wp, abs(y(k)))
        yp = y; yp(k) = y(k) + h
        call static_residual(yp, rp)
        if (allocated(error)) goto 90
        yp(k) = y(k) - h
        call static_residual(yp, rm)
        if (allocated(error)) goto 90
        jac(:, i) = (rp - rm) / (2 * h)
      end do
      b = -r
      if (.not. allocated(work)) then
        call dgelsd(m, m, 1, jac, m, b, m, s, -1.0_wp, rank, wq, -1, iwq, info)
        allocate (work(int(wq(1))), iwork(max(1, iwq(1))))
      end if
      call dgelsd(m, m, 1, jac, m, b, m, s, 1.0e-12_wp, rank, work, size(work), iwork, info)
      if (info /= 0) then
        call make_error(error, RD_ERR_RUNTIME, 'least-squares solver (dgelsd) did not converge')
        goto 90
      end if
      ! Rounding floor: far along the track (sigma ~ 1e3 m) the frames and attachment points
      ! carry ~1e-13 m of rounding, which a stiff support (k/m ~ 1e4..1e6 1/s^2) turns into
      ! residual accelerations of ~1e-9 m/s^2 that no step can remove. An update below
      ! 1e-12 of the unknowns (units m, rad) means Newton has converged as far as the
      ! evaluation allows; the residual must still be small (1e-8 of the initial one).
      if (maxval(abs(b) / max(1.0_wp, abs(y(unknown)))) <= 1.0e-12_wp .and. rnorm <= 1.0e-8_wp * scale) then
        converged = .true.
        exit
      end if
      ! Step limit: a start with the wheels just off the rails (profiles touch at a gap of
      ! ~0.2 mm) leaves the vehicle's vertical motion without stiffness in the first
      ! Jacobian; the minimum-norm step along that nearly singular direction can be metres.
      ! Coordinates move at most max_step per iteration (the direction is kept).
      step = maxval(abs(b), mask=unknown <= n)
      if (step > max_step) b = b * (max_step / step)
      ! Backtracking: halve the step while the pose cannot be evaluated (wheelset pose out
      ! of range, ...) or the residual grows (a step into deep wheel-rail penetration from a
      ! Jacobian without contact stiffness); after 10 halvings a valid step is taken anyway.
      y0 = y(unknown)
      r0 = norm2(r)
      do tries = 1, 20
        y(unknown) = y0 + b
        call static_residual(y, r)
        if (.not. allocated(error)) then
          if (norm2(r) < r0 .or. tries > 10) exit
        end if
        b = b / 2
      end do
      if (allocated(error)) goto 90
    end do
    rnorm = maxval(abs(r))
    residual = maxval(abs(r), mask=equation <= 2 * n)
    if (.not. converged) then
      call make_error(error, RD_ERR_RUNTIME, 'Newton did not converge in ' // trim(int_text(itmax)) // &
                      ' iterations (no stable equilibrium?): largest residual ' // trim(real_text(rnorm)))
    end if
90  mb%speed = saved
    if (allocated(error)) call error_context(error, 'static positions')
  contains
    !> Height y(k) of one body at which its vertical acceleration ydot(n + k) vanishes, the
    !> other unknowns fixed: bracket by steps doubling from 1 um towards the acceleration
    !> (at most 10 mm: a wheel further off its rail is a deck error for the Newton iteration
    !> to report), then the Illinois variant of the secant (regula falsi) inside the bracket
    !> to 1e-12 m.
    subroutine seat_body(k)
      integer, intent(in) :: k
      real(wp) :: za, zb, aa, ab, zc, ac, dz
      integer :: iter, side
      real(wp), parameter :: first_step = 1.0e-6_wp, longest_step = 1.0e-2_wp
      za = y(k)
      aa = acceleration(k, za); if (allocated(error)) return
      if (aa == 0) return
      dz = sign(first_step, aa)
      do
        zb = za + dz
        ab = acceleration(k, zb); if (allocated(error)) return
        if (sign(1.0_wp, ab) /= sign(1.0_wp, aa) .or. ab == 0) exit
        za = zb; aa = ab
        dz = 2 * dz
        if (abs(dz) > longest_step) then
          y(k) = za         ! no bracket: leave the body there, Newton reports
          return
        end if
      end do
      side = 0
      do iter = 1, 100
        zc = (za * ab - zb * aa) / (ab - aa)
        ac = acceleration(k, zc); if (allocated(error)) return
        if (ac == 0 .or. abs(zb - za) <= 1.0e-12_wp) exit
        if (sign(1.0_wp, ac) == sign(1.0_wp, ab)) then
          zb = zc; ab = ac
          if (side == -1) aa = aa / 2
          side = -1
        else
          za = zc; aa = ac
          if (side == 1) ab = ab / 2
          side = 1
        end if
      end do
      y(k) = zc
    end subroutine seat_body

    real(wp) function acceleration(kz, z)
      integer, intent(in) :: kz
      real(wp), intent(in) :: z
      real(wp) :: ydot(size(y))
      yp = y
      yp(kz) = z
      call mb%rhs(t, yp, ydot, error)
      acceleration = ydot(n + kz)
    end function acceleration

    subroutine static_residual(yy, res)
      real(wp), intent(in) :: yy(:)
      real(wp), intent(out) :: res(:)
      real(wp) :: ydot(size(yy))
      call mb%rhs(t, yy, ydot, error)
      res = ydot(equation)
    end subroutine static_residual
  end subroutine solve_static_positions
end module rd_static_preload
