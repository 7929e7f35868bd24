!> The wheelset contact reuses the geometry of the last pose when the next evaluation has
!> bitwise the same pose (y, z, roll, yaw): the finite-difference Jacobian perturbs one state
!> per call. Oracle: a freshly initialised provider (no history) evaluated at each state of a
!> sequence that alternates poses, repeats a pose with other velocities (creepages must
!> follow) and other longitudinal position / spin angle (not part of the geometry); forces
!> and moments must agree bitwise.
program test_wheelset_geometry_cache
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_contact_geometry, only: contact_geometry_t
  use rd_rigid_contact, only: rigid_contact
  use wheelset_test_support, only: circle_track_t, pose_kinematics
  use rd_test_support, only: fail, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 4.4_wp
  type(wheelset_contact_spec_t) :: spec
  type(wheelset_contact_t) :: ws
  type(contact_geometry_t) :: geo
  type(circle_track_t) :: track
  type(error_t), allocatable :: error
  real(wp) :: z, phi, q(6, 6), qd(6, 6)
  integer :: k

  spec%body = 1
  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  spec%contact_damping = 1.0e5_wp
  call build_contact_geometry(spec, geo, error)
  if (allocated(error)) error stop error%message
  ! flange-root two-patch contact: 5.2 mm shift, 8.5 mrad yaw, 30 um below rigid contact
  call rigid_contact(geo, 5.2e-3_wp, 8.5e-3_wp, z, phi, error)
  if (allocated(error)) error stop error%message
  track%kappa = 1.0_wp / 150
  q(:, 1) = [0.0_wp, 5.2e-3_wp, z - 3.0e-5_wp, 8.5e-3_wp, phi, 0.0_wp]
  qd(:, 1) = [0.0_wp, 0.01_wp, -0.002_wp, 0.001_wp, 0.0_wp, v / r0]
  q(:, 2) = q(:, 1); q(2, 2) = q(2, 2) + 1.0e-9_wp            ! lateral perturbation
  qd(:, 2) = qd(:, 1)
  q(:, 3) = q(:, 1); qd(:, 3) = qd(:, 1)                     ! back to the first pose
  q(:, 4) = q(:, 1); qd(:, 4) = qd(:, 1); qd(2, 4) = 0.02_wp   ! same pose, other velocity
  q(:, 5) = q(:, 1); q(1, 5) = 0.3_wp; q(6, 5) = 1.0_wp         ! same pose, other x and spin angle
  qd(:, 5) = qd(:, 1)
  q(:, 6) = q(:, 1); q(3, 6) = q(3, 6) - 1.0e-9_wp            ! vertical perturbation
  qd(:, 6) = qd(:, 1)

  call ws%build([spec], 1, error)
  if (allocated(error)) error stop error%message
  do k = 1, 6
    call compare(k)
  end do
  call test_summary('test_wheelset_geometry_cache')

contains

  subroutine compare(k)
    integer, intent(in) :: k
    type(wheelset_contact_t) :: fresh
    type(body_kinematics_t) :: kin
    real(wp) :: f(3), m(3), f0(3), m0(3)
    kin = pose_kinematics(track, 0.0_wp, v, q(:, k), qd(:, k))
    call ws%evaluate(1, 0.0_wp, kin, f, m, error)
    if (allocated(error)) error stop error%message
    call fresh%build([spec], 1, error)
    if (allocated(error)) error stop error%message
    call fresh%evaluate(1, 0.0_wp, kin, f0, m0, error)
    if (allocated(error)) error stop error%message
    if (all(f == f0) .and. all(m == m0) .and. norm2(f0) > 1.0e3_wp) then
      write (*, '(a,i0,a,3es13.5)') 'ok    state ', k, ': same force as a fresh provider ', f
    else
      write (*, '(a,i0,a,6es13.5)') 'FAIL  state ', k, ': cached vs fresh ', f, f0
      call fail()
    end if
  end subroutine compare

end program test_wheelset_geometry_cache
