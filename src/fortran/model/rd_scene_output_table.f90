!> The scene's output table: every channel registered once (register_outputs), filled
!> from the models at the current time (refresh_outputs) and written as one record
!> (write_step, write_record), with the &output groups that select what is written.
submodule (rd_scene) rd_scene_output_table
  implicit none

contains

  module procedure register_outputs
    integer :: k, id
    character(len=16) :: tag
    call self%outputs%clear()
    call self%outputs%add('vehicle/speed', 1, 'm/s', 'running speed V', 'V', id)
    call self%outputs%add('vehicle/distance', 1, 'm', &
                          'arc length sigma of the vehicle reference point', 'sigma', id)
    do k = 1, size(self%frame_offsets)
      write (tag, '(i0)') k
      associate (p => 'track/frames/' // trim(tag) // '/')
        call self%outputs%add(p // 'sigma', 1, 'm', 'arc length of the track frame', 'sigma', id)
        call self%outputs%add(p // 'position', 3, 'm', &
                              'track frame origin in the fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'angles', 3, 'rad', &
                              'heading, pitch (-atan gradient) and cant angle of the track frame', &
                              'heading pitch cant', id)
        call self%outputs%add(p // 'curvature', 1, '1/m', &
                              'horizontal curvature, > 0 for a left-hand curve', 'kappa', id)
        call self%outputs%add(p // 'superelevation', 1, 'm', &
                              'left rail over right rail', 'h', id)
        call self%outputs%add(p // 'angular_velocity', 3, 'rad/s', &
                              'angular velocity of the moving track frame, track components', &
                              'wx wy wz', id)
      end associate
    end do
    do k = 1, self%nbodies
      associate (p => 'bodies/' // self%mbs%bodies(k)%name // '/')
        call self%outputs%add(p // 'position_track', 6, 'm m m rad rad rad', &
          'coordinates q relative to the track frame (wheelset pitch: spin deviation beta)', &
          'x y z yaw roll pitch', id)
        call self%outputs%add(p // 'velocity_track', 6, 'm/s m/s m/s rad/s rad/s rad/s', &
          'dq/dt relative to the track frame', 'vx vy vz yaw_rate roll_rate pitch_rate', id)
        call self%outputs%add(p // 'acceleration_track', 6, 'm/s^2 m/s^2 m/s^2 rad/s^2 rad/s^2 rad/s^2', &
          'd2q/dt2 relative to the track frame', 'ax ay az yaw_acc roll_acc pitch_acc', id)
        call self%outputs%add(p // 'position_fixed', 3, 'm', 'centre of mass, fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'angles_fixed', 3, 'rad', &
          'Z-X-Y angles of the body frame relative to the fixed frame', 'yaw roll pitch', id)
        call self%outputs%add(p // 'velocity_fixed', 3, 'm/s', 'velocity of the centre of mass, fixed frame', &
          'vX vY vZ', id)
        call self%outputs%add(p // 'angular_velocity_fixed', 3, 'rad/s', 'angular velocity, fixed frame', &
          'wX wY wZ', id)
        call self%outputs%add(p // 'angular_velocity_body', 3, 'rad/s', 'angular velocity, body frame', &
          'wx wy wz', id)
        call self%outputs%add(p // 'acceleration_fixed', 3, 'm/s^2', &
          'acceleration of the centre of mass, fixed frame', 'aX aY aZ', id)
      end associate
    end do
    do k = 1, mbs_element_count(self)
      associate (p => 'elements/' // self%mbs%elements(k)%e%name // '/')
        call self%outputs%add(p // 'deflection', 3, 'm', &
          'deflection in element axes (torsion: rad)', 'dx dy dz', id)
        call self%outputs%add(p // 'force_element', 3, 'N', &
          'force on body 2 in element axes (torsion: moment, N*m)', 'fx fy fz', id)
        call self%outputs%add(p // 'force_fixed', 3, 'N', 'force on body 2, fixed frame', 'fX fY fZ', id)
      end associate
    end do
    if (associated(self%contact)) then
      do k = 1, size(self%wheelset_names)
        associate (p => 'wheelsets/' // trim(self%wheelset_names(k)) // '/')
          call self%outputs%add(p // 'summary', N_WHEELSET_CHANNELS, unit_tokens(wheelset_channel_units), &
            'derailment quotient (max Y/Q of the wheels) and sum of the guiding forces Y', &
            join(wheelset_channel_names), id)
          call self%outputs%add(p // 'rail_offsets', 4, 'm', 'rails displaced by the track irregularities ' // &
            'at the wheelset, track frame (zeros on the design track)', 'dy_left dz_left dy_right dz_right', id)
          block
            integer :: side, j
            character(len=5), parameter :: sides(2) = ['left ', 'right']
            character(len=8) :: tagj
            do side = 1, 2
              call self%outputs%add(p // trim(sides(side)) // '/wheel', N_WHEEL_CHANNELS, &
                unit_tokens(wheel_channel_units), 'wheel: patches, force on the wheel in track ' // &
                'components (longitudinal, Y, Q), Y/Q (> 0 towards flange climb), largest penetration', &
                join(wheel_channel_names), id)
              do j = 1, MAX_PATCHES
                write (tagj, '(i0)') j
                call self%outputs%add(p // trim(sides(side)) // '/patch' // trim(tagj), N_PATCH_CHANNELS, &
                  unit_tokens(patch_channel_units), 'contact patch (zeros when absent): geometry, ' // &
                  'normal force, creepages, creep forces on the wheel (contact frame)', &
                  join(patch_channel_names), id)
              end do
            end do
          end block
        end associate
      end do
    end if
    do k = 1, size(self%sensors)
      associate (p => 'sensors/' // self%sensors(k)%name // '/', &
                 on => ' of sensor ' // self%sensors(k)%name // ' (fixed to its body)')
        call self%outputs%add(p // 'position_track', 3, 'm', 'position' // on // &
          ' relative to its body''s track frame, track components', 'x y z', id)
        call self%outputs%add(p // 'position_fixed', 3, 'm', 'position' // on // ', fixed frame', 'X Y Z', id)
        call self%outputs%add(p // 'velocity_track', 3, 'm/s', 'absolute velocity' // on // &
          ', track-frame components', 'vx vy vz', id)
        call self%outputs%add(p // 'acceleration_track', 3, 'm/s^2', 'absolute acceleration' // on // &
          ', track-frame components', 'ax ay az', id)
        call self%outputs%add(p // 'velocity_body', 3, 'm/s', 'absolute velocity' // on // &
          ', body-frame components', 'vx vy vz', id)
        call self%outputs%add(p // 'acceleration_body', 3, 'm/s^2', 'absolute acceleration' // on // &
          ', body-frame components', 'ax ay az', id)
        call self%outputs%add(p // 'specific_force_body', 3, 'm/s^2', 'accelerometer reading' // on // &
          ': acceleration minus gravity, body-frame components', 'fx fy fz', id)
      end associate
    end do
    if (associated(self%mbs)) then
      block
        character(len=:), allocatable :: components, units
        call state_layout(self%mbs, components, units)
        call self%outputs%add('state/y', self%mbs%state_size(), units, 'integrator state y = [q_f; nu_f; ' // &
          'x_el] (free coordinates, generalized velocities, element states: rd_multibody); ' // &
          'raildyn run --restart continues from a row of it', components, id)
      end block
    end if
  end procedure register_outputs

  !> Column names and SI unit tokens of the state vector, in rd_multibody's layout:
  !> '<body>.<coordinate>' for q_f (a wheelset's pitch slot is its spin deviation beta),
  !> '<body>.nu_<coordinate>' for nu_f, '<element>.x<k>' for the elements' internal states.
  module procedure state_layout
    character(len=5), parameter :: dof_names(6) = ['x    ', 'y    ', 'z    ', 'yaw  ', 'roll ', 'pitch']
    character(len=5), parameter :: dof_units(6) = ['m    ', 'm    ', 'm    ', 'rad  ', 'rad  ', 'rad  ']
    character(len=5), parameter :: rate_units(6) = ['m/s  ', 'm/s  ', 'm/s  ', 'rad/s', 'rad/s', 'rad/s']
    character(len=:), allocatable :: q_names, q_units, nu_names, nu_units
    character(len=16), allocatable :: el_units(:)
    integer :: i, j, k
    q_names = ''; q_units = ''; nu_names = ''; nu_units = ''
    do i = 1, mbs%body_count()
      do j = 1, 6
        if (mbs%free_slot(i, j) == 0) cycle
        q_names = q_names // ' ' // mbs%bodies(i)%name // '.' // trim(dof_names(j))
        q_units = q_units // ' ' // trim(dof_units(j))
        nu_names = nu_names // ' ' // mbs%bodies(i)%name // '.nu_' // trim(dof_names(j))
        nu_units = nu_units // ' ' // trim(rate_units(j))
      end do
    end do
    components = q_names // nu_names
    units = q_units // nu_units
    do i = 1, mbs%element_count()
      if (allocated(el_units)) deallocate (el_units)
      allocate (el_units(mbs%elements(i)%e%state_count()))
      call mbs%elements(i)%e%state_units(el_units)
      do k = 1, size(el_units)
        components = components // ' ' // mbs%elements(i)%e%name // '.x' // trim(int_text(k))
        units = units // ' ' // trim(el_units(k))
      end do
    end do
    components = components(2:)
    units = units(2:)
  end procedure state_layout

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

  !> Space-separated unit tokens (docs/output.md: no spaces inside a token, '1' for none).
  pure function unit_tokens(units) result(text)
    character(len=*), intent(in) :: units(:)
    character(len=:), allocatable :: text
    integer :: i
    character(len=:), allocatable :: u
    text = ''
    do i = 1, size(units)
      u = trim(units(i))
      if (u == '-' .or. u == '') u = '1'
      if (u == 'N m') u = 'N*m'
      if (i > 1) text = text // ' '
      text = text // u
    end do
  end function unit_tokens

  pure function join(words) result(text)
    character(len=*), intent(in) :: words(:)
    character(len=:), allocatable :: text
    integer :: i
    text = trim(words(1))
    do i = 2, size(words)
      text = text // ' ' // trim(words(i))
    end do
  end function join

  pure integer function mbs_element_count(self)
    class(scene_t), intent(in) :: self
    mbs_element_count = 0
    if (associated(self%mbs)) mbs_element_count = self%mbs%element_count()
  end function mbs_element_count

  !> Record the state at the current time.
  module procedure write_step
    call self%refresh_outputs()
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

  module procedure refresh_outputs
    integer :: k, j
    real(wp) :: v, sigma
    type(track_point_t) :: p
    v = self%speed%speed(self%t)
    sigma = self%vehicle_sigma(self%t)
    j = 1
    self%outputs%channels(j)%values(1) = v; j = j + 1
    self%outputs%channels(j)%values(1) = sigma; j = j + 1
    do k = 1, size(self%frame_offsets)
      p = self%track%evaluate(sigma + self%frame_offsets(k))
      self%outputs%channels(j)%values(1) = p%sigma; j = j + 1
      self%outputs%channels(j)%values = p%r; j = j + 1
      self%outputs%channels(j)%values = [p%heading, p%grade_angle, p%cant_angle]; j = j + 1
      self%outputs%channels(j)%values(1) = p%curvature; j = j + 1
      self%outputs%channels(j)%values(1) = p%superelevation; j = j + 1
      self%outputs%channels(j)%values = v * p%omega; j = j + 1
    end do
    if (self%nbodies == 0) return
    block
      real(wp) :: rel(BODY_OUT_RELATIVE), fix(BODY_OUT_FIXED), el(ELEMENT_OUT)
      real(wp), allocatable :: ydot(:)
      type(error_t), allocatable :: error
      logical :: recoverable
      integer :: i
      ! One RHS evaluation at the output state refreshes kinematics, accelerations and
      ! element forces (the integrator's last evaluation may be at another state).
      allocate (ydot(size(self%y)))
      call self%mbs%rhs(self%t, self%y, ydot, error, recoverable)
      do i = 1, self%nbodies
        call self%mbs%body_output_relative(i, rel)
        call self%mbs%body_output_fixed(i, fix)
        if (self%mbs%bodies(i)%is_wheelset) then
          ! docs/conventions.md: a wheelset's pitch output is the spin deviation from
          ! nominal rolling, beta = theta - s(t)/r0 (and its rates), not the spin angle.
          associate (r0 => self%mbs%bodies(i)%r0)
            rel(6) = deviation_from_spin(rel(6), self%mbs%speed%distance(self%t), r0)
            rel(12) = deviation_from_spin(rel(12), self%mbs%speed%speed(self%t), r0)
            rel(18) = deviation_from_spin(rel(18), self%mbs%speed%acceleration(self%t), r0)
          end associate
        end if
        self%outputs%channels(j)%values = rel(1:6); j = j + 1
        self%outputs%channels(j)%values = rel(7:12); j = j + 1
        self%outputs%channels(j)%values = rel(13:18); j = j + 1
        self%outputs%channels(j)%values = fix(1:3); j = j + 1
        self%outputs%channels(j)%values = fix(4:6); j = j + 1
        self%outputs%channels(j)%values = fix(7:9); j = j + 1
        self%outputs%channels(j)%values = fix(10:12); j = j + 1
        self%outputs%channels(j)%values = fix(13:15); j = j + 1
        self%outputs%channels(j)%values = fix(16:18); j = j + 1
      end do
      do i = 1, self%mbs%element_count()
        call self%mbs%element_output(i, el)
        self%outputs%channels(j)%values = el(1:3); j = j + 1
        self%outputs%channels(j)%values = el(4:6); j = j + 1
        self%outputs%channels(j)%values = el(7:9); j = j + 1
      end do
      if (associated(self%contact)) then
        block
          integer :: w, side, k
          do w = 1, size(self%wheelset_names)
            associate (res => self%contact%results(w))
              call wheelset_channel_values(res, self%outputs%channels(j)%values); j = j + 1
              self%outputs%channels(j)%values = self%contact%rail_offsets(:, w); j = j + 1
              do side = 1, 2
                call wheel_channel_values(res%wheel(side), self%outputs%channels(j)%values); j = j + 1
                do k = 1, MAX_PATCHES
                  call patch_channel_values(res%wheel(side), k, self%outputs%channels(j)%values); j = j + 1
                end do
              end do
            end associate
          end do
        end block
      end if
      ! sensors after the contact: their channels were registered before the state's
      block
        type(point_motion_t) :: m
        integer :: s
        do s = 1, size(self%sensors)
          m = compute_point_motion(self%mbs%kin(self%sensors(s)%body), self%sensors(s)%position, &
                                   self%mbs%gravity)
          self%outputs%channels(j)%values = m%position_track; j = j + 1
          self%outputs%channels(j)%values = m%position_fixed; j = j + 1
          self%outputs%channels(j)%values = m%velocity_track; j = j + 1
          self%outputs%channels(j)%values = m%acceleration_track; j = j + 1
          self%outputs%channels(j)%values = m%velocity_body; j = j + 1
          self%outputs%channels(j)%values = m%acceleration_body; j = j + 1
          self%outputs%channels(j)%values = m%specific_force_body; j = j + 1
        end do
      end block
      self%outputs%channels(j)%values = self%y; j = j + 1
    end block
  end procedure refresh_outputs

end submodule rd_scene_output_table
