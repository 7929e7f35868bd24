!> Builds the bodies, track frames, force elements and external loads of a scene from
!> the deck's `&body`, `&element` and `&external_force` groups (docs/input_reference.md),
!> in the frames and numbering of docs/conventions.md.
module rd_scene_vehicle
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_rotation, only: rot_x, rot_y, rot_z
  use rd_deck, only: deck_t, deck_string_t
  use rd_deck_text, only: append_string, real_to_str
  use rd_body_spec, only: body_spec_t, DOF_Z, DOF_ROLL
  use rd_external_loads, only: external_loads_t, external_load_t, LOAD_FRAME_FIXED, &
                               LOAD_FRAME_TRACK, LOAD_FRAME_BODY
  use rd_force_element, only: force_element_t
  use rd_linear_spring_damper, only: linear_spring_damper_t
  use rd_torsion_spring_damper, only: torsion_spring_damper_t
  use rd_nonlinear_spring, only: nonlinear_spring_t, build_force_table
  use rd_series_spring_damper, only: series_spring_damper_t
  use rd_wheelset_contact_spec, only: wheelset_contact_spec_t
  use rd_profile, only: profile_t
  use rd_profile_source, only: load_wheel_profile, load_rail_profile
  use rd_text, only: lower_case, real_text
  implicit none
  private
  public :: build_bodies, build_element, build_external_loads, body_index, build_wheelset_specs
  public :: check_rail_bodies, check_body_inertia, stiffness_warnings, load_wheelset_profiles

  character(len=*), parameter :: dof_names(6) = [character(len=5) :: 'x', 'y', 'z', 'yaw', 'roll', 'pitch']
  character(len=*), parameter :: inertia_names(3) = [character(len=3) :: 'ixx', 'iyy', 'izz']

  !> Smallest radius of gyration sqrt(I/m) of a body [m]: a rigid body of a vehicle model
  !> is larger than a millimetre; below it the rotational equations are so stiff (I -> 0
  !> under finite moments) that the static solve and the integrators fail far from the
  !> deck line that caused it (ixx = 1e-300 failed as "equilibrium did not converge").
  real(wp), parameter :: min_gyration_radius = 1.0e-3_wp
  !> Natural frequency sqrt(k/m) [Hz] above which a stiffness makes a run crawl: every
  !> integrator must resolve it (a 1500 kg wheelset on 1e15 N/m, 130 kHz, took 20 times
  !> as long per simulated second as on 1e11 N/m, 1.3 kHz). Wheel-rail contact, the
  !> stiffest part of the shipped scenes, is below 1 kHz.
  real(wp), parameter :: crawl_frequency = 5.0e3_wp
  real(wp), parameter :: two_pi = 6.283185307179586_wp

