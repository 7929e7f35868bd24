!> How far bodies with a free longitudinal coordinate left their track frames in a run.
!>
!> The track frames move along the track by the imposed speed law; a body whose x is free
!> is carried along only by its forces. Nothing drives a vehicle whose bodies all have x
!> free: the creep forces' rolling resistance holds it back and it falls behind its frames
!> (the two-axle wagon of docs/first_vehicle.md: 0.086 m in 6 s), and its yaw and lateral
!> coordinates then refer to frames at the wrong place in curves. A body that left its frame
!> by more than DRIFT_LIMIT gets a run note. The limit is far above the longitudinal
!> suspension deflections of a vehicle pulled by a driven body (millimetres: the wheelsets of
!> the same wagon with its car body's x frozen stay within 0.2 mm).
module rd_frame_drift
  use rd_kinds, only: wp
  use rd_text, only: real_text, fixed_text
  use rd_multibody, only: multibody_t
  implicit none
  private
  public :: frame_drift_t, DRIFT_LIMIT

  real(wp), parameter :: DRIFT_LIMIT = 0.05_wp   !< [m]

  type :: frame_drift_t
    integer, allocatable :: slot(:)      !< slot of each body's x in the state (0: frozen)
    real(wp), allocatable :: least(:)    !< smallest x sampled [m] (< 0: behind its frame)
    real(wp), allocatable :: most(:)     !< largest x sampled [m]
  contains
    procedure :: start
    procedure :: note
    procedure :: notes
  end type frame_drift_t

contains

  !> From the state y at the start of the run.
  subroutine start(self, mbs, y)
    class(frame_drift_t), intent(inout) :: self
    type(multibody_t), intent(in) :: mbs
    real(wp), intent(in) :: y(:)
    integer :: i
    self%slot = [(mbs%free_slot(i, 1), i = 1, mbs%body_count())]
    allocate (self%least(size(self%slot)), self%most(size(self%slot)))
    self%least = 0
    self%most = 0
    call self%note(y)
  end subroutine start

  !> Count a sampled state.
  subroutine note(self, y)
    class(frame_drift_t), intent(inout) :: self
    real(wp), intent(in) :: y(:)
    integer :: i
    if (.not. allocated(self%slot)) return
    do i = 1, size(self%slot)
      if (self%slot(i) == 0) cycle
      self%least(i) = min(self%least(i), y(self%slot(i)))
      self%most(i) = max(self%most(i), y(self%slot(i)))
    end do
  end subroutine note

  !> `lead` + one note per body that left its frame by more than DRIFT_LIMIT ('' if none).
  function notes(self, mbs, lead) result(text)
    class(frame_drift_t), intent(in) :: self
    type(multibody_t), intent(in) :: mbs
    character(len=*), intent(in) :: lead
    character(len=:), allocatable :: text
    integer :: i
    real(wp) :: distance
    text = ''
    if (.not. allocated(self%slot)) return
    do i = 1, size(self%slot)
      if (self%slot(i) == 0) cycle
      distance = max(-self%least(i), self%most(i))
      if (distance <= DRIFT_LIMIT) cycle
      text = text // lead // 'body ' // mbs%bodies(i)%name // ' moved ' // trim(fixed_text(distance, 3)) // ' m ' // &
             trim(merge('behind ', 'ahead  ', -self%least(i) >= self%most(i))) // ' its track frame (x free; ' // &
             'more than ' // trim(real_text(DRIFT_LIMIT)) // ' m): nothing drives it at the imposed ' // &
             'speed; freeze its x or connect it to a body whose x is frozen (docs/first_vehicle.md)'
    end do
  end function notes
end module rd_frame_drift
