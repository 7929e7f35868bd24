!> The few key running-safety maxima of a run, for the completion line of `raildyn run`:
!> the largest Y/Q of any wheel and the largest |sum Y| of any wheelset against its
!> Prud'homme limit, both as 2 m sliding means along the track (EN 14363), and the largest
!> vertical wheel force Q. `raildyn assess` (python/raildyn/assess, docs/assessment.md)
!> computes the full set from the results file with the same windows, positions and static
!> load; it low-pass filters the forces at 20 Hz first (when the output rate resolves more
!> than 20 Hz), which this summary does not: it takes the records as written.
!>
!> Definitions (docs/output.md "Completion line"):
!> - track position of a wheelset: its track frame's sigma plus the body's x in that frame;
!> - sliding mean: the integral of the linear interpolant of the series over the window
!>   [s_i - 1 m, s_i + 1 m] centred on a record, divided by 2 m, for every record whose
!>   window lies within the positions the run covered;
!> - sum Y = Y_left + Y_right; Prud'homme limit 10 kN + 2 Q0 / 3 with Q0 the static wheel
!>   force, taken as the median over the records of (Q_left + Q_right) / 2 (2 Q0 the static
!>   axle load; in a curve the wheels share it unequally, their mean stays the static load).
!> Limits as the vehicle-dynamics literature quotes EN 14363 (secondary source, the text of
!> the standard was not at hand): (Y/Q)_lim = 0.8, Prud'homme alpha = 1.
module rd_safety_maxima
  use rd_kinds, only: wp
  use rd_text, only: fixed_text, int_text
  use rd_output_set, only: output_set_t
  implicit none
  private
  public :: safety_maxima_t, centred_sliding_mean, median, SLIDING_LENGTH, YQ_LIMIT

  real(wp), parameter :: SLIDING_LENGTH = 2.0_wp   !< m (EN 14363, Y/Q and sum Y)
  real(wp), parameter :: YQ_LIMIT = 0.8_wp         !< secondary source (module header)
  real(wp), parameter :: PRUDHOMME_BASE = 10.0e3_wp   !< N

  !> Columns of one wheelset in the packed output record, and its records so far.
  type :: wheelset_columns_t
    character(len=:), allocatable :: name
    integer :: sigma = 0, x = 0          !< frame sigma, body x (0: body not free -> x column kept)
    integer :: y(2) = 0, q(2) = 0, yq(2) = 0
  end type wheelset_columns_t

  type :: safety_maxima_t
    type(wheelset_columns_t), allocatable :: wheelsets(:)
    !> records: (quantity, wheelset, row) with quantity 1 position, 2-3 Y/Q left/right,
    !> 4 sum Y, 5-6 Q left/right
    real(wp), allocatable :: rows(:, :, :)
    integer :: n = 0
  contains
    procedure :: add_wheelset
    procedure :: add_record
    procedure :: summary
  end type safety_maxima_t

  integer, parameter :: NQ = 6

