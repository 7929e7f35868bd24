!> Builds the track of a scene from the deck's `&track` and `&segment` groups.
!>
!> Decks speak the railway engineer's language (radius, side, superelevation of the
!> outer rail); the track module takes signed curvature and the superelevation of
!> the left rail over the right one (docs/conventions.md). The conversion lives here
!> and nowhere else.
module rd_scene_track
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT
  use rd_deck, only: deck_t
  use rd_track_point, only: track_geometry_t
  use rd_track, only: track_t, track_settings_t, segment_spec_t, build_track, GRADIENT_UNCHANGED
  use rd_survey_track, only: survey_track_t, build_survey_track, read_survey_file
  use rd_track_irregularity, only: track_irregularity_t, build_track_irregularity, read_irregularity_file
  implicit none
  private
  public :: build_scene_track, build_scene_irregularity

contains

  subroutine build_scene_track(deck, track, error)
    type(deck_t), intent(in) :: deck
    class(track_geometry_t), allocatable, intent(out) :: track
    type(error_t), allocatable, intent(out) :: error
    type(track_settings_t) :: settings
    type(segment_spec_t), allocatable :: specs(:)
    type(track_t), allocatable :: segment_track
    type(survey_track_t), allocatable :: surveyed
    real(wp), allocatable :: x(:), y(:), z(:), h(:)
    real(wp), allocatable :: start_position(:)

    if (deck%count('track') > 0) then
      call deck%get('track', 1, 'gauge', settings%gauge, error)
      if (allocated(error)) return
      call deck%get('track', 1, 'cant_base', settings%cant_base, error)
      if (allocated(error)) return
      call deck%get('track', 1, 'start_heading', settings%start_heading, error)
      if (allocated(error)) return
      call deck%get('track', 1, 'start_position', start_position, error)
      if (allocated(error)) return
      settings%start_position = start_position
      settings%origin = deck%origin('track', 1)
      if (deck%given('track', 1, 'survey_file')) then
        call read_survey_file(deck%path('track', 1, 'survey_file'), x, y, z, h, error)
        if (allocated(error)) then
          call error_context(error, deck%origin('track', 1, 'survey_file'))
          return
        end if
        allocate (surveyed)
        call build_survey_track(surveyed, x, y, z, h, error, cant_base=settings%cant_base, &
                                gauge=settings%gauge, origin=deck%origin('track', 1, 'survey_file'))
        if (allocated(error)) return
        call move_alloc(surveyed, track)
        return
      end if
    end if

    call segment_specs(deck, settings, specs, error)
    if (allocated(error)) return
    allocate (segment_track)
    call build_track(segment_track, settings, specs, error)
    if (allocated(error)) return
    call move_alloc(segment_track, track)
  end subroutine build_scene_track

  !> Track irregularities of `&track irregularity_file` (path relative to the deck), scaled
  !> by irregularity_scale and faded in over irregularity_fade. `irregularity` stays
  !> unallocated when the deck names no file. File errors name the file and line, and the
  !> deck line that names the file.
  subroutine build_scene_irregularity(deck, irregularity, error)
    type(deck_t), intent(in) :: deck
    type(track_irregularity_t), allocatable, intent(out) :: irregularity
    type(error_t), allocatable, intent(out) :: error
    real(wp), allocatable :: sigma(:), values(:, :)
    real(wp) :: scale, fade
    if (deck%count('track') == 0) return
    if (.not. deck%given('track', 1, 'irregularity_file')) return
    if (deck%count('wheelset') == 0) then
      call make_error(error, RD_ERR_INPUT, deck%origin('track', 1, 'irregularity_file') // &
        ': irregularities act through the wheel-rail contact; expected &wheelset groups in the deck')
      return
    end if
    call deck%get('track', 1, 'irregularity_scale', scale, error)
    if (allocated(error)) return
    call deck%get('track', 1, 'irregularity_fade', fade, error)
    if (allocated(error)) return
    call read_irregularity_file(deck%path('track', 1, 'irregularity_file'), sigma, values, error)
    if (allocated(error)) then
      call error_context(error, deck%origin('track', 1, 'irregularity_file'))
      return
    end if
    allocate (irregularity)
    call build_track_irregularity(irregularity, sigma, values, error, scale=scale, fade=fade, &
                                  origin=deck%origin('track', 1, 'irregularity_file'))
    if (allocated(error)) deallocate (irregularity)
  end subroutine build_scene_irregularity

  !> One spec per `&segment`, in deck order. A deck without segments is a straight,
  !> level track (the vehicle may still run past its end, which continues tangentially).
  subroutine segment_specs(deck, settings, specs, error)
    type(deck_t), intent(in) :: deck
    type(track_settings_t), intent(in) :: settings
    type(segment_spec_t), allocatable, intent(out) :: specs(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, n
    character(len=:), allocatable :: kind, side, ramp
    real(wp) :: radius, cant, sign_side

    n = deck%count('segment')
    allocate (specs(n))
    do i = 1, n
      call deck%get('segment', i, 'type', kind, error)
      if (allocated(error)) return
      specs(i)%kind = kind
      call deck%get('segment', i, 'length', specs(i)%length, error)
      if (allocated(error)) return
      call deck%get('segment', i, 'cant_ramp', ramp, error)
      if (allocated(error)) return
      specs(i)%cant_ramp = ramp
      specs(i)%origin = deck%origin('segment', i)
      if (deck%given('segment', i, 'gradient')) then
        call deck%get('segment', i, 'gradient', specs(i)%gradient_end, error)
        if (allocated(error)) return
      else
        specs(i)%gradient_end = GRADIENT_UNCHANGED
      end if

      radius = 0
      sign_side = 0
      if (deck%given('segment', i, 'radius')) then
        call deck%get('segment', i, 'radius', radius, error)
        if (allocated(error)) return
        if (.not. deck%given('segment', i, 'side')) then
          call make_error(error, RD_ERR_INPUT, deck%origin('segment', i, 'side') // &
            ": missing; expected 'left' or 'right' with a radius (which way the track curves)")
          return
        end if
        call deck%get('segment', i, 'side', side, error)
        if (allocated(error)) return
        sign_side = merge(1.0_wp, -1.0_wp, side == 'left')
      end if

      select case (kind)
      case ('straight')
        if (deck%given('segment', i, 'radius')) then
          call make_error(error, RD_ERR_INPUT, deck%origin('segment', i, 'radius') // &
            ": a straight segment has no radius; expected type = 'curve' or 'clothoid'")
          return
        end if
      case ('curve')
        if (.not. deck%given('segment', i, 'radius')) then
          call make_error(error, RD_ERR_INPUT, deck%origin('segment', i, 'radius') // &
            ': missing; expected the radius of the curve in metres (> 0)')
          return
        end if
      end select
      if (sign_side /= 0) specs(i)%curvature_end = sign_side / radius

      ! Cant is the superelevation of the outer rail of the segment's side; the track
      ! module wants the left rail over the right one: a left curve raises the right rail.
      call deck%get('segment', i, 'cant', cant, error)
      if (allocated(error)) return
      if (cant /= 0 .and. sign_side == 0) then
        call make_error(error, RD_ERR_INPUT, deck%origin('segment', i, 'cant') // &
          ": cant needs a curve side; expected radius and side = 'left' or 'right' " // &
          "(the outer rail of that side is raised)")
        return
      end if
      specs(i)%superelevation_end = -sign_side * cant
    end do
    if (settings%gauge <= 0) then
      call make_error(error, RD_ERR_INPUT, trim(settings%origin) // ": 'gauge' must be > 0")
    end if
  end subroutine segment_specs
end module rd_scene_track
