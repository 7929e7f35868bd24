!> The scene's output table: every channel defined by one row of `rows` (name, unit, column
!> names, description) and filled by the same row from the outputs of one explicit evaluation
!> at the current time and state (calc_output, OpenFAST's "calc output" step), then written
!> as one record (write_step, write_record) with the &output groups that select what is written.
submodule (rd_scene) rd_scene_output_table
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use rd_point_motion, only: compute_point_motion
  use rd_body_spec, only: deviation_from_spin
  use rd_body_kinematics, only: fixed_angles
  use rd_wheel_contact_result, only: MAX_PATCHES, patch_channel_names, patch_channel_units, &
    wheel_channel_names, wheel_channel_units, patch_channel_values, wheel_channel_values
  implicit none

  !> What a row repeats over (its channels' path prefix): the vehicle, each track frame, body,
  !> element, wheelset, wheel of a wheelset, patch slot of a wheel, sensor, and the state.
  integer, parameter :: VEHICLE = 1, FRAME = 2, BODY = 3, ELEMENT = 4, WHEELSET = 5, WHEEL = 6, &
                        PATCH = 7, SENSOR = 8, STATE = 9

  !> One row per channel. unit: one SI token or one per column (docs/output.md); '*': the
  !> unit and column names come from the contact's channel lists (rd_wheel_contact_result) or
  !> the state's layout (multibody%state_layout); '#' in a description: the sensor's name.
  type :: channel_row_t
    integer :: each
    character(len=24) :: name
    character(len=48) :: unit
    character(len=48) :: components
    character(len=200) :: description
  end type channel_row_t

  type(channel_row_t), parameter :: rows(*) = [ &
    channel_row_t(VEHICLE, 'speed', 'm/s', 'V', 'running speed V'), &
    channel_row_t(VEHICLE, 'distance', 'm', 'sigma', 'arc length sigma of the vehicle reference point'), &
    channel_row_t(FRAME, 'sigma', 'm', 'sigma', 'arc length of the track frame'), &
    channel_row_t(FRAME, 'position', 'm', 'X Y Z', 'track frame origin in the fixed frame'), &
    channel_row_t(FRAME, 'angles', 'rad', 'heading pitch cant', 'heading, pitch (-atan gradient) and cant angle of the track frame'), &
    channel_row_t(FRAME, 'curvature', '1/m', 'kappa', 'horizontal curvature, > 0 for a left-hand curve'), &
    channel_row_t(FRAME, 'superelevation', 'm', 'h', 'left rail over right rail'), &
    channel_row_t(FRAME, 'angular_velocity', 'rad/s', 'wx wy wz', 'angular velocity of the moving track frame, track components'), &
    channel_row_t(BODY, 'position_track', 'm m m rad rad rad', 'x y z yaw roll pitch', &
                  'coordinates q relative to the track frame (wheelset pitch: spin deviation beta)'), &
    channel_row_t(BODY, 'velocity_track', 'm/s m/s m/s rad/s rad/s rad/s', 'vx vy vz yaw_rate roll_rate pitch_rate', &
                  'dq/dt relative to the track frame'), &
    channel_row_t(BODY, 'acceleration_track', 'm/s^2 m/s^2 m/s^2 rad/s^2 rad/s^2 rad/s^2', &
                  'ax ay az yaw_acc roll_acc pitch_acc', 'd2q/dt2 relative to the track frame'), &
    channel_row_t(BODY, 'position_fixed', 'm', 'X Y Z', 'centre of mass, fixed frame'), &
    channel_row_t(BODY, 'angles_fixed', 'rad', 'yaw roll pitch', 'Z-X-Y angles of the body frame relative to the fixed frame'), &
    channel_row_t(BODY, 'velocity_fixed', 'm/s', 'vX vY vZ', 'velocity of the centre of mass, fixed frame'), &
    channel_row_t(BODY, 'angular_velocity_fixed', 'rad/s', 'wX wY wZ', 'angular velocity, fixed frame'), &
    channel_row_t(BODY, 'angular_velocity_body', 'rad/s', 'wx wy wz', 'angular velocity, body frame'), &
    channel_row_t(BODY, 'acceleration_fixed', 'm/s^2', 'aX aY aZ', 'acceleration of the centre of mass, fixed frame'), &
    channel_row_t(ELEMENT, 'deflection', 'm', 'dx dy dz', 'deflection in element axes (torsion: rad)'), &
    channel_row_t(ELEMENT, 'force_element', 'N', 'fx fy fz', 'force on body 2 in element axes (torsion: moment, N*m)'), &
    channel_row_t(ELEMENT, 'force_fixed', 'N', 'fX fY fZ', 'force on body 2, fixed frame'), &
    channel_row_t(WHEELSET, 'summary', '1 N', 'derailment_quotient guiding_force_sum', &
                  'derailment quotient (max Y/Q of the wheels) and sum of the guiding forces Y'), &
    channel_row_t(WHEELSET, 'rail_offsets', 'm', 'dy_left dz_left dy_right dz_right', &
                  'rails displaced by the track irregularities at the wheelset, track frame (zeros on the design track)'), &
    channel_row_t(WHEEL, 'wheel', '*', '*', 'wheel: patches, force on the wheel in track components (longitudinal, Y, Q), ' // &
                  'Y/Q (> 0 towards flange climb), largest penetration'), &
    channel_row_t(PATCH, 'patch', '*', '*', &
                  'contact patch (zeros when absent): geometry, normal force, creepages, creep forces on the wheel (contact frame)'), &
    channel_row_t(SENSOR, 'position_track', 'm', 'x y z', &
                  'position of sensor # (fixed to its body) relative to its body''s track frame, track components'), &
    channel_row_t(SENSOR, 'position_fixed', 'm', 'X Y Z', 'position of sensor # (fixed to its body), fixed frame'), &
    channel_row_t(SENSOR, 'velocity_track', 'm/s', 'vx vy vz', 'absolute velocity of sensor # (fixed to its body), track-frame components'), &
    channel_row_t(SENSOR, 'acceleration_track', 'm/s^2', 'ax ay az', &
                  'absolute acceleration of sensor # (fixed to its body), track-frame components'), &
    channel_row_t(SENSOR, 'velocity_body', 'm/s', 'vx vy vz', 'absolute velocity of sensor # (fixed to its body), body-frame components'), &
    channel_row_t(SENSOR, 'acceleration_body', 'm/s^2', 'ax ay az', &
                  'absolute acceleration of sensor # (fixed to its body), body-frame components'), &
    channel_row_t(SENSOR, 'specific_force_body', 'm/s^2', 'fx fy fz', &
                  'accelerometer reading of sensor # (fixed to its body): acceleration minus gravity, body-frame components'), &
    channel_row_t(STATE, 'y', '*', '*', 'integrator state y = [q_f; nu_f; x_el] (free coordinates, generalized velocities, ' // &
                  'element states: rd_multibody); raildyn run --restart continues from a row of it')]

contains

  !> Every row's channels, instance after instance in the order of the file's groups.
  module procedure register_outputs
    integer :: k, side, j
    character(len=5), parameter :: sides(2) = ['left ', 'right']
    call self%outputs%clear()
    call add_rows(VEHICLE, 'vehicle/', [0, 0, 0])
    do k = 1, size(self%frame_offsets)
      call add_rows(FRAME, 'track/frames/' // trim(int_text(k)) // '/', [k, 0, 0])
    end do
    if (associated(self%mbs)) then
      do k = 1, self%nbodies
        call add_rows(BODY, 'bodies/' // self%mbs%bodies(k)%name // '/', [k, 0, 0])
      end do
      do k = 1, self%mbs%element_count()
        call add_rows(ELEMENT, 'elements/' // self%mbs%elements(k)%e%name // '/', [k, 0, 0])
      end do
    end if
    if (associated(self%contact)) then
      do k = 1, size(self%wheelset_names)
        call add_rows(WHEELSET, 'wheelsets/' // trim(self%wheelset_names(k)) // '/', [k, 0, 0])
        do side = 1, 2
          call add_rows(WHEEL, 'wheelsets/' // trim(self%wheelset_names(k)) // '/' // trim(sides(side)) // '/', [k, side, 0])
          do j = 1, MAX_PATCHES
            call add_rows(PATCH, 'wheelsets/' // trim(self%wheelset_names(k)) // '/' // trim(sides(side)) // '/', [k, side, j])
          end do
        end do
      end do
    end if
    do k = 1, size(self%sensors)
      call add_rows(SENSOR, 'sensors/' // self%sensors(k)%name // '/', [k, 0, 0])
    end do
    if (associated(self%mbs)) call add_rows(STATE, 'state/', [0, 0, 0])
  contains
    !> The channels of the rows of kind `each` for one instance (a patch slot: its number after the name).
    subroutine add_rows(each, prefix, instance)
      integer, intent(in) :: each, instance(3)
      character(len=*), intent(in) :: prefix
      character(len=:), allocatable :: name, units, components, description
      integer :: r, id, at
      do r = 1, size(rows)
        if (rows(r)%each /= each) cycle
        name = prefix // trim(rows(r)%name)
        units = trim(rows(r)%unit)
        components = trim(rows(r)%components)
        description = trim(rows(r)%description)
        select case (each)
        case (WHEEL)
          units = join(wheel_channel_units); components = join(wheel_channel_names)
        case (PATCH)
          units = join(patch_channel_units); components = join(patch_channel_names)
          name = name // trim(int_text(instance(3)))
        case (SENSOR)
          at = index(description, '#')
          description = description(:at - 1) // self%sensors(instance(1))%name // description(at + 1:)
        case (STATE)
          call self%mbs%state_layout(components, units)
        end select
        call self%outputs%add(name, count([(components(at:at) == ' ', at = 1, len(components))]) &
                              + merge(1, 0, len(components) > 0), units, description, components, id)
        self%outputs%channels(id)%source = [r, instance]
      end do
    end subroutine add_rows
  end procedure register_outputs

  !> The &output groups entry a channel belongs to: its first path element, except the
  !> contact patch slots ('patches') under 'wheelsets'.
  pure function channel_group(name) result(group)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: group
    group = name(1:index(name // '/', '/') - 1)
    if (group == 'wheelsets' .and. index(name, '/patch', back=.true.) > 0) group = 'patches'
  end function channel_group

  !> The channel is written to the results file (&output groups).
  module procedure channel_written
    integer :: g
    channel_written = .false.
    do g = 1, size(self%written_groups)
      if (self%written_groups(g)%s == channel_group(self%outputs%channels(i)%name)) channel_written = .true.
    end do
  end procedure channel_written

  pure function join(words) result(text)
    character(len=*), intent(in) :: words(:)
    character(len=:), allocatable :: text
    integer :: i
    text = trim(words(1))
    do i = 2, size(words)
      text = text // ' ' // trim(words(i))
    end do
  end function join

  !> Record the state at the current time.
  module procedure write_step
    call self%refresh_outputs(error)
    if (allocated(error)) return
    call self%note_sample()
    call self%write_record(self%outputs%packed(), error)
  end procedure write_step

  !> Write one record at the current time: the channels' values packed as
  !> rd_output_set%packed (the state, or an interval mean).
  module procedure write_record
    integer :: i, k, n
    if (self%writing) then
      call self%check_values(values, error)
      if (allocated(error)) return
      k = 0
      do i = 1, self%outputs%n
        n = size(self%outputs%channels(i)%values)
        if (self%series(i) > 0) call self%writer%set(self%series(i), values(k + 1:k + n), error)
        if (allocated(error)) return
        k = k + n
      end do
      call self%writer%end_step(self%t, error)
      if (allocated(error)) return
    end if
    call self%safety%add_record(values)
    self%output_steps = self%output_steps + 1
  end procedure write_record

  !> Count the sample just refreshed into the run's statistics: bodies' distance from their
  !> track frames (rd_frame_drift), wheels without any contact patch, largest vertical
  !> wheel force.
  module procedure note_sample
    integer :: w, side
    if (allocated(self%y)) call self%drift%note(self%y)
    if (.not. associated(self%contact)) return
    self%contact_samples = self%contact_samples + 1
    do w = 1, size(self%wheelset_names)
      do side = 1, 2
        associate (wheel => self%contact%results(w)%wheel(side))
          if (wheel%n_patches == 0) self%samples_without_contact(side, w) = self%samples_without_contact(side, w) + 1
          self%max_sampled_q(side, w) = max(self%max_sampled_q(side, w), wheel%force_track(3))
        end associate
      end do
    end do
  end procedure note_sample

  !> Error naming the first channel of the packed values that holds a non-finite number.
  module procedure check_values
    integer :: i, k, n
    k = 0
    do i = 1, self%outputs%n
      n = size(self%outputs%channels(i)%values)
      if (.not. all(ieee_is_finite(values(k + 1:k + n)))) then
        call make_error(error, RD_ERR_RUNTIME, 'non-finite value in output ' // &
                        self%outputs%channels(i)%name // ' at t = ' // trim(real_text(self%t)))
        return
      end if
      k = k + n
    end do
  end procedure check_values

  !> OpenFAST's "calc output" step for the scene: the outputs at its time and state, from
  !> one evaluation of the multibody there (multibody%calc_output), whose error is returned.
  module procedure calc_output
    integer :: s
    out%speed = self%speed%speed(self%t)
    out%sigma = self%vehicle_sigma(self%t)
    out%frames = [(self%track%evaluate(out%sigma + self%frame_offsets(s)), s = 1, size(self%frame_offsets))]
    if (self%nbodies == 0) return
    call self%mbs%calc_output(self%t, self%y, out%mbs, error)
    if (allocated(error)) return
    if (associated(self%contact)) out%contact = self%contact%results
    out%sensors = [(compute_point_motion(out%mbs%bodies(self%sensors(s)%body), self%sensors(s)%position, &
                    self%mbs%gravity), s = 1, size(self%sensors))]
  end procedure calc_output

  !> Every channel filled by its row (channel%source: row, instance) from calc_output.
  module procedure refresh_outputs
    type(scene_output_t) :: out
    integer :: i
    call self%calc_output(out, error)
    if (allocated(error)) return
    do i = 1, self%outputs%n
      associate (r => self%outputs%channels(i)%source(1), k => self%outputs%channels(i)%source(2:4), &
                 v => self%outputs%channels(i)%values)
      v = ieee_value(v, ieee_quiet_nan)   ! a row without a fill below: non-finite, refused when written
      select case (rows(r)%each)
      case (VEHICLE)
        v = merge(out%speed, out%sigma, rows(r)%name == 'speed')
      case (FRAME)
        associate (p => out%frames(k(1)))
          select case (rows(r)%name)
          case ('sigma'); v = p%sigma
          case ('position'); v = p%r
          case ('angles'); v = [p%heading, p%grade_angle, p%cant_angle]
          case ('curvature'); v = p%curvature
          case ('superelevation'); v = p%superelevation
          case ('angular_velocity'); v = out%speed * p%omega
          end select
        end associate
      case (BODY)
        ! docs/conventions.md: a wheelset's pitch output is the spin deviation from nominal
        ! rolling, beta = theta - s(t)/r0 (and its rates), not the spin angle
        associate (b => out%mbs%bodies(k(1)), spin => self%mbs%bodies(k(1))%is_wheelset, &
                   r0 => self%mbs%bodies(k(1))%r0, speed => self%mbs%speed)
          select case (rows(r)%name)
          case ('position_track'); v = b%q; if (spin) v(6) = deviation_from_spin(v(6), speed%distance(self%t), r0)
          case ('velocity_track'); v = b%qdot; if (spin) v(6) = deviation_from_spin(v(6), speed%speed(self%t), r0)
          case ('acceleration_track'); v = b%qddot; if (spin) v(6) = deviation_from_spin(v(6), speed%acceleration(self%t), r0)
          case ('position_fixed'); v = b%r
          case ('angles_fixed'); v = fixed_angles(b%rot)
          case ('velocity_fixed'); v = b%v
          case ('angular_velocity_fixed'); v = b%omega
          case ('angular_velocity_body'); v = b%omega_body
          case ('acceleration_fixed'); v = b%acc
          end select
        end associate
      case (ELEMENT)
        associate (e => out%mbs%elements(k(1)))
          select case (rows(r)%name)
          case ('deflection'); v = e%deflection
          case ('force_element'); v = e%force_local
          case ('force_fixed'); v = e%force
          end select
        end associate
      case (WHEELSET)
        associate (res => out%contact(k(1)))
          if (rows(r)%name == 'summary') v = [res%derailment_quotient, res%guiding_force_sum]
          if (rows(r)%name == 'rail_offsets') v = res%rail_offsets
        end associate
      case (WHEEL)
        call wheel_channel_values(out%contact(k(1))%wheel(k(2)), v)
      case (PATCH)
        call patch_channel_values(out%contact(k(1))%wheel(k(2)), k(3), v)
      case (SENSOR)
        associate (m => out%sensors(k(1)))
          select case (rows(r)%name)
          case ('position_track'); v = m%position_track
          case ('position_fixed'); v = m%position_fixed
          case ('velocity_track'); v = m%velocity_track
          case ('acceleration_track'); v = m%acceleration_track
          case ('velocity_body'); v = m%velocity_body
          case ('acceleration_body'); v = m%acceleration_body
          case ('specific_force_body'); v = m%specific_force_body
          end select
        end associate
      case (STATE)
        v = self%y
      end select
      end associate
    end do
  end procedure refresh_outputs

end submodule rd_scene_output_table
