!> The vehicle's speed along the track as a function of time, V(t) = d sigma / dt.
!>
!> A piecewise-linear table of (t_i, V_i) (one point = constant speed), held constant
!> before the first and after the last point. The distance travelled s(t) = int_0^t V dt
!> is integrated exactly (trapezoids of a piecewise-linear V), so no extra ODE state is
!> needed and the track frames' positions sigma_k(t) = sigma_0 + offset_k + s(t) carry no
!> integration error. `override` replaces the law from a given time on (the C API sets the
!> speed as an input), optionally through a linear ramp.
module rd_speed_law
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_cubic_spline, only: locate_interval
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: speed_law_t, constant_speed, table_speed

  type :: speed_law_t
    real(wp), allocatable :: t(:)      !< breakpoints [s], strictly increasing
    real(wp), allocatable :: v(:)      !< speed at the breakpoints [m/s]
    real(wp), allocatable :: s(:)      !< distance travelled at the breakpoints [m], s(t=0) = 0
  contains
    procedure :: speed => speed_at
    procedure :: acceleration => acceleration_at
    procedure :: distance => distance_at
    procedure :: override
  end type speed_law_t

contains

  !> Constant speed v [m/s].
  function constant_speed(v) result(law)
    real(wp), intent(in) :: v
    type(speed_law_t) :: law
    law%t = [0.0_wp]
    law%v = [v]
    law%s = [0.0_wp]
  end function constant_speed

  !> Piecewise-linear speed through the points (t(i), v(i)); t strictly increasing.
  subroutine table_speed(law, t, v, error)
    type(speed_law_t), intent(out) :: law
    real(wp), intent(in) :: t(:), v(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i
    if (size(t) < 1 .or. size(t) /= size(v)) then
      call make_error(error, RD_ERR_INPUT, 'speed table: expected equal, non-empty lists of times and speeds')
      return
    end if
    do i = 2, size(t)
      if (.not. t(i) > t(i - 1)) then
        call make_error(error, RD_ERR_INPUT, 'speed table: times must be strictly increasing')
        return
      end if
    end do
    if (any(.not. ieee_is_finite(v)) .or. any(.not. ieee_is_finite(t))) then
      call make_error(error, RD_ERR_INPUT, 'speed table: times and speeds must be finite')
      return
    end if
    law%t = t
    law%v = v
    allocate (law%s(size(t)))
    call rebuild_distances(law)
  end subroutine table_speed

  !> s at the breakpoints, s(0) = 0 (exact integral of the piecewise-linear V).
  pure subroutine rebuild_distances(law)
    type(speed_law_t), intent(inout) :: law
    integer :: i, n
    real(wp) :: s0
    n = size(law%t)
    law%s(1) = 0
    do i = 2, n
      law%s(i) = law%s(i - 1) + 0.5_wp * (law%v(i) + law%v(i - 1)) * (law%t(i) - law%t(i - 1))
    end do
    ! shift so that s(t = 0) = 0
    s0 = distance_raw(law, 0.0_wp)
    law%s = law%s - s0
  end subroutine rebuild_distances

  !> Largest index i with t(i) <= t (the segment [t(i), t(i+1)) holding t); 0 before the
  !> table, n after its end. Zero-width segments (a step) are never returned for t inside.
  pure integer function segment(law, t) result(i)
    type(speed_law_t), intent(in) :: law
    real(wp), intent(in) :: t
    if (t < law%t(1)) then
      i = 0
    else if (t >= law%t(size(law%t))) then
      i = size(law%t)
    else
      i = locate_interval(law%t, t)
    end if
  end function segment

  pure real(wp) function speed_at(self, t) result(v)
    class(speed_law_t), intent(in) :: self
    real(wp), intent(in) :: t
    integer :: i
    i = segment(self, t)
    if (i == 0) then
      v = self%v(1)
    else if (i == size(self%t)) then
      v = self%v(i)
    else
      v = self%v(i) + (self%v(i + 1) - self%v(i)) * (t - self%t(i)) / (self%t(i + 1) - self%t(i))
    end if
  end function speed_at

  !> dV/dt (zero outside the table; the right derivative at a breakpoint).
  pure real(wp) function acceleration_at(self, t) result(a)
    class(speed_law_t), intent(in) :: self
    real(wp), intent(in) :: t
    integer :: i
    i = segment(self, t)
    if (i == 0 .or. i == size(self%t)) then
      a = 0
    else
      a = (self%v(i + 1) - self%v(i)) / (self%t(i + 1) - self%t(i))
    end if
  end function acceleration_at

  pure real(wp) function distance_at(self, t) result(s)
    class(speed_law_t), intent(in) :: self
    real(wp), intent(in) :: t
    s = distance_raw(self, t)
  end function distance_at

  pure real(wp) function distance_raw(law, t) result(s)
    type(speed_law_t), intent(in) :: law
    real(wp), intent(in) :: t
    integer :: i
    real(wp) :: tau, a
    i = segment(law, t)
    if (i == 0) then
      s = law%s(1) - law%v(1) * (law%t(1) - t)
    else if (i == size(law%t)) then
      s = law%s(i) + law%v(i) * (t - law%t(i))
    else
      tau = t - law%t(i)
      a = (law%v(i + 1) - law%v(i)) / (law%t(i + 1) - law%t(i))
      s = law%s(i) + law%v(i) * tau + 0.5_wp * a * tau**2
    end if
  end function distance_raw

  !> From time t0 on, the speed goes linearly from V(t0) to v_new in `ramp_time` seconds
  !> (0 or absent: a step) and then stays constant. The law before t0 is kept, so s(t)
  !> stays continuous and the past is unchanged. A step is stored as two breakpoints at
  !> the same time (the only place the table may repeat a time).
  subroutine override(self, t0, v_new, ramp_time, error)
    class(speed_law_t), intent(inout) :: self
    real(wp), intent(in) :: t0, v_new
    real(wp), intent(in), optional :: ramp_time
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: ramp, v0
    real(wp), allocatable :: t(:), v(:)
    integer :: n
    ramp = 0
    if (present(ramp_time)) ramp = ramp_time
    if (.not. (ramp >= 0) .or. (.not. ieee_is_finite(v_new)) .or. (.not. ieee_is_finite(t0))) then
      call make_error(error, RD_ERR_INPUT, 'speed override: expected a finite speed and ramp_time >= 0')
      return
    end if
    v0 = self%speed(t0)
    n = count(self%t < t0)
    t = [self%t(1:n), t0, t0 + ramp]
    v = [self%v(1:n), v0, v_new]
    call move_alloc(t, self%t)
    call move_alloc(v, self%v)
    deallocate (self%s)
    allocate (self%s(size(self%t)))
    call rebuild_distances(self)
  end subroutine override
end module rd_speed_law
