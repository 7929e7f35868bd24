!> The wheelset contact's two caches (rd_wheelset_contact, wheelset_cache_t): the geometry of
!> the last poses, reused when an evaluation has bitwise the same pose (y, z, roll, yaw), and
!> the whole result of the last evaluation, reused when every input of the pipeline is
!> bitwise the same (pose, velocities, track frame, attachment rotation, x). Both must be
!> exact. Oracle: a freshly built provider (no cache) evaluated at each state of a sequence
!> that alternates poses, repeats a state exactly (a result-cache hit), and changes one input
!> at a time that the result cache's key must hold (a lateral or roll rate, the track
!> position, the speed, the longitudinal position; the spin angle, which is not an input);
!> forces, moments, each wheel's force and the per-patch results must agree bitwise.
program test_wheelset_contact_caches
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
  integer, parameter :: n_states = 12
  real(wp), parameter :: r0 = 0.46_wp, v = 4.4_wp
  type(wheelset_contact_spec_t) :: spec
  type(wheelset_contact_t) :: ws
  type(contact_geometry_t) :: geo
  type(circle_track_t) :: track
  type(error_t), allocatable :: error
  real(wp) :: z, phi, q(6, n_states), qd(6, n_states), sigma(n_states), speed(n_states)
  character(len=48) :: what(n_states)
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
  sigma = 0
  speed = v
  q(:, 1) = [0.0_wp, 5.2e-3_wp, z - 3.0e-5_wp, 8.5e-3_wp, phi, 0.0_wp]
  qd(:, 1) = [0.0_wp, 0.01_wp, -0.002_wp, 0.001_wp, 0.0_wp, v / r0]
  what(1) = 'first'
  call follow(2, 'lateral perturbation'); q(2, 2) = q(2, 2) + 1.0e-9_wp
  call follow(3, 'back to the first state'); q(:, 3) = q(:, 1); qd(:, 3) = qd(:, 1)
  call follow(4, 'same pose, other lateral velocity'); qd(2, 4) = 0.02_wp
  call follow(5, 'same pose, other x and spin angle'); q(1, 5) = 0.3_wp; q(6, 5) = 1.0_wp
  call follow(6, 'vertical perturbation'); q(3, 6) = q(3, 6) - 1.0e-9_wp
  call follow(7, 'the same state again (result cache)')
  call follow(8, 'other roll rate'); qd(5, 8) = 0.01_wp
  call follow(9, 'other track position'); sigma(9) = 5.0_wp
  call follow(10, 'other speed'); speed(10) = 5.0_wp
  call follow(11, 'other spin angle only'); q(6, 11) = 2.0_wp
  call follow(12, 'the same state again (result cache)')

  call ws%build([spec], 1, error)
  if (allocated(error)) error stop error%message
  do k = 1, n_states
    call compare(k)
  end do
  call test_summary('test_wheelset_contact_caches')

contains

  !> State k starts as a copy of state k - 1.
  subroutine follow(k, label)
    integer, intent(in) :: k
    character(len=*), intent(in) :: label
    q(:, k) = q(:, k - 1); qd(:, k) = qd(:, k - 1)
    sigma(k) = sigma(k - 1); speed(k) = speed(k - 1)
    what(k) = label
  end subroutine follow

  subroutine compare(k)
    integer, intent(in) :: k
    type(wheelset_contact_t) :: fresh
    type(body_kinematics_t) :: kin
    real(wp) :: f(3), m(3), f0(3), m0(3), fw(3, 2), fw0(3, 2)
    logical :: same
    kin = pose_kinematics(track, sigma(k), speed(k), q(:, k), qd(:, k))
    call ws%evaluate(1, 0.0_wp, kin, f, m, error, wheel_force=fw)
    if (allocated(error)) error stop error%message
    call fresh%build([spec], 1, error)
    if (allocated(error)) error stop error%message
    call fresh%evaluate(1, 0.0_wp, kin, f0, m0, error, wheel_force=fw0)
    if (allocated(error)) error stop error%message
    same = all(f == f0) .and. all(m == m0) .and. all(fw == fw0) .and. &
           ws%results(1)%wheel(1)%n_patches == fresh%results(1)%wheel(1)%n_patches .and. &
           all(ws%results(1)%wheel(:)%patch(1)%normal_force == fresh%results(1)%wheel(:)%patch(1)%normal_force) .and. &
           all(ws%results(1)%wheel(:)%patch(1)%xi == fresh%results(1)%wheel(:)%patch(1)%xi) .and. &
           all(ws%results(1)%wheel(:)%patch(1)%point_rail(1) == fresh%results(1)%wheel(:)%patch(1)%point_rail(1))
    if (same .and. norm2(f0) > 1.0e3_wp) then
      write (*, '(a,i0,a,a,3es13.5)') 'ok    state ', k, ' (' // trim(what(k)) // ')', &
        ': same results as a fresh provider ', f
    else
      write (*, '(a,i0,a,a,6es13.5)') 'FAIL  state ', k, ' (' // trim(what(k)) // ')', ': cached vs fresh ', f, f0
      call fail()
    end if
  end subroutine compare

end program test_wheelset_contact_caches
