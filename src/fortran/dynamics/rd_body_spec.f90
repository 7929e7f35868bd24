!> What defines one rigid body of the multibody model (parameters, fixed after build).
!>
!> Coordinates q = (x, y, z, psi, phi, theta) relative to the body's track frame
!> (docs/conventions.md, thesis eq. 4.6 and 4.29); orientation B = Rz(psi) Rx(phi) Ry(theta).
module rd_body_spec
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  implicit none
  private
  public :: body_spec_t, validate_body_spec, spin_from_deviation, deviation_from_spin
  public :: DOF_X, DOF_Y, DOF_Z, DOF_YAW, DOF_ROLL, DOF_PITCH

  integer, parameter :: DOF_X = 1, DOF_Y = 2, DOF_Z = 3
  integer, parameter :: DOF_YAW = 4, DOF_ROLL = 5, DOF_PITCH = 6

  type :: body_spec_t
    character(len=:), allocatable :: name
    real(wp) :: mass = 0                 !< [kg]
    real(wp) :: inertia(3, 3) = 0        !< inertia tensor at the CG, body-frame components [kg m^2]
    !> Initial coordinates relative to the track frame [m, rad]. For a wheelset q0(6) is the
    !> initial spin deviation beta(0) (theta = s(t)/r0 + beta, s(0) = 0).
    real(wp) :: q0(6) = 0
    !> Initial rates relative to the track frame [m/s, rad/s]. For a wheelset qdot0(6) is the
    !> spin-rate deviation dbeta/dt(0) from nominal rolling V(0)/r0 (0 = rolling freely).
    real(wp) :: qdot0(6) = 0
    integer :: frame = 1                 !< index of the track frame the body is referred to
    logical :: frozen(6) = .false.       !< frozen coordinates keep q0 and leave the state
    !> Quasi-static coordinates leave the state too, but follow the body's load: each
    !> evaluation solves them for zero relative acceleration (their inertia neglected) and
    !> gives them zero relative rate. Only a wheelset's z and roll (quasi-static normal
    !> contact, docs/theory.md "Quasi-static normal contact").
    logical :: quasi_static(6) = .false.
    logical :: is_wheelset = .false.
    real(wp) :: r0 = 0                   !< nominal rolling radius of a wheelset [m]
  end type body_spec_t

contains

  !> Check one body's data; `nframes` is the number of track frames of the model.
  subroutine validate_body_spec(spec, nframes, error)
    type(body_spec_t), intent(in) :: spec
    integer, intent(in) :: nframes
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: who
    real(wp) :: i(3, 3), d1, d2, d3
    who = 'body'
    if (allocated(spec%name)) who = 'body "' // spec%name // '"'
    if (.not. (spec%mass > 0)) then
      call make_error(error, RD_ERR_INPUT, who // ': mass must be > 0 kg'); return
    end if
    i = spec%inertia
    if (any(.not. ieee_is_finite(i)) .or. maxval(abs(i - transpose(i))) > 1.0e-9_wp * maxval(abs(i))) then
      call make_error(error, RD_ERR_INPUT, who // ': inertia must be a finite symmetric 3x3 tensor'); return
    end if
    ! positive definite (Sylvester): leading principal minors > 0
    d1 = i(1, 1)
    d2 = i(1, 1) * i(2, 2) - i(1, 2) * i(2, 1)
    d3 = i(1, 1) * (i(2, 2) * i(3, 3) - i(2, 3) * i(3, 2)) - i(1, 2) * (i(2, 1) * i(3, 3) - i(2, 3) * i(3, 1)) &
         + i(1, 3) * (i(2, 1) * i(3, 2) - i(2, 2) * i(3, 1))
    if (.not. (d1 > 0 .and. d2 > 0 .and. d3 > 0)) then
      call make_error(error, RD_ERR_INPUT, who // ': inertia tensor must be positive definite [kg m^2]'); return
    end if
    if (spec%frame < 1 .or. spec%frame > nframes) then
      call make_error(error, RD_ERR_INPUT, who // ': track frame index out of range 1..number of frames'); return
    end if
    if (any(.not. ieee_is_finite(spec%q0)) .or. any(.not. ieee_is_finite(spec%qdot0))) then
      call make_error(error, RD_ERR_INPUT, who // ': NaN in initial coordinates or rates'); return
    end if
    if (abs(spec%q0(DOF_ROLL)) >= 1.5_wp) then
      call make_error(error, RD_ERR_INPUT, who // ': initial roll must be well inside +-pi/2 (Z-X-Y angles are singular at 90 deg)'); return
    end if
    if (any(spec%quasi_static .and. spec%frozen)) then
      call make_error(error, RD_ERR_INPUT, who // ': a coordinate cannot be both frozen and quasi-static'); return
    end if
    if (any(spec%quasi_static) .and. (.not. spec%is_wheelset .or. &
        any(spec%quasi_static([1, 2, 4, 6])))) then
      call make_error(error, RD_ERR_INPUT, who // ': only a wheelset''s z and roll can be quasi-static'); return
    end if
    if (spec%is_wheelset .and. .not. (spec%r0 > 0)) then
      call make_error(error, RD_ERR_INPUT, who // ': a wheelset needs a nominal rolling radius r0 > 0 m'); return
    end if
  end subroutine validate_body_spec

  !> A wheelset's spin from its stored deviation from nominal rolling (docs/conventions.md):
  !> theta = s / r0 + beta, with `rolled` the distance s; for the rates and accelerations
  !> `rolled` is the speed V or dV/dt.
  elemental real(wp) function spin_from_deviation(beta, rolled, r0) result(theta)
    real(wp), intent(in) :: beta, rolled, r0
    theta = rolled / r0 + beta
  end function spin_from_deviation

  !> The inverse of spin_from_deviation: beta = theta - s / r0 (and its rates).
  elemental real(wp) function deviation_from_spin(theta, rolled, r0) result(beta)
    real(wp), intent(in) :: theta, rolled, r0
    beta = theta - rolled / r0
  end function deviation_from_spin
end module rd_body_spec
