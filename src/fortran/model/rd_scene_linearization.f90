!> The linearised equations of motion of a scene about its current time and state
!> (docs/theory_stability.md): A = df/dy of y' = f(t, y) by central differences of the
!> scene's right-hand side (rd_multibody rhs), with the running speed, track and loads as
!> the scene has them at that time. Used by `raildyn eigen` and `raildyn critical-speed`
!> (runner/rd_cmd_eigen.f90) and by the C API's rd_linearize.
!>
!> Rows and columns follow the state layout of rd_multibody (docs/output.md, /state/y):
!> free coordinates q_f, their rates nu_f, the elements' internal states.
!>
!> Differences: y_j +- h_j with h_j = 1e-8 max(1, |y_j|) (metres, radians, m/s, rad/s):
!> small against the Hertz approach of a wheel (~5e-5 m; its force goes as approach^1.5,
!> so the truncation error is ~ (h/approach)^2 ~ 1e-7 relative) and against the creepages'
!> linear range (~1e-3 V), large enough that round-off (~1e-16 |f| / h) stays below 1e-7
!> of the entries. A linear scene gives its matrix to round-off.
module rd_scene_linearization
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_HANDLE, RD_ERR_INPUT
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_body_spec, only: DOF_X, DOF_Y, DOF_Z, DOF_YAW, DOF_ROLL, DOF_PITCH
  use rd_deck, only: deck_string_t
  use rd_text, only: int_text, sci_text
  implicit none
  private
  public :: linearize_scene, scene_state_names, scene_state_weights, select_states, spin_rate_rows, DOF_NAMES

  !> Coordinate names in rd_multibody's order (docs/conventions.md, body frames).
  character(len=5), parameter :: DOF_NAMES(6) = ['x    ', 'y    ', 'z    ', 'yaw  ', 'roll ', 'pitch']

