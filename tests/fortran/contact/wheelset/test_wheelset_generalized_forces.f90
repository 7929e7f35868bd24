!> Generalized contact forces (thesis 4.8.1-4.8.2) by virtual work, written here
!> independently, against the provider's resultant projected as the multibody does.
!>
!> An S1002/60E1 wheelset (FASTSIM) in a left curve R = 300 m, shifted 6.5 mm to the left
!> (flange contact on the left wheel, tread on the right), yawed and rolled at rigid contact
!> lowered 30 um, with lateral, yaw, roll and spin-deviation rates (all creepages non-zero).
!> Per patch the provider reports the force on the wheel F_p, the normal n_p, the spin
!> moment Mz_p and the wheel's material point r_p - r_G (fixed frame). Holding those forces,
!>   Q_j = sum_p [ F_p . d r_p / d q_j + Mz_p n_p . d pi / d q_j ]
!> with r_p(q) = p + A (w + B(q) u_p), u_p the body-fixed coordinates of the material point,
!> B = Rz(psi) Rx(phi) Ry(theta) built here from elementary rotations, and the virtual
!> rotation d pi from unskew(dR R^T), R = A B: central differences in q. The provider +
!> multibody give Q_w = A^T F_G and Q_a = H^T (A B)^T M_G (rd_body_kinematics' H).
!> They must agree to 1e-6. The thesis' eqs. 4.89 / 4.99 differentiate the intermediate
!> frame B_zx instead of B: for the spin coordinate they give 0; printed against the
!> correct value (the check that it is far from 0 makes the comparison meaningful).
program test_wheelset_generalized_forces
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_rotation, only: rot_x, rot_y, rot_z, unskew
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, angle_rate_matrix
  use rd_rigid_contact, only: rigid_contact
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use wheelset_test_support, only: circle_track_t, pose_kinematics
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 15.0_wp, sigma = 40.0_wp, h = 1.0e-6_wp
  type(wheelset_contact_spec_t) :: spec
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(circle_track_t) :: curve
  type(body_kinematics_t) :: kin
  type(track_point_t) :: tp
  real(wp) :: q(6), qd(6), z, phi, f(3), m(3), a(3, 3), r(3, 3), q_proj(6), q_vw(6), u(3), dr(3), dpi(3)
  real(wp) :: qp(6), qm(6), scale, err, q_spin_thesis
  integer :: j, s, k, np

  spec%body = 1
  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  spec%nominal_radius = r0
  spec%creep_law = 'fastsim'
  ! every patch force at its material point (the classic strip force): the check is of the
  ! projection, which the potential force's own line of action would hide
  ! (test_wheelset_energy checks that force through its work)
  spec%strip_normal_force = 'centroid'
  call ws%build([spec], 1, error)
  if (allocated(error)) error stop error%message
  curve%kappa = 1.0_wp / 300.0_wp

  call rigid_contact(ws%models(1)%geo, 6.5e-3_wp, 4.0e-3_wp, z, phi, error)
  if (allocated(error)) error stop error%message
  q = [0.0_wp, 6.5e-3_wp, z - 3.0e-5_wp, 4.0e-3_wp, phi, 0.37_wp]
  qd = [0.0_wp, 0.03_wp, 0.002_wp, 0.02_wp, -0.01_wp, v / r0 + 0.2_wp]
  kin = pose_kinematics(curve, sigma, v, q, qd)
  call ws%evaluate(1, 0.0_wp, kin, f, m, error)
  if (allocated(error)) error stop error%message

  tp = curve%evaluate(sigma)
  a = tp%a
  r = matmul(a, zxy(q(4:6)))
  q_proj(1:3) = matmul(transpose(a), f)
  q_proj(4:6) = matmul(transpose(angle_rate_matrix(q(5), q(6))), matmul(transpose(r), m))

  q_vw = 0
  q_spin_thesis = 0
  np = 0
  do s = 1, 2
    associate (w => ws%results(1)%wheel(s))
      do k = 1, w%n_patches
        np = np + 1
        associate (p => w%patch(k))
          u = matmul(transpose(r), p%lever_fixed)          ! body-fixed coordinates
          do j = 1, 6
            qp = q; qm = q
            qp(j) = q(j) + h; qm(j) = q(j) - h
            dr = (point(qp, u) - point(qm, u)) / (2 * h)
            dpi = unskew(matmul(matmul(a, zxy(qp(4:6))), transpose(matmul(a, zxy(qm(4:6)))))) / (2 * h)
            q_vw(j) = q_vw(j) + dot_product(p%force_fixed, dr) + p%mz * dot_product(p%normal_fixed, dpi)
          end do
          ! the thesis' 4.89 + 4.99 for the spin: the point and the couple's arm held in
          ! the intermediate frame B_zx = Rz(psi) Rx(phi), which does not depend on theta
          qp = q; qm = q
          qp(6) = q(6) + h; qm(6) = q(6) - h
          u = matmul(transpose(matmul(a, zx(q(4:5)))), p%lever_fixed)
          dr = matmul(a, matmul(zx(qp(4:5)) - zx(qm(4:5)), u)) / (2 * h)
          dpi = unskew(matmul(matmul(a, zx(qp(4:5))), transpose(matmul(a, zx(qm(4:5)))))) / (2 * h)
          q_spin_thesis = q_spin_thesis + dot_product(p%force_fixed, dr) + p%mz * dot_product(p%normal_fixed, dpi)
        end associate
      end do
    end associate
  end do
  scale = maxval(abs(q_proj(1:3))) + maxval(abs(q_proj(4:6))) / r0
  err = max(maxval(abs(q_vw(1:3) - q_proj(1:3))), maxval(abs(q_vw(4:6) - q_proj(4:6))) / r0)
  write (*, '(a,i0,a)') 'patches: ', np, '; generalized forces (x, y, z [N]; yaw, roll, spin [N m])'
  write (*, '(a,6es13.5)') '  provider + H^T projection: ', q_proj
  write (*, '(a,6es13.5)') '  virtual work (here):       ', q_vw
  write (*, '(a,es13.5,a,es13.5,a)') '  spin: thesis 4.89/4.99 (B_zx) ', q_spin_thesis, ' N m, virtual work ', q_vw(6), ' N m'
  write (*, '(a,2f8.4)') '  contact angles left, right: ', ws%results(1)%wheel(1)%patch(1)%contact_angle, &
    ws%results(1)%wheel(2)%patch(1)%contact_angle
  call check(np >= 2 .and. abs(ws%results(1)%wheel(1)%patch(1)%contact_angle) > 0.5_wp, &
             'a flange contact (|gamma| > 0.5 rad) on the left wheel, tread on the right')
  call check(err < 1.0e-6_wp * scale, 'generalized forces: provider resultant + H^T projection = virtual work')
  call check(abs(q_vw(6)) > 100, 'the spin generalized force is far from the thesis'' 0 (> 100 N m)')
  call test_summary('test_wheelset_generalized_forces')

contains

  !> B = Rz(psi) Rx(phi) Ry(theta) from the elementary rotations
  pure function zxy(ang) result(b)
    real(wp), intent(in) :: ang(3)
    real(wp) :: b(3, 3)
    b = matmul(rot_z(ang(1)), matmul(rot_x(ang(2)), rot_y(ang(3))))
  end function zxy

  pure function zx(ang) result(b)
    real(wp), intent(in) :: ang(2)
    real(wp) :: b(3, 3)
    b = matmul(rot_z(ang(1)), rot_x(ang(2)))
  end function zx

  !> position of the body-fixed point u for coordinates qq (track frame fixed at sigma)
  function point(qq, u) result(x)
    real(wp), intent(in) :: qq(6), u(3)
    real(wp) :: x(3)
    x = tp%r + matmul(tp%a, qq(1:3) + matmul(zxy(qq(4:6)), u))
  end function point

end program test_wheelset_generalized_forces
