!> `raildyn track`: the alignment of a scene's track sampled along sigma, written to
!> HDF5 (and optionally CSV and a plot), so users can check a deck's track before
!> running a vehicle on it.
module rd_track_export
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_IO
  use rd_track_point, only: track_point_t
  use rd_hdf5_writer, only: h5_writer_t
  use rd_scene, only: scene_t
  use rd_build_info, only: python_command, shell_quote
  implicit none
  private
  public :: export_track

  integer, parameter :: nchan = 6
  character(len=*), parameter :: names(nchan) = [character(len=24) :: &
    'track/position', 'track/angles', 'track/curvature', 'track/superelevation', &
    'track/cant_angle', 'track/gradient']

contains

  !> Sample the track every `step` metres (0: about 2000 samples, at most 1 m apart).
  subroutine export_track(scene, path, csv, plot, step, error)
    type(scene_t), intent(in) :: scene
    character(len=*), intent(in) :: path, csv, plot
    real(wp), intent(in) :: step
    type(error_t), allocatable, intent(out) :: error
    type(h5_writer_t) :: writer
    type(track_point_t) :: p
    real(wp) :: ds, total
    integer :: i, n, id(nchan), unit, ios, status
    character(len=*), parameter :: units(nchan) = [character(len=8) :: 'm', 'rad', '1/m', 'm', 'rad', '1']
    character(len=*), parameter :: comps(nchan) = [character(len=24) :: 'X Y Z', 'heading pitch cant', &
                                                    'kappa', 'h', 'phi', 'dz/dsigma']
    character(len=*), parameter :: descr(nchan) = [character(len=80) :: &
      'centreline position, fixed frame', 'heading, pitch (-atan gradient), cant angle', &
      'horizontal curvature, > 0 for a left-hand curve', 'left rail over right rail', &
      'cant angle, > 0 lifts the left rail', 'vertical gradient']

    total = scene%track%length()
    ds = step
    if (ds <= 0) ds = min(1.0_wp, total / 2000)
    n = max(2, ceiling(total / ds) + 1)

    call writer%open(path, error, axis_name='sigma', axis_unit='m', &
                     axis_description='arc length along the track (horizontal projection)')
    if (allocated(error)) return
    do i = 1, nchan
      call writer%add_series(names(i), merge(3, 1, i <= 2), trim(units(i)), trim(descr(i)), id(i), &
                             error, component_names=trim(comps(i)))
      if (allocated(error)) return
    end do
    if (len(csv) > 0) then
      open (newunit=unit, file=csv, status='replace', action='write', iostat=ios)
      if (ios /= 0) then
        call make_error(error, RD_ERR_IO, 'cannot write ' // csv)
        return
      end if
      write (unit, '(a)') '# raildyn track alignment; SI units (m, rad, 1/m)'
      write (unit, '(a)') 'sigma,x,y,z,heading,pitch,cant,curvature,superelevation'
    end if
    do i = 1, n
      p = scene%track%evaluate(min(total, (i - 1) * ds))
      call writer%set(id(1), p%r, error); if (allocated(error)) return
      call writer%set(id(2), [p%heading, p%grade_angle, p%cant_angle], error); if (allocated(error)) return
      call writer%set(id(3), [p%curvature], error); if (allocated(error)) return
      call writer%set(id(4), [p%superelevation], error); if (allocated(error)) return
      call writer%set(id(5), [p%cant_angle], error); if (allocated(error)) return
      call writer%set(id(6), [-tan(p%grade_angle)], error); if (allocated(error)) return
      call writer%end_step(p%sigma, error); if (allocated(error)) return
      if (len(csv) > 0) write (unit, '(*(es22.14e3,:,","))') p%sigma, p%r, p%heading, p%grade_angle, &
        p%cant_angle, p%curvature, p%superelevation
    end do
    if (len(csv) > 0) close (unit)
    call writer%close('completed', total, 0.0_wp, error)
    if (allocated(error)) return
    if (len(plot) > 0) then
      call execute_command_line(python_command() // ' -m raildyn.plots track ' // shell_quote(path) // &
                                ' ' // shell_quote(plot), exitstat=status)
      if (status /= 0) call make_error(error, RD_ERR_IO, 'plotting ' // plot // ' failed (needs ' // &
                                       'Python 3 with h5py and matplotlib; the HDF5 file was written)')
    end if
  end subroutine export_track

end module rd_track_export
