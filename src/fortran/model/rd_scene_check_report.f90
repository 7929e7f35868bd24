!> What a modeller checks first about a scene (raildyn check prints it), from the scene
!> after initialize (static equilibrium done, no integration):
!>
!>   masses        each body's mass, the total and its weight
!>   wheel loads   the static vertical wheel forces Q and their sum against the weight
!>   reference radius  per wheelset, the reference rolling radius r0 of its nominal spin
!>                 V / r0 and where it comes from (&wheelset reference_radius, the centred
!>                 rolling radius of the profiles, or a knife edge's nominal_radius), with
!>                 the tape-circle radius nominal_radius beside it
!>   conicity      per wheelset, the rolling-radius difference of patch 1 with the wheelset
!>                 shifted by +-CONICITY_SHIFT (roll held; lowered in steps of LOWERING_STEP
!>                 until both wheels touch): lambda = (dr(+y) - dr(-y)) / (4 y),
!>                 dr = r_left - r_right (a secant conicity of the contact geometry, not the
!>                 harmonic UIC 519 equivalent conicity)
!>   curves        each circular curve of the track (constant non-zero curvature): radius,
!>                 cant, the speed when the vehicle reference enters it, the unbalanced
!>                 lateral acceleration in the track plane a_q = V^2/R cos(phi) - g sin(phi)
!>                 and the cant deficiency I = cant_base a_q / g (small-angle form of
!>                 I = cant_base V^2 / (g R) - h)
!>   equilibrium   how far the static equilibrium moved each body from the deck's position,
!>                 with a warning above MOVE_LIMIT / TURN_LIMIT (a wheelset placed at z = 0
!>                 instead of its rolling radius moves 0.46 m without a word otherwise)
submodule (rd_scene) rd_scene_check_report
  use rd_text, only: fixed_text
  use rd_body_spec, only: DOF_Z
  use rd_contact_geometry, only: CONTACT_MODEL_STRIP
  implicit none

  real(wp), parameter :: CONICITY_SHIFT = 0.003_wp   !< [m], the usual lateral amplitude
  real(wp), parameter :: LOWERING_STEP = 2.0e-5_wp    !< [m], see conicities
  integer, parameter :: MAX_LOWERING_STEPS = 150      !< up to 3 mm
  !> The equilibrium moved a body further than a deck's position should be off: [m], [rad]
  real(wp), parameter :: MOVE_LIMIT = 0.05_wp, TURN_LIMIT = 0.05_wp
  real(wp), parameter :: CURVE_SCAN_STEP = 1.0_wp    !< [m]

contains

  module function scene_check_report(self) result(text)
    class(scene_t), intent(inout) :: self
    character(len=:), allocatable :: text
    character(len=1), parameter :: nl = new_line('a')
    text = ''
    if (.not. self%initialized) return
    if (associated(self%mbs)) then
      text = text // masses(self) // nl
      if (associated(self%contact)) text = text // wheel_loads(self) // nl // reference_radii(self) // nl // &
                                           conicities(self) // nl
    end if
    text = text // curves(self)
    if (associated(self%mbs)) text = text // nl // equilibrium_moves(self)
  end function scene_check_report

  function masses(self) result(text)
    type(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    real(wp) :: total
    integer :: i
    text = 'masses:'
    total = 0
    do i = 1, self%mbs%body_count()
      if (i > 1) text = text // ','
      text = text // ' ' // self%mbs%bodies(i)%name // ' ' // trim(fixed_text(self%mbs%bodies(i)%mass, 1)) // ' kg'
      total = total + self%mbs%bodies(i)%mass
    end do
    text = text // '; total ' // trim(fixed_text(total, 1)) // ' kg, weight ' // &
           trim(fixed_text(1e-3_wp * total * self%mbs%gravity, 2)) // ' kN'
  end function masses

  !> Q of every wheel after the equilibrium, and their sum against the weight of all bodies
  !> (rail bodies of flexible track included: they are carried by their pads, not by the
  !> wheels, so the share is then below 100 %).
  function wheel_loads(self) result(text)
    type(scene_t), intent(inout) :: self
    character(len=:), allocatable :: text
    real(wp) :: total, weight
    integer :: w, side
    type(scene_output_t) :: out
    type(error_t), allocatable :: error
    text = 'static wheel loads Q:'
    call self%calc_output(out, error)
    if (allocated(error)) then
      text = text // ' n/a (' // error%message // ')'
      return
    end if
    total = 0
    do w = 1, size(self%wheelset_names)
      if (w > 1) text = text // ';'
      text = text // ' ' // trim(self%wheelset_names(w))
      do side = 1, 2
        associate (q => out%contact(w)%wheel(side)%force_track(3))
          text = text // ' ' // trim(merge('left ', 'right', side == 1)) // ' ' // trim(fixed_text(1e-3_wp * q, 2)) // ' kN'
          total = total + q
        end associate
      end do
    end do
    weight = sum([(self%mbs%bodies(w)%mass, w = 1, self%mbs%body_count())]) * self%mbs%gravity
    text = text // '; sum ' // trim(fixed_text(1e-3_wp * total, 2)) // ' kN = ' // &
           trim(fixed_text(100 * total / weight, 1)) // ' % of the weight'
  end function wheel_loads

  function reference_radii(self) result(text)
    type(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    type(error_t), allocatable :: error
    real(wp) :: tape
    integer :: w
    text = 'reference rolling radius r0 (nominal spin V / r0):'
    do w = 1, size(self%wheelset_names)
      if (w > 1) text = text // ';'
      call self%deck%get('wheelset', w, 'nominal_radius', tape, error)
      text = text // ' ' // trim(self%wheelset_names(w)) // ' ' // &
             trim(fixed_text(self%mbs%bodies(self%contact%models(w)%body)%r0, 6)) // ' m ('
      if (self%deck%given('wheelset', w, 'reference_radius')) then
        text = text // 'reference_radius'
      else if (self%contact%models(w)%geo%model == CONTACT_MODEL_STRIP) then
        text = text // 'centred rolling radius of the profiles'
      else
        text = text // 'knife edge: nominal_radius'
      end if
      text = text // '; tape circle ' // trim(fixed_text(tape, 6)) // ' m)'
    end do
  end function reference_radii

  function conicities(self) result(text)
    type(scene_t), intent(inout) :: self
    character(len=:), allocatable :: text
    real(wp), allocatable :: y0(:)
    real(wp) :: difference(2), shift(2)
    integer :: w, slot, z_slot, k, lowering
    type(scene_output_t) :: out
    type(error_t), allocatable :: error
    text = 'conicity (r_left - r_right of patch 1 at y = +-' // trim(fixed_text(1e3_wp * CONICITY_SHIFT, 0)) // &
           ' mm, divided by 2 y):'
    y0 = self%y
    shift = [CONICITY_SHIFT, -CONICITY_SHIFT]
    do w = 1, size(self%wheelset_names)
      if (w > 1) text = text // ';'
      text = text // ' ' // trim(self%wheelset_names(w)) // ' '
      slot = self%mbs%free_slot(self%contact%models(w)%body, DOF_Y)
      if (slot == 0) then
        text = text // 'n/a (y frozen)'
        cycle
      end if
      z_slot = self%mbs%free_slot(self%contact%models(w)%body, DOF_Z)
      do k = 1, 2
        ! shifted with its roll held, one wheel may lift off its rail: lowered just enough
        ! that both touch (the rolling radii hardly depend on the approach)
        do lowering = 0, merge(MAX_LOWERING_STEPS, 0, z_slot > 0)
          self%y = y0
          self%y(slot) = y0(slot) + shift(k)
          if (z_slot > 0) self%y(z_slot) = y0(z_slot) - lowering * LOWERING_STEP
          call self%calc_output(out, error)     ! an error here: lowered further, as without contact
          if (allocated(error)) cycle
          if (out%contact(w)%wheel(1)%n_patches > 0 .and. out%contact(w)%wheel(2)%n_patches > 0) exit
        end do
        if (allocated(error)) exit
        associate (res => out%contact(w))
          if (res%wheel(1)%n_patches == 0 .or. res%wheel(2)%n_patches == 0) exit
          difference(k) = res%wheel(1)%patch(1)%rolling_radius - res%wheel(2)%patch(1)%rolling_radius
        end associate
      end do
      if (allocated(error)) then
        text = text // 'n/a (' // error%message // ')'
        deallocate (error)
      else if (k <= 2) then
        text = text // 'n/a (a wheel without contact when shifted)'
      else
        text = text // trim(fixed_text((difference(1) - difference(2)) / (4 * CONICITY_SHIFT), 4))
      end if
    end do
    ! evaluated at the state again: the quasi-static solve starts from its last solution
    self%y = y0
    call self%calc_output(out, error)
    if (allocated(error)) text = text // ' (at the state: ' // error%message // ')'
  end function conicities

  !> Circular curves found by scanning the track every CURVE_SCAN_STEP.
  function curves(self) result(text)
    type(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    type(track_point_t) :: p, first
    real(wp) :: sigma, last, length, cant_base, gravity, v, t_entry, a_q, cant
    integer :: n
    logical :: inside
    type(error_t), allocatable :: error
    call self%deck%get('track', 1, 'cant_base', cant_base, error)
    call self%deck%get('simulation', 1, 'gravity', gravity, error)
    text = 'curves:'
    n = 0
    inside = .false.
    length = self%track%length()
    sigma = 0
    last = 0
    do
      p = self%track%evaluate(min(sigma, length))
      if (inside .and. .not. same_curve(p, first)) then
        call describe(first, last)
        inside = .false.
      end if
      if (.not. inside .and. is_circular(p)) then
        inside = .true.
        first = p
      end if
      if (inside) last = min(sigma, length)
      if (sigma >= length) exit
      sigma = sigma + CURVE_SCAN_STEP
    end do
    if (inside) call describe(first, last)
    if (n == 0) text = text // ' none (no stretch of constant non-zero curvature)'
  contains
    logical function is_circular(q)
      type(track_point_t), intent(in) :: q
      is_circular = abs(q%curvature) > 0 .and. abs(q%dcurvature) * CURVE_SCAN_STEP <= 1e-6_wp * abs(q%curvature)
    end function is_circular

    logical function same_curve(q, start)
      type(track_point_t), intent(in) :: q, start
      same_curve = is_circular(q) .and. abs(q%curvature - start%curvature) <= 1e-9_wp * abs(start%curvature)
    end function same_curve

    subroutine describe(start, sigma_end)
      type(track_point_t), intent(in) :: start
      real(wp), intent(in) :: sigma_end
      n = n + 1
      ! the cant is the outer rail over the inner one: superelevation is left over right,
      ! and the outer rail of a left-hand curve (curvature > 0) is the right one
      cant = -sign(1.0_wp, start%curvature) * start%superelevation
      text = text // new_line('a') // '  sigma ' // trim(fixed_text(start%sigma, 0)) // '-' // &
             trim(fixed_text(sigma_end, 0)) // ' m: R ' // trim(fixed_text(1 / abs(start%curvature), 0)) // ' m ' // &
             trim(merge('left ', 'right', start%curvature > 0)) // ', cant ' // trim(fixed_text(1e3_wp * cant, 0)) // ' mm'
      t_entry = entry_time(start%sigma)
      if (t_entry < 0) then
        text = text // '; not reached by t_end'
        return
      end if
      v = self%speed%speed(t_entry)
      a_q = v**2 * abs(start%curvature) * cos(start%cant_angle) - gravity * sin(abs(start%cant_angle)) * &
            sign(1.0_wp, cant)
      text = text // '; V ' // trim(fixed_text(v, 1)) // ' m/s at entry (t = ' // trim(fixed_text(t_entry, 2)) // &
             ' s): unbalanced lateral acceleration ' // trim(fixed_text(a_q, 3)) // ' m/s^2, cant deficiency ' // &
             trim(fixed_text(1e3_wp * cant_base * a_q / gravity, 0)) // ' mm'
    end subroutine describe

    !> First time the vehicle reference is at `at` (bisection: sigma(t) does not decrease);
    !> 0 when it starts beyond it, -1 when it does not get there by t_end.
    real(wp) function entry_time(at)
      real(wp), intent(in) :: at
      real(wp) :: lo, hi, mid
      integer :: k
      if (self%vehicle_sigma(0.0_wp) >= at) then
        entry_time = 0; return
      end if
      if (self%vehicle_sigma(self%t_end) < at) then
        entry_time = -1; return
      end if
      lo = 0; hi = self%t_end
      do k = 1, 60
        mid = 0.5_wp * (lo + hi)
        if (self%vehicle_sigma(mid) < at) then
          lo = mid
        else
          hi = mid
        end if
      end do
      entry_time = hi
    end function entry_time
  end function curves

  !> Per body, the largest change of a translation and of a rotation coordinate between the
  !> deck's configuration and the static equilibrium; warnings above the limits.
  function equilibrium_moves(self) result(text)
    type(scene_t), intent(in) :: self
    character(len=:), allocatable :: text
    character(len=5), parameter :: dof_names(6) = ['x    ', 'y    ', 'z    ', 'yaw  ', 'roll ', 'pitch']
    character(len=:), allocatable :: warnings
    real(wp) :: dq(6)
    integer :: i, j, slot, jt, jr
    text = 'equilibrium (' // self%equilibrium // ') moved the bodies from the deck''s positions by:'
    warnings = ''
    do i = 1, self%mbs%body_count()
      dq = 0
      do j = 1, 6
        slot = self%mbs%free_slot(i, j)
        if (slot > 0) dq(j) = self%y(slot) - self%y_as_built(slot)
      end do
      if (self%mbs%bodies(i)%is_wheelset) dq(DOF_PITCH) = 0   ! the spin is not a position
      jt = maxloc(abs(dq(1:3)), dim=1)
      jr = 3 + maxloc(abs(dq(4:6)), dim=1)
      if (i > 1) text = text // ','
      text = text // ' ' // self%mbs%bodies(i)%name // ' ' // trim(fixed_text(1e3_wp * dq(jt), 2)) // ' mm (' // trim(dof_names(jt)) // '), ' // &
             trim(fixed_text(1e3_wp * dq(jr), 2)) // ' mrad (' // trim(dof_names(jr)) // ')'
      if (abs(dq(jt)) > MOVE_LIMIT) warnings = warnings // new_line('a') // 'warning: the equilibrium moved ' // &
        self%mbs%bodies(i)%name // ' by ' // trim(fixed_text(dq(jt), 3)) // ' m in ' // trim(dof_names(jt)) // &
        ' (more than ' // trim(fixed_text(MOVE_LIMIT, 2)) // ' m): is its position in the deck right?'
      if (abs(dq(jr)) > TURN_LIMIT) warnings = warnings // new_line('a') // 'warning: the equilibrium turned ' // &
        self%mbs%bodies(i)%name // ' by ' // trim(fixed_text(dq(jr), 3)) // ' rad in ' // trim(dof_names(jr)) // &
        ' (more than ' // trim(fixed_text(TURN_LIMIT, 2)) // ' rad): is its orientation in the deck right?'
    end do
    text = text // warnings
  end function equilibrium_moves

end submodule rd_scene_check_report
