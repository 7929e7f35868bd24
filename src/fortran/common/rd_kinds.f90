!> Working precision and the few physical constants every module shares.
module rd_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private
  public :: wp, i4, i8, pi, standard_gravity

  integer, parameter :: wp = real64   !< all physics in double precision
  integer, parameter :: i4 = int32
  integer, parameter :: i8 = int64
  real(wp), parameter :: pi = 3.141592653589793238462643383279502884_wp
  !> Standard gravity [m/s^2] (CGPM 1901); decks may override it per scene.
  real(wp), parameter :: standard_gravity = 9.80665_wp
end module rd_kinds