contains

  !> x to 3 significant digits, for computed numbers in messages.
  function approx(x) result(text)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: text
    character(len=16) :: buf
    real(wp) :: rounded
    write (buf, '(es16.2e3)') x
    read (buf, *) rounded
    text = real_to_str(rounded)
  end function approx

  !> Index of the body called `name` (0 for 'ground', -1 if unknown).
  integer function body_index(deck, name) result(ib)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    type(error_t), allocatable :: error
    character(len=:), allocatable :: other
    integer :: i
    ib = -1
    if (name == 'ground') then
      ib = 0
      return
    end if
    do i = 1, deck%count('body')
      call deck%get('body', i, 'name', other, error)
      if (.not. allocated(error) .and. other == name) then
        ib = i
        return
      end if
    end do
  end function body_index

  !> One body spec per `&body` and the arc-length offsets of the track frames. A body
  !> with `frame = 'own'` gets a frame of its own at sigma_vehicle + frame_offset;
  !> otherwise it shares the frame of the named body (thesis 4.2.3: one frame per
  !> wheelset, the other bodies referred to the nearest one).
  subroutine build_bodies(deck, bodies, frame_offsets, error)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), allocatable, intent(out) :: bodies(:)
    real(wp), allocatable, intent(out) :: frame_offsets(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: n, i, j, k, nframes, hops, ia
    integer, allocatable :: frame_of(:), owner(:)
    character(len=:), allocatable :: name, frame, normal_contact
    type(deck_string_t), allocatable :: frozen(:)
    real(wp), allocatable :: v(:)
    real(wp) :: offset, ixy, ixz, iyz

    n = deck%count('body')
    allocate (bodies(n), frame_of(n), owner(n), frame_offsets(n))
    ! Frames owned by bodies with their own frame, in body order.
    nframes = 0
    do i = 1, n
      call deck%get('body', i, 'frame', frame, error); if (allocated(error)) return
      if (frame == 'own') then
        nframes = nframes + 1
        call deck%get('body', i, 'frame_offset', offset, error); if (allocated(error)) return
        frame_offsets(nframes) = offset
        frame_of(i) = nframes
      else
        frame_of(i) = 0
        owner(i) = body_index(deck, frame)
        if (owner(i) == i) then
          call make_error(error, RD_ERR_INPUT, deck%origin('body', i, 'frame') // &
                          ": a body cannot share its own frame; expected 'own' or another body's name")
          return
        end if
      end if
    end do
    ! Resolve shared frames (a chain of shares ends at a body with its own frame).
    do i = 1, n
      k = i
      hops = 0
      do while (frame_of(k) == 0)
        k = owner(k)
        hops = hops + 1
        if (k < 1 .or. hops > n) then
          call make_error(error, RD_ERR_INPUT, deck%origin('body', i, 'frame') // &
                          ': the chain of shared frames does not end at a body with its own frame')
          return
        end if
      end do
      bodies(i)%frame = frame_of(k)
    end do
    frame_offsets = frame_offsets(1:nframes)

    do i = 1, n
      associate (b => bodies(i))
        call deck%get('body', i, 'name', name, error); if (allocated(error)) return
        b%name = name
        call deck%get('body', i, 'mass', b%mass, error); if (allocated(error)) return
        call deck%get('body', i, 'ixx', b%inertia(1, 1), error); if (allocated(error)) return
        call deck%get('body', i, 'iyy', b%inertia(2, 2), error); if (allocated(error)) return
        call deck%get('body', i, 'izz', b%inertia(3, 3), error); if (allocated(error)) return
        call deck%get('body', i, 'ixy', ixy, error); if (allocated(error)) return
        call deck%get('body', i, 'ixz', ixz, error); if (allocated(error)) return
        call deck%get('body', i, 'iyz', iyz, error); if (allocated(error)) return
        ! The deck gives the inertia tensor's elements at the CG in body axes
        ! (ixy = I(1,2), products with their tensor sign).
        b%inertia(1, 2) = ixy; b%inertia(2, 1) = ixy
        b%inertia(1, 3) = ixz; b%inertia(3, 1) = ixz
        b%inertia(2, 3) = iyz; b%inertia(3, 2) = iyz
        call deck%get('body', i, 'position', v, error); if (allocated(error)) return
        b%q0(1:3) = v
        call deck%get('body', i, 'orientation', v, error); if (allocated(error)) return
        b%q0(4:6) = v
        call deck%get('body', i, 'velocity', v, error); if (allocated(error)) return
        b%qdot0(1:3) = v
        call deck%get('body', i, 'angular_rate', v, error); if (allocated(error)) return
        b%qdot0(4:6) = v
        if (deck%given('body', i, 'frozen')) then
          call deck%get('body', i, 'frozen', frozen, error); if (allocated(error)) return
          do j = 1, size(frozen)
            ! (a loop: gfortran 12's findloc misses deferred-length strings)
            k = 0
            do ia = 1, 6
              if (trim(dof_names(ia)) == frozen(j)%s) k = ia
            end do
            if (k == 0) then
              call make_error(error, RD_ERR_INPUT, deck%origin('body', i, 'frozen') // ": '" // &
                frozen(j)%s // "' is not a degree of freedom; expected x, y, z, yaw, roll or pitch")
              return
            end if
            b%frozen(k) = .true.
          end do
        end if
      end associate
    end do
    ! Wheelsets: the body named by a &wheelset spins about its axle (spin deviation state).
    do j = 1, deck%count('wheelset')
      call deck%get('wheelset', j, 'body', name, error); if (allocated(error)) return
      i = body_index(deck, name)
      if (i < 1) then
        call make_error(error, RD_ERR_INPUT, deck%origin('wheelset', j, 'body') // ": no &body named '" // &
                        name // "'")
        return
      end if
      ! its reference rolling radius r0 needs the contact geometry: set by the scene
      ! (rd_reference_radius) before the multibody system is built
      bodies(i)%is_wheelset = .true.
      call deck%get('wheelset', j, 'normal_contact', normal_contact, error); if (allocated(error)) return
      if (normal_contact == 'quasi_static') then
        if (bodies(i)%frozen(DOF_Z) .or. bodies(i)%frozen(DOF_ROLL)) then
          call make_error(error, RD_ERR_INPUT, deck%origin('wheelset', j, 'normal_contact') // &
                          ": quasi_static solves the z and roll of body '" // name // &
                          "', which has one of them frozen; unfreeze them or use 'elastic'")
          return
        end if
        bodies(i)%quasi_static([DOF_Z, DOF_ROLL]) = .true.
      end if
    end do
  end subroutine build_bodies

  !> Inertia data that the schema's per-value ranges cannot judge, each reported at its
  !> deck line: a radius of gyration below min_gyration_radius, and products of inertia
  !> that leave the tensor not positive definite (errors). Warnings: diagonal moments
  !> that break the triangle inequality (Ixx + Iyy >= Izz and permutations hold for any
  !> mass distribution: Ixx + Iyy - Izz = 2 int z^2 dm), and a wheelset whose roll and
  !> yaw moments differ (it spins about its axle, so the model's constant tensor in the
  !> non-spinning frame needs an axisymmetric wheelset, ixx = izz).
  subroutine check_body_inertia(deck, bodies, warnings, error)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: bodies(:)
    type(deck_string_t), allocatable, intent(inout) :: warnings(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, a
    real(wp) :: d(3), m, minor2, minor3
    do i = 1, size(bodies)
      d = [(bodies(i)%inertia(a, a), a=1, 3)]
      m = bodies(i)%mass
      do a = 1, 3
        if (.not. d(a) >= m * min_gyration_radius**2) then
          call make_error(error, RD_ERR_INPUT, deck%origin('body', i, inertia_names(a)) // ': ' // &
            real_to_str(d(a)) // ' kg m2 gives a radius of gyration of ' // &
            approx(sqrt(max(d(a), 0.0_wp) / m)) // ' m for the mass of ' // real_to_str(m) // &
            ' kg; expected ' // trim(inertia_names(a)) // ' >= mass x (1 mm)^2 = ' // &
            approx(m * min_gyration_radius**2) // ' kg m2')
          return
        end if
      end do
      associate (t => bodies(i)%inertia)
        minor2 = t(1, 1) * t(2, 2) - t(1, 2)**2
        minor3 = t(1, 1) * (t(2, 2) * t(3, 3) - t(2, 3)**2) - t(1, 2) * (t(1, 2) * t(3, 3) - t(2, 3) * t(1, 3)) &
                 + t(1, 3) * (t(1, 2) * t(2, 3) - t(2, 2) * t(1, 3))
        if (.not. (minor2 > 0 .and. minor3 > 0)) then
          call make_error(error, RD_ERR_INPUT, deck%origin('body', i, merge('ixy', 'ixz', .not. minor2 > 0)) // &
            ': the products of inertia (ixy = ' // real_to_str(t(1, 2)) // ', ixz = ' // &
            real_to_str(t(1, 3)) // ', iyz = ' // real_to_str(t(2, 3)) // &
            ') leave the inertia tensor not positive definite; expected products small against ' // &
            'the moments (e.g. ixy**2 < ixx iyy)')
          return
        end if
      end associate
      do a = 1, 3
        if (d(a) > d(mod(a, 3) + 1) + d(mod(a + 1, 3) + 1) + 1.0e-9_wp * maxval(d)) then
          call append_string(warnings, deck%origin('body', i, inertia_names(a)) // ': ' // &
            trim(inertia_names(a)) // ' = ' // real_to_str(d(a)) // ' kg m2 exceeds the sum of ' // &
            'the other two moments (' // approx(d(mod(a, 3) + 1) + d(mod(a + 1, 3) + 1)) // &
            ' kg m2), which no rigid body has; check the moments of inertia')
          exit
        end if
      end do
      if (bodies(i)%is_wheelset .and. abs(d(1) - d(3)) > 1.0e-6_wp * max(d(1), d(3))) then
        call append_string(warnings, deck%origin('body', i, 'izz') // ': wheelset body with ixx = ' // &
          real_to_str(d(1)) // ' and izz = ' // real_to_str(d(3)) // ' kg m2; a wheelset ' // &
          'spins about its axle, and the equations of motion hold its inertia constant in the ' // &
          'non-spinning frame, which needs ixx = izz (an axisymmetric wheelset)')
      end if
    end do
  end subroutine check_body_inertia

  !> A warning for every element whose stiffness puts a natural frequency above
  !> crawl_frequency (f = sqrt(k / m) / 2 pi, m the reduced mass of the two bodies; the
  !> moment of inertia about the same axis for torsion): legal, but the run crawls.
  subroutine stiffness_warnings(deck, bodies, warnings)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: bodies(:)
    type(deck_string_t), allocatable, intent(inout) :: warnings(:)
    type(error_t), allocatable :: error
    character(len=:), allocatable :: kind, b1, b2, param
    real(wp), allocatable :: k(:), e(:), f(:)
    real(wp) :: inertia1(3), inertia2(3), mass1, mass2, ks
    integer :: i, ib1, ib2, a
    do i = 1, deck%count('element')
      call deck%get('element', i, 'type', kind, error); if (allocated(error)) return
      call deck%get('element', i, 'body1', b1, error); if (allocated(error)) return
      call deck%get('element', i, 'body2', b2, error); if (allocated(error)) return
      ib1 = body_index(deck, b1); ib2 = body_index(deck, b2)
      if (ib2 < 1 .or. ib1 < 0) cycle
      mass2 = bodies(ib2)%mass
      inertia2 = [(bodies(ib2)%inertia(a, a), a=1, 3)]
      mass1 = huge(1.0_wp); inertia1 = huge(1.0_wp)   ! ground
      if (ib1 > 0) then
        mass1 = bodies(ib1)%mass
        inertia1 = [(bodies(ib1)%inertia(a, a), a=1, 3)]
      end if
      select case (kind)
      case ('spring_damper')
        param = 'stiffness'
        call deck%get('element', i, param, k, error); if (allocated(error)) return
        call warn_if_crawling(maxval(abs(k)), reduced(mass1, mass2), 'kg')
      case ('torsion')
        param = 'torsion_stiffness'
        call deck%get('element', i, param, k, error); if (allocated(error)) return
        ! element axes roughly along the body axes: the smallest moment is the safe side
        call warn_if_crawling(maxval(abs(k)), reduced(minval(inertia1), minval(inertia2)), 'kg m2')
      case ('series_spring_damper')
        param = 'series_stiffness'
        call deck%get('element', i, param, ks, error); if (allocated(error)) return
        call warn_if_crawling(ks, reduced(mass1, mass2), 'kg')
      case ('table')
        param = 'table_force'
        call deck%get('element', i, 'table_deflection', e, error); if (allocated(error)) return
        call deck%get('element', i, 'table_force', f, error); if (allocated(error)) return
        if (size(e) >= 2) call warn_if_crawling(maxval(abs((f(2:) - f(:size(f) - 1)) / &
                                                            (e(2:) - e(:size(e) - 1)))), reduced(mass1, mass2), 'kg')
      end select
    end do
  contains
    pure real(wp) function reduced(m1, m2)
      real(wp), intent(in) :: m1, m2
      if (m1 >= huge(1.0_wp)) then
        reduced = m2
      else
        reduced = m1 * m2 / (m1 + m2)
      end if
    end function reduced

    subroutine warn_if_crawling(stiffness, m, mass_unit)
      real(wp), intent(in) :: stiffness, m
      character(len=*), intent(in) :: mass_unit
      real(wp) :: frequency
      character(len=:), allocatable :: stiffness_unit
      frequency = sqrt(stiffness / m) / two_pi
      if (frequency <= crawl_frequency) return
      stiffness_unit = merge('N m/rad', 'N/m    ', mass_unit == 'kg m2')
      call append_string(warnings, deck%origin('element', i, param) // ': ' // real_to_str(stiffness) // &
        ' ' // trim(stiffness_unit) // ' on ' // approx(m) // ' ' // mass_unit // ' gives a natural frequency of ' // &
        approx(frequency) // ' Hz; the integrators must resolve it and the run will crawl ' // &
        '(expected at most ' // approx(m * (two_pi * crawl_frequency)**2) // ' ' // trim(stiffness_unit) // &
        ' for ' // approx(crawl_frequency) // ' Hz)')
    end subroutine warn_if_crawling
  end subroutine stiffness_warnings

  !> Element axes from the deck's (yaw, roll, pitch) angles, Z-X-Y as the body frames.
  pure function axes_from_angles(a) result(r)
    real(wp), intent(in) :: a(3)
    real(wp) :: r(3, 3)
    r = matmul(rot_z(a(1)), matmul(rot_x(a(2)), rot_y(a(3))))
  end function axes_from_angles

  !> The force element of `&element` number i.
  !> Element i of the deck. The reader has checked the type's rules (rd_deck_resolve
  !> check_element: required keys, table and series damping), once, for check and run.
  subroutine build_element(deck, i, element, error)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: i
    class(force_element_t), allocatable, intent(out) :: element
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: name, kind, b1, b2, axis
    real(wp), allocatable :: p1(:), p2(:), ang(:), k(:), c(:), pre(:), act(:), e(:), f(:)
    real(wp) :: clearance, ks
    integer :: ia

    call deck%get('element', i, 'name', name, error); if (allocated(error)) return
    call deck%get('element', i, 'type', kind, error); if (allocated(error)) return
    call deck%get('element', i, 'body1', b1, error); if (allocated(error)) return
    call deck%get('element', i, 'body2', b2, error); if (allocated(error)) return
    call deck%get('element', i, 'point1', p1, error); if (allocated(error)) return
    call deck%get('element', i, 'point2', p2, error); if (allocated(error)) return
    call deck%get('element', i, 'axes', ang, error); if (allocated(error)) return
    call deck%get('element', i, 'damping', c, error); if (allocated(error)) return

    select case (kind)
    case ('spring_damper')
      block
        type(linear_spring_damper_t), allocatable :: s
        allocate (s)
        call deck%get('element', i, 'stiffness', k, error); if (allocated(error)) return
        call deck%get('element', i, 'preload', pre, error); if (allocated(error)) return
        call deck%get('element', i, 'actuator_force', act, error); if (allocated(error)) return
        s%u1 = p1; s%u2 = p2; s%axes = axes_from_angles(ang)
        s%stiffness = k; s%damping = c; s%preload = pre; s%actuator = act
        call move_alloc(s, element)
      end block
    case ('torsion')
      block
        type(torsion_spring_damper_t), allocatable :: s
        allocate (s)
        call deck%get('element', i, 'torsion_stiffness', k, error); if (allocated(error)) return
        call deck%get('element', i, 'torsion_damping', c, error); if (allocated(error)) return
        s%axes1 = axes_from_angles(ang); s%axes2 = s%axes1
        s%stiffness = k; s%damping = c
        call move_alloc(s, element)
      end block
    case ('table')
      block
        type(nonlinear_spring_t), allocatable :: s
        allocate (s)
        call deck%get('element', i, 'table_axis', axis, error); if (allocated(error)) return
        ia = index('xyz', axis)
        call deck%get('element', i, 'table_deflection', e, error); if (allocated(error)) return
        call deck%get('element', i, 'table_force', f, error); if (allocated(error)) return
        call deck%get('element', i, 'clearance', clearance, error); if (allocated(error)) return
        s%u1 = p1; s%u2 = p2; s%axes = axes_from_angles(ang)
        s%clearance_pos(ia) = clearance
        s%clearance_neg(ia) = clearance
        s%damping(ia) = c(ia)
        call build_force_table(s%table_pos(ia), e, f, error)
        if (allocated(error)) then
          call error_context(error, deck%origin('element', i, 'table_deflection'))
          return
        end if
        call move_alloc(s, element)
      end block
    case ('series_spring_damper')
      block
        type(series_spring_damper_t), allocatable :: s
        allocate (s)
        call deck%get('element', i, 'series_stiffness', ks, error); if (allocated(error)) return
        s%u1 = p1; s%u2 = p2; s%stiffness = ks; s%damping = c(1)
        call move_alloc(s, element)
      end block
    case default
      call make_error(error, RD_ERR_INPUT, deck%origin('element', i, 'type') // ": unknown type '" // kind // "'")
      return
    end select
    element%name = name
    element%body1 = body_index(deck, b1)
    element%body2 = body_index(deck, b2)
    if (element%body1 < 0 .or. element%body2 < 1) then
      call make_error(error, RD_ERR_INPUT, deck%origin('element', i, merge('body1', 'body2', element%body1 < 0)) // &
                      ': no such body; expected the name of a &body' // trim(merge(" or 'ground'", '            ', element%body1 < 0)))
    end if
  end subroutine build_element

  subroutine build_external_loads(deck, loads, error)
    type(deck_t), intent(in) :: deck
    type(external_loads_t), intent(inout) :: loads
    type(error_t), allocatable, intent(out) :: error
    type(external_load_t) :: load
    character(len=:), allocatable :: name, frame
    real(wp), allocatable :: v(:)
    integer :: i
    allocate (loads%loads(0))
    do i = 1, deck%count('external_force')
      call deck%get('external_force', i, 'body', name, error); if (allocated(error)) return
      load%body = body_index(deck, name)
      call deck%get('external_force', i, 'frame', frame, error); if (allocated(error)) return
      select case (frame)
      case ('track'); load%frame = LOAD_FRAME_TRACK
      case ('body'); load%frame = LOAD_FRAME_BODY
      case default; load%frame = LOAD_FRAME_FIXED
      end select
      call deck%get('external_force', i, 'force', v, error); if (allocated(error)) return
      load%force = v
      call deck%get('external_force', i, 'moment', v, error); if (allocated(error)) return
      load%moment = v
      call deck%get('external_force', i, 't_start', load%t_on, error); if (allocated(error)) return
      call deck%get('external_force', i, 't_end', load%t_off, error); if (allocated(error)) return
      call loads%add_load(load, deck%count('body'), error)
      if (allocated(error)) then
        call error_context(error, deck%origin('external_force', i))
        return
      end if
    end do
  end subroutine build_external_loads
  !> Flexible track: the `&wheelset` rail bodies (left_rail_body, right_rail_body) must be
  !> bodies other than the wheelset, each other and any wheelset, in a track frame at the
  !> wheelset's frame offset (the contact adds their (y, z) to the rail offsets of the
  !> wheelset's frame), with x, yaw, roll and pitch frozen (the contact applies a force at
  !> their CG only; docs/theory_track_flexibility.md), and each under one wheel only (the
  !> co-moving model: a rail mass travels with its wheel, so two wheelsets on one rail body
  !> would load one mass at two places that the model puts at the same point).
  subroutine check_rail_bodies(deck, bodies, frame_offsets, error)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: bodies(:)
    real(wp), intent(in) :: frame_offsets(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), parameter :: keys(2) = [character(len=15) :: 'left_rail_body', 'right_rail_body']
    character(len=:), allocatable :: name, ws_name, origin_text, other
    integer :: j, side, ws, rb, rails(2)
    integer :: owner(size(bodies))   ! &wheelset group that uses the body as a rail, 0: none
    real(wp) :: d_rail, d_ws
    owner = 0
    do j = 1, deck%count('wheelset')
      call deck%get('wheelset', j, 'body', ws_name, error); if (allocated(error)) return
      ws = body_index(deck, ws_name)
      if (ws < 1) cycle       ! build_bodies reported it
      rails = 0
      do side = 1, 2
        call deck%get('wheelset', j, trim(keys(side)), name, error); if (allocated(error)) return
        if (name == 'none') cycle
        rb = body_index(deck, name)
        origin_text = deck%origin('wheelset', j, trim(keys(side)))
        if (rb < 1) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": no &body named '" // name // &
                          "'; expected the name of a rail body or 'none'")
          return
        end if
        if (rb == ws) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": the rail body '" // name // &
                          "' is the wheelset itself; expected a separate body on pad elements")
          return
        end if
        if (side == 2 .and. rb == rails(1)) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": '" // name // &
                          "' is also the left rail body; expected one body per rail")
          return
        end if
        if (bodies(rb)%is_wheelset) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": '" // name // &
                          "' is a wheelset body; expected a rail body on pad elements")
          return
        end if
        d_rail = frame_offsets(bodies(rb)%frame)
        d_ws = frame_offsets(bodies(ws)%frame)
        if (abs(d_rail - d_ws) > 1.0e-9_wp) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": the rail body '" // name // &
                          "' is in a track frame at frame_offset " // trim(real_text(d_rail)) // &
                          " m; expected the wheelset's (" // trim(real_text(d_ws)) // " m): give it frame = '" // &
                          ws_name // "' or the same frame_offset")
          return
        end if
        if (.not. all(bodies(rb)%frozen([1, 4, 5, 6]))) then
          call make_error(error, RD_ERR_INPUT, origin_text // ": the rail body '" // name // &
                          "' must have frozen = 'x', 'yaw', 'roll', 'pitch' (it moves laterally " // &
                          "and vertically only)")
          return
        end if
        if (owner(rb) > 0) then
          call deck%get('wheelset', owner(rb), 'name', other, error); if (allocated(error)) return
          call make_error(error, RD_ERR_INPUT, origin_text // ": the rail body '" // name // &
                          "' is already under &wheelset '" // other // "'; expected its own rail body for " // &
                          "each wheel (the co-moving rail mass travels with one wheel)")
          return
        end if
        owner(rb) = j
        rails(side) = rb
      end do
    end do
  end subroutine check_rail_bodies

  !> One contact spec per `&wheelset` (track placement from `&track`, run-time limits
  !> from `&simulation`).
  subroutine build_wheelset_specs(deck, specs, error)
    type(deck_t), intent(in) :: deck
    type(wheelset_contact_spec_t), allocatable, intent(out) :: specs(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=:), allocatable :: text
    real(wp) :: contact_distance
    integer :: i, grid
    allocate (specs(deck%count('wheelset')))
    do i = 1, size(specs)
      associate (w => specs(i))
        call deck%get('wheelset', i, 'body', text, error); if (allocated(error)) return
        w%body = body_index(deck, text)
        call deck%get('wheelset', i, 'left_rail_body', text, error); if (allocated(error)) return
        if (text /= 'none') w%rail_body(1) = body_index(deck, text)
        call deck%get('wheelset', i, 'right_rail_body', text, error); if (allocated(error)) return
        if (text /= 'none') w%rail_body(2) = body_index(deck, text)
        call deck%get('wheelset', i, 'contact', text, error); if (allocated(error)) return
        w%model = text
        if (w%model == 'profile') then
          ! the reader requires both profiles with contact = 'profile' (rd_deck_resolve)
          w%wheel_profile = deck%path('wheelset', i, 'wheel_profile')
          w%rail_profile = deck%path('wheelset', i, 'rail_profile')
          ! right side: its own profile only when given, else the same as the left one
          if (deck%given('wheelset', i, 'wheel_profile_right')) &
            w%wheel_profile_right = deck%path('wheelset', i, 'wheel_profile_right')
          if (deck%given('wheelset', i, 'rail_profile_right')) &
            w%rail_profile_right = deck%path('wheelset', i, 'rail_profile_right')
        end if
        call deck%get('wheelset', i, 'contact_geometry', text, error); if (allocated(error)) return
        w%contact_geometry = text
        call deck%get('wheelset', i, 'strip_normal_force', text, error); if (allocated(error)) return
        w%strip_normal_force = text
        call deck%get('wheelset', i, 'table_shift_step', w%table%shift_step, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'strip_spacing', w%surface%wheel_spacing, error); if (allocated(error)) return
        w%surface%rail_spacing = w%surface%wheel_spacing
        call deck%get('wheelset', i, 'nominal_radius', w%nominal_radius, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'back_to_back', w%back_to_back, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'flange_back', w%flange_back, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'rail_precant', w%rail_precant, error); if (allocated(error)) return
        if (deck%given('wheelset', i, 'rail_precant_right')) then
          call deck%get('wheelset', i, 'rail_precant_right', w%rail_precant_right, error); if (allocated(error)) return
        end if
        call deck%get('track', 1, 'gauge', w%gauge, error); if (allocated(error)) return
        call deck%get('track', 1, 'rail_inclination', w%rail_inclination, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'conicity', w%knife_conicity, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'contact_distance', contact_distance, error); if (allocated(error)) return
        w%knife_e0 = contact_distance / 2
        call deck%get('wheelset', i, 'rail_crown_radius', w%knife_rail_crown_radius, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'flange_clearance', w%knife_flange_clearance, error); if (allocated(error)) return
        if (w%knife_flange_clearance <= 0) w%knife_flange_clearance = -1
        call deck%get('wheelset', i, 'flange_stiffness', w%knife_flange_stiffness, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'shear_modulus', w%shear_modulus, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'poisson', w%poisson, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'hertz_method', text, error); if (allocated(error)) return
        w%hertz_method = text
        call deck%get('wheelset', i, 'contact_damping', w%contact_damping, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'friction', w%friction, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'creep_law', text, error); if (allocated(error)) return
        w%creep_law = text
        call deck%get('wheelset', i, 'spin_creep', w%spin_creep, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'creep_saturation', text, error); if (allocated(error)) return
        w%creep_options%saturation = text
        call deck%get('wheelset', i, 'fastsim_grid', grid, error); if (allocated(error)) return
        w%creep_options%grid_nx = grid
        w%creep_options%grid_ny = grid
        call deck%get('wheelset', i, 'fastsim_bound', text, error); if (allocated(error)) return
        w%creep_options%bound = text
        call deck%get('wheelset', i, 'fastsim_saturation_width', w%creep_options%saturation_width, error)
        if (allocated(error)) return
        call deck%get('wheelset', i, 'polach_ka', w%creep_options%polach_ka, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'polach_ks', w%creep_options%polach_ks, error); if (allocated(error)) return
        call deck%get('wheelset', i, 'polach_friction_ratio', w%creep_options%polach_friction_ratio, error)
        if (allocated(error)) return
        call deck%get('wheelset', i, 'polach_friction_decay', w%creep_options%polach_friction_decay, error)
        if (allocated(error)) return
        call deck%get('wheelset', i, 'creep_velocity_min', w%creep_v0, error); if (allocated(error)) return
        call deck%get('simulation', 1, 'max_wheel_lift', w%liftoff_limit, error); if (allocated(error)) return
      end associate
    end do
  end subroutine build_wheelset_specs

  !> Read the profile files named by the `&wheelset` groups (analytic keywords are left to
  !> the contact), each error prefixed with the deck line and the wheelset that names the
  !> file: "scene.nml:7: &wheelset 'wheel_profile' (wheelset 'w1'): wheel.prw:12: ...".
  !> The left profiles are handed to the contact as read; right ones the contact reads
  !> again (a few hundred lines).
  subroutine load_wheelset_profiles(deck, specs, error)
    type(deck_t), intent(in) :: deck
    type(wheelset_contact_spec_t), intent(inout) :: specs(:)
    type(error_t), allocatable, intent(out) :: error
    character(len=*), parameter :: keys(4) = [character(len=19) :: 'wheel_profile', 'rail_profile', &
                                              'wheel_profile_right', 'rail_profile_right']
    type(profile_t) :: profile
    character(len=:), allocatable :: path, name
    integer :: i, j
    do i = 1, size(specs)
      if (specs(i)%model /= 'profile') cycle
      call deck%get('wheelset', i, 'name', name, error); if (allocated(error)) return
      do j = 1, size(keys)
        if (.not. deck%given('wheelset', i, trim(keys(j)))) cycle
        path = deck%path('wheelset', i, trim(keys(j)))
        select case (lower_case(path))
        case ('s1002', '60e1', '54e1', 'uic60')
          cycle
        end select
        if (index(keys(j), 'wheel') == 1) then
          call load_wheel_profile(path, profile, error)
        else
          call load_rail_profile(path, profile, error)
        end if
        if (allocated(error)) then
          call error_context(error, deck%origin('wheelset', i, trim(keys(j))) // " (wheelset '" // &
                             name // "')")
          return
        end if
        if (j == 1) specs(i)%wheel_profile_data = profile
        if (j == 2) specs(i)%rail_profile_data = profile
      end do
    end do
  end subroutine load_wheelset_profiles
end module rd_scene_vehicle
