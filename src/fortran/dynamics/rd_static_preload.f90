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
module rd_static_preload
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_multibody, only: multibody_t
  implicit none
  private
  public :: solve_static_preloads

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
  subroutine solve_static_preloads(mb, t, y, residual, error)
    type(multibody_t), intent(inout) :: mb
    real(wp), intent(in) :: t
    real(wp), intent(in) :: y(:)
    real(wp), intent(out) :: residual
    type(error_t), allocatable, intent(out) :: error
    integer :: np, ne, e, j, k, n, rank, info, lwork, nb
    integer, allocatable :: first(:), iwork(:)
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
    residual = maxval(abs(ydot(ne + 1:2 * ne)))
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
end module rd_static_preload
