!> Pre-computed contact tables: a geometry provider that tabulates the strip model
!> (rd_strip_contact) of one wheel/rail pair once and interpolates it in the right-hand
!> side (docs/theory_contact_geometry.md, section "Contact tables").
!>
!> Table variables, per wheel (LEFT wheel model, the right one by mirroring as for strips):
!>   u   = lateral displacement of the wheel's reference point (tape circle, lowest point of
!>         the unrolled wheel) from its nominal place: u = y + y_tape (cos phi - 1) + r0 sin phi,
!>   phi = roll (tilt of the wheel profile), at zero yaw,
!> and a second table over u and the yaw psi at zero roll, which holds how much the yaw
!> changes each quantity (the angle of attack moves the flange contact by tens of um in height
!> and millimetres along the rail at 10-20 mrad).
!> Writing the table over u instead of the wheelset's y removes the roll's lever arm: at
!> fixed u only the small tilt of the profile depends on phi, so a few roll nodes suffice.
!>
!> Patch identity: the wheel profile is cut into a tread part, a flange-root part and a
!> flange-face part: the tread ends where its slope angle first exceeds `slot_angle` going
!> from the tape circle towards the flange, where the root begins; the root ends where the
!> slope angle exceeds `root_angle`, the face begins where it exceeds `face_angle`. With
!> face_angle < root_angle (the default) the root and the face overlap: a contact in the band
!> between is found by both slots, and their patches carry shares that sum to one across the
!> band where they are one contact (slot_shares), so it counts once; with face_angle > root_angle the wheel between the two
!> is in neither part. Each part is searched by the strip model on its own,
!> which gives each slot a signed gap even where it does not touch (onset and loss of a
!> patch are then a smooth sign change of its penetration, never a change of identity). The
!> cuts lie where the contact jumps over the wheel (S1002 on 60E1 / UIC60: tread 0.12 ->
!> root 0.29 rad, root 0.65 -> face 1.22 rad): one slot for root and face together held the
!> deepest of the two, and interpolation across that jump made a steep ramp of contact
!> angles that do not exist (docs/theory_contact_geometry.md section 10).
!>
!> Penetration model: per slot the table holds the height h of the reference point at which
!> that part just touches the rail (root of the strip model's signed maximum penetration),
!> and the patch data (points, contact angle, radius, curvatures) evaluated at the reference
!> normal approach `reference_approach` below that height. At run time the slot's normal
!> approach is the vertical overlap times the cosine of its contact angle,
!>   delta = (h(u, phi) - Z_ref) cos(gamma),
!> exact to first order in the approach (a vertical displacement dZ moves the wheel by
!> dZ cos(gamma) along the contact normal).
!>
!> Interpolation: cubic Hermite in u with Fritsch-Carlson slopes (C1, no overshoot at the
!> contact jumps), cubic Hermite in phi with central-difference slopes over the values
!> interpolated at the roll nodes (C1). Roll beyond the table's range keeps the exact
!> reference-point transformation and clamps only the tilt.
!> Yaw: v(u, phi, psi) = v(u, phi, 0) + D(u, psi), D(u, psi) = v(u, 0, psi) - v(u, 0, 0) from
!> the yaw table (exact at zero roll; the roll's effect on the yaw's change is left out). The
!> geometry is symmetric under x -> -x, which reverses the yaw: every quantity is even in psi
!> except the longitudinal positions of the contact points (odd), so the yaw nodes cover
!> psi >= 0 and the Hermite in |psi| takes its ghost node below 0 by that parity (C1 through
!> psi = 0). Yaw beyond the table's range clamps the change, not the exact reference point.
module rd_contact_table
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_RUNTIME
  use rd_text, only: sci_text
  use rd_contact_surfaces, only: wheel_surface_t, rail_surface_t
  use rd_contact_patch, only: patch_geometry_t, wheel_contact_t, PATCH_TREAD, PATCH_FLANGE
  use rd_strip_contact, only: strip_wheel_contact
  implicit none
  private
  public :: contact_table_options_t, contact_table_t, build_contact_table, table_wheel_contact, node_probe
  public :: PROBE_SHIFT_SHARES
  public :: split_wheel_surface, TABLE_SLOTS, TABLE_SLOT_TREAD, TABLE_SLOT_FLANGE, TABLE_SLOT_FACE, TABLE_QUANTITIES

  integer, parameter :: TABLE_SLOTS = 3
  !> distance along the wheel profile [m] beyond which a root and a face patch are two
  !> contacts (slot_shares)
  real(wp), parameter :: coincidence_length = 1.0e-3_wp
  integer, parameter :: TABLE_SLOT_TREAD = 1, TABLE_SLOT_FLANGE = 2, TABLE_SLOT_FACE = 3

  ! tabulated quantities per node and slot
  integer, parameter :: Q_HEIGHT = 1          !< touch height of the reference point [m]
  integer, parameter :: Q_ANGLE = 2           !< contact angle [rad]
  integer, parameter :: Q_RAIL_DY = 3         !< rail point Y minus reference point Y [m]
  integer, parameter :: Q_RAIL_Z = 4          !< rail point Z [m]
  integer, parameter :: Q_WHEEL_Y = 5         !< wheel point, intermediate frame y [m]
  integer, parameter :: Q_WHEEL_Z = 6         !< wheel point, intermediate frame z [m]
  integer, parameter :: Q_S_WHEEL = 7         !< wheel profile coordinate [m]
  integer, parameter :: Q_U_RAIL = 8          !< rail profile coordinate [m]
  integer, parameter :: Q_RADIUS = 9          !< rolling radius [m]
  integer, parameter :: Q_CURV_WHEEL_ROLL = 10
  integer, parameter :: Q_CURV_WHEEL_LAT = 11
  integer, parameter :: Q_CURV_RAIL_LAT = 12
  integer, parameter :: Q_WHEEL_X = 13        !< wheel point, intermediate frame x (the lead) [m]
  integer, parameter :: Q_RAIL_X = 14         !< rail point X minus reference point X [m]
  integer, parameter :: TABLE_QUANTITIES = 14
  !> node_probe's shifts at zero roll and yaw, as shares of the table's shift_max (then one
  !> rolled and one yawed pose at 0.3 of it: half the roll and yaw ranges)
  real(wp), parameter :: PROBE_SHIFT_SHARES(*) = [-0.5_wp, -0.25_wp, 0.0_wp, 0.15_wp, 0.25_wp, 0.3_wp, &
                                                  0.35_wp, 0.4_wp, 0.5_wp]
  !> parity in the yaw (x -> -x symmetry): -1 for the longitudinal positions, +1 for the rest
  real(wp), parameter :: yaw_parity(TABLE_QUANTITIES) = [1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, &
    1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp, -1.0_wp]

  !> A slot whose part sees no rail at a node is placed this far below the highest other
  !> slot's touch height (far from contact; only the interpolation's neighbourhood sees it) [m].
  real(wp), parameter :: absent_gap = 1.0e-2_wp
  !> A slot whose touch at zero yaw is this far below the highest slot's gets no yaw change [m]
  real(wp), parameter :: far_gap = 5.0e-3_wp

  !> What a table depends on besides the surfaces (all part of its cache key).
  type :: contact_table_options_t
    real(wp) :: shift_max = 0.02_wp            !< table covers u in [-shift_max, shift_max] [m]
    real(wp) :: shift_step = 1.0e-4_wp         !< node spacing in u [m]
    real(wp) :: roll_max = 0.03_wp             !< roll nodes in [-roll_max, roll_max] [rad]
    integer :: roll_nodes = 25                 !< number of roll nodes (odd: 0 is a node)
    real(wp) :: reference_approach = 2.0e-5_wp !< normal approach of the tabulated patch data [m]
    !> yaw nodes in [0, yaw_max] (the table is even / odd in the yaw): 5 mrad apart up to
    !> 50 mrad, beyond any wheelset's yaw short of derailment (the flange-climb scene: 21 mrad)
    real(wp) :: yaw_max = 0.05_wp
    integer :: yaw_nodes = 11
    real(wp) :: slot_angle = 0.2_wp            !< wheel slope angle of the tread/flange cut [rad]
    !> wheel slope angles where the flange-root part ends and the flange-face part begins
    !> [rad]: inside the slopes the contact jumps over on S1002 / 60E1 and UIC60 at zero yaw
    !> (0.65 -> 1.22 rad, `raildyn profile-scan`; the roll range moves them by 0.03). The root
    !> reaches 1.10 rad, past where a yawed wheel touches between root and face (the strips:
    !> 0.885 rad at 14.6 mrad in the Manchester acceptance scene), which the cut at 0.85 rad
    !> lost (that scene's window entries on tables 7.4 % of their family scale off the online
    !> run, 3.0 % now); the two overlap over 1.05-1.10 rad, blended by slot_shares. Where is a
    !> measured trade (docs/theory_contact_geometry.md section 10): a root part reaching further
    !> spans more of the zero-yaw jump between two shift nodes (test_contact_table's
    !> between-node force error, 0.485 here against its 0.5), a face part starting lower takes
    !> the root's near-conformal spill as its one patch (the node error), misses the yawed
    !> flange touch (2.5 um) and, from 1.02 rad, left the flange-climb scene on Polach without a
    !> balance before its derailment stop
    real(wp) :: root_angle = 1.1_wp
    real(wp) :: face_angle = 1.05_wp
  end type contact_table_options_t

  !> One wheel/rail pair (left-wheel model).
  type :: contact_table_t
    type(contact_table_options_t) :: options
    real(wp) :: y_tape = 0, r0 = 0
    real(wp) :: s_cut = 0                !< wheel profile coordinate of the tread/flange cut [m]
    real(wp) :: s_root_end = 0           !< ... of the flange root's end [m]
    real(wp) :: s_face_start = 0         !< ... of the flange face's start [m]
    integer :: nu = 0, nphi = 0, npsi = 0
    real(wp) :: u0 = 0, du = 1, phi0 = 0, dphi = 1, dpsi = 1
    !> values(q, iu, iphi, slot) at zero yaw and their u-derivatives (Fritsch-Carlson) [per m].
    !> The quantities of a node are contiguous: an evaluation reads all of them at four nodes
    !> (values(:, iu, j, slot) and the next), which the build's order (iu, j, q, slot) spread
    !> over 14 cache lines each (that gather was 18.6 % of the tables acceptance deck's CPU,
    !> 10 % in this order)
    real(wp), allocatable :: values(:, :, :, :)
    real(wp), allocatable :: slopes(:, :, :, :)
    !> yaw_change(q, iu, ipsi, slot) = v(u, 0, psi) - v(u, 0, 0) at psi = (ipsi - 1) dpsi, and
    !> its u-derivatives
    real(wp), allocatable :: yaw_change(:, :, :, :)
    real(wp), allocatable :: yaw_slopes(:, :, :, :)
  end type contact_table_t

