!> Jumps and kinks of a function sampled along a sweep: where a quantity computed on a fine,
!> uniform grid x(1..n) is discontinuous (jump) or has a discontinuous first derivative
!> (kink), and by how much. Used by bench/contact_smoothness to measure the wheel-rail
!> forces along pose and creepage sweeps; usable in tests that require a force to be smooth.
!>
!> Method (finite differences d_i = f(i+1) - f(i), s_i = d(i+1) - d(i), step h):
!> - a smooth function has s_i ~ f'' h^2, changing gradually along the sweep;
!> - a jump J between x(k) and x(k+1) makes d_k = J + f' h: the second differences get a
!>   dipole s_(k-1) = +J, s_k = -J;
!> - a kink (slope a -> b) between x(k) and x(k+1) puts (b - a) h into s_(k-1) and s_k,
!>   split by where the kink lies (one sign: a monopole).
!> A second difference is anomalous when |s_i| > ratio * max(local scale, floor), local
!> scale = median of |s| over the 2 window + 1 neighbours (robust to the anomaly itself),
!> floor = relative_floor * scale (round-off of a quantity of size `scale`). Anomalies within
!> two samples of each other form one event, analysed with the first differences just
!> outside it (dL before, dR after):
!> - slope change = (dR - dL - c) / h, c = what the smooth curvature around the event (the
!>   mean of the second differences just before and after it) accounts for over those
!>   differences; a kink when |dR - dL - c| > ratio * the event's local scale
!>   (median |s| of the window around the event, the event excluded); located at the
!>   centroid of its second differences (exact for an isolated kink);
!> - jump = the part of the first differences inside the event beyond the range [dL, dR]
!>   spanned by the slopes (zero for a pure kink, whose inner differences lie between the
!>   two slopes), a jump when |J| > ratio * local scale; located at the middle of the
!>   interval with the largest excess.
!> An event can be both (a jump where the slope also changes). Events whose references
!> would fall outside the samples (within two samples of an end) are not analysed. At a
!> resolution h a continuous change much steeper than the features around it (e.g. over
!> less than h) is indistinguishable from a jump: results are "at resolution h".
module rd_sweep_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: smoothness_feature_t, find_jumps_and_kinks, FEATURE_JUMP, FEATURE_KINK, window_median

  integer, parameter :: FEATURE_JUMP = 1   !< discontinuity of the value
  integer, parameter :: FEATURE_KINK = 2   !< discontinuity of the first derivative

  !> One detected feature.
  type :: smoothness_feature_t
    integer :: kind = 0          !< FEATURE_JUMP or FEATURE_KINK
    real(wp) :: x = 0            !< where [unit of x]
    !> jump: f(x+) - f(x-) [unit of f]; kink: f'(x+) - f'(x-) [unit of f / unit of x]
    real(wp) :: size = 0
    !> size relative to the noise it was detected against: |jump| / local scale, resp.
    !> |slope change| h / local scale (>= ratio by construction)
    real(wp) :: prominence = 0
    real(wp) :: width = 0        !< extent of the event's anomalous second differences [unit of x]
  end type smoothness_feature_t

