!> The scene's by-name surface for the C API and Python: the state vector (get, set, restart
!> from a results file) and outputs and inputs addressed by channel name.
submodule (rd_scene) rd_scene_by_name
  implicit none

contains

  !> After a failed run: stepping calls get the failure again, with what to do (the life
  !> cycle's advance and initialize, and this file's setters).
  module procedure refuse_after_failure
    if (.not. allocated(self%failure)) return
    call make_error(error, RD_ERR_HANDLE, 'scene: the run failed at t = ' // trim(real_text(self%t)) // &
                    ' s (' // self%failure // '); the results file records the failure and the ' // &
                    'run cannot go on: create a new model to run again')
  end procedure refuse_after_failure

  module procedure scene_get_state
    if (size(y) /= self%state_size()) then
      call make_error(error, RD_ERR_INPUT, 'get_state: the array has ' // trim(int_text(size(y))) // &
                      ' elements; expected the state size ' // trim(int_text(self%state_size())))
      return
    end if
    if (allocated(self%y)) y = self%y
  end procedure scene_get_state

  !> Replace the state at the current time (after initialize; the integrator restarts its
  !> history there). y in the layout of rd_multibody (state/y, docs/output.md).
  module procedure scene_set_state
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (.not. self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_state before initialize (set_start gives a ' // &
                      'state to start from)')
      return
    end if
    call check_state(self, y, 'set_state', error)
    if (allocated(error)) return
    self%y = y
    call self%integrator%reinit(self%t, self%y, error)
  end procedure scene_set_state

  !> Start the run at time t [s] from state y instead of the deck's initial state (a
  !> restart; before initialize). The first output row is (t, y).
  module procedure scene_set_start
    if (self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_start after initialize (set_state replaces ' // &
                      'the state at the current time)')
      return
    end if
    call self%build(error)
    if (allocated(error)) return
    if (.not. (ieee_is_finite(t) .and. t >= 0)) then
      call make_error(error, RD_ERR_INPUT, 'set_start: the time must be finite and >= 0 [s]')
      return
    end if
    call check_state(self, y, 'set_start', error)
    if (allocated(error)) return
    self%start_time = t
    self%start_state = y
  end procedure scene_set_start

  !> A restart from the last complete row of a results file's /state/y (rd_results_state),
  !> or from row `row` (counted from 0; raildyn eigen --state FILE:ROW): the deck must
  !> describe the same state (the column names, i.e. bodies, their free coordinates and the
  !> elements' states, must agree) and the file's rows must be states, not interval means.
  module procedure scene_continue_from
    type(results_state_t) :: saved
    integer :: id, row_wanted
    call self%build(error)
    if (allocated(error)) return
    row_wanted = -1
    if (present(row)) row_wanted = row
    call read_state_row(path, row_wanted, saved, error)
    if (allocated(error)) return
    if (saved%mean_samples > 0) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": its rows are interval means ' // &
        '(output_mean_samples = ' // trim(int_text(saved%mean_samples)) // '), not states; ' // &
        'a run cannot continue from it')
      return
    end if
    call self%outputs%find('state/y', id, error)
    if (allocated(error)) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": the deck has no bodies, so no state ' // &
                      'to continue from')
      return
    end if
    if (saved%components /= self%outputs%channels(id)%components) then
      call make_error(error, RD_ERR_INPUT, '"' // path // '": its state (' // &
        trim(int_text(size(saved%y))) // ' values) is not the state of this deck (' // &
        trim(int_text(self%mbs%state_size())) // ' values): ' // &
        first_difference(saved%components, self%outputs%channels(id)%components))
      return
    end if
    call self%set_start(saved%time, saved%y, error)
    if (allocated(error)) call error_context(error, '"' // path // '"')
  contains
    !> "column k is 'a' in the file, 'b' in the deck" for the first differing word.
    pure function first_difference(file_words, deck_words) result(text)
      character(len=*), intent(in) :: file_words, deck_words
      character(len=:), allocatable :: text
      character(len=:), allocatable :: a, b
      integer :: k, ia, ib
      a = file_words // ' '; b = deck_words // ' '
      k = 0
      do
        k = k + 1
        ia = index(a, ' '); ib = index(b, ' ')
        if (a(1:ia) /= b(1:ib) .or. len(a) <= 1 .or. len(b) <= 1) exit
        a = a(ia + 1:); b = b(ib + 1:)
      end do
      text = 'column ' // trim(int_text(k)) // " is '" // trim(a(1:max(ia, 1))) // "' in the file, '" // &
             trim(b(1:max(ib, 1))) // "' in the deck"
    end function first_difference
  end procedure scene_continue_from

  !> A state vector for this scene: the state size, finite.
  subroutine check_state(self, y, what, error)
    type(scene_t), intent(in) :: self
    real(wp), intent(in) :: y(:)
    character(len=*), intent(in) :: what
    type(error_t), allocatable, intent(out) :: error
    integer :: n
    n = 0
    if (associated(self%mbs)) n = self%mbs%state_size()
    if (size(y) /= n .or. n == 0) then
      call make_error(error, RD_ERR_INPUT, what // ': the state has ' // trim(int_text(size(y))) // &
                      ' values; expected the state size ' // trim(int_text(n)))
      return
    end if
    if (.not. all(ieee_is_finite(y))) then
      call make_error(error, RD_ERR_INPUT, what // ': the state values must be finite')
    end if
  end subroutine check_state

  module procedure scene_output_count
    scene_output_count = self%outputs%n
  end procedure scene_output_count

  module procedure scene_output_name
    if (index < 1 .or. index > self%outputs%n) then
      call make_error(error, RD_ERR_INPUT, 'output index ' // trim(int_text(index)) // &
                      ' out of range; expected 1 to ' // trim(int_text(self%outputs%n)))
      name = ''
      return
    end if
    name = self%outputs%channels(index)%name
  end procedure scene_output_name

  module procedure scene_output_size
    integer :: id
    n = 0
    call self%outputs%find(name, id, error)
    if (allocated(error)) return
    n = size(self%outputs%channels(id)%values)
  end procedure scene_output_size

  module procedure scene_get_output
    integer :: id
    call self%outputs%find(name, id, error)
    if (allocated(error)) return
    if (size(values) /= size(self%outputs%channels(id)%values)) then
      call make_error(error, RD_ERR_INPUT, 'output ' // name // ' has ' // &
                      trim(int_text(size(self%outputs%channels(id)%values))) // ' values; got an array of ' // &
                      trim(int_text(size(values))))
      return
    end if
    call self%refresh_outputs(error)
    if (allocated(error)) return
    values = self%outputs%channels(id)%values
  end procedure scene_get_output

  module procedure scene_set_input
    call refuse_after_failure(self, error)
    if (allocated(error)) return
    if (.not. self%initialized) then
      call make_error(error, RD_ERR_HANDLE, 'set_input before initialize')
      return
    end if
    if (.not. all(ieee_is_finite(values))) then
      call make_error(error, RD_ERR_INPUT, 'input ' // name // ': values must be finite')
      return
    end if
    select case (name)
    case ('speed')
      if (size(values) /= 1 .or. values(1) < 0) then
        call make_error(error, RD_ERR_INPUT, "input 'speed': expected one value >= 0 [m/s]")
        return
      end if
      call self%speed%override(self%t, values(1), error=error)
      if (allocated(error)) return
      if (associated(self%mbs)) then
        call self%mbs%speed%override(self%t, values(1), error=error)
        if (allocated(error)) return
        ! The right-hand side changes here: restart the integrator's history.
        call self%integrator%reinit(self%t, self%y, error)
      end if
    case default
      if (index(name, 'body/') == 1 .and. index(name, '/external_force') == len(name) - 14) then
        block
          integer :: ib
          ib = 0
          if (associated(self%mbs)) ib = body_index(self%deck, name(6:len(name) - 15))
          if (ib < 1) then
            call make_error(error, RD_ERR_INPUT, "input '" // name // "': no such body")
            return
          end if
          if (size(values) /= 6) then
            call make_error(error, RD_ERR_INPUT, "input '" // name // &
                            "': expected 6 values (force [N] and moment [N m], fixed frame)")
            return
          end if
          call self%mbs%set_override_load(ib, values(1:3), values(4:6), error)
          if (.not. allocated(error)) call self%integrator%reinit(self%t, self%y, error)
        end block
        return
      end if
      call make_error(error, RD_ERR_INPUT, "unknown input '" // name // &
                      "'; expected 'speed' or 'body/<name>/external_force'")
    end select
  end procedure scene_set_input

end submodule rd_scene_by_name