contains

  !> Tabulate the strip model of `wheel` on `rail` (left side surfaces).
  subroutine build_contact_table(wheel, rail, options, table, error)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    type(contact_table_options_t), intent(in) :: options
    type(contact_table_t), intent(out) :: table
    type(error_t), allocatable, intent(out) :: error
    type(wheel_surface_t) :: parts(TABLE_SLOTS)
    integer :: j, iu, slot
    real(wp) :: cuts(3)
    logical :: far(TABLE_SLOTS)
    real(wp), allocatable :: angles(:), zeros(:)
    !> the grids in the build's order (iu, j, q, slot)
    real(wp), allocatable :: values(:, :, :, :), slopes(:, :, :, :), yaw_change(:, :, :, :), yaw_slopes(:, :, :, :)

    call check_options(options, error)
    if (allocated(error)) return
    table%options = options
    table%y_tape = wheel%y_tape
    table%r0 = wheel%nominal_radius
    call split_wheel_surface(wheel, [options%slot_angle, options%root_angle, options%face_angle], parts, cuts, error)
    if (allocated(error)) then
      call error_context(error, 'build_contact_table')
      return
    end if
    table%s_cut = cuts(1)
    table%s_root_end = cuts(2)
    table%s_face_start = cuts(3)
    table%nu = 2 * nint(options%shift_max / options%shift_step) + 1
    table%du = options%shift_step
    table%u0 = -(table%nu - 1) / 2 * table%du
    table%nphi = options%roll_nodes
    table%dphi = 2 * options%roll_max / (table%nphi - 1)
    table%phi0 = -options%roll_max
    table%npsi = options%yaw_nodes
    table%dpsi = options%yaw_max / (table%npsi - 1)
    ! the roll table at zero yaw
    angles = [(table%phi0 + (j - 1) * table%dphi, j = 1, table%nphi)]
    zeros = spread(0.0_wp, 1, table%nphi)
    call tabulate_grid(parts, rail, table, angles, zeros, values, slopes, error)
    if (allocated(error)) return
    ! the yaw table at zero roll, held as the change from zero yaw
    angles = [((j - 1) * table%dpsi, j = 1, table%npsi)]
    zeros = spread(0.0_wp, 1, table%npsi)
    call tabulate_grid(parts, rail, table, zeros, angles, yaw_change, yaw_slopes, error)
    if (allocated(error)) return
    ! a slot far below the highest one at zero yaw (far_gap) has no yaw change: a flange part
    ! far from the rail has no meaningful touch (its nodes are filled at zero yaw, and when
    ! yawed its touch search can land on a corner of the rail: the face slot 5 mm off centre
    ! on the field side, 43.6 mm below the tread at zero yaw, touched 36 mm higher at 5 mrad
    ! and 0.37 m lower at 10 mrad, which the interpolation in the yaw turned into a phantom
    ! patch; the changes of slots near contact stay below 1.4 mm up to 42 mrad)
    do iu = 1, table%nu
      far = yaw_change(iu, 1, Q_HEIGHT, :) < maxval(yaw_change(iu, 1, Q_HEIGHT, :)) - far_gap
      do j = table%npsi, 1, -1
        yaw_change(iu, j, :, :) = yaw_change(iu, j, :, :) - yaw_change(iu, 1, :, :)
      end do
      do slot = 1, TABLE_SLOTS
        if (far(slot)) yaw_change(iu, :, :, slot) = 0
      end do
    end do
    call fill_slopes(yaw_change, table%du, yaw_slopes)
    table%values = node_major(values)
    table%slopes = node_major(slopes)
    table%yaw_change = node_major(yaw_change)
    table%yaw_slopes = node_major(yaw_slopes)
  contains
    !> a(iu, j, q, slot) as (q, iu, j, slot), the evaluation's order
    pure function node_major(a) result(b)
      real(wp), intent(in) :: a(:, :, :, :)
      real(wp) :: b(size(a, 3), size(a, 1), size(a, 2), size(a, 4))
      b = reshape(a, shape(b), order=[2, 3, 1, 4])
    end function node_major
  end subroutine build_contact_table

  !> The node evaluation the table is built from (tabulate_node: touch height, strip contact,
  !> patch data) at fixed probe poses, every slot: numbers that change when that code's output
  !> changes. rd_contact_table_cache hashes them into the table's key, so a table built by a
  !> runner whose strip geometry gave other nodes is never read (a change of the strips that
  !> left TABLE_FORMAT as it was once let an older table be used; measured 2026-11-30). Probes
  !> across the shift range at zero roll and yaw, and one rolled and one yawed pose near the
  !> flange. Layout: the three cuts of the wheel's parts, then for each pose and slot a flag
  !> (1 found, 0 no rail under the part, -1 the search failed) and the node's TABLE_QUANTITIES
  !> values (zeros unless found). About 50 node evaluations (milliseconds); a change of the
  !> table's own assembly (slopes, yaw changes) still needs a TABLE_FORMAT change.
  subroutine node_probe(wheel, rail, options, probe, error)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    type(contact_table_options_t), intent(in) :: options
    real(wp), allocatable, intent(out) :: probe(:)
    type(error_t), allocatable, intent(out) :: error
    type(wheel_surface_t) :: parts(TABLE_SLOTS)
    type(error_t), allocatable :: node_error
    real(wp) :: cuts(3), row(TABLE_QUANTITIES), poses(3, size(PROBE_SHIFT_SHARES) + 2)
    logical :: found
    integer :: i, k, slot
    call split_wheel_surface(wheel, [options%slot_angle, options%root_angle, options%face_angle], parts, cuts, error)
    if (allocated(error)) then
      call error_context(error, 'contact table probe')
      return
    end if
    ! (shift, roll, yaw)
    do i = 1, size(PROBE_SHIFT_SHARES)
      poses(:, i) = [PROBE_SHIFT_SHARES(i) * options%shift_max, 0.0_wp, 0.0_wp]
    end do
    poses(:, size(PROBE_SHIFT_SHARES) + 1) = [0.3_wp * options%shift_max, 0.5_wp * options%roll_max, 0.0_wp]
    poses(:, size(PROBE_SHIFT_SHARES) + 2) = [0.3_wp * options%shift_max, 0.0_wp, 0.5_wp * options%yaw_max]
    allocate (probe(3 + size(poses, 2) * TABLE_SLOTS * (1 + TABLE_QUANTITIES)))
    probe(1:3) = cuts
    k = 3
    do i = 1, size(poses, 2)
      do slot = 1, TABLE_SLOTS
        call tabulate_node(parts(slot), rail, poses(1, i), poses(2, i), poses(3, i), wheel%y_tape, &
                           wheel%nominal_radius, options%reference_approach, row, found, node_error)
        if (allocated(node_error)) then
          probe(k + 1) = -1
          row = 0
          deallocate (node_error)
        else
          probe(k + 1) = merge(1, 0, found)
          if (.not. found) row = 0
        end if
        probe(k + 2:k + 1 + TABLE_QUANTITIES) = row
        k = k + 1 + TABLE_QUANTITIES
      end do
    end do
  end subroutine node_probe

  !> values(iu, j, q, slot) of every slot at the shift nodes and the poses (phis(j), psis(j))
  !> of the wheelset, and their u-slopes.
  subroutine tabulate_grid(parts, rail, table, phis, psis, values, slopes, error)
    type(wheel_surface_t), intent(in) :: parts(TABLE_SLOTS)
    type(rail_surface_t), intent(in) :: rail
    type(contact_table_t), intent(in) :: table
    real(wp), intent(in) :: phis(:), psis(:)
    real(wp), allocatable, intent(out) :: values(:, :, :, :), slopes(:, :, :, :)
    type(error_t), allocatable, intent(out) :: error
    logical, allocatable :: present_at(:, :, :)
    integer :: iu, ip, slot, q, other, n
    real(wp) :: u, y, h, row(TABLE_QUANTITIES)
    logical :: found

    n = size(phis)
    allocate (values(table%nu, n, TABLE_QUANTITIES, TABLE_SLOTS), slopes(table%nu, n, TABLE_QUANTITIES, TABLE_SLOTS))
    allocate (present_at(table%nu, n, TABLE_SLOTS))
    values = 0
    do ip = 1, n
      do iu = 1, table%nu
        u = table%u0 + (iu - 1) * table%du
        ! the wheelset's y that puts the reference point at u (inverse of table_wheel_contact's)
        y = u + table%y_tape - cos(psis(ip)) * (table%y_tape * cos(phis(ip)) + table%r0 * sin(phis(ip)))
        do slot = 1, TABLE_SLOTS
          call tabulate_node(parts(slot), rail, y, phis(ip), psis(ip), table%y_tape, table%r0, &
                             table%options%reference_approach, row, found, error)
          ! a yawed flange part far from the rail can defeat the touch search (the face more
          ! than 3-17 mm of shift away from its contact at 5-40 mrad: not bracketed); it has
          ! the zero-yaw data there (below). The tread always meets the rail: its failure is
          ! an error, at any yaw
          if (allocated(error) .and. psis(ip) /= 0 .and. slot /= TABLE_SLOT_TREAD) then
            deallocate (error)
            found = .false.
          end if
          if (allocated(error)) then
            call error_context(error, 'build_contact_table: ' // trim(slot_name(slot)) // ' part at u = ' // &
                               trim(sci_text(u, 5)) // ' m, roll = ' // trim(sci_text(phis(ip), 5)) // &
                               ' rad, yaw = ' // trim(sci_text(psis(ip), 5)) // ' rad')
            return
          end if
          present_at(iu, ip, slot) = found
          if (found) values(iu, ip, :, slot) = row
        end do
      end do
    end do
    ! a part without rail under it: far below the highest other part's touch height, the
    ! other data from the nearest node where it has some (continuous, no force); at a yaw,
    ! where the yawed part is not found (or its touch not bracketed: a flange part far from
    ! the rail), the data of zero yaw (no change by the yaw there)
    do slot = 1, TABLE_SLOTS
      if (.not. any(present_at(:, :, slot))) then
        call make_error(error, RD_ERR_INPUT, 'build_contact_table: the ' // trim(slot_name(slot)) // &
                        ' part of the wheel never meets the rail within the table''s range')
        return
      end if
      do ip = 1, n
        if (psis(ip) /= 0) cycle
        do iu = 1, table%nu
          if (present_at(iu, ip, slot)) cycle
          other = 0
          do q = 1, TABLE_SLOTS
            if (q == slot .or. .not. present_at(iu, ip, q)) cycle
            if (other == 0) then
              other = q
            else if (values(iu, ip, Q_HEIGHT, q) > values(iu, ip, Q_HEIGHT, other)) then
              other = q
            end if
          end do
          if (other == 0) then
            call make_error(error, RD_ERR_INPUT, 'build_contact_table: no rail under the wheel at u = ' // &
                            sci_text(table%u0 + (iu - 1) * table%du, 5) // ' m; expected a smaller shift range')
            return
          end if
          h = values(iu, ip, Q_HEIGHT, other) - absent_gap
          values(iu, ip, :, slot) = values(nearest_present(present_at(:, ip, slot), iu), ip, :, slot)
          values(iu, ip, Q_HEIGHT, slot) = h
        end do
      end do
      do ip = 1, n
        if (psis(ip) == 0) cycle
        do iu = 1, table%nu
          ! (column 1 of the yaw grid is zero yaw)
          if (.not. present_at(iu, ip, slot)) values(iu, ip, :, slot) = values(iu, 1, :, slot)
        end do
      end do
    end do
    call fill_slopes(values, table%du, slopes)
  contains
    pure integer function nearest_present(mask, i) result(j)
      logical, intent(in) :: mask(:)
      integer, intent(in) :: i
      integer :: k
      j = i
      do k = 1, size(mask)
        if (i - k >= 1) then
          if (mask(i - k)) then
            j = i - k; return
          end if
        end if
        if (i + k <= size(mask)) then
          if (mask(i + k)) then
            j = i + k; return
          end if
        end if
      end do
    end function nearest_present
  end subroutine tabulate_grid

  !> Fritsch-Carlson u-slopes of every column of a table.
  pure subroutine fill_slopes(values, du, slopes)
    real(wp), intent(in) :: values(:, :, :, :), du
    real(wp), intent(out) :: slopes(:, :, :, :)
    integer :: ip, q, slot
    do slot = 1, size(values, 4)
      do q = 1, size(values, 3)
        do ip = 1, size(values, 2)
          call pchip_slopes(values(:, ip, q, slot), du, slopes(:, ip, q, slot))
        end do
      end do
    end do
  end subroutine fill_slopes

  subroutine check_options(options, error)
    type(contact_table_options_t), intent(in) :: options
    type(error_t), allocatable, intent(out) :: error
    ! below 0.02 mm the build (about 1-4 s at 0.1 mm, growing as 1/step) would take minutes
    if (.not. (options%shift_step >= 2.0e-5_wp .and. options%shift_step <= 1.0e-3_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: shift step must be in [2e-5, 1e-3] m')
    else if (.not. (options%shift_max >= 10 * options%shift_step .and. options%shift_max <= 0.05_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: shift range must be in [10 shift steps, 0.05 m]')
    else if (.not. (options%roll_max > 0 .and. options%roll_max <= 0.2_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: roll range must be in (0, 0.2] rad')
    else if (options%roll_nodes < 3 .or. options%roll_nodes > 101 .or. mod(options%roll_nodes, 2) == 0) then
      call make_error(error, RD_ERR_INPUT, 'contact table: roll nodes must be odd, 3..101')
    else if (.not. (options%yaw_max > 0 .and. options%yaw_max <= 0.2_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: yaw range must be in (0, 0.2] rad')
    else if (options%yaw_nodes < 2 .or. options%yaw_nodes > 101) then
      call make_error(error, RD_ERR_INPUT, 'contact table: yaw nodes must be 2..101')
    else if (.not. (options%reference_approach > 0 .and. options%reference_approach <= 1.0e-3_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: reference approach must be in (0, 1e-3] m')
    else if (.not. (options%slot_angle > 0.02_wp .and. options%slot_angle < 1.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: slot angle must be in (0.02, 1) rad')
    else if (.not. (min(options%root_angle, options%face_angle) > options%slot_angle + 0.1_wp .and. &
                    max(options%root_angle, options%face_angle) < 1.4_wp .and. &
                    abs(options%face_angle - options%root_angle) >= 0.01_wp)) then
      call make_error(error, RD_ERR_INPUT, 'contact table: expected slot angle + 0.1 < root and face angles < 1.4 rad, ' // &
                      'at least 0.01 rad apart')
    end if
  end subroutine check_options

  !> The tread, flange-root and flange-face parts of a left wheel surface. Cut k is the first
  !> point, going from the tape circle towards the flange, where the radius grows faster than
  !> tan(angles(k)) per metre (angles increasing): the tread is s >= s_cuts(1), the root
  !> s_cuts(2) <= s <= s_cuts(1), the face s <= s_cuts(3). Parts keep the full surface's point
  !> slopes and curvatures.
  !>
  !> Beyond a cut each part continues so that it never penetrates where the real wheel does
  !> not: the strip model extends a surface past its last point at the last radius, which
  !> for a part on the flange side of a cut would be a cylinder at the cut's radius over the
  !> lower wheel, deeper in the rail than the real wheel.
  !> - At the first cut (tread / flange root, a slope of 0.2) the part continues as a cone
  !>   receding at 45 degrees (radius falling away from the cut).
  !> - At the later cuts (the root's end and the face's start, slopes of 1.1 and 1.7, where a
  !>   cone at 45 degrees would not stay inside the wheel) it continues along the wheel's
  !>   tangent at the cut, bending away from it with the curvature `bend`
  !>   (r = r_c + r'_c dy - bend dy^2 / 2): a kinked, steeper cone there
  !>   made the part's deepest point sit on the kink whenever the other part carried the
  !>   contact, where the strip model's refined peak of a kinked gap is not smooth (S1002
  !>   on UIC60, 6.4 mm, roll 0.01: no patch opened 35 um below the touch height found).
  !> Between the cuts S1002 is concave (its slope grows towards the flange): towards the tread
  !> the real radius falls more slowly than the tangent, towards the flange it rises faster,
  !> so both continuations lie inside the real wheel on both sides of every cut.
  subroutine split_wheel_surface(wheel, angles, parts, s_cuts, error)
    type(wheel_surface_t), intent(in) :: wheel
    real(wp), intent(in) :: angles(:)
    type(wheel_surface_t), intent(out) :: parts(:)
    real(wp), intent(out) :: s_cuts(:)
    type(error_t), allocatable, intent(out) :: error
    !> length of the continuation [m]: beyond the strip search's lateral margin (2 mm)
    real(wp), parameter :: recede_length = 5.0e-3_wp
    !> curvature of the tangent continuation at the later cuts [1/m]: a 2 mm radius, so that
    !> the root's continuation (slope 1.1) turns over 2.3 mm beyond its end and is 0.5 mm
    !> below the cut's radius at the continuation's end, the face's (slope 1.7) falls 15 mm
    !> over its 5 mm, while 20 rail lines of 0.1 mm resolve a quarter turn of it
    real(wp), parameter :: bend = 500.0_wp
    integer :: i, i0, k, ncut, icut(size(angles))
    real(wp) :: h
    ncut = size(angles)
    if (ncut /= 3 .or. size(parts) /= 3 .or. size(s_cuts) /= 3) then
      call make_error(error, RD_ERR_INPUT, 'split_wheel_surface: expected three cut angles and three parts')
      return
    end if
    ! the tape circle's point, then towards smaller s (the flange side of a left wheel)
    i0 = minloc(abs(wheel%s), dim=1)
    do k = 1, ncut
      icut(k) = 0
      if (k > 1) i0 = icut(1) - 1          ! root end and face start each from the tread cut (they may overlap)
      do i = i0, 1, -1
        if (-wheel%slope(i) > tan(angles(k))) then
          icut(k) = i
          exit
        end if
      end do
      if (icut(k) < 3 .or. icut(k) > wheel%n - 3) then
        call make_error(error, RD_ERR_INPUT, 'split_wheel_surface: the wheel profile has no flange steeper than ' // &
                        'the slot angle ' // sci_text(angles(k), 3) // ' rad between the tape circle and the flange back')
        return
      end if
      s_cuts(k) = wheel%s(icut(k))
    end do
    h = wheel%y(icut(1) + 1) - wheel%y(icut(1))
    ! tread: from the first cut to the end, receding before the cut
    call part(icut(1), wheel%n, 0, 1, parts(1))
    call part(icut(2), icut(1), 1, 2, parts(2))
    call part(1, icut(3), 3, 0, parts(3))
  contains
    !> points i1..i2 of the wheel, with a receding cone before i1 at cut `before` (the
    !> flange side; 0: none) and after i2 at cut `after` (the tread side; 0: none)
    subroutine part(i1, i2, after, before, p)
      integer, intent(in) :: i1, i2, after, before
      type(wheel_surface_t), intent(out) :: p
      integer :: n, m, nb, na, j
      nb = 0; na = 0
      if (before > 0) nb = max(2, ceiling(recede_length / h))
      if (after > 0) na = max(2, ceiling(recede_length / h))
      m = i2 - i1 + 1
      n = nb + m + na
      allocate (p%s(n), p%y(n), p%r(n), p%slope(n), p%kappa(n), p%cone_slope(n - 1))
      p%s(nb + 1:nb + m) = wheel%s(i1:i2)
      p%y(nb + 1:nb + m) = wheel%y(i1:i2)
      p%r(nb + 1:nb + m) = wheel%r(i1:i2)
      p%slope(nb + 1:nb + m) = wheel%slope(i1:i2)
      p%kappa(nb + 1:nb + m) = wheel%kappa(i1:i2)
      if (before > 0) then
        ! towards smaller s (the flange side) of cut `before`, at point i1
        do j = 1, nb
          call continuation(before, -j * h, p%s(nb + 1 - j), p%y(nb + 1 - j), p%r(nb + 1 - j), &
                            p%slope(nb + 1 - j), p%kappa(nb + 1 - j))
        end do
      end if
      if (after > 0) then
        ! towards larger s (the tread side) of cut `after`, at point i2
        do j = 1, na
          call continuation(after, j * h, p%s(nb + m + j), p%y(nb + m + j), p%r(nb + m + j), &
                            p%slope(nb + m + j), p%kappa(nb + m + j))
        end do
      end if
      p%n = n
      do j = 1, n - 1
        p%cone_slope(j) = (p%r(j + 1) - p%r(j)) / (p%y(j + 1) - p%y(j))
      end do
      p%r_max = maxval(p%r)
      p%nominal_radius = wheel%nominal_radius
      p%y_tape = wheel%y_tape
    end subroutine part

    !> The point dy from cut k on its part's continuation (header).
    pure subroutine continuation(k, dy, ps, py, pr, pslope, pkappa)
      integer, intent(in) :: k
      real(wp), intent(in) :: dy
      real(wp), intent(out) :: ps, py, pr, pslope, pkappa
      integer :: ic
      ic = icut(k)
      ps = wheel%s(ic) + dy
      py = wheel%y(ic) + dy
      if (k == 1) then
        pr = wheel%r(ic) - abs(dy)
        pslope = -sign(1.0_wp, dy)
        pkappa = wheel%kappa(ic)
      else
        pr = wheel%r(ic) + wheel%slope(ic) * dy - 0.5_wp * bend * dy**2
        pslope = wheel%slope(ic) - bend * dy
        pkappa = bend / (1 + pslope**2)**1.5_wp
      end if
    end subroutine continuation
  end subroutine split_wheel_surface

  !> One node of one part: the wheelset height at which the part just touches (secant
  !> with bracketing on the signed maximum penetration, which is continuous and decreasing
  !> in z), then its deepest patch at the reference normal approach.
  subroutine tabulate_node(part, rail, y, phi, psi, y_tape, r0, approach, row, found, error)
    type(wheel_surface_t), intent(in) :: part
    type(rail_surface_t), intent(in) :: rail
    real(wp), intent(in) :: y, phi, psi, y_tape, r0, approach
    real(wp), intent(out) :: row(TABLE_QUANTITIES)
    logical, intent(out) :: found
    type(error_t), allocatable, intent(out) :: error
    type(wheel_contact_t) :: res, second
    real(wp) :: z_touch, z_eval, cosg, zref_offset, arm
    integer :: k
    row = 0
    call touch_height(part, rail, y, phi, psi, z_touch, found, error)
    if (allocated(error) .or. .not. found) return
    ! lower by the reference approach along the normal (two passes: the angle is known
    ! only once the patch is open). The second pass can find nothing where the first patch
    ! is on a part's steep continuation far from contact (its cos(gamma) floored: 20 times
    ! the approach; the flange root 20 mm off centre at 5 mrad of yaw): the first one's
    ! patch is kept there.
    z_eval = z_touch - approach
    call strip_wheel_contact(part, rail, y, z_eval, phi, psi, res)
    if (res%n_patches == 0) then
      call make_error(error, RD_ERR_RUNTIME, 'no patch opened below the touch height')
      return
    end if
    k = maxloc(res%patch(1:res%n_patches)%penetration, dim=1)
    cosg = max(cos(res%patch(k)%contact_angle), 0.05_wp)
    z_eval = z_touch - approach / cosg
    call strip_wheel_contact(part, rail, y, z_eval, phi, psi, second)
    if (second%n_patches > 0) then
      res = second
      k = maxloc(res%patch(1:res%n_patches)%penetration, dim=1)
    end if
    zref_offset = y_tape * sin(phi) - r0 * cos(phi)
    arm = y_tape * cos(phi) + r0 * sin(phi)         ! the reference point's lateral arm
    associate (p => res%patch(k))
      row(Q_HEIGHT) = z_touch + zref_offset
      row(Q_ANGLE) = p%contact_angle
      row(Q_RAIL_DY) = p%point_rail(2) - (y + cos(psi) * arm)
      row(Q_RAIL_Z) = p%point_rail(3)
      row(Q_WHEEL_Y) = p%point_wheel(2)
      row(Q_WHEEL_Z) = p%point_wheel(3)
      row(Q_S_WHEEL) = p%s_wheel
      row(Q_U_RAIL) = p%u_rail
      row(Q_RADIUS) = p%rolling_radius
      row(Q_CURV_WHEEL_ROLL) = p%curv_wheel_roll
      row(Q_CURV_WHEEL_LAT) = p%curv_wheel_lat
      row(Q_CURV_RAIL_LAT) = p%curv_rail_lat
      ! odd in the yaw: exactly 0 at zero yaw (x -> -x symmetry)
      if (psi /= 0) then
        row(Q_WHEEL_X) = p%point_wheel(1)
        row(Q_RAIL_X) = p%point_rail(1) + sin(psi) * arm
      end if
    end associate
  end subroutine tabulate_node

  !> Wheelset height z at which `part` touches the rail (signed maximum penetration 0).
  !> found = .false. when no rail line lies under the part.
  subroutine touch_height(part, rail, y, phi, psi, z, found, error)
    type(wheel_surface_t), intent(in) :: part
    type(rail_surface_t), intent(in) :: rail
    real(wp), intent(in) :: y, phi, psi
    real(wp), intent(out) :: z
    logical, intent(out) :: found
    type(error_t), allocatable, intent(out) :: error
    real(wp), parameter :: tol = 1.0e-12_wp
    real(wp) :: za, zb, ga, gb, zc, gc, step
    integer :: it, side
    found = .false.
    za = part%nominal_radius * cos(phi)
    ga = signed_depth(za)
    if (ga <= -0.5_wp * huge(1.0_wp)) return
    found = .true.
    ! bracket: step by the depth itself (its slope in z is -cos(gamma), |.| <= 1), growing
    step = ga
    if (abs(step) < 1.0e-6_wp) step = sign(1.0e-6_wp, ga)
    zb = za
    gb = ga
    do it = 1, 60
      zb = za + step
      gb = signed_depth(zb)
      if (gb <= -0.5_wp * huge(1.0_wp)) then
        step = 0.5_wp * step
        cycle
      end if
      if (sign(1.0_wp, gb) /= sign(1.0_wp, ga) .or. gb == 0) exit
      za = zb
      ga = gb
      step = 2 * step
    end do
    if (sign(1.0_wp, gb) == sign(1.0_wp, ga) .and. gb /= 0) then
      call make_error(error, RD_ERR_RUNTIME, 'touch height not bracketed')
      return
    end if
    ! Illinois regula falsi
    side = 0
    z = zb
    do it = 1, 200
      if (abs(zb - za) <= tol .or. gb == 0) exit
      zc = (za * gb - zb * ga) / (gb - ga)
      gc = signed_depth(zc)
      if (gc == 0) then
        za = zc; zb = zc; gb = 0
        exit
      end if
      if (sign(1.0_wp, gc) == sign(1.0_wp, gb)) then
        zb = zc; gb = gc
        if (side == -1) ga = 0.5_wp * ga
        side = -1
      else
        za = zb; ga = gb
        zb = zc; gb = gc
        side = 1
      end if
    end do
    z = zb
  contains
    real(wp) function signed_depth(zz)
      real(wp), intent(in) :: zz
      type(wheel_contact_t) :: r
      call strip_wheel_contact(part, rail, y, zz, phi, psi, r)
      signed_depth = r%max_penetration
    end function signed_depth
  end subroutine touch_height

  !> Fritsch-Carlson slopes of a uniformly sampled function (C1 cubic Hermite without
  !> overshoot: a slope is 0 at a local extremum of the data, else the harmonic mean of the
  !> two secants).
  pure subroutine pchip_slopes(f, h, d)
    real(wp), intent(in) :: f(:), h
    real(wp), intent(out) :: d(:)
    integer :: n, i
    real(wp) :: s1, s2
    n = size(f)
    if (n < 2) then
      d = 0
      return
    end if
    do i = 2, n - 1
      s1 = (f(i) - f(i - 1)) / h
      s2 = (f(i + 1) - f(i)) / h
      if (s1 * s2 <= 0) then
        d(i) = 0
      else
        d(i) = 2 * s1 * s2 / (s1 + s2)
      end if
    end do
    ! ends: one-sided, three-point, limited as in Fritsch-Carlson
    d(1) = end_slope((f(2) - f(1)) / h, (f(min(3, n)) - f(2)) / h)
    d(n) = end_slope((f(n) - f(n - 1)) / h, (f(n - 1) - f(max(n - 2, 1))) / h)
  contains
    pure real(wp) function end_slope(s_near, s_far) result(e)
      real(wp), intent(in) :: s_near, s_far
      e = 1.5_wp * s_near - 0.5_wp * s_far
      if (e * s_near <= 0) then
        e = 0
      else if (s_near * s_far <= 0 .and. abs(e) > 3 * abs(s_near)) then
        e = 3 * s_near
      end if
    end function end_slope
  end subroutine pchip_slopes

  !> The left wheel's contact from the table for the wheelset pose (y, z, phi, psi): the roll
  !> table at zero yaw plus the yaw table's change (header), with the exact position of the
  !> wheel's reference point.
  !> Outside the table's shift range: no patch and max_penetration = -huge (the wheelset
  !> provider reports it as "no rail under the wheel").
  pure subroutine table_wheel_contact(table, y, z, phi, psi, res, every_slot)
    type(contact_table_t), intent(in) :: table
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t), intent(out) :: res
    !> interpolate every slot, also those certainly clear of the rail (the test of that skip)
    logical, intent(in), optional :: every_slot
    real(wp) :: u, zref, yref, xref, x, t, hb(4), v(TABLE_QUANTITIES), phic, s, a, pv(TABLE_QUANTITIES, 4), delta
    real(wp) :: db(4), da(4), parity(TABLE_QUANTITIES), yaw_sign(TABLE_QUANTITIES), share
    real(wp) :: deltas(TABLE_SLOTS), shares(TABLE_SLOTS), vs(TABLE_QUANTITIES, TABLE_SLOTS)
    integer :: iu, ip, iy, k, slot, kk
    res%n_patches = 0
    res%max_penetration = -huge(1.0_wp)
    deltas = -1
    vs = 0
    if (.not. allocated(table%values)) return
    ! the wheel's reference point (yaw and roll about the wheelset centre, exact)
    yref = y + cos(psi) * (table%y_tape * cos(phi) + table%r0 * sin(phi))
    xref = -sin(psi) * (table%y_tape * cos(phi) + table%r0 * sin(phi))
    u = yref - table%y_tape
    x = (u - table%u0) / table%du
    if (x < 0 .or. x > table%nu - 1) return
    iu = min(int(x) + 1, table%nu - 1)
    t = x - (iu - 1)
    ! cubic Hermite basis in u (values h00, h01; slopes h10, h11 times the step)
    hb = [(2 * t - 3) * t * t + 1, t * t * (3 - 2 * t), ((t - 2) * t + 1) * t * table%du, t * t * (t - 1) * table%du]
    phic = min(max(phi, table%phi0), table%phi0 + (table%nphi - 1) * table%dphi)
    s = (phic - table%phi0) / table%dphi
    ip = min(int(s) + 1, table%nphi - 1)
    s = s - (ip - 1)
    db = [(2 * s - 3) * s * s + 1, s * s * (3 - 2 * s), ((s - 2) * s + 1) * s, s * s * (s - 1)]
    ! |psi| clamped to the yaw table's range, its interval and Hermite basis
    a = min(abs(psi), (table%npsi - 1) * table%dpsi) / table%dpsi
    iy = min(int(a) + 1, table%npsi - 1)
    a = a - (iy - 1)
    da = [(2 * a - 3) * a * a + 1, a * a * (3 - 2 * a), ((a - 2) * a + 1) * a, a * a * (a - 1)]
    ! the odd quantities' change takes the yaw's sign
    yaw_sign = merge(1.0_wp, sign(1.0_wp, psi), yaw_parity > 0)
    zref = z + table%y_tape * sin(phi) - table%r0 * cos(phi)
    do slot = 1, TABLE_SLOTS
      ! a flange slot certainly clear of the rail by more than the tread's approach adds
      ! nothing (no patch, not the largest approach): skip its interpolations (two thirds of
      ! them where the tread alone touches)
      if (slot /= TABLE_SLOT_TREAD .and. .not. present(every_slot)) then
        if (clear_of_rail()) cycle
      end if
      ! values at the roll nodes ip-1 .. ip+2 (clamped), interpolated in u
      do k = 1, 4
        pv(:, k) = along_u(table%values, table%slopes, min(max(ip - 2 + k, 1), table%nphi))
      end do
      ! Hermite in roll with central-difference slopes (one-sided at the table's ends)
      v = db(1) * pv(:, 2) + db(2) * pv(:, 3) + db(3) * node_slope(2, ip, table%nphi, .false.) + &
          db(4) * node_slope(3, ip + 1, table%nphi, .false.)
      ! the yaw's change at the yaw nodes iy-1 .. iy+2: below psi = 0 the mirror node by the
      ! quantity's parity, clamped at the table's end
      do k = 1, 4
        kk = iy - 2 + k
        parity = 1
        if (kk < 1) then
          kk = 2 - kk
          parity = yaw_parity
        end if
        pv(:, k) = parity * along_u(table%yaw_change, table%yaw_slopes, min(kk, table%npsi))
      end do
      v = v + yaw_sign * (da(1) * pv(:, 2) + da(2) * pv(:, 3) + da(3) * node_slope(2, iy, table%npsi, .true.) + &
                          da(4) * node_slope(3, iy + 1, table%npsi, .true.))
      ! cos(gamma) floored as in the build: far from contact a slot's interpolated angle may
      ! pass the vertical (the face slot's closest approach is then on the rail's gauge face),
      ! where cos < 0 made a negative overlap a positive approach: a phantom patch
      delta = (v(Q_HEIGHT) - zref) * max(cos(v(Q_ANGLE)), 0.05_wp)
      res%max_penetration = max(res%max_penetration, delta)
      deltas(slot) = delta
      vs(:, slot) = v
    end do
    shares = slot_shares(deltas, vs(Q_S_WHEEL, :))
    do slot = 1, TABLE_SLOTS
      delta = deltas(slot)
      share = shares(slot)
      if (delta <= 0 .or. share <= 0) cycle
      v = vs(:, slot)
      res%n_patches = res%n_patches + 1
      associate (p => res%patch(res%n_patches))
        p%kind = merge(PATCH_TREAD, PATCH_FLANGE, slot == TABLE_SLOT_TREAD)
        p%penetration = share**(2.0_wp / 3) * delta
        p%contact_angle = v(Q_ANGLE)
        p%normal = [0.0_wp, sin(v(Q_ANGLE)), cos(v(Q_ANGLE))]
        p%point_rail = [xref + v(Q_RAIL_X), yref + v(Q_RAIL_DY), v(Q_RAIL_Z)]
        p%point_wheel = [v(Q_WHEEL_X), v(Q_WHEEL_Y), v(Q_WHEEL_Z)]
        p%s_wheel = v(Q_S_WHEEL)
        p%u_rail = v(Q_U_RAIL)
        p%u_rail_min = v(Q_U_RAIL)
        p%u_rail_max = v(Q_U_RAIL)
        p%rolling_radius = v(Q_RADIUS)
        p%curv_wheel_roll = v(Q_CURV_WHEEL_ROLL)
        p%curv_wheel_lat = v(Q_CURV_WHEEL_LAT)
        p%curv_rail_roll = 0
        p%curv_rail_lat = v(Q_CURV_RAIL_LAT)
        p%strip_length = 0
        p%share = share
      end associate
    end do
  contains
    !> Shares of the slots' patches (approaches d, wheel coordinates sw): 1, except where the
    !> root and face parts overlap (face_angle < root_angle: s_root_end < s_face_start). There
    !> the face's patch carries band_rise of its s (0 at the face's start, 1 at the root's end):
    !> near its start the face part's one patch is the tail of a contact the root holds (or the
    !> root's near-conformal spill), so it fades out; and the root's patch gives up band_rise
    !> of its s times c, the weight of the two patches being one contact (1 at the same s and
    !> approach, 0 when they are coincidence_length apart along the wheel or one has no
    !> approach; smooth), so that one contact in the band counts once while a root contact
    !> beside a distinct face contact keeps its whole force. C1 in the pose (3 t^2 - 2 t^3 and
    !> smooth weights). By the wheel coordinate, not the contact angle: towards the flange tip
    !> the slope falls below the band again, on the face part only
    !> (docs/theory_contact_geometry.md section 10).
    pure function slot_shares(d, sw) result(w)
      real(wp), intent(in) :: d(TABLE_SLOTS), sw(TABLE_SLOTS)
      real(wp) :: w(TABLE_SLOTS)
      real(wp) :: c, x, r
      w = 1
      if (table%s_root_end >= table%s_face_start) return
      w(TABLE_SLOT_FACE) = band_rise(sw(TABLE_SLOT_FACE))
      if (d(TABLE_SLOT_FLANGE) <= 0 .or. d(TABLE_SLOT_FACE) <= 0) return
      x = (sw(TABLE_SLOT_FLANGE) - sw(TABLE_SLOT_FACE)) / coincidence_length
      if (abs(x) >= 1) return
      r = min(d(TABLE_SLOT_FLANGE), d(TABLE_SLOT_FACE)) / max(d(TABLE_SLOT_FLANGE), d(TABLE_SLOT_FACE))
      c = (1 - x * x)**2 * r * r * (3 - 2 * r)
      w(TABLE_SLOT_FLANGE) = 1 - c * band_rise(sw(TABLE_SLOT_FLANGE))
    end function slot_shares

    !> 0 at s_face_start, 1 at s_root_end, C1 (3 t^2 - 2 t^3) across the band
    pure real(wp) function band_rise(sw) result(b)
      real(wp), intent(in) :: sw
      real(wp) :: t
      t = min(max((table%s_face_start - sw) / (table%s_face_start - table%s_root_end), 0.0_wp), 1.0_wp)
      b = t * t * (3 - 2 * t)
    end function band_rise

    !> Whether this slot's interpolated touch height is certainly below the reference point,
    !> with an approach below the largest one found so far (the tread's), from the node
    !> values it is interpolated from: along u the Fritsch-Carlson cubic stays between its two
    !> nodes; the Hermite in roll (in yaw) with central-difference slopes exceeds the maximum
    !> of its four nodes by at most 8/27 of their range (the slope terms' basis functions are
    !> at most 4/27, each slope at most the range); the height is even in the yaw, its ghost
    !> node below zero yaw is node 2. Then delta = (h - zref) max(cos gamma, 0.05) is at most
    !> 0.05 (bound - zref). Exact: what the slot would give is not a patch and not the
    !> largest approach, so skipping it changes nothing.
    pure logical function clear_of_rail()
      real(wp) :: hmax, hmin, dmax, dmin, bound
      integer :: jlo, jhi
      jlo = max(ip - 1, 1); jhi = min(ip + 2, table%nphi)
      hmax = maxval(table%values(Q_HEIGHT, iu:iu + 1, jlo:jhi, slot))
      hmin = minval(table%values(Q_HEIGHT, iu:iu + 1, jlo:jhi, slot))
      jlo = max(iy - 1, 1); jhi = min(iy + 2, table%npsi)
      dmax = maxval(table%yaw_change(Q_HEIGHT, iu:iu + 1, jlo:jhi, slot))
      dmin = minval(table%yaw_change(Q_HEIGHT, iu:iu + 1, jlo:jhi, slot))
      bound = hmax + (8.0_wp / 27) * (hmax - hmin) + dmax + (8.0_wp / 27) * (dmax - dmin)
      clear_of_rail = bound < zref .and. 0.05_wp * (bound - zref) < res%max_penetration
    end function clear_of_rail

    !> A column j of a table (values, u-slopes) of this slot interpolated at u.
    pure function along_u(values, slopes, j) result(w)
      real(wp), intent(in) :: values(:, :, :, :), slopes(:, :, :, :)
      integer, intent(in) :: j
      real(wp) :: w(TABLE_QUANTITIES)
      w = hb(1) * values(:, iu, j, slot) + hb(2) * values(:, iu + 1, j, slot) + &
          hb(3) * slopes(:, iu, j, slot) + hb(4) * slopes(:, iu + 1, j, slot)
    end function along_u

    !> Central-difference slope (per node step) at column kc of pv (2 or 3), which holds node
    !> j: one-sided at the last node n, and at node 1 unless the table is `mirrored` below it
    !> (the yaw: column 1 then holds the ghost node at -dpsi).
    pure function node_slope(kc, j, n, mirrored) result(d)
      integer, intent(in) :: kc, j, n
      logical, intent(in) :: mirrored
      real(wp) :: d(TABLE_QUANTITIES)
      integer :: lo, hi
      lo = kc - 1; hi = kc + 1
      if (j == 1 .and. .not. mirrored) lo = kc
      if (j == n) hi = kc
      d = (pv(:, hi) - pv(:, lo)) / (hi - lo)
    end function node_slope
  end subroutine table_wheel_contact

  pure function slot_name(slot) result(name)
    integer, intent(in) :: slot
    character(len=:), allocatable :: name
    select case (slot)
    case (TABLE_SLOT_TREAD); name = 'tread'
    case (TABLE_SLOT_FLANGE); name = 'flange-root'
    case default; name = 'flange-face'
    end select
  end function slot_name

end module rd_contact_table
