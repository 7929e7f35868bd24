!> A single Manchester wheelset (vehicle 1: 1813 kg) rolling at its nominal speed on
!> straight track, with both contact models (knife-edge cones; analytic S1002 on 60E1 1:40):
!>
!> 1. Statics: the height at which the contact carries the weight (bisection on z, done
!>    here) gives equal normal forces on both wheels whose vertical components sum to the
!>    weight, no lateral force and no roll or yaw moment (symmetry).
!> 2. Creepages at pure rolling (spin rate V/r0), closed forms: eta = 0; xi = (V - w rho)/V_ref
!>    with rho the distance of the contact's material point from the axle (the deformed
!>    surfaces meet half-way: rho = r - delta/cos(g) + delta cos(g)/2 from the rolling radius
!>    r, approach delta and contact angle g the geometry reports), V_ref = (V + w rho)/2;
!>    spin phi = w sin(g) / V_ref (thesis 3.6.1.3: phi = -sin(g)/r in the thesis' sign, ours
!>    takes the spin about n from the rail into the wheel, docs/conventions.md).
!> 3. Mirror invariance: for an asymmetric pose and rates (shift, yaw, roll, their rates,
!>    a spin deviation), and on straight track and in a left curve against the mirrored
!>    right curve, the forces are odd under Y -> -Y: (Fx, -Fy, Fz) and moments (-Mx, My, -Mz),
!>    left and right wheel outputs swapped.
program test_wheelset_static
  use rd_kinds, only: wp, standard_gravity
  use rd_error, only: error_t
  use rd_body_kinematics, only: body_kinematics_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_rigid_contact, only: rigid_contact
  use rd_wheel_contact_result, only: wheelset_result_t, N_PATCH_CHANNELS, N_WHEEL_CHANNELS, patch_channel_names, &
    wheel_channel_names, patch_channel_values, wheel_channel_values
  use wheelset_test_support, only: circle_track_t, pose_kinematics, rel_err
  use rd_test_support, only: check, test_summary
  implicit none
  real(wp), parameter :: r0 = 0.46_wp, v = 20.0_wp, mass = 1813.0_wp
  !> 'profile': the default strip force (distributed over the strips, rd_hertz_strip);
  !> 'profile_centroid': the patch force along the contact normal (`strip_normal_force =
  !> 'centroid'`, the frame relation checked below); 'profile_potential': the effective
  !> penetration's gradient (`strip_normal_force = 'potential'`)
  character(len=17) :: models(4) = [character(len=17) :: 'knife_edge', 'profile', 'profile_centroid', &
                                    'profile_potential']
  integer :: im
  type(wheelset_contact_spec_t) :: spec
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(circle_track_t) :: straight, left_curve, right_curve
  type(body_kinematics_t) :: kin
  real(wp) :: weight, zlo, zhi, z, f(3), m(3), fm(3), mm(3), rho, omega, vref, xi_ref, g, d, r
  real(wp) :: q(6), qd(6), pch(N_PATCH_CHANNELS), wch(N_WHEEL_CHANNELS)
  type(wheelset_result_t) :: a, b
  integer :: it, side
  character(len=:), allocatable :: model

  do im = 1, size(models)
    call run_model(trim(models(im)))
  end do
  call test_summary('test_wheelset_static')

