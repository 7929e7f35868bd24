!> `&wheelset spin_creep = .false.` (thesis 5.5-5.6 compare FASTSIM and Polach "as the spin
!> creepage is not taken into account"): the creep law must get zero spin while the spin
!> creepage is still computed and reported. Two identical knife-edge wheelsets (lambda = 0.2,
!> so each patch spins with (V/r0) sin(gamma)), one with the option, are evaluated at the same
!> yawed, shifted pose (lowered 50 um: N of order 50 kN); each patch's creep forces are compared with an independent call of the
!> same creep law (rd_creep_factory) on the reported a, b, N and creepages: with (xi, eta, phi)
!> for the default wheelset and (xi, eta, 0) for the other. A mutation that ignored the option
!> fails the second comparison, since the spin changes Fy by far more than the tolerance
!> (checked: |Fy(spin) - Fy(no spin)| > 1% of mu N).
program test_wheelset_spin_option
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  use rd_rigid_contact, only: rigid_contact
  use rd_creepage, only: creepage_t
  use rd_creep_law, only: creep_law_t, creep_patch_t, creep_force_t, creep_law_options_t
  use rd_creep_factory, only: build_creep_law
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use wheelset_test_support, only: circle_track_t, pose_kinematics
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 20.0_wp, y = 2.0e-3_wp, psi = 1.5e-3_wp, lowering = 5.0e-5_wp
  type(wheelset_contact_spec_t) :: spec(2)
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(circle_track_t) :: straight
  type(body_kinematics_t) :: kin
  class(creep_law_t), allocatable :: law
  type(creep_patch_t) :: cp
  type(creep_force_t) :: with_spin, without_spin
  real(wp) :: z, phi, f(3), m(3), tol
  integer :: i, side

  spec(1)%body = 1
  spec(1)%model = 'knife_edge'
  spec(1)%knife_conicity = 0.2_wp
  spec(1)%knife_e0 = 0.75_wp
  spec(1)%nominal_radius = r0
  spec(1)%creep_law = 'fastsim'
  spec(2) = spec(1)
  spec(2)%body = 2
  spec(2)%spin_creep = .false.
  call ws%build(spec, 2, error)
  if (allocated(error)) error stop error%message
  call build_creep_law('fastsim', creep_law_options_t(), law, error)
  if (allocated(error)) error stop error%message

  do i = 1, 2
    call rigid_contact(ws%models(i)%geo, y, psi, z, phi, error)
    if (allocated(error)) error stop error%message
    kin = pose_kinematics(straight, 0.0_wp, v, [0.0_wp, y, z - lowering, psi, phi, 0.0_wp], &
                          [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
    call ws%evaluate(i, 0.0_wp, kin, f, m, error)
    if (allocated(error)) error stop error%message
  end do

  do side = 1, 2
    associate (p1 => ws%results(1)%wheel(side)%patch(1), p2 => ws%results(2)%wheel(side)%patch(1))
      call check(ws%results(1)%wheel(side)%n_patches == 1 .and. ws%results(2)%wheel(side)%n_patches == 1, &
                 'one patch per wheel')
      call check(abs(p1%spin) > 0.1_wp .and. abs(p2%spin - p1%spin) <= 1.0e-12_wp * abs(p1%spin), &
                 'the spin creepage is computed and reported with and without the option')
      cp = creep_patch_t(a=p1%a, b=p1%b, normal_force=p1%normal_force, friction=0.3_wp, rolling_speed=p1%v_ref)
      call law%compute(cp, creepage_t(xi=p1%xi, eta=p1%eta, phi=p1%spin, v_ref=p1%v_ref), with_spin)
      cp = creep_patch_t(a=p2%a, b=p2%b, normal_force=p2%normal_force, friction=0.3_wp, rolling_speed=p2%v_ref)
      call law%compute(cp, creepage_t(xi=p2%xi, eta=p2%eta, phi=0.0_wp, v_ref=p2%v_ref), without_spin)
      tol = 1.0e-9_wp * 0.3_wp * p1%normal_force
      write (*, '(a,i2,a,3es13.5,a,3es13.5)') 'side', side, ': Fx Fy spin(default) ', p1%fx, p1%fy, p1%spin, &
        ' | Fx Fy (spin_creep off) ', p2%fx, p2%fy
      call check(abs(p1%fx - with_spin%fx) < tol .and. abs(p1%fy - with_spin%fy) < tol, &
                 'default: the law gets (xi, eta, phi)')
      call check(abs(p2%fx - without_spin%fx) < tol .and. abs(p2%fy - without_spin%fy) < tol, &
                 'spin_creep = .false.: the law gets (xi, eta, 0)')
      call check(abs(with_spin%fy - without_spin%fy) > 0.01_wp * 0.3_wp * p1%normal_force, &
                 'the spin matters at this pose (the test can fail)')
    end associate
  end do
  call test_summary('test_wheelset_spin_option')
end program test_wheelset_spin_option
