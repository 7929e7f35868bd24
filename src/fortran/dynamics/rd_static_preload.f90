!> Element preloads that put a vehicle in static equilibrium at its initial configuration
!> (thesis 5.2.1 d: "the preload for the suspensions are predefined by calculating the
!> amount of the normal load carried by each spring ... in the pre-processing stage").
!>
!> The accelerations of the free coordinates are affine in the adjustable preload
!> components p: a(p) = a0 + G p (the mass matrix is fixed at a given configuration).
!> G is built column by column from unit preloads (exact up to rounding: the map is
!> affine) and the minimum-norm least-squares solution of G p = -a0 is taken (LAPACK
!> dgelsd), so redundant supports share the load evenly and unloaded directions get no
!> preload. Call it at the initial state on straight level track (any constant speed).
!>
!> Alternatively `solve_static_positions` keeps the preloads and moves the bodies: Newton
!> on the free accelerations with zero velocities and frozen time (the frames do not
!> move), Jacobian by central differences, minimum-norm steps (dgelsd) so that neutral
!> directions (an unrestrained spin or longitudinal position) stay where they are.
module rd_static_preload
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_multibody, only: multibody_t
  use rd_speed_law, only: speed_law_t, constant_speed
  implicit none
  private
  public :: solve_static_preloads, solve_static_positions

  interface
    subroutine dgelsd(m, n, nrhs, a, lda, b, ldb, s, rcond, rank, work, lwork, iwork, info)
      import :: wp
      integer, intent(in) :: m, n, nrhs, lda, ldb, lwork
      real(wp), intent(inout) :: a(lda, *), b(ldb, *)
      real(wp), intent(out) :: s(*), work(*)
      real(wp), intent(in) :: rcond
      integer, intent(out) :: rank, iwork(*), info
    end subroutine dgelsd
  end interface

contains

  !> Set the preloads of all elements with adjustable components so that the free
  !> accelerations vanish at (t, y). `residual` is max |qddot| afterwards [m/s^2, rad/s^2].
  !> `supported(ib)`: body ib is held by something that is not an element (wheel-rail
  !> contact): its equations are left out of the balance, its residual is for the contact
  !> to carry (a static position solve follows).
  subroutine solve_static_preloads(mb, t, y, residual, error, supported)
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
    logical :: rec
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
    call mb%rhs(t, y, ydot, error, rec)
    if (allocated(error)) then
      call error_context(error, 'static preloads'); return
    end if
    a0 = ydot(ne + 1:2 * ne)
    do j = 1, np
      p = 0
      p(j) = 1
      call apply(p)
      call mb%rhs(t, y, ydot, error, rec)
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
    call mb%rhs(t, y, ydot, error, rec)
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
  end subroutine solve_static_preloads

  !> Move the free coordinates of y (rates set to zero) to the static equilibrium at time t
  !> with the speed taken as zero. `residual` is max |qddot| at the solution.
  subroutine solve_static_positions(mb, t, y, residual, error, max_iterations)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: t
    real(wp), intent(inout) :: y(:)
    real(wp), intent(out) :: residual
    type(error_t), allocatable, intent(out) :: error
    integer, intent(in), optional :: max_iterations
    type(speed_law_t) :: saved
    real(wp), allocatable :: a(:), ap(:), am(:), jac(:, :), b(:), s(:), work(:), yp(:)
    integer, allocatable :: iwork(:)
    real(wp) :: h, wq(1), scale
    integer :: n, it, j, rank, info, iwq(1), itmax
    itmax = 50
    if (present(max_iterations)) itmax = max_iterations
    n = mb%nfree
    if (n == 0) then
      call make_error(error, RD_ERR_INPUT, 'static positions: no free coordinate'); return
    end if
    saved = mb%speed
    ! frozen time: speed 0, frames kept where they are at t
    mb%speed = constant_speed(0.0_wp)
    mb%speed%s = saved%distance(t)
    y(n + 1:2 * n) = 0
    allocate (a(n), ap(n), am(n), jac(n, n), b(n), s(n), yp(size(y)))
    call free_accelerations(y, a)
    if (allocated(error)) goto 90
    scale = max(1.0_wp, maxval(abs(a)))
    do it = 1, itmax
      residual = maxval(abs(a))
      if (residual <= 1.0e-10_wp * scale) exit
      do j = 1, n
        h = 1.0e-7_wp * max(1.0_wp, abs(y(j)))
        yp = y; yp(j) = y(j) + h
        call free_accelerations(yp, ap)
        if (allocated(error)) goto 90
        yp(j) = y(j) - h
        call free_accelerations(yp, am)
        if (allocated(error)) goto 90
        jac(:, j) = (ap - am) / (2 * h)
      end do
      b = -a
      if (.not. allocated(work)) then
        call dgelsd(n, n, 1, jac, n, b, n, s, -1.0_wp, rank, wq, -1, iwq, info)
        allocate (work(int(wq(1))), iwork(max(1, iwq(1))))
      end if
      call dgelsd(n, n, 1, jac, n, b, n, s, 1.0e-12_wp, rank, work, size(work), iwork, info)
      if (info /= 0) then
        call make_error(error, RD_ERR_RUNTIME, 'static positions: least-squares solver (dgelsd) did not converge')
        goto 90
      end if
      y(1:n) = y(1:n) + b
      call free_accelerations(y, a)
      if (allocated(error)) goto 90
    end do
    residual = maxval(abs(a))
    if (residual > 1.0e-10_wp * scale) then
      call make_error(error, RD_ERR_RUNTIME, 'static positions: Newton did not converge (no stable equilibrium?)')
    end if
90  mb%speed = saved
    if (allocated(error)) call error_context(error, 'static positions')
  contains
    subroutine free_accelerations(yy, acc)
      real(wp), intent(in) :: yy(:)
      real(wp), intent(out) :: acc(:)
      real(wp) :: ydot(size(yy))
      logical :: rec
      call mb%rhs(t, yy, ydot, error, rec)
      acc = ydot(n + 1:2 * n)
    end subroutine free_accelerations
  end subroutine solve_static_positions
end module rd_static_preload
