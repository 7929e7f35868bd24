!> Track irregularities: the measured (or synthetic) deviations of the rails from the
!> design track, as per-rail offsets in the track frame (docs/conventions.md, "Track
!> irregularities"; docs/theory_track.md).
!>
!> Input: a table over the arc length sigma of the four classical components
!>   alignment (+ = centre line moved to +Y_T, left), level (+ = up),
!>   cross_level (+ = left rail higher), gauge (+ = widened),
!> from which each rail's offset follows (EN 13848-1 definitions, linearised):
!>   left  rail  dy_L = alignment + gauge/2,  dz_L = level + cross_level/2
!>   right rail  dy_R = alignment - gauge/2,  dz_R = level - cross_level/2.
!> Cross-level is the height difference of the rails. The rails are translated, not rotated:
!> the rail-head rotation cross_level / cant_base (1.3e-3 rad for 2 mm) is neglected.
!>
!> Evaluation: linear interpolation between the points (a measured record is a sampled
!> signal; linear interpolation adds no overshoot between samples and keeps the offsets
!> continuous in sigma), times `scale`, zero outside [sigma_1, sigma_n]. With fade > 0 the
!> offsets are multiplied by a linear ramp from 0 at sigma_1 to 1 at sigma_1 + fade, and
!> back to 0 at sigma_n, so a run entering or leaving the record sees no step.
!>
!> Parameters are fixed by the build routine; `rail_offsets` is pure and allocates nothing
!> (it runs once per wheelset per right-hand side).
module rd_track_irregularity
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_text, only: int_text, real_text
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_cubic_spline, only: locate_interval
  use rd_numeric_table, only: read_numeric_table
  implicit none
  private
  public :: track_irregularity_t, build_track_irregularity, read_irregularity_file
  public :: IRREGULARITY_MAX_OFFSET, IRR_ALIGNMENT, IRR_LEVEL, IRR_CROSS_LEVEL, IRR_GAUGE

  !> Largest |offset| accepted in a file [m]: a track with 0.1 m irregularities is not a
  !> track, so a larger number means the file is in millimetres.
  real(wp), parameter :: IRREGULARITY_MAX_OFFSET = 0.1_wp
  !> Rows of `values(4, n)`: the file's columns 2 to 5.
  integer, parameter :: IRR_ALIGNMENT = 1, IRR_LEVEL = 2, IRR_CROSS_LEVEL = 3, IRR_GAUGE = 4

  type :: track_irregularity_t
    private
    real(wp), allocatable :: sigma(:)      !< strictly increasing arc lengths [m]
    real(wp), allocatable :: values(:, :)  !< (4, n): alignment, level, cross-level, gauge [m]
    real(wp) :: scale = 1                  !< factor on every offset [-]
    real(wp) :: fade = 0                   !< fade-in / fade-out length [m]
  contains
    procedure :: components => irregularity_components
    procedure :: rail_offsets => irregularity_rail_offsets
  end type track_irregularity_t

contains

  !> Build from arrays: sigma (strictly increasing, >= 2 points) and values(4, n) =
  !> alignment, level, cross-level, gauge [m]. scale >= 0 (default 1), fade >= 0 m
  !> (default 0). `origin` prefixes the messages (the file, the deck line).
  subroutine build_track_irregularity(irr, sigma, values, error, scale, fade, origin)
    type(track_irregularity_t), intent(out) :: irr
    real(wp), intent(in) :: sigma(:), values(:, :)
    type(error_t), allocatable, intent(out) :: error
    real(wp), intent(in), optional :: scale, fade
    character(len=*), intent(in), optional :: origin
    character(len=:), allocatable :: where
    integer :: n, i
    where = 'track irregularity'
    if (present(origin)) where = origin
    n = size(sigma)
    if (size(values, 1) /= 4 .or. size(values, 2) /= n) then
      call make_error(error, RD_ERR_INPUT, where // ': expected values(4, n) (alignment level cross_level gauge) ' // &
                      'for n = size(sigma) points')
      return
    end if
    if (n < 2) then
      call make_error(error, RD_ERR_INPUT, where // ': ' // trim(int_text(n)) // ' points given, at least 2 are needed')
      return
    end if
    if (.not. (all(ieee_is_finite(sigma)) .and. all(ieee_is_finite(values)))) then
      call make_error(error, RD_ERR_INPUT, where // ': sigma and the offsets must be finite numbers')
      return
    end if
    do i = 2, n
      if (.not. (sigma(i) > sigma(i - 1))) then
        call make_error(error, RD_ERR_INPUT, where // ': point ' // trim(int_text(i)) // ': sigma ' // &
                        trim(real_text(sigma(i))) // ' m does not increase; sigma must be strictly increasing')
        return
      end if
    end do
    do i = 1, n
      if (any(abs(values(:, i)) > IRREGULARITY_MAX_OFFSET)) then
        call make_error(error, RD_ERR_INPUT, where // ': point ' // trim(int_text(i)) // ': ' // offset_message())
        return
      end if
    end do
    irr%scale = 1
    if (present(scale)) irr%scale = scale
    irr%fade = 0
    if (present(fade)) irr%fade = fade
    ! finiteness first: an ordered comparison with NaN traps in Debug builds
    if (.not. non_negative(irr%scale)) then
      call make_error(error, RD_ERR_INPUT, where // ': irregularity scale must be a finite number >= 0')
      return
    end if
    if (.not. non_negative(irr%fade)) then
      call make_error(error, RD_ERR_INPUT, where // ': irregularity fade length must be a finite number >= 0 m')
      return
    end if
    irr%sigma = sigma
    irr%values = values
  end subroutine build_track_irregularity

  !> Read a text file: '#' starts a comment, blank lines are skipped, separators are
  !> blanks, tabs or commas; each data line holds exactly 5 numbers
  !>   sigma_m alignment_m level_m cross_level_m gauge_m
  !> with sigma strictly increasing and every offset within IRREGULARITY_MAX_OFFSET.
  !> Errors name path:line and what is expected.
  subroutine read_irregularity_file(path, sigma, values, error)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: sigma(:), values(:, :)
    type(error_t), allocatable, intent(out) :: error
    integer, parameter :: ncol = 5
    character(len=*), parameter :: columns = '(sigma alignment level cross_level gauge, metres)'
    real(wp), allocatable :: table(:, :)
    integer, allocatable :: line_of(:)
    integer :: i

    call read_numeric_table(path, ncol, 'irregularity file', columns, 'sigma', 2, table, line_of, error)
    if (allocated(error)) return
    do i = 1, size(line_of)
      if (any(abs(table(2:, i)) > IRREGULARITY_MAX_OFFSET)) then
        call make_error(error, RD_ERR_INPUT, path // ':' // trim(int_text(line_of(i))) // ': ' // offset_message())
        return
      end if
    end do
    sigma = table(1, :)
    values = table(2:ncol, :)
  end subroutine read_irregularity_file

  elemental logical function non_negative(x)
    real(wp), intent(in) :: x
    non_negative = .false.
    if (ieee_is_finite(x)) non_negative = x >= 0
  end function non_negative

  pure function offset_message() result(s)
    character(len=:), allocatable :: s
    s = 'an offset exceeds ' // trim(real_text(IRREGULARITY_MAX_OFFSET)) // &
        ' m; irregularities are given in metres (millimetres given?)'
  end function offset_message

  !> alignment, level, cross-level, gauge [m] at arc length sigma: interpolated, scaled,
  !> faded; zero outside the record.
  pure function irregularity_components(self, sigma) result(c)
    class(track_irregularity_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    real(wp) :: c(4)
    real(wp) :: w, s1, sn
    integer :: i
    c = 0
    if (.not. allocated(self%sigma)) return
    ! the contact provider rejects a non-finite track position before it gets here; the
    ! guard keeps an ordered comparison with NaN from trapping in Debug builds
    if (.not. ieee_is_finite(sigma)) return
    s1 = self%sigma(1)
    sn = self%sigma(size(self%sigma))
    if (.not. (sigma >= s1 .and. sigma <= sn)) return
    i = locate_interval(self%sigma, sigma)
    w = (sigma - self%sigma(i)) / (self%sigma(i + 1) - self%sigma(i))
    c = (1 - w) * self%values(:, i) + w * self%values(:, i + 1)
    w = self%scale
    if (self%fade > 0) w = w * min(1.0_wp, (sigma - s1) / self%fade, (sn - sigma) / self%fade)
    c = w * c
  end function irregularity_components

  !> Offsets of each rail at arc length sigma, track frame [m]: offset(:, side) = (dy, dz),
  !> side 1 left, 2 right (docs/conventions.md).
  pure function irregularity_rail_offsets(self, sigma) result(offset)
    class(track_irregularity_t), intent(in) :: self
    real(wp), intent(in) :: sigma
    real(wp) :: offset(2, 2)
    real(wp) :: c(4)
    c = self%components(sigma)
    offset(1, 1) = c(IRR_ALIGNMENT) + 0.5_wp * c(IRR_GAUGE)
    offset(2, 1) = c(IRR_LEVEL) + 0.5_wp * c(IRR_CROSS_LEVEL)
    offset(1, 2) = c(IRR_ALIGNMENT) - 0.5_wp * c(IRR_GAUGE)
    offset(2, 2) = c(IRR_LEVEL) - 0.5_wp * c(IRR_CROSS_LEVEL)
  end function irregularity_rail_offsets

end module rd_track_irregularity