contains

  !> Detect jumps and kinks of f sampled at uniformly spaced x (n >= 7, strictly monotonic,
  !> spacing equal within 1e-6 relative). `scale`: the quantity's natural size (e.g. the wheel
  !> load for a force), sets the round-off floor. Options: `ratio` (default 20), `window`
  !> (half width of the local-scale neighbourhood, default 10 samples), `relative_floor`
  !> (default 1e-9). Features are returned in order of x.
  subroutine find_jumps_and_kinks(x, f, scale, features, error, ratio, window, relative_floor)
    real(wp), intent(in) :: x(:), f(:)
    real(wp), intent(in) :: scale
    type(smoothness_feature_t), allocatable, intent(out) :: features(:)
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: ratio, relative_floor
    integer, intent(in), optional :: window
    real(wp) :: k_ratio, floor, h, dl, dr, dslope, lo, hi, excess, jump, best, local, sw, swx, sa, sax
    real(wp), allocatable :: d(:), s(:), as(:)
    logical, allocatable :: anomalous(:)
    integer :: n, w, i, p, q, m, mbest, nfeat
    type(smoothness_feature_t), allocatable :: found(:)

    n = size(x)
    k_ratio = 20.0_wp
    if (present(ratio)) k_ratio = ratio
    w = 10
    if (present(window)) w = window
    floor = 1.0e-9_wp * abs(scale)
    if (present(relative_floor)) floor = relative_floor * abs(scale)
    allocate (features(0))
    if (size(f) /= n) then
      call make_error(error, RD_ERR_INPUT, 'find_jumps_and_kinks: x and f differ in length')
      return
    else if (n < 7) then
      call make_error(error, RD_ERR_INPUT, 'find_jumps_and_kinks: expected at least 7 samples')
      return
    else if (.not. (k_ratio > 1 .and. w >= 2 .and. floor >= 0)) then
      call make_error(error, RD_ERR_INPUT, 'find_jumps_and_kinks: expected ratio > 1, window >= 2, floor >= 0')
      return
    end if
    h = (x(n) - x(1)) / (n - 1)
    if (.not. (h /= 0 .and. all(abs((x(2:n) - x(1:n - 1)) - h) <= 1.0e-6_wp * abs(h)))) then
      call make_error(error, RD_ERR_INPUT, 'find_jumps_and_kinks: x must be uniformly spaced')
      return
    end if
    if (.not. all(abs(f) <= huge(1.0_wp))) then
      call make_error(error, RD_ERR_INPUT, 'find_jumps_and_kinks: f has non-finite values')
      return
    end if

    d = f(2:n) - f(1:n - 1)          ! d(i), i = 1..n-1
    s = d(2:n - 1) - d(1:n - 2)      ! s(i) = d(i+1) - d(i), centred at x(i+1), i = 1..n-2
    as = abs(s)
    allocate (anomalous(n - 2), found(n))
    do i = 1, n - 2
      anomalous(i) = as(i) > k_ratio * max(window_median(as, i - w, i + w, 0, -1), floor)
    end do

    nfeat = 0
    i = 1
    do while (i <= n - 2)
      if (.not. anomalous(i)) then
        i = i + 1
        cycle
      end if
      ! the event: anomalies no more than two samples apart
      p = i
      q = i
      do while (q + 1 <= n - 2)
        if (anomalous(q + 1)) then
          q = q + 1
        else if (q + 2 <= n - 2) then
          if (.not. anomalous(q + 2)) exit
          q = q + 2
        else
          exit
        end if
      end do
      i = q + 1
      ! references one difference outside the event: dL = d(p-1), dR = d(q+2)
      if (p - 1 < 1 .or. q + 2 > n - 1) cycle
      dl = d(p - 1)
      dr = d(q + 2)
      local = max(window_median(as, p - w, q + w, p - 1, q + 1), floor)
      ! jump: the inner differences' excess over the range the two slopes span
      lo = min(dl, dr)
      hi = max(dl, dr)
      jump = 0
      best = -1
      mbest = p
      do m = p, q + 1
        excess = d(m) - max(lo, min(hi, d(m)))
        jump = jump + excess
        if (abs(excess) > best) then
          best = abs(excess)
          mbest = m
        end if
      end do
      if (abs(jump) > k_ratio * local) then
        nfeat = nfeat + 1
        found(nfeat) = smoothness_feature_t(kind=FEATURE_JUMP, x=0.5_wp * (x(mbest) + x(mbest + 1)), size=jump, &
                                            prominence=abs(jump) / local, width=(q - p) * abs(h))
      end if
      ! the smooth curvature's own change of slope over the q - p + 3 differences from dL
      ! to dR, from the second differences just outside the event
      dslope = dr - dl - (q - p + 3) * background_curvature(s, p - 2, q + 2)
      if (abs(dslope) > k_ratio * local) then
        ! centroid of the event's second differences (their signed sum is dR - dL up to
        ! the two outer ones); the unsigned one when a jump's dipole cancels the sign
        sw = 0; swx = 0; sa = 0; sax = 0
        do m = p - 1, q + 1
          sw = sw + s(m); swx = swx + s(m) * x(m + 1)
          sa = sa + as(m); sax = sax + as(m) * x(m + 1)
        end do
        nfeat = nfeat + 1
        if (abs(sw) > 0.5_wp * sa) then
          found(nfeat)%x = swx / sw
        else
          found(nfeat)%x = sax / sa
        end if
        found(nfeat)%kind = FEATURE_KINK
        found(nfeat)%size = dslope / h
        found(nfeat)%prominence = abs(dslope) / local
        found(nfeat)%width = (q - p) * abs(h)
      end if
    end do
    features = found(1:nfeat)
  end subroutine find_jumps_and_kinks

  !> Mean of the second differences s(before) and s(after) that exist (0 if neither).
  pure real(wp) function background_curvature(s, before, after) result(c)
    real(wp), intent(in) :: s(:)
    integer, intent(in) :: before, after
    integer :: k
    c = 0
    k = 0
    if (before >= 1) then
      c = c + s(before); k = k + 1
    end if
    if (after <= size(s)) then
      c = c + s(after); k = k + 1
    end if
    if (k > 0) c = c / k
  end function background_curvature

  !> Median of a(lo..hi) (clipped to the array) without the entries skip_lo..skip_hi.
  pure real(wp) function window_median(a, lo, hi, skip_lo, skip_hi) result(med)
    real(wp), intent(in) :: a(:)
    integer, intent(in) :: lo, hi, skip_lo, skip_hi
    real(wp) :: v(hi - lo + 1), t
    integer :: i, j, k
    k = 0
    do i = max(lo, 1), min(hi, size(a))
      if (i >= skip_lo .and. i <= skip_hi) cycle
      ! insertion sort: windows are a few tens of values
      t = a(i)
      j = k
      do while (j >= 1)
        if (v(j) <= t) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = t
      k = k + 1
    end do
    if (k == 0) then
      med = 0
    else if (mod(k, 2) == 1) then
      med = v(k / 2 + 1)
    else
      med = 0.5_wp * (v(k / 2) + v(k / 2 + 1))
    end if
  end function window_median

end module rd_sweep_smoothness
