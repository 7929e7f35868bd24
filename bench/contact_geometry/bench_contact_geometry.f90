!> Cost of one wheel's contact geometry per call: strip model (analytic S1002 on 60E1 at
!> 1:40, three point spacings) and knife-edge model, centred (tread only) and at 7 mm
!> shift with and without yaw (tread + flange), and the rigid-contact search.
!> Prints a markdown table (bench/contact_geometry/run.sh puts it in docs/performance.md).
program bench_contact_geometry
  use, intrinsic :: iso_fortran_env, only: int64, compiler_version
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_profile, only: profile_t
  use rd_profile_analytic, only: s1002_profile, rail_head_profile, RAIL_60E1
  use rd_contact_surfaces, only: track_placement_t, surface_options_t
  use rd_contact_geometry, only: contact_geometry_t, build_strip_contact, build_knife_edge_contact, wheel_contact, SIDE_LEFT
  use rd_knife_edge_contact, only: knife_edge_t
  use rd_contact_patch, only: wheel_contact_t
  use rd_rigid_contact, only: rigid_contact
  implicit none
  type(profile_t) :: wpf, rpf
  type(error_t), allocatable :: error
  type(track_placement_t) :: pl
  type(surface_options_t) :: opt
  type(contact_geometry_t) :: geo
  type(knife_edge_t) :: knife
  real(wp), parameter :: spacing(3) = [2.0e-4_wp, 1.0e-4_wp, 0.5e-4_wp]
  real(wp) :: t_ns, t_knife, sink
  integer :: i
  character(len=160) :: row

  call s1002_profile(wpf, 5.0e-5_wp, error)
  call rail_head_profile(RAIL_60E1, rpf, 5.0e-5_wp, error)
  sink = 0
  write (*, '(a)') '### Contact geometry (bench/contact_geometry)'
  write (*, '(a)') ''
  write (*, '(a)') 'Cost of one wheel per call (`wheel_contact`, left wheel), Release build, ' // compiler_version() // '.'
  write (*, '(a)') 'Strip model: analytic S1002 on 60E1 at 1:40; wheelset at rigid contact lowered by 20 um.'
  write (*, '(a)') 'Points = wheel points / rail lines after resampling; "7 mm + yaw" has 16.8 mrad of yaw;'
  write (*, '(a)') '"two-point" is the shift (given) just past 4.5 mm where rigid contact touches tread and flange root.'
  write (*, '(a)') ''
  write (*, '(a)') '| model | spacing [mm] | points (wheel/rail) | pose | patches | us per call | rigid contact [us] |'
  write (*, '(a)') '|---|---:|---:|---|---:|---:|---:|'
  do i = 1, size(spacing)
    opt%wheel_spacing = spacing(i); opt%rail_spacing = spacing(i)
    call build_strip_contact(geo, wpf, rpf, pl, opt, error)
    if (allocated(error)) error stop error%message
    call one('strip', 0.0_wp, 0.0_wp, 'centred (tread)')
    call one('strip', 7.0e-3_wp, 0.0_wp, '7 mm (flange)')
    call one('strip', 7.0e-3_wp, 16.8e-3_wp, '7 mm + yaw (flange)')
    call one('strip', 4.5e-3_wp, 0.0_wp, 'two-point (tread + flange root)', two=.true.)
  end do
  knife%cone_angle = 0.05_wp; knife%r0 = 0.46_wp
  call build_knife_edge_contact(geo, knife, error)
  call one('knife edge', 0.0_wp, 0.0_wp, 'centred')
  call one('knife edge', 7.0e-3_wp, 16.8e-3_wp, '7 mm + yaw')
  write (*, '(a)') ''
  write (*, '(a,es10.3,a)') '(checksum ', sink, ')'
contains
  subroutine one(model, y, psi, pose, two)
    character(len=*), intent(in) :: model, pose
    real(wp), intent(in) :: y, psi
    logical, intent(in), optional :: two
    real(wp) :: z, phi, t_rigid, yy
    character(len=40) :: note
    type(wheel_contact_t) :: res
    integer(int64) :: c0, c1, rate
    integer :: n, k, reps
    yy = y
    if (present(two)) then        ! the shift past 4.5 mm where tread and flange root both touch
      do k = 0, 200
        yy = y + 5.0e-6_wp * k
        call rigid_contact(geo, yy, psi, z, phi, error)
        call wheel_contact(geo, SIDE_LEFT, yy, z - 2.0e-5_wp, phi, psi, res)
        if (res%n_patches >= 2) exit
      end do
    end if
    call system_clock(c0, rate)
    reps = 0
    do
      call rigid_contact(geo, yy, psi, z, phi, error)
      reps = reps + 1
      call system_clock(c1)
      if (real(c1 - c0, wp) / rate > 0.2_wp .or. reps >= 2000) exit
    end do
    t_rigid = 1.0e6_wp * real(c1 - c0, wp) / rate / reps
    note = ''
    if (present(two)) write (note, '(" at ",f6.3," mm")') 1000 * yy
    n = 0
    call system_clock(c0)
    do
      do k = 1, 200
        call wheel_contact(geo, SIDE_LEFT, yy, z - 2.0e-5_wp + 1.0e-12_wp * k, phi, psi, res)
        sink = sink + res%max_penetration
      end do
      n = n + 200
      call system_clock(c1)
      if (real(c1 - c0, wp) / rate > 0.3_wp) exit
    end do
    t_ns = 1.0e6_wp * real(c1 - c0, wp) / rate / n
    if (model == 'strip') then
      write (row, '("| ",a," | ",f5.2," | ",i0,"/",i0," | ",a," | ",i0," | ",f9.2," | ",f9.1," |")') model, &
        1000 * opt%wheel_spacing, geo%wheel%n, geo%rail%n, pose // trim(note), res%n_patches, t_ns, t_rigid
    else
      t_knife = t_ns
      write (row, '("| ",a," | - | - | ",a," | ",i0," | ",f9.3," | ",f9.1," |")') model, pose, res%n_patches, t_ns, t_rigid
    end if
    write (*, '(a)') trim(row)
  end subroutine one
end program bench_contact_geometry