contains

  !> Follow the wheelset `name` whose body is `body` in track frame `frame` (channel names
  !> of docs/output.md).
  subroutine add_wheelset(self, outputs, name, body, frame)
    class(safety_maxima_t), intent(inout) :: self
    type(output_set_t), intent(in) :: outputs
    character(len=*), intent(in) :: name, body
    integer, intent(in) :: frame
    type(wheelset_columns_t) :: w
    character(len=5), parameter :: sides(2) = ['left ', 'right']
    integer :: side
    if (.not. allocated(self%wheelsets)) allocate (self%wheelsets(0))
    w%name = name
    w%sigma = outputs%packed_index('track/frames/' // trim(int_text(frame)) // '/sigma', 'sigma')
    w%x = outputs%packed_index('bodies/' // body // '/position_track', 'x')
    do side = 1, 2
      associate (p => 'wheelsets/' // name // '/' // trim(sides(side)) // '/wheel')
        w%y(side) = outputs%packed_index(p, 'force_lateral_Y')
        w%q(side) = outputs%packed_index(p, 'force_vertical_Q')
        w%yq(side) = outputs%packed_index(p, 'Y_over_Q')
      end associate
    end do
    ! every column exists for a scene with this wheelset (register_outputs); a missing one
    ! would be a renamed channel: the maxima then leave the wheelset out rather than read
    ! another channel's column
    if (any([w%sigma, w%x, w%y, w%q, w%yq] == 0)) return
    self%wheelsets = [self%wheelsets, w]
  end subroutine add_wheelset

  !> Keep one output record (the packed values of every channel).
  subroutine add_record(self, values)
    class(safety_maxima_t), intent(inout) :: self
    real(wp), intent(in) :: values(:)
    real(wp), allocatable :: grown(:, :, :)
    integer :: w
    if (.not. allocated(self%wheelsets)) return
    if (size(self%wheelsets) == 0) return
    if (.not. allocated(self%rows)) allocate (self%rows(NQ, size(self%wheelsets), 256))
    if (self%n == size(self%rows, 3)) then
      allocate (grown(NQ, size(self%wheelsets), 2 * self%n))
      grown(:, :, 1:self%n) = self%rows
      call move_alloc(grown, self%rows)
    end if
    self%n = self%n + 1
    do w = 1, size(self%wheelsets)
      associate (c => self%wheelsets(w), r => self%rows(:, w, self%n))
        r(1) = values(c%sigma) + values(c%x)
        r(2:3) = values(c%yq)
        r(4) = values(c%y(1)) + values(c%y(2))
        r(5:6) = values(c%q)
      end associate
    end do
  end subroutine add_record

  !> The completion-line text: '' for a scene without wheelsets.
  function summary(self) result(text)
    class(safety_maxima_t), intent(in) :: self
    character(len=:), allocatable :: text
    real(wp), allocatable :: mean(:)
    logical, allocatable :: inside(:)
    real(wp) :: best_yq, at_yq, best_ratio, best_sum, at_sum, limit_sum, best_q, at_q, q0, covered
    integer :: w, side, i, wyq, syq, wsum, wq, sq
    text = ''
    if (self%n == 0) return
    best_yq = -huge(1.0_wp); best_ratio = -1; best_q = -huge(1.0_wp)
    wyq = 0; syq = 0; wsum = 0; wq = 0; sq = 0
    at_yq = 0; at_sum = 0; at_q = 0; best_sum = 0; limit_sum = 0
    covered = huge(1.0_wp)
    allocate (mean(self%n), inside(self%n))
    do w = 1, size(self%wheelsets)
      associate (s => self%rows(1, w, 1:self%n))
        covered = min(covered, maxval(s) - minval(s))
        do side = 1, 2
          call centred_sliding_mean(s, self%rows(1 + side, w, 1:self%n), SLIDING_LENGTH, mean, inside)
          do i = 1, self%n
            if (inside(i) .and. mean(i) > best_yq) then
              best_yq = mean(i); at_yq = s(i); wyq = w; syq = side
            end if
          end do
          do i = 1, self%n
            if (self%rows(4 + side, w, i) > best_q) then
              best_q = self%rows(4 + side, w, i); at_q = s(i); wq = w; sq = side
            end if
          end do
        end do
        q0 = median(0.5_wp * (self%rows(5, w, 1:self%n) + self%rows(6, w, 1:self%n)))
        call centred_sliding_mean(s, self%rows(4, w, 1:self%n), SLIDING_LENGTH, mean, inside)
        do i = 1, self%n
          if (inside(i) .and. abs(mean(i)) / prudhomme_limit(q0) > best_ratio) then
            best_ratio = abs(mean(i)) / prudhomme_limit(q0); best_sum = abs(mean(i)); at_sum = s(i)
            limit_sum = prudhomme_limit(q0); wsum = w
          end if
        end do
      end associate
    end do
    text = 'running safety (EN 14363, unfiltered records, 2 m sliding means along the track; ' // &
           'raildyn assess: the full set): '
    if (wyq > 0) then
      text = text // 'max Y/Q ' // trim(fixed_text(best_yq, 3)) // ' (' // self%wheelsets(wyq)%name // ' ' // &
             side_name(syq) // ' at ' // trim(fixed_text(at_yq, 1)) // ' m; limit ' // trim(fixed_text(YQ_LIMIT, 1)) // &
             '); max |sum Y| ' // trim(fixed_text(1.0e-3_wp * best_sum, 1)) // ' kN (' // &
             self%wheelsets(wsum)%name // ' at ' // trim(fixed_text(at_sum, 1)) // ' m) = ' // &
             trim(fixed_text(100 * best_ratio, 0)) // ' % of its Prud''homme limit ' // &
             trim(fixed_text(1.0e-3_wp * limit_sum, 1)) // ' kN; '
    else
      text = text // 'no 2 m window: the wheelsets covered ' // trim(fixed_text(covered, 2)) // ' m of track; '
    end if
    text = text // 'max Q ' // trim(fixed_text(1.0e-3_wp * best_q, 1)) // ' kN (' // self%wheelsets(wq)%name // &
           ' ' // side_name(sq) // ' at ' // trim(fixed_text(at_q, 1)) // ' m)'
  contains
    pure function side_name(side) result(name)
      integer, intent(in) :: side
      character(len=:), allocatable :: name
      name = trim(merge('left ', 'right', side == 1))
    end function side_name
  end function summary

  !> Prud'homme limit alpha (10 kN + 2 Q0 / 3), alpha = 1, Q0 the static wheel force [N].
  pure real(wp) function prudhomme_limit(q0)
    real(wp), intent(in) :: q0
    prudhomme_limit = PRUDHOMME_BASE + 2 * q0 / 3
  end function prudhomme_limit

  !> Mean of y over the window [s_i - length/2, s_i + length/2] centred on every sample i,
  !> y taken linear between samples (positions s non-decreasing); inside(i) tells whether
  !> the window lies within [s(1), s(n)] (else mean(i) = 0).
  pure subroutine centred_sliding_mean(s, y, length, mean, inside)
    real(wp), intent(in) :: s(:), y(:), length
    real(wp), intent(out) :: mean(:)
    logical, intent(out) :: inside(:)
    real(wp), allocatable :: integral(:)
    real(wp) :: upper, lower
    integer :: i, n, lo, hi
    n = size(s)
    mean = 0
    inside = .false.
    if (n < 2) return
    allocate (integral(n))
    integral(1) = 0
    do i = 2, n
      integral(i) = integral(i - 1) + 0.5_wp * (y(i) + y(i - 1)) * (s(i) - s(i - 1))
    end do
    lo = 1; hi = 1
    do i = 1, n
      if (s(i) - length / 2 < s(1) .or. s(i) + length / 2 > s(n)) cycle
      inside(i) = .true.
      call integral_at(s(i) + length / 2, hi, upper)
      call integral_at(s(i) - length / 2, lo, lower)
      mean(i) = (upper - lower) / length
    end do
  contains
    !> Integral of the interpolant from s(1) to a; k: the last sample with s(k) <= a (kept
    !> between calls: the window ends move forward), at most n - 1.
    pure subroutine integral_at(a, k, integral_a)
      real(wp), intent(in) :: a
      integer, intent(inout) :: k
      real(wp), intent(out) :: integral_a
      real(wp) :: dx, h, slope
      do while (k < n - 1)
        if (s(k + 1) > a) exit
        k = k + 1
      end do
      dx = s(k + 1) - s(k)
      h = a - s(k)
      slope = 0
      if (dx > 0) slope = (y(k + 1) - y(k)) / dx
      integral_a = integral(k) + y(k) * h + 0.5_wp * slope * h**2
    end subroutine integral_at
  end subroutine centred_sliding_mean

  !> Median (mean of the two middle values for an even count), as numpy's median.
  pure real(wp) function median(x)
    real(wp), intent(in) :: x(:)
    real(wp), allocatable :: v(:)
    integer :: n
    v = x
    n = size(v)
    if (mod(n, 2) == 1) then
      call select_kth(v, (n + 1) / 2, median)
    else
      ! after selecting the (n/2+1)-th, the n/2 smaller values lie before it
      call select_kth(v, n / 2 + 1, median)
      median = 0.5_wp * (median + maxval(v(1:n / 2)))
    end if
  end function median

  !> The k-th smallest entry of v (Hoare's selection, expected O(n): the runs' records are
  !> many); v is reordered so that v(1:k-1) <= v(k) <= v(k+1:).
  pure subroutine select_kth(v, k, value)
    real(wp), intent(inout) :: v(:)
    integer, intent(in) :: k
    real(wp), intent(out) :: value
    integer :: lo, hi, i, j
    real(wp) :: pivot, t
    lo = 1; hi = size(v)
    do while (lo < hi)
      pivot = v((lo + hi) / 2)
      i = lo; j = hi
      do while (i <= j)
        do while (v(i) < pivot)
          i = i + 1
        end do
        do while (v(j) > pivot)
          j = j - 1
        end do
        if (i <= j) then
          t = v(i); v(i) = v(j); v(j) = t
          i = i + 1; j = j - 1
        end if
      end do
      if (k <= j) then
        hi = j
      else if (k >= i) then
        lo = i
      else
        exit
      end if
    end do
    value = v(k)
  end subroutine select_kth
end module rd_safety_maxima
