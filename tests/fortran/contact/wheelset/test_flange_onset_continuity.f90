!> Continuity of the wheel-rail normal forces across flange onset (S1002 / 60E1 1:40, the
!> Manchester wheelset): the strip geometry plus Hertz, evaluated along fine sweeps of the
!> lateral shift (wheelset height and roll held) and of the yaw angle, through tread-only
!> contact, the tread and flange-root bumps merging into one run, the conformal flange root
!> and the flange. An integrator needs the right-hand side to be a continuous function of
!> the state; a jump shows up as one increment far larger than both of its neighbours.
!>
!> Oracle (independent of the code's numbers): a continuous function sampled with a step
!> much finer than its features has increments that change gradually, so no increment may
!> exceed `ratio_limit` times the larger of its two neighbours (kinks, e.g. a patch opening
!> with N ~ delta^1.5, give ratios <= 1; the jumps of the one-patch-per-run rule measured
!> 75x, the chord-slope depth conversion 10x). Increments below 1e-3 of the largest one are
!> noise floor. Checked on the resultant force and on its moment about the wheelset centre
!> (which sees contact-point jumps even at equal force).
program test_flange_onset_continuity
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry, build_hertz_params
  use rd_contact_geometry, only: contact_geometry_t, wheel_contact, SIDE_LEFT
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  use rd_hertz, only: hertz_params_t, hertz_patch_t, hertz_from_penetration
  use rd_test_support, only: fail, test_summary
  implicit none
  real(wp), parameter :: jump_tolerance = 1.0e-3_wp
  integer, parameter :: nstep = 10000
  !> sweeps stop at this wheel force [N], beyond any flange force of the benchmark (the
  !> deep, millimetre penetrations past it are not a state the dynamics reaches)
  real(wp), parameter :: force_limit = 1.5e5_wp
  type(wheelset_contact_spec_t) :: spec
  type(contact_geometry_t) :: geo
  type(hertz_params_t) :: hertz
  type(error_t), allocatable :: error

  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  call build_contact_geometry(spec, geo, error)
  if (allocated(error)) error stop error%message
  call build_hertz_params(spec, hertz, error)
  if (allocated(error)) error stop error%message

  ! lateral sweeps of +-1 mm around: tread + flange root merging (5 mm), the conformal
  ! flange root (6 mm), the flange (6.5 mm); yaw as the leading wheelset at flange onset
  ! in the Manchester curve (8.5 mrad) and the opposite sign
  call lateral_sweep(5.0e-3_wp, 8.5e-3_wp, 'tread/flange-root merge, yaw +8.5 mrad')
  call lateral_sweep(6.0e-3_wp, 8.5e-3_wp, 'flange root, yaw +8.5 mrad')
  call lateral_sweep(6.5e-3_wp, 8.5e-3_wp, 'flange, yaw +8.5 mrad')
  call lateral_sweep(5.5e-3_wp, 0.0_wp, 'tread/flange root, no yaw')
  call yaw_sweep(5.2e-3_wp, 'yaw -15..+15 mrad at 5.2 mm')
  call yaw_sweep(6.0e-3_wp, 'yaw -15..+15 mrad at 6.0 mm')

  call test_summary('test_flange_onset_continuity')

contains

  !> Left-wheel normal force resultant f (track frame) and its moment m about the
  !> wheelset centre, Hertz on every patch.
  subroutine wheel_forces(y, z, phi, psi, f, m, np)
    real(wp), intent(in) :: y, z, phi, psi
    real(wp), intent(out) :: f(3), m(3)
    integer, intent(out) :: np
    type(wheel_contact_t) :: res
    type(hertz_patch_t) :: hp
    real(wp) :: fk(3), r(3)
    integer :: k
    call wheel_contact(geo, SIDE_LEFT, y, z, phi, psi, res)
    f = 0; m = 0
    np = res%n_patches
    do k = 1, res%n_patches
      associate (p => res%patch(k))
        call hertz_from_penetration(hertz, [p%curv_wheel_roll, p%curv_wheel_lat, p%curv_rail_roll, &
                                    p%curv_rail_lat], p%penetration, hp)
        if (.not. (hp%normal_force >= 0 .and. hp%normal_force < 1.0e7_wp)) then
          write (*, '(a,es12.4)') 'FAIL  non-finite or absurd normal force ', hp%normal_force
          call fail()
          cycle
        end if
        fk = hp%normal_force * p%normal
        r = p%point_rail - [0.0_wp, y, z]
        f = f + fk
        m = m + [r(2) * fk(3) - r(3) * fk(2), r(3) * fk(1) - r(1) * fk(3), r(1) * fk(2) - r(2) * fk(1)]
      end associate
    end do
  end subroutine wheel_forces

  subroutine lateral_sweep(y0, psi, what)
    real(wp), intent(in) :: y0, psi
    character(len=*), intent(in) :: what
    real(wp) :: z, phi, y, f(6, 0:nstep), m(3)
    integer :: i, np, npmax, nlast
    ! height and roll of the rigid contact at y0, lowered by 30 um (~ the Hertz approach
    ! under a wheel load): the sweep then runs from tread-only into deep flange contact
    call rigid_contact(geo, y0, psi, z, phi, error)
    if (allocated(error)) error stop error%message
    z = z - 3.0e-5_wp
    npmax = 0
    do i = 0, nstep
      y = y0 - 1.0e-3_wp + 2.0e-3_wp * i / nstep
      call wheel_forces(y, z, phi, psi, f(1:3, i), m, np)
      f(4:6, i) = m
      npmax = max(npmax, np)
      nlast = i
      if (norm2(f(1:3, i)) > force_limit) exit
    end do
    call check_continuous(f(:, 0:nlast), 'lateral sweep, ' // what, npmax)
  end subroutine lateral_sweep

  subroutine yaw_sweep(y0, what)
    real(wp), intent(in) :: y0
    character(len=*), intent(in) :: what
    real(wp) :: z, phi, psi, f(6, 0:nstep), m(3)
    integer :: i, np, npmax
    call rigid_contact(geo, y0, 0.0_wp, z, phi, error)
    if (allocated(error)) error stop error%message
    z = z - 3.0e-5_wp
    npmax = 0
    do i = 0, nstep
      psi = -1.5e-2_wp + 3.0e-2_wp * i / nstep
      call wheel_forces(y0, z, phi, psi, f(1:3, i), m, np)
      f(4:6, i) = m
      npmax = max(npmax, np)
    end do
    call check_continuous(f, 'yaw sweep, ' // what, npmax)
  end subroutine yaw_sweep

  !> Jump detector. A jump J at step i adds J to increment i alone; a kink (a patch
  !> opening, a share reaching 0 or 1) puts increment i between its neighbours, and a smooth
  !> function changes its increments gradually. So the excess
  !>    e_i = |d_i - (d_(i-1) + d_(i+1))/2| - |d_(i+1) - d_(i-1)|/2
  !> is <= 0 for kinks, O(h^3 f''') for smooth functions, and ~ |J| at a jump. The largest
  !> excess must stay below `jump_tolerance` of the largest |value| of its group (force,
  !> moment). Measured: the one-patch-per-run rule jumps by 0.12 of the force at the tread /
  !> flange-root merge, the chord-slope depth conversion by ~1e-3 on the flange.
  subroutine check_continuous(f, what, npmax)
    real(wp), intent(in) :: f(:, 0:)
    character(len=*), intent(in) :: what
    integer, intent(in) :: npmax
    real(wp) :: df(size(f, 1), size(f, 2) - 1), scale, worst, e
    integer :: c, i, n, iworst, cworst, g
    n = size(f, 2) - 1
    df = f(:, 1:n) - f(:, 0:n - 1)
    worst = 0; iworst = 0; cworst = 0
    do c = 1, size(f, 1)
      g = 3 * ((c - 1) / 3)
      scale = maxval(abs(f(g + 1:g + 3, :)))
      if (.not. (scale > 0)) cycle
      do i = 2, n - 1
        e = abs(df(c, i) - 0.5_wp * (df(c, i - 1) + df(c, i + 1))) - 0.5_wp * abs(df(c, i + 1) - df(c, i - 1))
        if (e / scale > worst) then
          worst = e / scale; iworst = i; cworst = c
        end if
      end do
    end do
    if (worst <= jump_tolerance .and. maxval(abs(f(1:3, n))) > 0) then
      write (*, '(a,es9.2,a,i0,a,i0,a)') 'ok    ' // what // ': largest jump / scale ', worst, &
        ' (', n, ' steps, up to ', npmax, ' patches)'
    else
      write (*, '(a,es9.2,a,i0,a,i0)') 'FAIL  ' // what // ': largest jump / scale ', worst, &
        ' at step ', iworst, ' (or no contact); patches up to ', npmax
      call fail()
      if (iworst > 0) write (*, '(a,i0,a,4es14.6)') '      component ', cworst, ', values around: ', &
        f(cworst, iworst - 2:iworst + 1)
    end if
  end subroutine check_continuous

end program test_flange_onset_continuity
