!> Creep forces where a patch splits (rd_strip_contact split_run): the Manchester wheelset
!> (S1002 / 60E1 1:40, FASTSIM 10 x 10, friction 0.4, 4.4 m/s) yawed 15 mrad, height and roll
!> held, swept laterally through y = 6.193 mm where the flange-root bump of its left wheel
!> separates from the flange bump and a third patch appears.
!>
!> Oracle (independent of the code's numbers): a continuously differentiable function
!> sampled with a fine uniform step h has second differences ~ h^2 F'' of one size along the
!> sweep; a slope jump shows as one second difference far above the others (h |jump|), and
!> the cusp of an ellipse growing like share^(1/3) (creep forces with infinite slope, the
!> previous blending) as a much larger one. Checked: near the onset of the split, the largest
!> |second difference| of the wheel's summed creep forces Fx, Fy stays below `ratio_limit`
!> times their median over the sweep. Measured: 12 and 10 (the C1 smoothstep ramp of the
!> split fraction, whose second derivative jumps at the onset) with the centroid normal force;
!> 3.9 and 2.3 with the distributed one (default), whose patch loads are its strips' and
!> whose energy resolves the contact edge between strips (a strip energy delta_+^2 kinked at
!> each onset: 31 and 82; eased over 1 um: 7 and 15); the share^(2/3)-penetration patches with
!> a linear ramp gave 1362 and 1901.
program test_patch_split_smoothness
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  use rd_sweep_smoothness, only: window_median
  use rd_test_support, only: check, test_summary
  implicit none
  integer, parameter :: n = 800
  real(wp), parameter :: y0 = 6.185e-3_wp, y1 = 6.201e-3_wp, psi = 0.015_wp
  !> height and roll: rigid contact at y = 6.193 mm, yaw 15 mrad, lowered by 58 um
  real(wp), parameter :: z = 0.4601989_wp, phi = 6.795757e-4_wp
  real(wp), parameter :: speed = 4.4_wp, ratio_limit = 30
  type(wheelset_contact_spec_t) :: spec
  type(wheelset_contact_t) :: ws
  type(error_t), allocatable :: error
  type(track_point_t) :: tp
  type(body_kinematics_t) :: kin
  real(wp) :: f(3), m(3), creep(2, 0:n), d2(2, n - 1), y, worst(2), med(2)
  integer :: patches(0:n), i, k, onset

  call sweep('distributed')
  call sweep('centroid')
  call test_summary('test_patch_split_smoothness')

contains

  !> The sweep with the strip normal force `force` (the creep forces' patch loads and
  !> points follow it).
  subroutine sweep(force)
    character(len=*), intent(in) :: force
    type(wheelset_contact_t) :: ws       ! a model per force
    spec = wheelset_contact_spec_t()
    spec%body = 1
    spec%wheel_profile = 's1002'
    spec%rail_profile = '60e1'
    spec%friction = 0.4_wp
    spec%strip_normal_force = force
    spec%body = 1
    call ws%build([spec], 1, error)
    if (allocated(error)) error stop error%message
    tp%a = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    tp%dr = [1.0_wp, 0.0_wp, 0.0_wp]
    do i = 0, n
      y = y0 + (y1 - y0) * i / n
      call compute_body_kinematics(kin, tp, speed, 0.0_wp, [0.0_wp, y, z, psi, phi, 0.0_wp], &
                                   [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, speed / spec%nominal_radius], .true.)
      call ws%evaluate(1, 0.0_wp, kin, f, m, error)
      if (allocated(error)) error stop error%message
      associate (w => ws%results(1)%wheel(1))
        patches(i) = w%n_patches
        creep(:, i) = [sum(w%patch(1:w%n_patches)%fx), sum(w%patch(1:w%n_patches)%fy)]
      end associate
    end do
    onset = 0
    do i = 1, n
      if (patches(i) > patches(i - 1)) then
        onset = i
        exit
      end if
    end do
    if (onset == 0 .or. onset < 10 .or. onset > n - 10) then
      print '(a)', 'FAIL the sweep does not cross the split (no third patch appears inside it)'
      error stop 1
    end if
    print '(a,f10.6,a)', force // ': third patch from y = ', 1.0e3_wp * (y0 + (y1 - y0) * onset / n), ' mm'
    d2 = creep(:, 2:n) - 2 * creep(:, 1:n - 1) + creep(:, 0:n - 2)
    do k = 1, 2
      med(k) = window_median(abs(d2(k, :)), 1, n - 1, 0, -1)
      worst(k) = maxval(abs(d2(k, onset - 6:onset + 5)))
      print '(a,i1,a,es11.3,a,es11.3,a,f8.1)', force // ': creep force component ', k, ': largest |d2| at the onset ', &
        worst(k), ', median ', med(k), ', ratio ', worst(k) / med(k)
      call check(worst(k) <= ratio_limit * med(k), 'creep force component ' // achar(48 + k) // &
                 ' smooth where the patch splits (' // force // ' normal force): ratio below 30')
    end do
  end subroutine sweep


end program test_patch_split_smoothness
