!> Creepages of knife-edge conical wheelsets (r0 = 0.46 m, e0 = 0.75 m) against the classic
!> closed forms (thesis 3.6.1; Garg & Dukkipati 1984, ch. 6):
!>
!> - lateral velocity and yaw: eta = ydot/V - psi. This linear form neglects terms of order
!>   gamma^2 (the cos(gamma) projection of the slip on y_c, and the longitudinal shift
!>   -r0 tan(gamma) psi of the contact on a yawed cone, whose vertical rolling velocity
!>   projects on the tilted y_c): checked on a low-conicity wheelset (lambda = 0.02) where
!>   they are below 0.1%.
!> - lateral shift y (lambda = 0.2): xi = -+Dr / r0 on the left/right wheel with
!>   Dr = lambda (y + r0 phi), phi the roll of rigid contact: when the wheelset rolls by
!>   phi the knife edge moves r0 phi across the wheel, and phi = Dr / e0, so
!>   Dr = lambda y / (1 - lambda r0 / e0) (the thesis' eq. 5.2-5.4 geometry; the textbook
!>   xi = -lambda y / r0 is its limit r0 lambda / e0 -> 0).
!> - spin (lambda = 0.2): phi = (+-(V/r0) sin(gamma) + psidot cos(gamma)) / V_ref with
!>   V_ref = V +- psidot e0 / 2 (rd_creepage's reference speed: the mean of forward and
!>   circumferential speeds); the thesis' phi = -sin(gamma)/r has the opposite sign convention.
!> - flange stop of the knife-edge model (clearance 8 mm, 1e7 N/m): at y = 10 mm the left
!>   wheel gets a patch with N = k (y - c) along -Y_T, no creep force, and Y/Q > 0.
!> - contact damping (1e5 N s/m): moving down at 0.5 mm/s adds c 0.0005 cos(gamma) to N (the
!>   approach rate is the wheel point's velocity towards the rail along n; c rate < N_el);
!>   moving down at 0.01 m/s the viscous term is bounded by the elastic force, N = 2 N_el;
!>   moving up fast the force is 0 (no adhesion).
!> The wheelset is placed at rigid contact (rd_rigid_contact) lowered by 1 um, so the
!> half-approach correction of the contact radius (1e-6 relative) is negligible.
program test_wheelset_creepage
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  use rd_rigid_contact, only: rigid_contact
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use wheelset_test_support, only: circle_track_t, pose_kinematics, rel_err
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 20.0_wp, lambda = 0.2_wp, lowering = 1.0e-6_wp
  type(wheelset_contact_spec_t) :: spec, spec2, spec3, spec4
  real(wp) :: n_static
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(circle_track_t) :: straight
  type(body_kinematics_t) :: kin
  real(wp) :: z, phi, f(3), m(3), y, psi, ydot, psidot, g, eta_ref, xi_ref, dr, vref, sgn
  integer :: side

  spec%body = 1
  spec%model = 'knife_edge'
  spec%knife_conicity = lambda
  spec%knife_e0 = 0.75_wp
  spec%nominal_radius = r0
  spec%creep_law = 'linear'
  spec2 = spec
  spec2%body = 2
  spec2%knife_conicity = 0.02_wp
  spec3 = spec
  spec3%body = 3
  spec3%knife_flange_clearance = 8.0e-3_wp
  spec3%knife_flange_stiffness = 1.0e7_wp
  spec4 = spec
  spec4%body = 4
  spec4%contact_damping = 1.0e5_wp
  call ws%build([spec, spec2, spec3, spec4], 4, error)
  if (allocated(error)) error stop error%message
  g = atan(lambda)

  ! 1. lateral velocity and yaw, centred, low conicity
  y = 0; psi = 2.0e-3_wp; ydot = 0.01_wp
  call place(2, y, psi, [0.0_wp, ydot, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  eta_ref = ydot / v - psi
  do side = 1, 2
    associate (p => ws%results(2)%wheel(side)%patch(1))
      write (*, '(a,i2,a,2es14.6)') 'side', side, ': eta, ydot/V - psi ', p%eta, eta_ref
      call check(rel_err(p%eta, eta_ref) < 1.0e-3_wp, 'eta = ydot/V - psi within 0.1% (lambda 0.02)')
    end associate
  end do

  ! 2. lateral shift: rolling radius difference
  y = 3.0e-3_wp; psi = 0
  call place(1, y, psi, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  write (*, '(a,es12.4,a,es12.4)') 'roll of rigid contact ', phi, ', lambda y / (e0 - lambda r0) ', lambda * y / (0.75_wp - lambda * r0)
  call check(rel_err(phi, lambda * y / (0.75_wp - lambda * r0)) < 1.0e-2_wp, 'roll = lambda y / (e0 - lambda r0) within 1%')
  dr = lambda * (y + r0 * phi)
  do side = 1, 2
    associate (p => ws%results(1)%wheel(side)%patch(1))
      sgn = merge(1.0_wp, -1.0_wp, side == 1)
      xi_ref = -sgn * dr / r0
      write (*, '(a,i2,a,3es14.6)') 'side', side, ': xi, -+Dr/r0, rolling radius ', p%xi, xi_ref, p%rolling_radius
      call check(rel_err(p%xi, xi_ref) < 1.0e-2_wp, 'xi = -+lambda (y + r0 phi) / r0 within 1%')
      call check(abs(p%rolling_radius - (r0 + sgn * dr)) < 1.0e-2_wp * dr, 'rolling radius r0 +- lambda (y + r0 phi) within 1%')
    end associate
  end do

  ! 3. spin, centred, without and with a yaw rate
  y = 0; psi = 0
  do side = 0, 1
    psidot = 0.1_wp * side
    call place(1, y, psi, [0.0_wp, 0.0_wp, 0.0_wp, psidot, 0.0_wp, v / r0])
    associate (pl => ws%results(1)%wheel(1)%patch(1), pr => ws%results(1)%wheel(2)%patch(1))
      write (*, '(a,f5.2,a,4es14.6)') 'yaw rate ', psidot, ': phi left, right; closed forms ', pl%spin, pr%spin, &
        (-v / r0 * sin(g) + psidot * cos(g)) / (v + 0.375_wp * psidot), (v / r0 * sin(g) + psidot * cos(g)) / (v - 0.375_wp * psidot)
      vref = v + 0.375_wp * psidot
      call check(rel_err(pl%spin, (-v / r0 * sin(g) + psidot * cos(g)) / vref) < 1.0e-4_wp, &
                 'phi left = (-(V/r0) sin(gamma) + psidot cos(gamma)) / V_ref')
      vref = v - 0.375_wp * psidot
      call check(rel_err(pr%spin, (v / r0 * sin(g) + psidot * cos(g)) / vref) < 1.0e-4_wp, &
                 'phi right = ((V/r0) sin(gamma) + psidot cos(gamma)) / V_ref')
    end associate
  end do
  ! 4. flange stop
  y = 10.0e-3_wp; psi = 0
  call place(3, y, psi, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  associate (wl => ws%results(3)%wheel(1), wr => ws%results(3)%wheel(2))
    write (*, '(a,2i3,a,es12.4,a,3es12.4)') 'flange stop: patches ', wl%n_patches, wr%n_patches, '; N ', &
      wl%patch(2)%normal_force, '; left wheel force (track) ', wl%force_track
    call check(wl%n_patches == 2 .and. wr%n_patches == 1 .and. wl%patch(2)%kind == 4, 'flange stop: second patch on the left wheel only')
    call check(rel_err(wl%patch(2)%normal_force, 1.0e7_wp * (y - 8.0e-3_wp)) < 1.0e-12_wp .and. wl%patch(2)%fx == 0 &
               .and. wl%patch(2)%fy == 0, 'flange stop: N = k (y - clearance), no creep force')
    call check(abs(wl%force_track(2) - (wl%patch(1)%normal_force * sin(wl%patch(1)%contact_angle) &
               + wl%patch(1)%fy * cos(wl%patch(1)%contact_angle) - 2.0e4_wp)) < 1.0e-6_wp * 2.0e4_wp, &
               'flange stop: pushes the left wheel to -Y')
    call check(wl%y_over_q > 0 .and. ws%results(3)%derailment_quotient == wl%y_over_q, &
               'flange contact on the left wheel: Y/Q > 0 and it is the derailment quotient')
  end associate

  ! 5. contact damping
  call place(4, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, v / r0])
  n_static = ws%results(4)%wheel(1)%patch(1)%normal_force
  call place(4, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, -0.0005_wp, 0.0_wp, 0.0_wp, v / r0])
  associate (p => ws%results(4)%wheel(1)%patch(1))
    write (*, '(a,2es13.5)') 'damping: N static, N moving down 0.5 mm/s ', n_static, p%normal_force
    call check(1.0e5_wp * 0.0005_wp < n_static .and. &
               abs(p%normal_force - (n_static + 1.0e5_wp * 0.0005_wp * cos(g))) < 1.0e-9_wp * p%normal_force, &
               'damping: N = N_el + c d(delta)/dt, d(delta)/dt = 0.0005 cos(gamma)')
  end associate
  call place(4, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, -0.01_wp, 0.0_wp, 0.0_wp, v / r0])
  associate (p => ws%results(4)%wheel(1)%patch(1))
    write (*, '(a,2es13.5)') 'damping: N static, N moving down 0.01 m/s ', n_static, p%normal_force
    call check(1.0e5_wp * 0.01_wp * cos(g) > n_static .and. abs(p%normal_force - 2 * n_static) < 1.0e-9_wp * p%normal_force, &
               'damping: c d(delta)/dt > N_el is bounded by N_el: N = 2 N_el (continuous at first touch)')
  end associate
  call place(4, 0.0_wp, 0.0_wp, [0.0_wp, 0.0_wp, 0.5_wp, 0.0_wp, 0.0_wp, v / r0])
  call check(ws%results(4)%wheel(1)%patch(1)%normal_force == 0 .and. ws%results(4)%wheel(1)%patch(1)%fx == 0, &
             'damping: separating fast, N = 0 (no adhesion) and no creep force')
  call test_summary('test_wheelset_creepage')

contains

  !> rigid contact for (y, psi), lowered by `lowering`, and the pipeline evaluated there
  subroutine place(i, y, psi, qd)
    integer, intent(in) :: i
    real(wp), intent(in) :: y, psi, qd(6)
    call rigid_contact(ws%models(i)%geo, y, psi, z, phi, error)
    if (allocated(error)) error stop error%message
    kin = pose_kinematics(straight, 0.0_wp, v, [0.0_wp, y, z - lowering, psi, phi, 0.0_wp], qd)
    call ws%evaluate(i, 0.0_wp, kin, f, m, error)
    if (allocated(error)) error stop error%message
  end subroutine place

end program test_wheelset_creepage
