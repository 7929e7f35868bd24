!> Online strip geometry replayed on wheelset poses: both wheels of the Manchester wheelset
!> (S1002 / 60E1 1:40, strips 0.2 mm: the acceptance deck's wheelsets) at each pose (y, z,
!> roll, yaw; one a line) of a text file (run.sh takes them from a run of the acceptance
!> deck: bench/geometry_replay/poses.py), CPU time per wheel (less exposed to the other jobs
!> of a shared machine than the wall time), best of REPEATS passes; prints a
!> markdown table. DUMP: every result (patch counts, largest penetration, every patch field)
!> written bitwise to that file, so that two builds can be compared exactly (cmp;
!> bench/compare_builds.py --replay).
!>
!>   bench_geometry_replay POSES [REPEATS] [DUMP]
program bench_geometry_replay
  use, intrinsic :: iso_fortran_env, only: compiler_version
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_contact_geometry, only: contact_geometry_t, wheelset_contact
  use rd_contact_patch, only: wheel_contact_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t, build_contact_geometry
  implicit none
  type(wheelset_contact_spec_t) :: spec
  type(contact_geometry_t) :: geo
  type(error_t), allocatable :: error
  type(wheel_contact_t) :: left, right
  real(wp), allocatable :: poses(:, :)
  real(wp) :: sink, best, t, patches, t0, t1
  character(len=512) :: arg
  integer :: lu, n, i, k, ios, reps, r, du
  real(wp) :: p(4)

  call get_command_argument(1, arg)
  open (newunit=lu, file=trim(arg), status='old', action='read')
  n = 0
  do
    read (lu, *, iostat=ios) p
    if (ios /= 0) exit
    n = n + 1
  end do
  rewind (lu)
  allocate (poses(4, n))
  do i = 1, n
    read (lu, *) poses(:, i)
  end do
  close (lu)
  reps = 3
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg); read (arg, *) reps
  end if
  spec%wheel_profile = 's1002'
  spec%rail_profile = '60e1'
  call build_contact_geometry(spec, geo, error)
  if (allocated(error)) error stop 'geometry'
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    open (newunit=du, file=trim(arg), access='stream', form='unformatted', status='replace')
    do i = 1, n
      call wheelset_contact(geo, poses(1, i), poses(2, i), poses(3, i), poses(4, i), left, right, error)
      if (allocated(error)) error stop 'pose'
      write (du) left%n_patches, left%max_penetration, right%n_patches, right%max_penetration
      do k = 1, left%n_patches
        write (du) left%patch(k)
      end do
      do k = 1, right%n_patches
        write (du) right%patch(k)
      end do
    end do
    close (du)
  end if
  sink = 0
  patches = 0
  best = huge(1.0_wp)
  do r = 1, reps
    call cpu_time(t0)
    do i = 1, n
      call wheelset_contact(geo, poses(1, i), poses(2, i), poses(3, i), poses(4, i), left, right, error)
      sink = sink + left%max_penetration + right%max_penetration
      if (r == 1) patches = patches + left%n_patches + right%n_patches
    end do
    call cpu_time(t1)
    t = t1 - t0
    best = min(best, t)
  end do
  write (*, '(a)') '### Geometry replay (bench/geometry_replay)'
  write (*, '(a)') ''
  write (*, '(a)') 'The online strip geometry (`wheelset_contact`, both wheels) at wheelset poses of a run of the'
  write (*, '(a)') 'acceptance deck (inputs/manchester_v1_tc1.nml: its four wheelsets at every 20 ms output row,'
  write (*, '(a)') 'bench/geometry_replay/poses.py), S1002 / 60E1 1:40, strips 0.2 mm; Release build, ' // &
    compiler_version() // '.'
  write (*, '(a)') ''
  write (*, '(a)') '| poses | wheel evaluations | patches per wheel | CPU us per wheel (best of passes) | passes |'
  write (*, '(a)') '|---:|---:|---:|---:|---:|'
  write (*, '(a,i0,a,i0,a,f6.2,a,f8.2,a,i0,a)') '| ', n, ' | ', 2 * n, ' | ', patches / (2 * n), ' | ', &
    best / (2 * n) * 1.0e6_wp, ' | ', reps, ' |'
  write (*, '(a)') ''
  write (*, '(a,es12.5,a)') '(checksum ', sink, ')'
end program bench_geometry_replay
