!> Cost of one call of the whole per-wheelset contact pipeline (both wheels: geometry,
!> Hertz, creepages, creep law, loads and outputs) = wheelset_contact_t%evaluate, for
!> the contact models and creep laws a scene can choose. The wheelset sweeps a lateral
!> shift of -6..6 mm with 2.4 mrad/mm yaw (as Manchester A-2.2) at 20 m/s, lowered 20 um
!> below rigid contact, so tread and flange contacts are both in the mix. Prints a
!> markdown table (run.sh writes it into docs/performance.md).
program bench_contact_pipeline
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_track_point, only: track_point_t
  use rd_body_kinematics, only: body_kinematics_t, compute_body_kinematics
  use rd_rigid_contact, only: rigid_contact
  use rd_contact_patch, only: wheel_contact_t
  use rd_contact_geometry, only: wheelset_contact
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_wheelset_contact, only: wheelset_contact_t
  implicit none
  integer, parameter :: npose = 49
  real(wp), parameter :: v = 20.0_wp, r0 = 0.46_wp
  type(wheelset_contact_spec_t) :: spec
  type(body_kinematics_t) :: kin(npose)
  character(len=40) :: label(6)
  real(wp) :: cost(6), geo_cost
  integer :: k

  label = [character(len=40) :: 'knife-edge + linear', 'strips + linear', 'strips + FASTSIM 10 x 10', &
           'strips + FASTSIM 20 x 20', 'strips + Polach', 'strips: geometry alone']
  spec%body = 1
  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  spec%nominal_radius = r0
  spec%model = 'knife_edge'; spec%creep_law = 'linear'
  cost(1) = time_case(spec)
  spec%model = 'profile'
  cost(2) = time_case(spec)
  spec%creep_law = 'fastsim'; spec%creep_options%grid_nx = 10; spec%creep_options%grid_ny = 10
  cost(3) = time_case(spec)
  spec%creep_options%grid_nx = 20; spec%creep_options%grid_ny = 20
  cost(4) = time_case(spec)
  spec%creep_law = 'polach'
  cost(5) = time_case(spec, geo_cost)
  cost(6) = geo_cost

  write (*, '(a)') 'Contact pipeline per wheelset and call (both wheels: geometry, Hertz, creepages, creep law, loads),'
  write (*, '(a)') 'S1002 / 60E1 1:40 (analytic), strip spacing of rd_contact_surfaces defaults, 49 poses'
  write (*, '(a)') '(y = -6..6 mm, yaw 2.4 mrad/mm, 20 um below rigid contact); Release build, one core.'
  write (*, '(a)') ''
  write (*, '(a)') '| pipeline | us per call | relative to knife-edge + linear |'
  write (*, '(a)') '|---|---|---|'
  do k = 1, 6
    write (*, '(a,a,a,f10.2,a,f8.1,a)') '| ', trim(label(k)), ' |', cost(k), ' |', cost(k) / cost(1), ' |'
  end do

contains

  !> microseconds per evaluate() call, averaged over the poses and repeated to >= 0.3 s
  real(wp) function time_case(spec, geometry_cost) result(us)
    type(wheelset_contact_spec_t), intent(in) :: spec
    real(wp), intent(out), optional :: geometry_cost
    type(wheelset_contact_t) :: ws
    type(error_t), allocatable :: error
    type(track_point_t) :: tp
    type(wheel_contact_t) :: l, r
    real(wp) :: y, psi, z, phi, f(3), m(3), t0, t1, acc
    integer :: i, rep, nrep
    call ws%build([spec], 1, error)
    if (allocated(error)) error stop error%message
    tp%a = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    tp%dr = [1.0_wp, 0.0_wp, 0.0_wp]
    do i = 1, npose
      y = -6.0e-3_wp + 12.0e-3_wp * (i - 1) / (npose - 1)
      psi = 2.4_wp * y
      call rigid_contact(ws%models(1)%geo, y, psi, z, phi, error)
      if (allocated(error)) error stop error%message
      call compute_body_kinematics(kin(i), tp, v, 0.0_wp, [0.0_wp, y, z - 2.0e-5_wp, psi, phi, 0.0_wp], &
                                   [0.0_wp, 0.01_wp, 0.0_wp, 0.001_wp, 0.0_wp, v / r0], .true.)
    end do
    acc = 0
    nrep = 1
    do
      call cpu_time(t0)
      do rep = 1, nrep
        do i = 1, npose
          call ws%evaluate(1, 0.0_wp, kin(i), f, m, error)
          if (allocated(error)) error stop error%message
          acc = acc + f(3)
        end do
      end do
      call cpu_time(t1)
      if (t1 - t0 > 0.3_wp) exit
      nrep = nrep * 4
    end do
    us = 1.0e6_wp * (t1 - t0) / (nrep * npose)
    if (acc /= acc) write (*, '(a)') 'NaN'
    if (present(geometry_cost)) then
      nrep = 1
      do
        call cpu_time(t0)
        do rep = 1, nrep
          do i = 1, npose
            call wheelset_contact(ws%models(1)%geo, kin(i)%q(2), kin(i)%q(3), kin(i)%q(5), kin(i)%q(4), l, r, error)
            acc = acc + l%max_penetration
          end do
        end do
        call cpu_time(t1)
        if (t1 - t0 > 0.3_wp) exit
        nrep = nrep * 4
      end do
      geometry_cost = 1.0e6_wp * (t1 - t0) / (nrep * npose)
      if (acc /= acc) write (*, '(a)') 'NaN'
    end if
  end function time_case

end program bench_contact_pipeline