contains

  subroutine run_model(model_in)
    character(len=*), intent(in) :: model_in
    model = model_in
    spec = wheelset_contact_spec_t()

    write (*, '(a)') '--- model ' // model
    spec%body = 1
    spec%model = model
    if (model == 'profile_potential' .or. model == 'profile_centroid') then
      spec%model = 'profile'
      spec%strip_normal_force = model(9:)
    end if
    spec%wheel_profile = 's1002'
    spec%rail_profile = '60e1'
    spec%nominal_radius = r0
    spec%creep_law = 'linear'
    call ws%build([spec], 1, error)
    if (allocated(error)) error stop error%message

    weight = mass * standard_gravity
    omega = v / r0
    ! bisection: the vertical contact force falls as the wheelset rises
    zlo = r0 - 2.0e-3_wp; zhi = r0 + 2.0e-3_wp
    do it = 1, 100
      z = 0.5_wp * (zlo + zhi)
      call eval(straight, [0.0_wp, 0.0_wp, z, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, omega], f, m)
      if (f(3) > weight) then
        zlo = z
      else
        zhi = z
      end if
    end do
    associate (res => ws%results(1), wl => ws%results(1)%wheel(1), wr => ws%results(1)%wheel(2))
      write (*, '(a,f10.6,a,2i3,a,2es12.4)') 'equilibrium z = ', z, ' m; patches ', wl%n_patches, wr%n_patches, &
        '; N ', wl%patch(1)%normal_force, wr%patch(1)%normal_force
      call check(wl%n_patches == 1 .and. wr%n_patches == 1, model // ': one patch per wheel when centred')
      call check(rel_err(wl%patch(1)%normal_force, wr%patch(1)%normal_force) < 1.0e-9_wp, &
                 model // ': equal normal forces on both wheels')
      call check(rel_err(wl%force_track(3) + wr%force_track(3), weight) < 1.0e-6_wp, &
                 model // ': Q_left + Q_right = weight')
      ! contact frame at zero yaw: n = (0, sin g, cos g), y_c = n x X = (0, cos g, -sin g),
      ! so Q = N cos(g) - Fy sin(g) and Y = N sin(g) + Fy cos(g) (spin creep gives Fy) for the
      ! patch force along the normal; the distributed and the potential strip forces act
      ! along their strips' depth gradients instead (test_hertz_strip, test_strip_potential,
      ! test_wheelset_energy)
      do side = 1, 2
        if (model == 'profile' .or. model == 'profile_potential') exit
        associate (p => ws%results(1)%wheel(side)%patch(1), wf => ws%results(1)%wheel(side)%force_track)
          call check(abs(wf(3) - (p%normal_force * cos(p%contact_angle) - p%fy * sin(p%contact_angle))) < 1.0e-9_wp * weight &
                     .and. abs(wf(2) - (p%normal_force * sin(p%contact_angle) + p%fy * cos(p%contact_angle))) < 1.0e-9_wp * weight, &
                     model // ': Q = N cos(g) - Fy sin(g), Y = N sin(g) + Fy cos(g)')
        end associate
      end do
      call check(abs(res%force(2)) < 1.0e-9_wp * weight .and. abs(m(1)) < 1.0e-9_wp * weight &
                 .and. abs(m(3)) < 1.0e-9_wp * weight, model // ': no lateral force, no roll or yaw moment')
      call check(abs(res%guiding_force_sum) < 1.0e-9_wp * weight, model // ': Y_left + Y_right = 0')
      call check(wl%patch(1)%contact_angle < 0 .and. wr%patch(1)%contact_angle > 0, &
                 model // ': contact angles: left < 0, right > 0 (rails lean inwards)')
      ! output channels: names and values line up
      call patch_channel_values(wl, 1, pch)
      call wheel_channel_values(wr, wch)
      call check(size(patch_channel_names) == N_PATCH_CHANNELS .and. size(wheel_channel_names) == N_WHEEL_CHANNELS &
                 .and. pch(findloc(patch_channel_names, 'normal_force', 1)) == wl%patch(1)%normal_force &
                 .and. pch(findloc(patch_channel_names, 'spin', 1)) == wl%patch(1)%spin &
                 .and. pch(findloc(patch_channel_names, 'rail_point_y', 1)) == wl%patch(1)%point_rail(2) &
                 .and. pch(findloc(patch_channel_names, 'semi_axis_b', 1)) == wl%patch(1)%b &
                 .and. wch(findloc(wheel_channel_names, 'force_vertical_Q', 1)) == wr%force_track(3) &
                 .and. wch(findloc(wheel_channel_names, 'Y_over_Q', 1)) == wr%y_over_q, &
                 model // ': output channels match their names')
      call patch_channel_values(wl, 2, pch)
      call check(all(pch == 0), model // ': empty patch slot outputs zeros')
      do side = 1, 2
        associate (p => ws%results(1)%wheel(side)%patch(1))
          g = p%contact_angle; d = p%penetration; r = p%rolling_radius
          rho = r - d / cos(g) + 0.5_wp * d * cos(g)
          vref = sqrt((0.5_wp * (v + omega * rho))**2 + spec%creep_v0**2)
          xi_ref = (v - omega * rho) / vref
          write (*, '(a,i2,a,5es13.5)') ' side', side, ': xi, ref, eta, phi, ref ', p%xi, xi_ref, p%eta, p%spin, &
            omega * sin(g) / vref
          ! 2e-6 = 1 um of radius over r0: the strip model interpolates the contact point
          ! between strips 0.1 mm apart (exact for the knife edge)
          call check(abs(p%xi - xi_ref) < 1.0e-3_wp * abs(xi_ref) + 2.0e-6_wp, model // ': xi at pure rolling (closed form)')
          call check(abs(p%eta) < 1.0e-12_wp, model // ': eta = 0 at pure rolling')
          call check(rel_err(p%spin, omega * sin(g) / vref) < 1.0e-5_wp, model // ': spin = w sin(gamma) / V_ref')
          call check(abs(p%spin - sin(g) / r) < 2.0e-3_wp * abs(sin(g) / r), model // ': spin = sin(gamma)/r within 0.2%')
        end associate
      end do
    end associate

    ! mirror invariance at an asymmetric pose with rates, straight and curved
    q = [0.01_wp, 2.0e-3_wp, z - 1.0e-5_wp, 3.0e-3_wp, 1.0e-3_wp, 0.7_wp]
    qd = [0.0_wp, 0.05_wp, 0.002_wp, 0.01_wp, -0.02_wp, omega + 0.4_wp]
    left_curve%kappa = 1.0_wp / 300.0_wp
    right_curve%kappa = -1.0_wp / 300.0_wp
    call eval(straight, q, qd, f, m)
    a = ws%results(1)
    call eval(straight, mirror_q(q), mirror_q(qd), fm, mm)
    b = ws%results(1)
    call check_mirror('straight')
    call eval(left_curve, q, qd, f, m)
    a = ws%results(1)
    call eval(right_curve, mirror_q(q), mirror_q(qd), fm, mm)
    b = ws%results(1)
    call check_mirror('left curve vs right curve')
    call check(abs(a%force(2)) > 1.0e-3_wp * weight, model // ': the asymmetric case has a lateral force (test can fail)')

    ! flange contact sign (conventions.md): shifted 8 mm to the left, rigid contact lowered
    ! 20 um, the left flange touches with gamma < 0, is pushed to -Y, and Y/Q_left > 0
    if (model /= 'knife_edge') then
      call rigid_contact(ws%models(1)%geo, 8.0e-3_wp, 0.0_wp, zlo, zhi, error)
      if (allocated(error)) error stop error%message
      call eval(straight, [0.0_wp, 8.0e-3_wp, zlo - 2.0e-5_wp, 0.0_wp, zhi, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, omega], f, m)
      associate (wl => ws%results(1)%wheel(1), wr => ws%results(1)%wheel(2))
        write (*, '(a,i2,a,4f9.4)') 'left flange: patches', wl%n_patches, '; gamma, Y/Q left, right, quotient ', &
          minval(wl%patch(1:wl%n_patches)%contact_angle), wl%y_over_q, wr%y_over_q, ws%results(1)%derailment_quotient
        call check(minval(wl%patch(1:wl%n_patches)%contact_angle) < -0.5_wp .and. wl%force_track(2) < 0 &
                   .and. wl%y_over_q > 0.3_wp .and. wr%y_over_q < 0.3_wp .and. ws%results(1)%derailment_quotient == wl%y_over_q, &
                   model // ': left flange contact: gamma < 0, Y_left < 0, Y/Q_left > 0 is the derailment quotient')
      end associate
    end if
  end subroutine run_model

    subroutine eval(track, q, qd, f, m)
      type(circle_track_t), intent(in) :: track
      real(wp), intent(in) :: q(6), qd(6)
      real(wp), intent(out) :: f(3), m(3)
      kin = pose_kinematics(track, 10.0_wp, v, q, qd)
      call ws%evaluate(1, 0.0_wp, kin, f, m, error)
      if (allocated(error)) error stop error%message
    end subroutine eval

    subroutine check_mirror(what)
      character(len=*), intent(in) :: what
      real(wp) :: scale, err
      integer :: s, k
      ! forces in track components: the fixed frames of the two curves are mirror images
      scale = weight
      err = maxval(abs([a%wheel(1)%force_track - mirror_v(b%wheel(2)%force_track), &
                        a%wheel(2)%force_track - mirror_v(b%wheel(1)%force_track)]))
      call check(err < 1.0e-9_wp * scale, model // ', ' // what // ': wheel forces odd under mirroring')
      err = maxval(abs(f - mirror_v(fm)))
      call check(err < 1.0e-9_wp * scale, model // ', ' // what // ': resultant force odd under mirroring')
      err = maxval(abs(m + mirror_v(mm)))
      call check(err < 1.0e-9_wp * scale, model // ', ' // what // ': resultant moment odd (pseudo-vector) under mirroring')
      err = 0
      do s = 1, 2
        do k = 1, a%wheel(s)%n_patches
          associate (p => a%wheel(s)%patch(k), pm => b%wheel(3 - s)%patch(k))
            err = max(err, abs(p%xi - pm%xi), abs(p%eta + pm%eta), abs(p%spin + pm%spin) * 0.46_wp, &
                      abs(p%fx - pm%fx) / scale, abs(p%fy + pm%fy) / scale, abs(p%contact_angle + pm%contact_angle))
          end associate
        end do
      end do
      call check(err < 1.0e-9_wp, model // ', ' // what // ': creepages and creep forces mirror (xi, -eta, -phi)')
    end subroutine check_mirror

  !> Y -> -Y: (x, -y, z, -yaw, -roll, spin) for coordinates and rates
  pure function mirror_q(q) result(qm)
    real(wp), intent(in) :: q(6)
    real(wp) :: qm(6)
    qm = [q(1), -q(2), q(3), -q(4), -q(5), q(6)]
  end function mirror_q

  !> a polar vector's mirror image in the fixed frame (Y -> -Y); a pseudo-vector (moment)
  !> mirrors as minus this
  pure function mirror_v(x) result(y)
    real(wp), intent(in) :: x(3)
    real(wp) :: y(3)
    y = [x(1), -x(2), x(3)]
  end function mirror_v

end program test_wheelset_static
