!> Modes of a linear system y' = A y (docs/theory_stability.md): the eigenvalues of A
!> (LAPACK dgeev), each real eigenvalue and each complex-conjugate pair reported once, with
!> its frequency, damping ratio and the states that dominate its eigenvector.
!>
!> For an eigenvalue lambda = re + i im (im >= 0, the partner -im is the same mode):
!>   frequency     = im / (2 pi)                   [Hz], the damped frequency,
!>   damping ratio = -re / |lambda|                (1 for a decaying real eigenvalue, -1 for
!>                                                  a growing one), so that a second-order
!>                                                  mode lambda = -zeta w0 +- i w0 sqrt(1 - zeta^2)
!>                                                  gives back zeta.
!> A neutral mode (a coordinate without restoring force: a wheelset's spin angle, a free x)
!> has lambda = 0, which dgeev returns as round-off of size eps ||A|| with any sign and
!> phase: |lambda| <= NEUTRAL_TOLERANCE eps ||A||_F is reported as lambda = 0 exactly,
!> damping ratio 0, `neutral` set.
!> Participation: the share of each state in the mode's kinetic energy, weights(i) |v_i|^2 /
!> sum_j weights(j) |v_j|^2, with weights the mass or moment of inertia of a coordinate row
!> and 0 elsewhere (units of m and rad cannot be compared, energies can). A mode without any
!> weighted component (an element's internal state relaxing alone, e.g. a series damper) is
!> shared by |v_i|^2 over all states.
module rd_linear_modes
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_text, only: int_text
  implicit none
  private
  public :: linear_mode_t, linear_modes, MAX_DOMINANT, DOMINANT_SHARE_MIN

  !> Eigenvalues within this many eps ||A||_F of 0 are neutral (module header): dgeev's
  !> backward error is a small multiple of eps ||A|| (LAPACK Users' Guide 4.8); measured on
  !> the TGV bogie (||A|| ~ 1e7), its spin modes come out at ~1e-14 1/s. For ||A|| ~ 1e7 the
  !> bound is ~2e-5 1/s, a time constant of half a day.
  real(wp), parameter :: NEUTRAL_TOLERANCE = 1.0e4_wp

  !> The dominant states of a mode: at most this many,
  integer, parameter :: MAX_DOMINANT = 3
  !> each with at least this share of the mode (the largest one is always listed).
  real(wp), parameter :: DOMINANT_SHARE_MIN = 0.05_wp

  type :: linear_mode_t
    real(wp) :: real_part = 0          !< Re lambda [1/s]; > 0: the mode grows
    real(wp) :: imag_part = 0          !< Im lambda [rad/s], >= 0
    real(wp) :: frequency = 0          !< Im lambda / (2 pi) [Hz]
    real(wp) :: damping_ratio = 0      !< -Re lambda / |lambda|
    logical :: neutral = .false.       !< lambda = 0 to round-off (module header)
    integer :: n_dominant = 0
    integer :: dominant(MAX_DOMINANT) = 0     !< state (row) indices, largest share first
    real(wp) :: share(MAX_DOMINANT) = 0       !< their shares of the mode, in (0, 1]
  end type linear_mode_t

contains

  !> The modes of `a` (n x n), least damped first (ascending damping ratio, then ascending
  !> frequency). `weights(n)` >= 0: the participation weights (module header).
  subroutine linear_modes(a, weights, modes, error)
    real(wp), intent(in) :: a(:, :)
    real(wp), intent(in) :: weights(:)
    type(linear_mode_t), allocatable, intent(out) :: modes(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: work_a(:, :), wr(:), wi(:), vr(:, :), vl(:, :), work(:), energy(:)
    real(wp) :: query(1), zero_bound
    integer :: n, info, j, count, lwork
    type(linear_mode_t), allocatable :: found(:)

    n = size(a, 1)
    if (n < 1 .or. size(a, 2) /= n .or. size(weights) /= n) then
      call make_error(error, RD_ERR_INPUT, 'linear modes: expected a square matrix with one weight per row, got ' // &
                      trim(int_text(size(a, 1))) // ' x ' // trim(int_text(size(a, 2))) // ' and ' // &
                      trim(int_text(size(weights))) // ' weights')
      return
    end if
    if (.not. all(ieee_is_finite(a))) then
      call make_error(error, RD_ERR_RUNTIME, 'linear modes: the system matrix holds NaN or Inf')
      return
    end if
    allocate (work_a(n, n), wr(n), wi(n), vr(n, n), vl(1, 1))
    work_a = a
    call dgeev('N', 'V', n, work_a, n, wr, wi, vl, 1, vr, n, query, -1, info)
    lwork = max(4 * n, int(query(1)))
    allocate (work(lwork))
    call dgeev('N', 'V', n, work_a, n, wr, wi, vl, 1, vr, n, work, lwork, info)
    if (info /= 0) then
      call make_error(error, RD_ERR_RUNTIME, 'linear modes: LAPACK dgeev did not converge (info = ' // &
                      trim(int_text(info)) // ')')
      return
    end if

    zero_bound = NEUTRAL_TOLERANCE * epsilon(1.0_wp) * norm2(a)
    allocate (found(n), energy(n))
    count = 0
    do j = 1, n
      if (wi(j) < 0) cycle                 ! the conjugate of the previous column's pair
      count = count + 1
      if (wi(j) > 0) then
        ! dgeev: columns j, j+1 hold the real and imaginary parts of the eigenvector
        energy = vr(:, j)**2 + vr(:, j + 1)**2
      else
        energy = vr(:, j)**2
      end if
      found(count) = mode_of(wr(j), wi(j), energy)
    end do
    modes = found(:count)
    call sort_least_damped_first(modes)

  contains

    type(linear_mode_t) function mode_of(re, im, magnitude) result(mode)
      real(wp), intent(in) :: re, im, magnitude(:)
      real(wp) :: share(size(magnitude)), total
      integer :: k, i
      if (hypot(re, im) <= zero_bound) then
        mode%neutral = .true.
      else
        mode%real_part = re
        mode%imag_part = im
        mode%frequency = im / (2 * pi)
        mode%damping_ratio = -re / hypot(re, im)
      end if
      share = weights * magnitude
      total = sum(share)
      if (.not. total > 0) then
        share = magnitude
        total = sum(share)
      end if
      if (total > 0) share = share / total
      do k = 1, MAX_DOMINANT
        i = maxloc(share, dim=1)
        if (share(i) <= 0 .or. (k > 1 .and. share(i) < DOMINANT_SHARE_MIN)) exit
        mode%n_dominant = k
        mode%dominant(k) = i
        mode%share(k) = share(i)
        share(i) = -1
      end do
    end function mode_of
  end subroutine linear_modes

  !> Least damped first: selection by (damping ratio, frequency); a few hundred modes at most.
  pure subroutine sort_least_damped_first(modes)
    type(linear_mode_t), intent(inout) :: modes(:)
    type(linear_mode_t) :: unsorted(size(modes))
    logical :: taken(size(modes))
    integer :: k, j, best
    unsorted = modes
    taken = .false.
    do k = 1, size(modes)
      best = findloc(taken, .false., dim=1)
      do j = best + 1, size(modes)
        if (.not. taken(j) .and. comes_before(unsorted(j), unsorted(best))) best = j
      end do
      taken(best) = .true.
      modes(k) = unsorted(best)
    end do
  end subroutine sort_least_damped_first

  pure logical function comes_before(a, b)
    type(linear_mode_t), intent(in) :: a, b
    if (a%damping_ratio /= b%damping_ratio) then
      comes_before = a%damping_ratio < b%damping_ratio
    else
      comes_before = a%frequency < b%frequency
    end if
  end function comes_before
end module rd_linear_modes
