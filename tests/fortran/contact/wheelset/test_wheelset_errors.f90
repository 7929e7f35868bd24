!> Errors of the wheelset contact: bad specs give one RD_ERR_INPUT (RD_ERR_IO for a missing
!> profile file) line naming the wheelset and what is expected; at run time a wheel lifted
!> beyond the limit or derailed (contact beyond the flange tip, no rail under the wheel) is
!> RD_ERR_PHYSICS, a NaN velocity RD_ERR_RUNTIME, with time, wheelset and side in the message.
!> A lift within the limit is no error and gives no force.
program test_wheelset_errors
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_ERR_INPUT, RD_ERR_IO, RD_ERR_PHYSICS, RD_ERR_RUNTIME
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_body_kinematics, only: body_kinematics_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use wheelset_test_support, only: circle_track_t, pose_kinematics
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 10.0_wp
  type(wheelset_contact_spec_t) :: knife, prof, bad
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(circle_track_t) :: straight
  type(body_kinematics_t) :: kin
  real(wp) :: f(3), m(3)

  knife%body = 1
  knife%model = 'knife_edge'
  knife%nominal_radius = r0
  prof%body = 2
  prof%wheel_profile = 's1002'
  prof%rail_profile = '60e1'

  ! ---- specs
  bad = knife; bad%model = 'knife'
  call expect_init(bad, RD_ERR_INPUT, 'knife_edge', 'unknown contact model')
  bad = knife; bad%creep_law = 'kalker'
  call expect_init(bad, RD_ERR_INPUT, 'linear, fastsim, polach', 'unknown creep law')
  bad = knife; bad%body = 3
  call expect_init(bad, RD_ERR_INPUT, 'body index', 'body index out of range')
  bad = knife; bad%knife_flange_clearance = 0.008_wp
  call expect_init(bad, RD_ERR_INPUT, 'flange stiffness', 'flange clearance without stiffness')
  bad = knife; bad%friction = -0.1_wp
  call expect_init(bad, RD_ERR_INPUT, 'friction', 'negative friction')
  bad = prof; bad%wheel_profile = 'no/such/wheel.prw'
  call expect_init(bad, RD_ERR_IO, 'no/such/wheel.prw', 'missing wheel profile file')
  bad = prof; bad%rail_profile = '61e1'
  call expect_init(bad, RD_ERR_IO, '61e1', 'unknown rail keyword read as a (missing) file')
  bad = knife; bad%hertz_method = 'exact'
  call expect_init(bad, RD_ERR_INPUT, 'hertz_method', 'unknown Hertz method')

  call ws%build([knife, prof], 2, error)
  if (allocated(error)) error stop error%message

  ! ---- run time
  call eval(1, [0.0_wp, 0.0_wp, r0 + 0.005_wp, 0.0_wp, 0.0_wp, 0.0_wp])
  call check(.not. allocated(error), 'lift of 5 mm (limit 20 mm): no error')
  call check(all(f == 0) .and. all(m == 0) .and. ws%results(1)%wheel(1)%n_patches == 0, 'lifted wheelset: no force, no patch')
  call check(abs(ws%results(1)%wheel(1)%max_penetration + 0.005_wp * cos(atan(0.2_wp))) < 1.0e-6_wp, &
             'lifted wheelset: max_penetration = -gap normal to the cone')
  call eval(1, [0.0_wp, 0.0_wp, r0 + 0.03_wp, 0.0_wp, 0.0_wp, 0.0_wp])
  call expect_run(RD_ERR_PHYSICS, ['lift-off    ', 'left wheel  ', 'wheelset con', 't = 1.25000 '], 'lift-off beyond the limit')
  call eval(2, [0.0_wp, 0.044_wp, 0.5_wp, 0.0_wp, 0.0_wp, 0.0_wp])
  call expect_run(RD_ERR_PHYSICS, ['derailment  ', 'flange tip  ', 'left wheel  ', 'contact 2   '], &
                  'contact beyond the flange tip')
  call eval(2, [0.0_wp, -0.3_wp, 0.4_wp, 0.0_wp, 0.0_wp, 0.0_wp])
  call expect_run(RD_ERR_PHYSICS, ['derailment  ', 'field side  ', 'left wheel  ', 'contact 2   '], &
                  'wheel off the rail (rail beyond the tread)')
  kin = pose_kinematics(straight, 0.0_wp, v, [0.0_wp, 0.0_wp, r0, 0.0_wp, 0.0_wp, 0.0_wp], &
                        [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  kin%v(2) = ieee_value(1.0_wp, ieee_quiet_nan)
  call ws%evaluate(1, 1.25_wp, kin, f, m, error)
  call expect_run(RD_ERR_RUNTIME, ['non-finite  ', 'contact 1   ', 't = 1.25000 ', 'velocity    '], 'NaN velocity')
  kin = pose_kinematics(straight, 0.0_wp, v, [0.0_wp, 0.0_wp, r0, 0.0_wp, 0.0_wp, 0.0_wp], &
                        [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  kin%is_wheelset = .false.
  call ws%evaluate(1, 1.25_wp, kin, f, m, error)
  call expect_run(RD_ERR_INPUT, ['not a wheel ', 'contact 1   ', 'spin        ', 'wheelset    '], 'body that is not a wheelset')
  call test_summary('test_wheelset_errors')

contains

  subroutine eval(i, q)
    integer, intent(in) :: i
    real(wp), intent(in) :: q(6)
    kin = pose_kinematics(straight, 0.0_wp, v, q, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
    call ws%evaluate(i, 1.25_wp, kin, f, m, error)
  end subroutine eval

  subroutine expect_init(spec, code, needle, what)
    type(wheelset_contact_spec_t), intent(in) :: spec
    integer, intent(in) :: code
    character(len=*), intent(in) :: needle, what
    type(wheelset_contact_t) :: w
    call w%build([spec], 2, error)
    if (.not. allocated(error)) then
      call check(.false., what // ': no error')
      return
    end if
    write (*, '(a)') '      message: ' // error%message
    call check(error%code == code .and. index(error%message, needle) > 0 .and. index(error%message, 'wheelset contact 1') > 0 &
               .and. index(error%message, new_line('a')) == 0, what // ': one-line error with the expected code and text')
  end subroutine expect_init

  subroutine expect_run(code, needles, what)
    integer, intent(in) :: code
    character(len=*), intent(in) :: needles(:)
    character(len=*), intent(in) :: what
    integer :: k
    logical :: ok
    if (.not. allocated(error)) then
      call check(.false., what // ': no error')
      return
    end if
    write (*, '(a)') '      message: ' // error%message
    ok = error%code == code
    do k = 1, size(needles)
      ok = ok .and. index(error%message, trim(needles(k))) > 0
    end do
    call check(ok, what // ': error code and message (time, wheelset, side)')
  end subroutine expect_run

end program test_wheelset_errors
