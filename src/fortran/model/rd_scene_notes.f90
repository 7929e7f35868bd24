!> What a scene tells its user in words: the one-line summary, the completion line, the
!> run notes kept in the results file, the build warnings and the files the deck reads.
submodule (rd_scene) rd_scene_notes
  implicit none

contains

  module procedure scene_summary
    text = 'track ' // trim(real_text(self%track%length())) // ' m, ' // &
           trim(int_text(self%deck%count('segment'))) // ' segments, ' // &
           trim(int_text(self%deck%count('body'))) // ' bodies, ' // &
           trim(int_text(self%deck%count('element'))) // ' elements, ' // &
           trim(int_text(self%deck%count('wheelset'))) // ' wheelsets, t_end ' // trim(real_text(self%t_end)) // ' s'
  end procedure scene_summary

  !> One line for the runner: time reached, output steps and the integrator's effort (the
  !> counters /meta/solver keeps: a run that took many steps or failed many error tests
  !> shows it without opening the file), then 'note: ' + each run note.
  module procedure scene_completion_summary
    type(integrator_stats_t) :: st
    character(len=:), allocatable :: safety
    text = 'completed t = ' // trim(real_text(self%t)) // ' s, ' // trim(int_text(int(self%output_steps))) // &
           ' output steps'
    if (associated(self%integrator)) then
      call self%integrator_stats(st)
      text = text // '; solver: ' // trim(int_text(st%steps)) // ' steps, ' // &
             trim(int_text(st%rhs_evals + st%rhs_evals_jacobian)) // ' RHS calls (' // &
             trim(int_text(st%rhs_evals_jacobian)) // ' for Jacobians), ' // &
             trim(int_text(st%error_test_failures)) // ' error-test failures, ' // &
             trim(int_text(st%nonlinear_conv_failures)) // ' Newton failures'
    end if
    safety = self%safety%summary()
    if (len(safety) > 0) text = text // new_line('a') // safety
    text = text // contact_notes(self, new_line('a') // 'note: ')
    if (associated(self%mbs)) text = text // self%drift%notes(self%mbs, new_line('a') // 'warning: ')
  end procedure scene_completion_summary

  !> Warnings about legal but suspicious input (one line each, deck line first; empty
  !> before build): raildyn check and run print them.
  module procedure scene_warnings
    if (allocated(self%warning_list)) then
      list = self%warning_list
    else
      allocate (list(0))
    end if
  end procedure scene_warnings

  !> The run's notes for readers, one per line ('' when there are none): wheels that lost
  !> contact, bodies that left their track frames (rd_frame_drift). A user must know that
  !> the results contain flights and impacts (flange bouncing, lift-off) or a vehicle left
  !> behind before reading means off them; the runner prints them and the results file
  !> keeps them (/meta attribute 'notes', docs/output.md).
  module procedure scene_run_notes
    notes = contact_notes(self, new_line('a'))
    if (associated(self%mbs)) notes = notes // self%drift%notes(self%mbs, new_line('a'))
    notes = notes(2:)            ! '' stays ''
  end procedure scene_run_notes

  !> Each wheel that had no contact patch in some output samples, as `lead` followed by its
  !> note (share of the samples, largest sampled vertical force).
  function contact_notes(self, lead) result(notes)
    class(scene_t), intent(in) :: self
    character(len=*), intent(in) :: lead
    character(len=:), allocatable :: notes
    integer :: w, side
    character(len=16) :: pct, qmax
    notes = ''
    if (.not. allocated(self%samples_without_contact)) return
    do w = 1, size(self%wheelset_names)
      do side = 1, 2
        if (self%samples_without_contact(side, w) == 0) cycle
        pct = percent_text(100.0_wp * real(self%samples_without_contact(side, w), wp) / &
                           real(self%contact_samples, wp))
        qmax = one_decimal(1.0e-3_wp * self%max_sampled_q(side, w))
        notes = notes // lead // 'wheelset ' // trim(self%wheelset_names(w)) // ' ' // &
                trim(merge('left ', 'right', side == 1)) // ' wheel without contact in ' // trim(pct) // &
                ' % of ' // trim(int_text(int(self%contact_samples))) // ' output samples (largest sampled Q ' // &
                trim(qmax) // ' kN)'
      end do
    end do
  contains
    !> A share in % to one decimal; a share that is not zero but rounds to it reads '< 0.1'
    pure function percent_text(x) result(text)
      real(wp), intent(in) :: x
      character(len=16) :: text
      if (x > 0 .and. x < 0.05_wp) then
        text = '< 0.1'
      else
        text = one_decimal(x)
      end if
    end function percent_text
    !> x to one decimal with its leading zero (f0.1 alone prints '.0' and '.5')
    pure function one_decimal(x) result(text)
      real(wp), intent(in) :: x
      character(len=16) :: text
      write (text, '(f0.1)') x
      if (text(1:1) == '.') text = '0' // text
    end function one_decimal
  end function contact_notes

  !> Every file the scene's deck reads (rd_deck input_files): the deck, its includes at any
  !> depth, profile, irregularity and survey files. Empty before a deck was loaded.
  module procedure scene_input_files
    files = self%deck%input_files()
  end procedure scene_input_files

end submodule rd_scene_notes
