!> Interval means of the output channels (`&output mean_samples = N`): each record after the
!> first is the mean of every channel over the preceding output interval, by the trapezoid
!> rule on N equal sub-intervals,
!>    mean_k = (1/N) sum_{j=1..N} (s_{j-1} + s_j) / 2,
!> s_0 the last sub-sample of the previous interval (the record time), s_N the one at the
!> record time. Why: a record of the state at its time aliases motions faster than half the
!> output rate into slow spurious ones (a wheelset bouncing at 100-200 Hz sampled at 50 Hz
!> shifts window means of its wheel loads by several kN); the mean is a box-car low-pass of
!> the history that keeps the file small. N sub-samples per record resolve frequencies up to
!> N / (2 interval).
!>
!> The channels are handled as one flat vector (rd_output_set pack order); channels such as
!> patch slots or angles are averaged as numbers (docs/output.md says which means mean little).
module rd_output_average
  use rd_kinds, only: wp
  implicit none
  private
  public :: output_average_t

  type :: output_average_t
    integer :: samples = 0            !< N sub-intervals per record, 0: records are samples (set before start)
    integer :: taken = 0              !< sub-samples added since the last record
    real(wp), allocatable :: previous(:)   !< last sub-sample
    real(wp), allocatable :: total(:)      !< trapezoid sum of this interval so far
  contains
    procedure :: start => average_start
    procedure :: add => average_add
    procedure :: complete => average_complete
    procedure :: take_mean => average_take_mean
    procedure :: next_fraction => average_next_fraction
  end type output_average_t

contains

  !> Begin with the sample at the first record (self%samples > 0 sub-intervals per record).
  subroutine average_start(self, first)
    class(output_average_t), intent(inout) :: self
    real(wp), intent(in) :: first(:)
    self%taken = 0
    self%previous = first
    allocate (self%total(size(first)))
    self%total = 0
  end subroutine average_start

  !> Add the next sub-sample (at the next sub-interval end).
  subroutine average_add(self, sample)
    class(output_average_t), intent(inout) :: self
    real(wp), intent(in) :: sample(:)
    self%total = self%total + 0.5_wp * (self%previous + sample)
    self%previous = sample
    self%taken = self%taken + 1
  end subroutine average_add

  !> All N sub-samples of the interval are in.
  pure logical function average_complete(self)
    class(output_average_t), intent(in) :: self
    average_complete = self%samples > 0 .and. self%taken == self%samples
  end function average_complete

  !> The interval's mean; starts the next interval.
  function average_take_mean(self) result(mean)
    class(output_average_t), intent(inout) :: self
    real(wp), allocatable :: mean(:)
    mean = self%total / self%samples
    self%total = 0
    self%taken = 0
  end function average_take_mean

  !> Position of the next sub-sample within the interval, in (0, 1].
  pure real(wp) function average_next_fraction(self) result(f)
    class(output_average_t), intent(in) :: self
    f = real(self%taken + 1, wp) / self%samples
  end function average_next_fraction

end module rd_output_average