contains

  !> A (n x n, n the state size) about the scene's current time and state. The scene must
  !> be initialized and hold bodies. `rate`: f(t, y) itself (zero at an equilibrium).
  subroutine linearize_scene(scene, a, error, rate)
    type(scene_t), intent(in) :: scene
    real(wp), allocatable, intent(out) :: a(:, :)
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable, intent(out), optional :: rate(:)
    type(multibody_t), pointer :: mbs
    real(wp), allocatable :: y(:), yp(:), fp(:), fm(:)
    real(wp) :: h, t
    integer :: n, j
    n = scene%state_size()
    mbs => scene%system()
    if (n == 0 .or. .not. associated(mbs)) then
      call make_error(error, RD_ERR_HANDLE, 'linearize: the scene has no state (initialize it first; ' // &
                      'a deck without bodies has nothing to linearise)')
      return
    end if
    allocate (y(n), fp(n), fm(n), a(n, n))
    call scene%get_state(y, error)
    if (allocated(error)) return
    t = scene%time()
    do j = 1, n
      h = 1.0e-8_wp * max(1.0_wp, abs(y(j)))
      yp = y
      yp(j) = y(j) + h
      call mbs%rhs(t, yp, fp, error)
      if (.not. allocated(error)) then
        yp(j) = y(j) - h
        call mbs%rhs(t, yp, fm, error)
      end if
      if (allocated(error)) then
        call error_context(error, 'linearize: state ' // trim(int_text(j)) // ' (' // &
                           state_name(mbs, j) // ') moved by ' // trim(sci_text(h, 2)))
        return
      end if
      a(:, j) = (fp - fm) / (2 * h)
    end do
    ! the system's last evaluation at the state itself: its quasi-static coordinates start there
    call mbs%rhs(t, y, fp, error)
    if (present(rate)) rate = fp
  end subroutine linearize_scene

  !> Name of each state as `raildyn run` writes it (/state/y components): '<body>.<dof>',
  !> '<body>.nu_<dof>', '<element>.x<k>'.
  function scene_state_names(scene) result(names)
    type(scene_t), intent(in) :: scene
    type(deck_string_t), allocatable :: names(:)
    character(len=:), allocatable :: components, units
    type(multibody_t), pointer :: mbs
    integer :: j, start, length
    allocate (names(scene%state_size()))
    if (size(names) == 0) return
    mbs => scene%system()
    call mbs%state_layout(components, units)
    components = components // ' '
    start = 1
    do j = 1, size(names)
      length = index(components(start:), ' ') - 1
      names(j)%s = components(start:start + length - 1)
      start = start + length + 1
    end do
  end function scene_state_names

  !> Participation weights (rd_linear_modes): mass [kg] on the x, y, z rows of a body,
  !> its moments of inertia about the body axes [kg m^2] on yaw (z), roll (x), pitch (y),
  !> 0 on rates and internal states.
  function scene_state_weights(scene) result(weights)
    type(scene_t), intent(in) :: scene
    real(wp), allocatable :: weights(:)
    type(multibody_t), pointer :: mbs
    integer :: b, d, k
    integer, parameter :: inertia_axis(DOF_YAW:DOF_PITCH) = [3, 1, 2]
    mbs => scene%system()
    allocate (weights(scene%state_size()), source=0.0_wp)
    if (.not. associated(mbs)) return
    do b = 1, mbs%body_count()
      do d = 1, 6
        k = mbs%free_slot(b, d)
        if (k == 0) cycle
        if (d <= DOF_Z) then
          weights(k) = mbs%bodies(b)%mass
        else
          weights(k) = mbs%bodies(b)%inertia(inertia_axis(d), inertia_axis(d))
        end if
      end do
    end do
  end function scene_state_weights

  !> True on the rows of the wheelsets' spin rates (d beta / dt, docs/conventions.md): at
  !> speed the loaded rolling radius differs slightly from r0, so longitudinal creep drives
  !> the spin to a steady deviation from nominal rolling; the static solve (at V = 0) cannot
  !> know it. The spin angle itself enters no force, so this drift leaves the matrix as it is.
  function spin_rate_rows(scene) result(spin)
    type(scene_t), intent(in) :: scene
    logical, allocatable :: spin(:)
    type(multibody_t), pointer :: mbs
    integer :: b, k
    mbs => scene%system()
    allocate (spin(scene%state_size()), source=.false.)
    if (.not. associated(mbs)) return
    do b = 1, mbs%body_count()
      k = mbs%free_slot(b, DOF_PITCH)
      if (mbs%bodies(b)%is_wheelset .and. k > 0) spin(mbs%nfree + k) = .true.
    end do
  end function spin_rate_rows

  !> The states kept by a selection of coordinates (raildyn eigen --dofs): each word is a
  !> coordinate name (x, y, z, yaw, roll, pitch: that coordinate of every body), a body
  !> name (all its free coordinates) or '<body>.<coordinate>'. A kept coordinate keeps its
  !> rate; the elements' internal states are always kept; the other coordinates are held
  !> at their values (rows and columns removed). An empty selection keeps everything.
  subroutine select_states(scene, words, kept, error)
    type(scene_t), intent(in) :: scene
    type(deck_string_t), intent(in) :: words(:)
    integer, allocatable, intent(out) :: kept(:)
    type(error_t), allocatable, intent(out) :: error
    type(multibody_t), pointer :: mbs
    logical, allocatable :: keep(:)
    logical :: matched
    integer :: w, b, d, k, dot, n
    character(len=:), allocatable :: body, dof
    mbs => scene%system()
    n = scene%state_size()
    if (size(words) == 0 .or. .not. associated(mbs)) then
      kept = [(k, k = 1, n)]
      return
    end if
    allocate (keep(n), source=.false.)
    keep(2 * mbs%nfree + 1:) = .true.
    do w = 1, size(words)
      dot = index(words(w)%s, '.')
      body = ''
      dof = words(w)%s
      if (dot > 0) then
        body = words(w)%s(:dot - 1)
        dof = words(w)%s(dot + 1:)
      else if (all(DOF_NAMES /= words(w)%s)) then
        body = words(w)%s
        dof = ''
      end if
      if (len(dof) > 0 .and. all(DOF_NAMES /= dof)) then
        call make_error(error, RD_ERR_INPUT, "--dofs: '" // words(w)%s // "': unknown coordinate '" // dof // &
                        "'; expected x, y, z, yaw, roll or pitch, a body name or <body>.<coordinate>")
        return
      end if
      matched = .false.
      do b = 1, mbs%body_count()
        if (len(body) > 0 .and. mbs%bodies(b)%name /= body) cycle
        do d = 1, 6
          if (len(dof) > 0 .and. DOF_NAMES(d) /= dof) cycle
          k = mbs%free_slot(b, d)
          if (k == 0) cycle
          keep(k) = .true.
          keep(mbs%nfree + k) = .true.
          matched = .true.
        end do
      end do
      if (.not. matched) then
        call make_error(error, RD_ERR_INPUT, "--dofs: '" // words(w)%s // "' selects no free coordinate " // &
                        '(body names and free coordinates: /state/y in docs/output.md; frozen ones are not states)')
        return
      end if
    end do
    kept = pack([(k, k = 1, n)], keep)
  end subroutine select_states

  !> Name of state j (scene_state_names).
  function state_name(mbs, j) result(name)
    type(multibody_t), intent(in) :: mbs
    integer, intent(in) :: j
    character(len=:), allocatable :: name
    character(len=:), allocatable :: components, units
    integer :: k, start
    call mbs%state_layout(components, units)
    components = components // ' '
    start = 1
    do k = 1, j - 1
      start = start + index(components(start:), ' ')
    end do
    name = components(start:start + index(components(start:), ' ') - 2)
  end function state_name
end module rd_scene_linearization
