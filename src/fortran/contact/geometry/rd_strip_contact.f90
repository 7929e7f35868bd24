!> Strip interpenetration contact between a real wheel and a real rail (thesis 4.7,
!> eqs. 4.64-4.77): the wheel is the revolution of its profile (each segment a cone), the
!> rail the extrusion of its profile (each point a longitudinal line = one strip); the
!> virtual penetration of each line into the wheel is found analytically (rd_line_cone),
!> contiguous penetrating strips form a patch, and the patch's contact point is the strip
!> of maximum penetration (4.77), refined by a parabola through it and its neighbours so
!> that the point and the penetration move continuously with the pose.
!>
!> Works on the LEFT wheel/rail (rd_contact_surfaces); rd_contact_geometry mirrors the pose
!> for the right wheel. Pure; its scratch arrays are automatic (gfortran puts them on the heap
!> unless -fstack-arrays: about 3 allocations per wheel call, ~2 % of the instructions, callgrind).
module rd_strip_contact
  use rd_kinds, only: wp
  use rd_rotation, only: cross
  use rd_contact_surfaces, only: wheel_surface_t, rail_surface_t, locate
  use rd_contact_patch, only: patch_geometry_t, patch_potential_t, strip_normal_t, wheel_contact_t, MAX_PATCHES, &
    PATCH_TREAD, PATCH_FLANGE, PATCH_FLANGE_BACK
  use rd_line_cone, only: line_cone_roots, line_cone_max_depth_slope
  use rd_hertz_strip, only: strip_stiffness, interval_energy
  use rd_strip_potential, only: effective_penetration, strip_force_direction, region_mean, wheel_point_curvatures, &
    deepest_point_py_gradient, smooth_line_depth, smooth_wheel_radius, lehmer_order
  implicit none
  private
  public :: strip_wheel_contact

  real(wp), parameter :: flange_angle = 0.3_wp   !< |contact angle| from which a patch is a flange patch
  real(wp), parameter :: coarse_gap = 5.0e-4_wp  !< strips farther than this from touching are interpolated [m]
  real(wp), parameter :: virtual_eps = 0.55_wp   !< virtual penetration factor (Kik-Piotrowski: 0.55; see theory doc)
  !> region factor of the energy-consistent force's effective penetration (rd_strip_potential):
  !> 0.2-0.4 kept the friction-0.6 Manchester deck quiet in the first variant, 0.55 did not
  !> (docs/theory_flange_chatter.md section 13)
  real(wp), parameter :: potential_eps = 0.3_wp

contains

  !> Contact of the left wheel with the left rail for the wheelset pose relative to the
  !> track frame: lateral y, vertical z of the wheelset centre, roll phi, yaw psi
  !> (B = R_z(psi) R_x(phi), docs/conventions.md).
  pure subroutine strip_wheel_contact(wheel, rail, y, z, phi, psi, res, exhaustive, potential, distributed)
    type(wheel_surface_t), intent(in) :: wheel
    type(rail_surface_t), intent(in) :: rail
    real(wp), intent(in) :: y, z, phi, psi
    type(wheel_contact_t), intent(out) :: res
    !> search every cone a line can reach instead of hill climbing (reference for tests)
    logical, intent(in), optional :: exhaustive
    !> the energy-consistent normal force (rd_strip_potential) instead of the refined peak
    !> along the centroid's normal
    logical, intent(in), optional :: potential
    !> the distributed strip normal force (rd_hertz_strip): res%distributed
    logical, intent(in), optional :: distributed
    logical :: full_search, use_potential, use_distributed
    !> distributed force: each strip's normal load per unit E*, w_i phi_i s'(delta_i), and its
    !> depth into the smooth wheel (0 off contact; the patch points' weights)
    real(wp), allocatable :: sload(:), sdepth(:)
    !> distributed force: each evaluated strip's signed depth into the smooth wheel (-huge
    !> where not evaluated): the depths that decide how a run splits into patches
    real(wp), allocatable :: sdepth_signed(:)
    !> distributed force: each strip's deepest point on the smooth wheel (intermediate frame)
    !> and its segment: the patches' points and Hertz curvature means are taken there
    real(wp), allocatable :: sdeep(:, :)
    integer, allocatable :: sdeep_j(:)
    integer :: jprev
    real(wp) :: delta(rail%n), tline(rail%n), pw(3, rail%n)
    integer :: jseg(rail%n)
    logical :: pos(rail%n)
    real(wp) :: bt(3, 3), d(3), a, cp, sp, cs, ss, ext, ylo, yhi, w, dep, d1, dd, wstep(8)
    integer :: i, ilo, ihi, i1, i2, np, ifirst, ilast
    logical :: is_pos, is_max

    full_search = .false.
    if (present(exhaustive)) full_search = exhaustive
    use_potential = .false.
    if (present(potential)) use_potential = potential
    if (use_potential) allocate (res%potential(MAX_PATCHES))
    use_distributed = .false.
    if (present(distributed)) use_distributed = distributed
    if (use_distributed) allocate (res%distributed)
    jprev = 1
    cp = cos(phi); sp = sin(phi); cs = cos(psi); ss = sin(psi)
    ! B^T for B = R_z(psi) R_x(phi): rows are B's columns
    bt(1, :) = [cs, ss, 0.0_wp]
    bt(2, :) = [-ss * cp, cs * cp, sp]
    bt(3, :) = [ss * sp, -cs * sp, cp]
    d = bt(:, 1)                          ! track x axis in the intermediate frame
    a = hypot(d(1), d(3))

    ! lateral window: rail lines under the wheel's footprint (bounding box of the rolled,
    ! yawed wheel), found by bisection on the rail's monotonic Y
    ext = wheel%r_max * (abs(sp) + abs(ss)) + 2.0e-3_wp
    ylo = y + min(wheel%y(1) * cp, wheel%y(1)) - ext
    yhi = y + max(wheel%y(wheel%n) * cp, wheel%y(wheel%n)) + ext
    ilo = max(1, locate(rail%y, ylo) - 1)
    ihi = min(rail%n, locate(rail%y, yhi) + 2)

    ! No clearing of the scratch arrays (it cost more than the search on a fine rail, 2563
    ! lines at 0.05 mm): only ilo..ihi is read, every strip there is either evaluated
    ! (strip_depths sets all four) or interpolated (delta only: tline, pw and jseg are read
    ! only at penetrating strips and their neighbours, which are always evaluated).
    if (full_search .or. ihi - ilo < 4 * rail%coarse_stride) then
      call evaluate_lines(ilo, ihi, 1, delta, tline, pw, jseg, jprev)
    else
      ! Coarse-to-fine: every rail%coarse_stride-th strip first; the strips between two coarse
      ! ones are evaluated only if one of them is within coarse_gap of touching, otherwise
      ! interpolated (they are then far from contact: the relative curvature of wheel and
      ! rail, below 1/3 mm^-1, cannot raise a bump of coarse_gap between strips at most
      ! 1.6 mm apart: rail%coarse_stride).
      ! the interpolation weights of a full coarse step (the same quotients as below)
      do i = 1, min(rail%coarse_stride, size(wstep)) - 1
        wstep(i) = real(i, wp) / rail%coarse_stride
      end do
      call evaluate_lines(ilo, ihi, rail%coarse_stride, delta, tline, pw, jseg, jprev)
      i1 = ilo
      do while (i1 < ihi)
        i2 = min(i1 + rail%coarse_stride, ihi)
        if (max(delta(i1), delta(i2)) > -coarse_gap) then
          if (i2 - i1 > 1) call evaluate_lines(i1 + 1, i2 - 1, 1, delta, tline, pw, jseg, jprev)
        else
          d1 = delta(i1); dd = delta(i2) - delta(i1)
          if (i2 - i1 == rail%coarse_stride .and. rail%coarse_stride <= size(wstep)) then
            do i = i1 + 1, i2 - 1
              delta(i) = d1 + wstep(i - i1) * dd
            end do
          else
            do i = i1 + 1, i2 - 1
              w = real(i - i1, wp) / (i2 - i1)
              delta(i) = d1 + w * dd
            end do
          end if
        end if
        i1 = i2
      end do
    end if

    res%n_patches = 0
    res%max_penetration = -huge(1.0_wp)
    if (ihi < ilo) return
    ! max over the refined local maxima (not the refinement of the global discrete max):
    ! stays continuous when the deepest point switches between two separate bumps.
    ! A local maximum whose refined peak is positive opens a patch even if no strip is
    ! positive yet, so that patches appear with zero penetration.
    ! One pass also notes the first and last marked strip, so that the patch scan below
    ! covers the contact region only instead of the whole window again.
    ! (Both tests of a strip inside the window without branches: most strips are neither
    ! a maximum nor positive, and a branch on each comparison was mispredicted often.)
    ifirst = 0; ilast = -1
    do i = ilo, ihi
      is_pos = delta(i) > 0
      if (i > ilo .and. i < ihi) then
        is_max = .not. (delta(i) < delta(i - 1)) .and. .not. (delta(i) <= delta(i + 1))
      else
        is_max = .true.
        if (i > ilo) is_max = .not. (delta(i) < delta(i - 1))
        if (is_max .and. i < ihi) is_max = .not. (delta(i) <= delta(i + 1))
      end if
      if (is_max .or. is_pos) then
        if (is_max) then
          dep = refined_peak(delta, i, ilo, ihi)
          res%max_penetration = max(res%max_penetration, dep)
          if (dep > 0) is_pos = .true.
        end if
        if (is_pos) then
          if (ifirst == 0) ifirst = i
          ilast = i
        end if
      end if
      pos(i) = is_pos
    end do

    ! Patches. A run of penetrating strips may hold several bumps of the gap function (tread
    ! and flange root of one wheel, thesis 4.7.2). One patch per run (the old rule) makes the
    ! force jump when two runs merge (the valley between them rises above zero: the second
    ! patch vanished with its full force) and one patch per bump makes it jump when a bump
    ! fades into the flank of another. split_run blends the two descriptions continuously
    ! (docs/theory_contact_geometry.md, "Bumps within one run").
    ! the distributed normal force first: the patches take their loads from its strips
    if (use_distributed) then
      allocate (sload(ilo:ihi), sdepth(ilo:ihi), sdepth_signed(ilo:ihi), sdeep(3, ilo:ihi), sdeep_j(ilo:ihi))
      call distributed_force(ifirst, ilast, sload, sdepth, sdepth_signed, sdeep, sdeep_j, res%distributed)
      call attach_edge_loads(sload)
    end if
    i = ifirst
    np = 0
    do while (i <= ilast)
      if (.not. pos(i)) then
        i = i + 1
        cycle
      end if
      i1 = i
      do while (i < ihi)
        if (.not. pos(i + 1)) exit
        i = i + 1
      end do
      i2 = i
      i = i + 1
      call split_run(i1, i2, np, res%patch, res%potential, res%distributed)
    end do
    res%n_patches = np

  contains

    !> The distributed strip normal force (rd_hertz_strip; docs/theory_flange_chatter.md
    !> section 14): U = int c delta_+^2 ds across the strips, as the sum over the intervals
    !> between neighbouring strips of c h int ((1-t) delta_i + t delta_(i+1))_+^2 dt
    !> (rd_hertz_strip interval_energy: the contact edge resolved inside the interval), c the
    !> mean of the two strips' c_i = E* phi(A_i, B_i) (the curvatures at a strip's deepest
    !> point: the wheel's rolling and lateral curvature there, the rail's lateral one at the
    !> strip), h the rail arc length between them, delta_i a strip's depth into the smooth
    !> wheel at its line's deepest point on that wheel (rd_strip_potential smooth_line_depth). Minus its gradient, per unit E*:
    !> sum (c (q_a G_i + q_b G_(i+1)) - q grad c), G_i minus the strip
    !> depth's gradient (rd_strip_potential) and grad c through the deepest points' lateral
    !> positions (their shift included). Force in the track frame, moment about the wheelset
    !> centre in the intermediate frame.
    pure subroutine distributed_force(i1, i2, sload, sdepth, sdepth_signed, sdeep, sdeep_j, sn)
      integer, intent(in) :: i1, i2
      !> each strip's load per unit E*, the derivative of U by its depth, and its depth into
      !> the smooth wheel (both 0 off contact)
      real(wp), intent(inout) :: sload(ilo:), sdepth(ilo:)
      !> that depth signed (-huge where not evaluated)
      real(wp), intent(inout) :: sdepth_signed(ilo:)
      !> each evaluated strip's deepest point on the smooth wheel and its segment (set only for
      !> the strips of the contact region and their neighbours, the only ones read: the patches'
      !> curvature means and points)
      real(wp), intent(inout) :: sdeep(:, ilo:)
      integer, intent(inout) :: sdeep_j(ilo:)
      type(strip_normal_t), intent(inout) :: sn
      integer :: lo, hi, i, j
      real(wp) :: gpy(6), k_roll, k_lat, dk_roll, dk_lat, dph_da, dph_db, h, c, qi, qa, qb, gc(6), f6(6), q(3)
      ! per strip: smooth depth, G = -grad depth (force, moment), phi and its gradient
      ! (over the contact region and its margin only, not the whole window)
      real(wp) :: dep(max(i1 - 2, ilo):min(i2 + 2, ihi)), gg(6, max(i1 - 2, ilo):min(i2 + 2, ihi)), &
                  ph(max(i1 - 2, ilo):min(i2 + 2, ihi)), gph(6, max(i1 - 2, ilo):min(i2 + 2, ihi))
      logical :: have(max(i1 - 2, ilo):min(i2 + 2, ihi))
      f6 = 0; sn%energy = 0
      sload = 0; sdepth = 0
      if (i1 < ilo) return               ! no strip in contact (i1 = 0)
      ! the contact region's strips and two beyond on either side (evaluated by the search:
      ! the smooth wheel reaches ~h^2 / (8 R), 0.3 um, further than the cones, and an edge
      ! interval needs its outer strip)
      lo = max(i1 - 2, ilo); hi = min(i2 + 2, ihi)
      have = .false.
      sdepth_signed(lo:hi) = -huge(1.0_wp)      ! (only the runs' strips and neighbours are read)
      do i = lo, hi
        if (.not. (delta(i) > -coarse_gap)) cycle      ! (interpolated strips: no deepest point)
        have(i) = .true.
        call smooth_line_depth(pw(:, i), d, jseg(i), wheel%y, wheel%r, wheel%r_spline, wheel%r_fourth, q, j, dep(i), gg(:, i), &
                               gpy)
        sdepth(i) = max(dep(i), 0.0_wp); sdepth_signed(i) = dep(i)
        sdeep(:, i) = q; sdeep_j(i) = j
        call wheel_point_curvatures(q(2), j, wheel%y, wheel%k_roll, wheel%kappa, k_roll, k_lat, dk_roll, dk_lat, &
                                    wheel%k_roll_spline, wheel%kappa_spline)
        ! half sums of the two bodies' curvatures (the straight rail has no rolling one)
        call strip_stiffness(0.5_wp * k_roll, 0.5_wp * (k_lat + rail%kappa(i)), ph(i), dph_da, dph_db)
        gph(:, i) = 0.5_wp * (dph_da * dk_roll + dph_db * dk_lat) * gpy
      end do
      ! the intervals between neighbouring strips: U = c h int_0^1 ((1-t) a + t b)_+^2 dt with
      ! c their mean stiffness (edge-resolving: C2 in the depths where the contact edge
      ! crosses the interval, so no strip enters with a kink)
      do i = lo, hi - 1
        if (.not. (have(i) .and. have(i + 1))) cycle
        if (.not. (dep(i) > 0 .or. dep(i + 1) > 0)) cycle
        h = rail%interval(i)
        call interval_energy(dep(i), dep(i + 1), h, qi, qa, qb)
        c = 0.5_wp * (ph(i) + ph(i + 1))
        gc = 0.5_wp * (gph(:, i) + gph(:, i + 1))
        sn%energy = sn%energy + c * qi
        sload(i) = sload(i) + c * qa
        sload(i + 1) = sload(i + 1) + c * qb
        f6 = f6 + c * (qa * gg(:, i) + qb * gg(:, i + 1)) - qi * gc
      end do
      sn%force = matmul(f6(1:3), bt)      ! B f: intermediate -> track frame
      sn%moment = f6(4:6)
    end subroutine distributed_force


    !> The edge intervals put load on the strips just outside a run of the cones' contact
    !> (their depth is <= 0 but their interval's positive part is not): move each such load
    !> onto the nearest run's end strip (half to each where two runs are equally near), so
    !> that the patches' loads add up to the strips' total and do not jump when a run grows
    !> by a strip (the load stays in the same patch).
    pure subroutine attach_edge_loads(sl)
      real(wp), intent(inout) :: sl(ilo:)
      integer :: i, k, kl, kr
      do i = ilo, ihi
        if (pos(i) .or. sl(i) == 0) cycle
        kl = 0; kr = 0
        do k = 1, 3
          if (kl == 0 .and. i - k >= ilo) then
            if (pos(i - k)) kl = i - k
          end if
          if (kr == 0 .and. i + k <= ihi) then
            if (pos(i + k)) kr = i + k
          end if
        end do
        if (kl > 0 .and. kr > 0) then
          if (i - kl < kr - i) then
            kr = 0
          else if (i - kl > kr - i) then
            kl = 0
          end if
        end if
        if (kl > 0 .and. kr > 0) then
          sl(kl) = sl(kl) + 0.5_wp * sl(i); sl(kr) = sl(kr) + 0.5_wp * sl(i)
          sl(i) = 0
        else if (kl > 0) then
          sl(kl) = sl(kl) + sl(i); sl(i) = 0
        else if (kr > 0) then
          sl(kr) = sl(kr) + sl(i); sl(i) = 0
        end if
      end do
    end subroutine attach_edge_loads

    !> The distributed normal load of the stretch a..b of the run r1..r2 (per unit E*)
    !> between its split positions xl, xh: each strip's part of it (strip_part; a strip next
    !> to a split position is shared by the stretches on either side). The blended patches'
    !> loads (share times this) then add up to the strips' total,
    !> (1 - lambda) S_ab + lambda (S_a..xv + S_xv..b) = S_ab, and do not jump where the
    !> lowest valley strip changes (the split position moves continuously).
    pure real(wp) function stretch_load(a, b, r1, r2, xl, xh) result(s)
      integer, intent(in) :: a, b, r1, r2
      real(wp), intent(in) :: xl, xh
      integer :: i
      s = 0
      do i = max(a - 2, r1), min(b + 2, r2)
        s = s + strip_part(i, xl, xh) * sload(i)
      end do
    end function stretch_load


    !> Patches of the run i1..i2. A stretch a..b with a valley (a strip below the maxima on
    !> both sides; the lowest one) is, with the split fraction
    !>    lambda = smoothstep(1 - v / ((1 - eps) d_lo))   (the argument clipped to [0, 1]),
    !> lambda parts two stretches a..kv, kv..b (each handled the same way) and 1 - lambda one
    !> patch over a..b. Kik & Piotrowski (2008) count two bumps as separate contacts while
    !> their virtual-penetration regions delta > (1 - eps) d are disjoint, i.e. while the
    !> valley is below (1 - eps) d_lo; lambda ramps from touching runs (v = 0: lambda = 1, the
    !> two patches of the separate runs) to connected regions (lambda = 0, one patch, also
    !> when the lower bump fades into the flank: v -> d_lo). The part is a share of normal
    !> force: a patch of share w gets the penetration w^(2/3) delta (Hertz, N ~ delta^(3/2)
    !> at fixed curvatures, so N scales with w). Where lambda > 0 the valley is below both
    !> bumps' centroid thresholds (1 - eps) d, so the valley strip contributes nothing to
    !> either centroid and moving the split from one strip to the next is smooth.
    !>
    !> v and the peaks are extrema of the C1 interpolant through the strips' depths
    !> (cubic_minimum), d_lo a smooth minimum of the two peaks (smooth_min), the split
    !> position xv the minimum of the C2 B-spline of the depths, and the strips next to it
    !> shared between the two stretches (strip_part): the lowest strip's depth and the
    !> highest ones' kinked lambda wherever the valley's or a peak's strip changed, and a
    !> strip's box split at xv kinked the patches where xv crossed a strip's edge (Fx by 28 %
    !> of its range-scaled slope where the flange root's region merges with the tread's;
    !> docs/theory_contact_geometry.md "Bumps within one run"). The depths are the smooth wheel's
    !> with the distributed force (the cones' kink where a line's deepest point changes
    !> profile point), the cones' otherwise.
    !> Continuous except where two valleys of one run tie while both split (rare).
    pure subroutine split_run(i1, i2, np, patch, pot, sn)
      integer, intent(in) :: i1, i2
      integer, intent(inout) :: np
      type(patch_geometry_t), intent(inout) :: patch(:)
      !> the patches' potential data (allocated with the energy-consistent force only)
      type(patch_potential_t), allocatable, intent(inout) :: pot(:)
      !> the distributed normal force (allocated with it only): the patches' loads
      type(strip_normal_t), allocatable, intent(inout) :: sn
      integer, parameter :: stack_size = 32
      integer :: lo(stack_size), hi(stack_size), top, a, b, kv, k, kc, kl, kr
      real(wp) :: share(stack_size), wn, v, pmax, lambda, x, dlo, dlam(6), gshare(6, stack_size), gw(6)
      real(wp) :: tv, sb, wv(5), wb(5), pl, wl(5), pr, wr(5), dlo_l, dlo_r, gv(6), gd(6), tp
      ! the stretches' split positions in strip units (strip_part)
      real(wp) :: xlo(stack_size), xhi(stack_size), xl, xh, xv
      real(wp) :: smax(i1:i2)     ! smax(k) = max(ds(k+1:b)) of the current stretch
      ! the depths that decide the split, with two neighbours either side (-huge: none)
      real(wp) :: ds(i1 - 2:i2 + 2)
      do k = i1 - 2, i2 + 2
        ds(k) = -huge(1.0_wp)
        if (k < ilo .or. k > ihi) cycle
        if (use_distributed) then
          ds(k) = sdepth_signed(k)
        else
          ds(k) = delta(k)
        end if
      end do
      top = 1
      lo(1) = i1; hi(1) = i2; share(1) = 1; gshare(:, 1) = 0
      xlo(1) = -huge(1.0_wp); xhi(1) = huge(1.0_wp)     ! (the run's ends: strip_part)
      do while (top > 0)
        a = lo(top); b = hi(top); wn = share(top); gw = gshare(:, top); xl = xlo(top); xh = xhi(top)
        top = top - 1
        kc = a - 1 + maxloc(delta(a:b), dim=1)
        ! lowest valley: a strip strictly below the maxima on both of its sides
        ! (suffix maxima in one backward pass: maxval(ds(k+1:b)) for every candidate
        ! was quadratic in the run length, 200 strips at 0.05 mm)
        kv = 0
        v = huge(1.0_wp)
        if (b - a >= 2) then
          smax(b - 1) = ds(b)
          do k = b - 2, a + 1, -1
            smax(k) = max(smax(k + 1), ds(k + 1))
          end do
        end if
        pmax = ds(a)
        do k = a + 1, b - 1
          if (ds(k) < pmax .and. ds(k) < v) then
            if (ds(k) < smax(k)) then
              kv = k; v = ds(k)
            end if
          end if
          pmax = max(pmax, ds(k))
        end do
        lambda = 0
        dlam = 0
        if (kv > 0 .and. top + 2 <= stack_size) then
          ! the valley and the two peaks on the interpolant through the depths
          call cubic_minimum(ds(kv - 2:kv + 2), .false., v, wv, tp)
          call cubic_minimum(ds(kv - 2:kv + 2), .true., sb, wb, tv)    ! (the split's position)
          kl = a - 1 + maxloc(ds(a:kv), dim=1)
          kr = kv - 1 + maxloc(ds(kv:b), dim=1)
          call cubic_minimum(-ds(kl - 2:kl + 2), .false., pl, wl, tp)
          call cubic_minimum(-ds(kr - 2:kr + 2), .false., pr, wr, tp)
          pl = -pl; pr = -pr
          call smooth_min(pl, pr, dlo, dlo_l, dlo_r)      ! the lower of the two peaks
          x = 1 - v / ((1 - virtual_eps) * dlo)
          x = min(max(x, 0.0_wp), 1.0_wp)
          ! C1 ramp (smoothstep): the linear ramp's slope jumped where the split starts/ends
          lambda = x * x * (3 - 2 * x)
          ! its pose gradient (potential patches, the share term of rd_strip_potential):
          ! dx = (-d v + (v / dlo) d dlo) / ((1 - eps) dlo), d delta_i = -G_i d pose, the
          ! extrema's derivatives by the depths their spline weights
          if (use_potential .and. x > 0 .and. x < 1) then
            gv = weighted_wrench(kv, wv)
            gd = dlo_l * weighted_wrench(kl, wl) + dlo_r * weighted_wrench(kr, wr)
            dlam = 6 * x * (1 - x) * (gv - (v / dlo) * gd) / ((1 - virtual_eps) * dlo)
          end if
        end if
        if (lambda < 1) call add_patch(a, b, kc, wn * (1 - lambda), i1, i2, xl, xh, np, patch, pot, sn, &
                                     (1 - lambda) * gw - wn * dlam)
        if (lambda > 0) then
          xv = kv + tv
          top = top + 1
          lo(top) = a; hi(top) = kv; share(top) = wn * lambda; gshare(:, top) = lambda * gw + wn * dlam
          xlo(top) = xl; xhi(top) = xv
          top = top + 1
          lo(top) = kv; hi(top) = b; share(top) = wn * lambda; gshare(:, top) = lambda * gw + wn * dlam
          xlo(top) = xv; xhi(top) = xh
        end if
      end do
    end subroutine split_run

    !> sum over strips k-2..k+2 of w G: minus the gradient of an interpolant's extremum near
    !> strip k (weights w) with respect to the wheel's pose (strips with weight 0 not read)
    pure function weighted_wrench(k, w) result(g)
      integer, intent(in) :: k
      real(wp), intent(in) :: w(-2:2)
      real(wp) :: g(6)
      integer :: j
      g = 0
      do j = -2, 2
        if (w(j) /= 0) g = g + w(j) * strip_wrench(k + j)
      end do
    end function weighted_wrench

    !> One patch over the stretch a..b (peak strip kc, bounds xl..xh in strip units) of the
    !> run r1..r2 with force share wn.
    pure subroutine add_patch(a, b, kc, wn, r1, r2, xl, xh, np, patch, pot, sn, gwn)
      integer, intent(in) :: a, b, kc, r1, r2
      real(wp), intent(in) :: wn, xl, xh
      !> gradient of the share wn with respect to the wheel's translation and rotation
      !> (intermediate frame; potential patches only)
      real(wp), intent(in) :: gwn(6)
      integer, intent(inout) :: np
      type(patch_geometry_t), intent(inout) :: patch(:)
      type(patch_potential_t), allocatable, intent(inout) :: pot(:)
      type(strip_normal_t), allocatable, intent(inout) :: sn
      real(wp) :: pen, e, f(3), fm(3), curv(3), cgrad(6, 3)
      integer :: iw
      if (use_potential) then
        call potential_of_stretch(a, b, kc, e, f, fm, curv, cgrad)
        pen = wn**(2.0_wp / 3.0_wp) * e
      else
        pen = wn**(2.0_wp / 3.0_wp) * refined_peak(delta, kc, ilo, ihi)
      end if
      if (np < MAX_PATCHES) then
        np = np + 1
        iw = np
      else                                  ! keep the MAX_PATCHES deepest
        iw = minloc(patch(:)%penetration, dim=1)
        if (patch(iw)%penetration >= pen) return
      end if
      call fill_patch(patch(iw), a, b, kc, pen, r1, r2, xl, xh)
      patch(iw)%share = wn
      if (use_distributed) sn%patch_load(iw) = wn * stretch_load(a, b, r1, r2, xl, xh)
      if (use_potential) then
        patch(iw)%curv_wheel_roll = curv(1)
        patch(iw)%curv_wheel_lat = curv(2)
        patch(iw)%curv_rail_lat = curv(3)
        associate (q => pot(iw))
          q%force_dir = matmul(f, bt)          ! B f: intermediate -> track frame
          q%force_moment = fm
          q%curv_grad(4:6, :) = cgrad(4:6, :)
          q%curv_grad(1:3, :) = matmul(transpose(bt), cgrad(1:3, :))
          q%share_grad(4:6) = gwn(4:6)
          q%share_grad(1:3) = matmul(transpose(bt), gwn(1:3))
        end associate
      end if
    end subroutine add_patch

    !> The energy-consistent description of the stretch a..b (rd_strip_potential): effective
    !> penetration e, f = sum c_i g_i and fm = sum c_i p_i x g_i (minus the gradient of e
    !> with respect to the wheel's translation and rotation, intermediate frame), the Hertz
    !> curvatures as E-weighted means over the region (wheel rolling, wheel lateral, rail
    !> lateral) and their gradients cgrad (translation 1:3, rotation 4:6). The patch's
    !> share enters only its magnitude (the share's own gradient, section 6's "share
    !> term", is not included).
    pure subroutine potential_of_stretch(a, b, kc, e, f, fm, curv, cgrad)
      integer, intent(in) :: a, b, kc
      real(wp), intent(out) :: e, f(3), fm(3), curv(3), cgrad(6, 3)
      real(wp) :: c(a:b), g(6, a:b), v(a:b, 3), dv(a:b, 3), dmean(a:b, 3), wn(a:b), gpy(6, a:b), pp(3), x, t, &
                  dt(a:b)
      integer :: kk, j, q
      call effective_penetration(delta(a:b), potential_eps, e, c, t, dt)
      f = 0; fm = 0
      ! only penetrating strips carry weight (c_i, wn_i and dmean_i vanish elsewhere)
      do kk = a, b
        if (.not. (delta(kk) > 0)) then
          v(kk, :) = 0
          cycle
        end if
        j = jseg(kk)
        pp = pw(:, kk)
        g(1:3, kk) = strip_force_direction(pp, delta(kk), wheel%y(j), wheel%y(j + 1), &
                                           wheel%slope(j), wheel%slope(j + 1), wheel%cone_slope(j))
        g(4:6, kk) = cross(pp, g(1:3, kk))
        call wheel_point_curvatures(pp(2), j, wheel%y, wheel%k_roll, wheel%kappa, &
                                    v(kk, 1), v(kk, 2), dv(kk, 1), dv(kk, 2))
        v(kk, 3) = rail%kappa(kk); dv(kk, 3) = 0
        x = (pp(2) - wheel%y(j)) / (wheel%y(j + 1) - wheel%y(j))
        gpy(:, kk) = deepest_point_py_gradient(pp, d, wheel%cone_slope(j), x > 1.0e-9_wp .and. x < 1 - 1.0e-9_wp)
        f = f + c(kk) * g(1:3, kk)
        fm = fm + c(kk) * g(4:6, kk)
      end do
      ! no penetrating strip (a patch opened by its refined peak alone): the rail normal
      if (all(f == 0)) f = matmul(bt, [0.0_wp, rail%ny(kc), rail%nz(kc)])
      ! d kappa / d pose = sum dmean_i d delta_i / d pose + sum wn_i kappa_i' d py_i / d pose,
      ! d delta_i / d pose = -(g_i, p_i x g_i), d py_i / d pose = gpy_i
      call region_mean(delta(a:b), t, dt, v, curv, dmean, wn)
      cgrad = 0
      do kk = a, b
        if (.not. (delta(kk) > 0)) cycle
        do q = 1, 3
          cgrad(:, q) = cgrad(:, q) - dmean(kk, q) * g(:, kk) + wn(kk) * dv(kk, q) * gpy(:, kk)
        end do
      end do
    end subroutine potential_of_stretch

    !> G_i = (g_i, p_i x g_i): minus the gradient of strip i's depth with respect to the
    !> wheel's translation and rotation (intermediate frame; rd_strip_potential)
    pure function strip_wrench(i) result(gi)
      integer, intent(in) :: i
      real(wp) :: gi(6)
      integer :: j
      j = jseg(i)
      gi(1:3) = strip_force_direction(pw(:, i), delta(i), wheel%y(j), wheel%y(j + 1), &
                                      wheel%slope(j), wheel%slope(j + 1), wheel%cone_slope(j))
      gi(4:6) = cross(pw(:, i), gi(1:3))
    end function strip_wrench

    !> Strips first, first + stride, ..., last (and last itself): strip_depths on this pose.
    pure subroutine evaluate_lines(first, last, stride, delta, tline, pw, jseg, jprev)
      integer, intent(in) :: first, last, stride
      real(wp), intent(inout) :: delta(:), tline(:), pw(:, :)
      integer, intent(inout) :: jseg(:), jprev
      call strip_depths(first, last, stride, wheel%n, wheel%y, wheel%r, wheel%slope, wheel%cone_slope, &
                        wheel%r_max, rail%n, rail%y, rail%z, bt, d, a, y, z, full_search, &
                        delta, tline, pw, jseg, jprev)
    end subroutine evaluate_lines

    !> Patch over the stretch a..b (peak strip kc) of the run r1..r2, penetration pen.
    pure subroutine fill_patch(p, a, b, kc, pen, r1, r2, xl, xh)
      type(patch_geometry_t), intent(out) :: p
      integer, intent(in) :: a, b, kc, r1, r2
      real(wp), intent(in) :: pen
      real(wp), intent(in) :: xl, xh          !< the stretch's split positions (distributed force)
      real(wp) :: x, w, slope, rr, ky, te, tx, thr, wsum, qsum, krsum, kwsum, wq, wcurv, lsum, lsum1, peak
      integer :: kk, jw
      ! Contact point: centroid of the strips inside the virtual-penetration region of
      ! Kik & Piotrowski (VSD 46, 2008), delta_i > (1 - eps) delta_max with their eps = 0.55,
      ! weighted by delta_i - (1 - eps) delta_max. For a Hertzian (parabolic) gap this is
      ! the strip of maximum penetration of eq. 4.77; for the wide, flat gaps of worn or
      ! near-conformal profiles it follows the pressure resultant instead of a flat maximum.
      ! Over the bump's stretch a..b only (split_run): Kik & Piotrowski's separate regions.
      p%penetration = pen
      peak = refined_peak(delta, kc, ilo, ihi)
      thr = (1 - virtual_eps) * peak
      wsum = 0; qsum = 0; krsum = 0; kwsum = 0; wcurv = 0
      if (use_distributed) then
        ! the distributed force: CONTACT's reference point, the centre of the
        ! interpenetration weighted by its square over the area, int delta^2 dA (Vollebregt's
        ! default weighting): per strip w_i int delta_i(x)^2 dx over its chord 2 sqrt(delta_i / A),
        ! proportional to w_i delta_i^(5/2) (A varies little across a patch). Manchester
        ! A-2.2 through the pipeline: every contact position within 0.06 mm of CONTACT's
        ! (the threshold centroid below: 0.71 mm in case 2). The Hertz curvatures stay
        ! the threshold region's means (below): averaged with these weights over the whole
        ! region they took in the near-conformal flange root next to a flange face, and the
        ! ellipse grew to 16 x 1.1 mm; the leading wheelset of the R 80 m scene
        ! (bench/extremes) then flipped between root and face (Y 4-98 kN at 14 Hz).
        ! the curvature means' threshold: (1 - eps) times a smooth stand-in for the peak depth,
        ! (2q + 1) / (2q) times the Lehmer mean of the smooth depths (the peak of every parabolic
        ! gap: rd_strip_potential effective_penetration); the refined peak of the cones' depths
        ! kinked where the deepest strip changed, and the means with it
        lsum = 0; lsum1 = 0
        ! (the strips next to a split position are shared with the neighbouring stretch)
        do kk = max(a - 2, r1), min(b + 2, r2)
          if (sdepth(kk) > 0) then
            lsum = lsum + strip_part(kk, xl, xh) * sdepth(kk)**lehmer_order
            lsum1 = lsum1 + strip_part(kk, xl, xh) * sdepth(kk)**(lehmer_order - 1)
          end if
        end do
        thr = 0
        p%point_depth = pen
        if (lsum1 > 0) then
          thr = (1 - virtual_eps) * (2 * lehmer_order + 1) / (2.0_wp * lehmer_order) * lsum / lsum1
          ! the material point's approach: the same smooth peak, share-scaled as pen (pen is
          ! share^(2/3) times the refined peak); the refined peak's kinks moved the point's
          ! radius and the longitudinal creepage (Fx 6 % at 0.23 mm on the tread)
          if (peak > 0) p%point_depth = pen / peak * thr / (1 - virtual_eps)
        end if
        do kk = max(a - 2, r1), min(b + 2, r2)
          if (sdepth(kk) > 0) then
            ! the strips' depths into the smooth wheel: those into the cones kinked the point
            ! wherever a strip's deepest point crossed a profile point
            wq = strip_part(kk, xl, xh) * rail%width(kk) * sdepth(kk)**2 * sqrt(sdepth(kk))
            wsum = wsum + wq
            qsum = qsum + wq * (kk - kc)
          end if
          if (sdepth(kk) > thr) then
            ! squared weights: a strip crossing the threshold enters the means with zero
            ! slope (with delta - thr the curvatures, the Hertz ellipse and the creep forces
            ! kinked there, every few hundredths of a millimetre of shift on a wide tread patch)
            wq = strip_part(kk, xl, xh) * (sdepth(kk) - thr)**2
            wcurv = wcurv + wq
            krsum = krsum + wq * rail%kappa(kk)
            kwsum = kwsum + wq * wheel_kappa_smooth(kk)
          end if
        end do
      else
        do kk = a, b
          if (delta(kk) > thr) then
            wsum = wsum + (delta(kk) - thr)
            wcurv = wcurv + (delta(kk) - thr)
            qsum = qsum + (delta(kk) - thr) * (kk - kc)
            krsum = krsum + (delta(kk) - thr) * rail%kappa(kk)
            kwsum = kwsum + (delta(kk) - thr) * wheel_kappa_at(kk)
          end if
        end do
      end if
      x = 0
      if (wsum > 0) x = qsum / wsum
      if (use_distributed) then
        call blend_point(kc, x, p)
      else
        call interpolate_point(kc, x, p)
      end if
      ! Lateral curvatures for Hertz: the mean over the virtual-penetration region with the
      ! centroid's weights (exact for a Hertzian gap, whose curvatures are constant over the
      ! patch). The curvatures at the point alone vary over tenths of a millimetre of wheelset
      ! shift where the flange root of S1002 meets the R80 / R13 arcs of the rail nearly
      ! conformally (relative curvature 0.04-1 1/m, Hertz constant x2 over 0.05 mm), so that
      ! N = K(q) delta^1.5 is no gradient field: a closed loop of poses of 0.1 x 0.05 mm got
      ! 35 % of its gross work back, the energy source of the flange chatter
      ! (docs/theory_flange_chatter.md; test_wheelset_energy).
      if (wcurv > 0) p%curv_rail_lat = krsum / wcurv
      p%curv_rail_roll = 0
      jw = locate(wheel%y, p%point_wheel(2))
      x = (p%point_wheel(2) - wheel%y(jw)) / (wheel%y(jw + 1) - wheel%y(jw))
      x = min(max(x, 0.0_wp), 1.0_wp)
      p%s_wheel = wheel%s(jw) + x * (wheel%s(jw + 1) - wheel%s(jw))
      rr = wheel%r(jw) + x * (wheel%r(jw + 1) - wheel%r(jw))
      slope = wheel%slope(jw) + x * (wheel%slope(jw + 1) - wheel%slope(jw))
      ! the distributed force's patches: the smooth wheel's radius and slope (that of its
      ! strip depths, C1 along the profile; linear between the points kinked the rolling
      ! radius, and with it the longitudinal creepage, at every profile point)
      if (use_distributed) call smooth_wheel_radius(p%point_wheel(2), jw, wheel%y, wheel%r, wheel%r_spline, wheel%r_fourth, &
                                                   rr, slope, ky)
      p%rolling_radius = rr
      p%curv_wheel_lat = wheel%kappa(jw) + x * (wheel%kappa(jw + 1) - wheel%kappa(jw))
      if (wcurv > 0) p%curv_wheel_lat = kwsum / wcurv    ! (see curv_rail_lat)
      ! normal curvature of a surface of revolution along its parallel: cos(gamma_s)/r
      ! (the inverse of the thesis' indentation radius R_s = r_s / cos(gamma_s), eq. 4.75)
      p%curv_wheel_roll = 1 / (rr * sqrt(1 + slope**2))
      if (abs(p%contact_angle) < flange_angle) then
        p%kind = PATCH_TREAD
      else if (slope > 0) then
        p%kind = PATCH_FLANGE_BACK
      else
        p%kind = PATCH_FLANGE
      end if
      ! extent: zero crossings of the signed penetration at the ends of the run, the valley
      ! strip where the bump borders another one
      p%u_rail_min = rail%u(a)
      if (a == r1 .and. a > ilo .and. delta(a) > 0) then
        if (delta(a - 1) > -huge(1.0_wp)) then
          w = delta(a) / (delta(a) - delta(a - 1))
          p%u_rail_min = rail%u(a) + w * (rail%u(a - 1) - rail%u(a))
        end if
      end if
      p%u_rail_max = rail%u(b)
      if (b == r2 .and. b < ihi .and. delta(b) > 0) then
        if (delta(b + 1) > -huge(1.0_wp)) then
          w = delta(b) / (delta(b) - delta(b + 1))
          p%u_rail_max = rail%u(b) + w * (rail%u(b + 1) - rail%u(b))
        end if
      end if
      call strip_ends(kc, te, tx)
      p%strip_length = tx - te
    end subroutine fill_patch

    !> The centroid force's patch point at the continuous strip position kc + x (fill_patch):
    !> every strip quantity interpolated linearly between the two neighbouring strips.
    pure subroutine interpolate_point(kc, x, p)
      integer, intent(in) :: kc               !< the stretch's peak strip
      real(wp), intent(in) :: x               !< the point's strip offset from kc
      type(patch_geometry_t), intent(inout) :: p
      real(wp) :: w, te, tx, tm1, tm2
      integer :: kk, kc2
      kk = kc + floor(x)
      w = x - floor(x)
      if (kk + 1 > ihi) then
        kk = ihi - 1; w = 1
      end if
      kc2 = kk
      kk = kc2 + 1
      ! Along the strip: the middle of the interpenetration chord (entry and exit of the
      ! rail line through the wheel, eqs. 4.68-4.71), not the deepest point of the line.
      ! For a Hertzian gap they coincide (the ellipse is symmetric about its centre); on a
      ! yawed flange root the depth along the line is flat with several maxima, and the
      ! deepest one jumps between them while the chord moves continuously.
      call strip_ends(kc2, te, tx)
      tm1 = 0.5_wp * (te + tx)
      call strip_ends(kk, te, tx)
      tm2 = 0.5_wp * (te + tx)
      p%point_rail = [lerp(tm1, tm2, w), lerp(rail%y(kc2), rail%y(kk), w), lerp(rail%z(kc2), rail%z(kk), w)]
      p%point_wheel = lerp3(pw(:, kc2) + (tm1 - tline(kc2)) * d, pw(:, kk) + (tm2 - tline(kk)) * d, w)
      p%u_rail = lerp(rail%u(kc2), rail%u(kk), w)
      p%normal = [0.0_wp, lerp(rail%ny(kc2), rail%ny(kk), w), lerp(rail%nz(kc2), rail%nz(kk), w)]
      p%normal = p%normal / norm2(p%normal)
      p%contact_angle = atan2(p%normal(2), p%normal(3))
      p%curv_rail_lat = lerp(rail%kappa(kc2), rail%kappa(kk), w)
    end subroutine interpolate_point

    !> The distributed force's patch point at the continuous strip position kc + x (CONTACT's
    !> reference point, fill_patch): every strip quantity blended over the three strips
    !> around it with the quadratic B-spline weights (1/2 - t)^2 / 2, 3/4 - t^2,
    !> (1/2 + t)^2 / 2, t = x - nint(x), which are C1 in x and reproduce a quantity linear
    !> in the strip index. Linear interpolation between the two neighbouring strips kinked
    !> the point, its normal and with them the creep forces every time the position crossed a strip
    !> (every ~0.19 mm of wheelset shift at 0.2 mm strips: bench/contact_smoothness).
    pure subroutine blend_point(kc, x, p)
      integer, intent(in) :: kc               !< the stretch's peak strip
      real(wp), intent(in) :: x               !< the point's strip offset from kc
      type(patch_geometry_t), intent(inout) :: p
      real(wp) :: t, bw(3), tm
      integer :: i0, k, i
      i0 = min(max(kc + nint(x), ilo + 1), ihi - 1)
      t = min(max(x - (i0 - kc), -0.5_wp), 0.5_wp)
      bw = [0.5_wp * (0.5_wp - t)**2, 0.75_wp - t * t, 0.5_wp * (0.5_wp + t)**2]
      p%point_rail = 0; p%point_wheel = 0; p%u_rail = 0; p%normal = 0; p%curv_rail_lat = 0
      do k = 1, 3
        i = i0 - 2 + k
        ! along the line: the deepest point on the smooth wheel (unique and smooth in the pose;
        ! the cones' chord middle moved in kinks wherever the chord's ends crossed profile
        ! points, and with it the rolling radius at the point and the longitudinal creepage)
        tm = tline(i) + dot_product(sdeep(:, i) - pw(:, i), d)
        p%point_rail = p%point_rail + bw(k) * [tm, rail%y(i), rail%z(i)]
        p%point_wheel = p%point_wheel + bw(k) * sdeep(:, i)
        p%u_rail = p%u_rail + bw(k) * rail%u(i)
        p%normal = p%normal + bw(k) * [0.0_wp, rail%ny(i), rail%nz(i)]
        p%curv_rail_lat = p%curv_rail_lat + bw(k) * rail%kappa(i)
      end do
      p%normal = p%normal / norm2(p%normal)
      p%contact_angle = atan2(p%normal(2), p%normal(3))
    end subroutine blend_point

    !> Wheel profile curvature at rail line i's deepest point on the smooth wheel, smooth along the
    !> profile (C2: rd_strip_potential wheel_point_curvatures, the distributed force's). Linear
    !> between the points it kinked the patches' Hertz curvature means at every profile point,
    !> and at the cones' deepest point, which a yawed line holds on a profile point for a while,
    !> on the yawed flange every few hundredths of a millimetre.
    pure real(wp) function wheel_kappa_smooth(i) result(k)
      integer, intent(in) :: i
      real(wp) :: k_roll, dk_roll, dk_lat
      call wheel_point_curvatures(sdeep(2, i), sdeep_j(i), wheel%y, wheel%k_roll, wheel%kappa, k_roll, k, dk_roll, &
                                  dk_lat, wheel%k_roll_spline, wheel%kappa_spline)
    end function wheel_kappa_smooth

    !> Wheel profile curvature at the deepest point of rail line i (on its cone jseg(i)).
    pure real(wp) function wheel_kappa_at(i) result(k)
      integer, intent(in) :: i
      real(wp) :: x
      integer :: j
      j = jseg(i)
      x = (pw(2, i) - wheel%y(j)) / (wheel%y(j + 1) - wheel%y(j))
      x = min(max(x, 0.0_wp), 1.0_wp)
      k = wheel%kappa(j) + x * (wheel%kappa(j + 1) - wheel%kappa(j))
    end function wheel_kappa_at

    !> Entry and exit of rail line i through the wheel (thesis 4.68-4.71: when alpha falls
    !> outside [0, 1] the intersection continues on segment j-1 or j+1).
    pure subroutine strip_ends(i, t_entry, t_exit)
      integer, intent(in) :: i
      real(wp), intent(out) :: t_entry, t_exit
      real(wp) :: q0(3), tr(2), al(2)
      integer :: j, it, nr, side
      q0 = matmul(bt, [0.0_wp, rail%y(i) - y, rail%z(i) - z])
      t_entry = tline(i); t_exit = tline(i)
      do side = 1, 2
        j = jseg(i)
        do it = 1, wheel%n
          call line_cone_roots(q0, d, wheel%y(j), wheel%r(j), wheel%y(j + 1), wheel%r(j + 1), nr, tr, al)
          if (nr < 2) exit
          if (al(side) < 0) then
            if (j == 1) exit
            j = j - 1
          else if (al(side) > 1) then
            if (j == wheel%n - 1) exit
            j = j + 1
          else
            if (side == 1) then
              t_entry = tr(1)
            else
              t_exit = tr(2)
            end if
            exit
          end if
        end do
      end do
    end subroutine strip_ends

  end subroutine strip_wheel_contact

  !> Deepest penetration of the rail lines first, first + stride, ..., last (and last
  !> itself) into the wheel (strips i): delta(i) normal to the wheel surface, the line
  !> parameter tline(i) and wheel point pw(:, i) of the deepest point and its cone jseg(i).
  !>
  !> The hot path of the online geometry (docs/performance.md), written for the processor:
  !> - explicit-shape arrays (wheel%y ... of the surfaces, contiguous: no copies) and the pose
  !>   as B^T (bt), the track x axis d = bt(:, 1) and a = |(d1, d3)|;
  !> - the lines in blocks of `block` and each block in passes over independent lines
  !>   (closest approach to the axle; the cone under it; depth on that cone; normal depth),
  !>   so that the square roots and divisions of neighbouring lines overlap instead of
  !>   each line waiting for its own chain of them (a line's result depends on that line
  !>   alone: the hunt's guess changes how fast its segment is found, not which);
  !> - the cone depth of rd_line_cone's line_cone_max_depth_slope written out with the same
  !>   operations for the common case (the depth's stationary point inside the cone under the
  !>   closest approach, where the hill climb stops at once); every other line (clamped to a
  !>   cone edge, climbing to a neighbouring cone, the exhaustive search) takes line_depth,
  !>   the general search.
  !> Every line gets the operations it got in one loop, in the same order: the results are
  !> the same bit for bit.
  pure subroutine strip_depths(first, last, stride, nw, wy, wr, wslope, wcone, r_max, nr, ry, rz, &
                               bt, d, a, y, z, full_search, delta, tline, pw, jseg, jprev)
    integer, intent(in) :: first, last, stride, nw, nr
    real(wp), intent(in) :: wy(nw), wr(nw), wslope(nw), wcone(nw - 1), r_max, ry(nr), rz(nr)
    real(wp), intent(in) :: bt(3, 3), d(3), a, y, z
    logical, intent(in) :: full_search
    real(wp), intent(inout) :: delta(nr), tline(nr), pw(3, nr)
    integer, intent(inout) :: jseg(nr), jprev
    !> as line_cone_max_depth_slope's inside_margin
    real(wp), parameter :: inside_margin = 1.0e-9_wp
    !> lines per block (scratch on the stack)
    integer, parameter :: block = 64
    !> line states: above the axle; far from the wheel; depth found on the hunted cone
    !> (inside); the general search needed
    integer, parameter :: ABOVE = 0, FAR = 1, INSIDE = 2, GENERAL = 3
    real(wp) :: p01(block), p02(block), p03(block), t0(block), py0(block), pz0(block), rho(block)
    real(wp) :: best(block), taub(block), ryb(block), rzb(block), w1(block), w2(block), s1(block)
    real(wp) :: s2(block), dl(block), tb(block)
    integer :: il(block), jh(block), jb(block), state(block)
    real(wp) :: rel2, rel3, proj, px0, a2, dy, y1, y2, kc, c, tau, py, ww, k, ylo_far, yhi_far
    integer :: m, n, i, inext
    a2 = a**2
    dy = d(2)
    ylo_far = wy(1) - 0.2_wp
    yhi_far = wy(nw) + 0.2_wp
    inext = first
    do while (inext > 0)
      ! the next block of lines
      n = 0
      do while (n < block .and. inext > 0)
        n = n + 1
        il(n) = inext
        if (inext == last) then
          inext = 0
        else
          inext = min(inext + stride, last)
        end if
      end do
      ! closest approach of each line to the axle (vectorised: the rail points gathered first)
      do m = 1, n
        ryb(m) = ry(il(m)); rzb(m) = rz(il(m))
      end do
      !GCC$ vector
      do m = 1, n
        rel2 = ryb(m) - y
        rel3 = rzb(m) - z
        p01(m) = bt(1, 2) * rel2 + bt(1, 3) * rel3     ! B^T rel, rel(1) = 0
        p02(m) = bt(2, 2) * rel2 + bt(2, 3) * rel3
        p03(m) = bt(3, 2) * rel2 + bt(3, 3) * rel3
        proj = p01(m) * d(1) + p03(m) * d(3)
        t0(m) = -proj / a2                  ! closest approach of the line to the axle
        px0 = p01(m) + t0(m) * d(1)
        pz0(m) = p03(m) + t0(m) * d(3)
        py0(m) = p02(m) + t0(m) * d(2)
        rho(m) = sqrt(px0**2 + pz0(m)**2)
      end do
      ! the cone under it (lines come in lateral order: O(1) search); above the axle is not
      ! the running surface
      do m = 1, n
        if (pz0(m) >= 0) then
          state(m) = ABOVE
        else
          jprev = hunt_segment(nw, wy, py0(m), jprev)
          jh(m) = jprev
          if (rho(m) < r_max .and. py0(m) > ylo_far .and. py0(m) < yhi_far) then
            state(m) = GENERAL
          else
            state(m) = FAR
          end if
        end if
      end do
      ! the depth on that cone where its stationary point lies inside it (the hill climb of
      ! line_depth stops there: p_y of the deepest point is inside the cone)
      if (.not. full_search .and. dy /= 0) then
        do m = 1, n
          if (state(m) /= GENERAL) cycle
          y1 = wy(jh(m)); y2 = wy(jh(m) + 1)
          if (.not. (y2 > y1)) cycle
          kc = wcone(jh(m))
          c = kc * dy
          if (.not. (abs(c) < a)) cycle
          tau = c * rho(m) / (a * sqrt(a2 - c**2))
          py = py0(m) + dy * tau
          if (py > y1 + inside_margin .and. py < y2 - inside_margin) then
            best(m) = wr(jh(m)) + kc * (py0(m) + dy * tau - y1) - sqrt(rho(m)**2 + (a * tau)**2)
            if (t0(m) /= t0(m)) best(m) = t0(m)   ! propagate a NaN pose instead of hiding it
            jb(m) = jh(m); taub(m) = tau
            state(m) = INSIDE
          end if
        end do
      end if
      ! the general search for the rest
      do m = 1, n
        if (state(m) == GENERAL) then
          call line_depth(t0(m), rho(m), py0(m), jh(m), best(m), jb(m), taub(m))
        else if (state(m) == FAR) then
          best(m) = -huge(1.0_wp); jb(m) = jh(m); taub(m) = 0
        end if
      end do
      ! radial depth -> depth normal to the wheel surface; first the far lines' radial gap
      ! and the points of each line's cone gathered, then the depths (vectorised)
      do m = 1, n
        if (state(m) == ABOVE) then
          ! (harmless values for the vector pass; the line gets its own below)
          best(m) = 0; taub(m) = 0; py0(m) = 0; w1(m) = 0; w2(m) = 1; s1(m) = 0; s2(m) = 0
          cycle
        end if
        if (best(m) == -huge(1.0_wp)) then
          ! far away: the radial gap is enough. The wheel radius at py0 is wheel_radius_at's
          ! interpolation on the hunted segment (= jb here): the hunt finds the segment
          ! locate would.
          ww = (py0(m) - wy(jb(m))) / (wy(jb(m) + 1) - wy(jb(m)))
          ww = min(max(ww, 0.0_wp), 1.0_wp)
          best(m) = wr(jb(m)) + ww * (wr(jb(m) + 1) - wr(jb(m))) - rho(m)
          taub(m) = 0
        end if
        w1(m) = wy(jb(m)); w2(m) = wy(jb(m) + 1)
        s1(m) = wslope(jb(m)); s2(m) = wslope(jb(m) + 1)
      end do
      ! (thesis 4.75-4.76: delta ~ d cos(gamma_s)), with the profile slope interpolated
      ! between the points at the deepest point: the chord slope of the cone would jump
      ! where the deepest point crosses a profile point (a 2 % jump of the depth on the
      ! flange, where tan(gamma_s) ~ 2.4).
      !GCC$ vector
      do m = 1, n
        ww = (py0(m) + dy * taub(m) - w1(m)) / (w2(m) - w1(m))
        ww = min(max(ww, 0.0_wp), 1.0_wp)
        k = s1(m) + ww * (s2(m) - s1(m))
        dl(m) = best(m) / sqrt(1 + k**2)
        tb(m) = t0(m) + taub(m)
      end do
      do m = 1, n
        i = il(m)
        if (state(m) == ABOVE) then
          delta(i) = -huge(1.0_wp); tline(i) = 0; pw(:, i) = 0; jseg(i) = 1
        else
          delta(i) = dl(m)
          tline(i) = tb(m)
          pw(1, i) = p01(m) + tb(m) * d(1)
          pw(2, i) = p02(m) + tb(m) * d(2)
          pw(3, i) = p03(m) + tb(m) * d(3)
          jseg(i) = jb(m)
        end if
      end do
    end do

  contains

    !> Deepest radial depth `best` of the line (t0, rho, py0) over the wheel's cones, its cone
    !> jb and line offset taub from t0, starting at the hunted cone jhunt; best = -huge(1.0)
    !> if none is found.
    pure subroutine line_depth(t0, rho, py0, jhunt, best, jb, taub)
      real(wp), intent(in) :: t0, rho, py0
      integer, intent(in) :: jhunt
      real(wp), intent(out) :: best, taub
      integer, intent(out) :: jb
      real(wp) :: half, dep, tau, pyb
      integer :: j, jlo, jhi, step
      logical :: found
      best = -huge(1.0_wp); jb = jhunt; taub = 0
      if (full_search) then
        ! every cone the line can reach: rho(t) < r_max bounds |t - t0|, hence p_y
        half = abs(d(2)) * sqrt(r_max**2 - rho**2) / a
        jlo = locate(wy, py0 - half)
        jhi = locate(wy, py0 + half)
        do j = jlo, jhi
          call cone_depth(j, t0, rho, py0, found, dep, tau)
          if (found .and. dep > best) then
            best = dep; jb = j; taub = tau
          end if
        end do
      else
        ! Hill climb from the cone under the closest approach: the depth is concave on
        ! each cone, so when its maximum sits on a cone's edge the maximum along the line
        ! continues on the neighbouring cone (thesis 4.7.1.5: alpha < 0 -> segment j-1,
        ! alpha > 1 -> j+1). The stationary point lies rho k dy^2 / a^2 from p_y(t0),
        ! a few segments at most on a yawed flange.
        j = jhunt
        call cone_depth(j, t0, rho, py0, found, dep, tau)
        if (found) then
          best = dep; jb = j; taub = tau
          do step = 1, nw
            pyb = py0 + d(2) * taub
            if (pyb >= wy(jb + 1) .and. jb < nw - 1) then
              j = jb + 1
            else if (pyb <= wy(jb) .and. jb > 1) then
              j = jb - 1
            else
              exit
            end if
            call cone_depth(j, t0, rho, py0, found, dep, tau)
            if (.not. (found .and. dep > best)) exit
            best = dep; jb = j; taub = tau
          end do
        end if
      end if
    end subroutine line_depth

    !> Deepest point of the line (t0, rho, py0) on cone j: rd_line_cone's
    !> line_cone_max_depth_slope with the cone slope of the wheel surface; found = .false.
    !> where no cone (y(j+1) <= y(j)).
    pure subroutine cone_depth(j, t0, rho, py0, found, dep, tau)
      integer, intent(in) :: j
      real(wp), intent(in) :: t0, rho, py0
      logical, intent(out) :: found
      real(wp), intent(out) :: dep, tau
      found = .false.; dep = -huge(1.0_wp); tau = 0
      if (.not. (wy(j + 1) > wy(j))) return
      call line_cone_max_depth_slope(t0, rho, py0, a, d(2), wy(j), wr(j), wy(j + 1), wcone(j), found, dep, tau)
    end subroutine cone_depth

  end subroutine strip_depths

  !> Index j with y(j) <= x < y(j+1) (clamped to [1, n-1]), walking from a guess.
  pure integer function hunt_segment(n, y, x, jguess) result(j)
    integer, intent(in) :: n
    real(wp), intent(in) :: y(n)
    real(wp), intent(in) :: x
    integer, intent(in) :: jguess
    j = min(max(jguess, 1), n - 1)
    if (abs(x - y(j)) > 64 * (y(min(j + 1, n)) - y(j))) then
      j = locate(y, x)                      ! far: bisection
      return
    end if
    do while (j > 1)
      if (x >= y(j)) exit
      j = j - 1
    end do
    do while (j < n - 1)
      if (x < y(j + 1)) exit
      j = j + 1
    end do
  end function hunt_segment

  pure function lerp3(u, v, w) result(r)
    real(wp), intent(in) :: u(3), v(3), w
    real(wp) :: r(3)
    r = u + w * (v - u)
  end function lerp3

  pure real(wp) function lerp(u, v, w)
    real(wp), intent(in) :: u, v, w
    lerp = u + w * (v - u)
  end function lerp

  !> Local minimum near strip k (a strip no deeper than its neighbours) of a cubic curve
  !> through the strips' depths d(k-2..k+2), on the piece between strip k and the neighbour
  !> it falls towards: its value s, the weights w (s = sum w d: the derivatives of s by the
  !> depths, s' = 0 there) and its offset t from strip k. Two curves:
  !> - interpolating (Catmull-Rom: cubic Hermite between strips with the slopes
  !>   (d(j+1) - d(j-1)) / 2; C1, through every depth): s <= d(k), so s <= 0 where the valley
  !>   strip leaves contact (two runs join with lambda = 1: no jump; a mean of the depths such
  !>   as an approximating spline's minimum is still positive there);
  !> - bspline (the uniform cubic B-spline with the depths as control points; C2, so its
  !>   minimum's position is C1 in the depths: the interpolant's s'' jumps at the strips and
  !>   its minimum's position kinks there).
  !> Either curve is one function along the strips, so its minimum moves continuously where
  !> the lowest strip changes to a neighbour (it lies between the two) and s is C1 in the
  !> depths where the lowest strip's own depth kinks. A missing depth (+-huge) or a minimum
  !> outside the piece (a degenerate valley) gives the strip itself.
  pure subroutine cubic_minimum(d, bspline, s, w, t)
    real(wp), intent(in) :: d(-2:2)
    logical, intent(in) :: bspline
    real(wp), intent(out) :: s, w(-2:2), t
    real(wp) :: q(0:3), a, b, c, sq, tt, m0, m1, h00, h10, h01, h11
    integer :: j0
    w = 0; w(0) = 1; s = d(0); t = 0
    if (any(abs(d) >= huge(1.0_wp))) return       ! (a peak's depths come negated)
    ! the slope at strip k, (d(1) - d(-1)) / 2 on both curves, says which piece
    if (d(1) < d(-1)) then
      j0 = 0          ! falling through strip k: the minimum is on its right
    else if (d(1) > d(-1)) then
      j0 = -1
    else
      return
    end if
    q = d(j0 - 1:j0 + 2)
    ! the piece's derivative in its parameter tt in [0, 1]: a tt^2 + b tt + c
    if (bspline) then
      a = 0.5_wp * (-q(0) + 3 * q(1) - 3 * q(2) + q(3)); b = q(0) - 2 * q(1) + q(2); c = 0.5_wp * (q(2) - q(0))
    else
      ! Hermite from q(1) to q(2) with the slopes m0 = (q(2) - q(0)) / 2, m1 = (q(3) - q(1)) / 2
      m0 = 0.5_wp * (q(2) - q(0)); m1 = 0.5_wp * (q(3) - q(1))
      a = 3 * (2 * (q(1) - q(2)) + m0 + m1); b = 2 * (3 * (q(2) - q(1)) - 2 * m0 - m1); c = m0
    end if
    ! the minimum: the root with the second derivative 2 a tt + b = sqrt(disc) > 0
    tt = -1
    if (a == 0) then
      if (b > 0) tt = -c / b
    else if (b * b - 4 * a * c >= 0) then
      sq = sqrt(b * b - 4 * a * c)
      if (b > 0) then
        tt = 2 * c / (-b - sq)            ! = (-b + sq) / (2 a) without the cancellation
      else
        tt = (-b + sq) / (2 * a)
      end if
    end if
    if (.not. (tt >= 0 .and. tt <= 1)) return
    w = 0
    if (bspline) then
      w(j0 - 1) = (1 - tt)**3 / 6
      w(j0) = (3 * tt**3 - 6 * tt**2 + 4) / 6
      w(j0 + 1) = (-3 * tt**3 + 3 * tt**2 + 3 * tt + 1) / 6
      w(j0 + 2) = tt**3 / 6
    else
      h00 = (1 + 2 * tt) * (1 - tt)**2; h10 = tt * (1 - tt)**2
      h01 = tt**2 * (3 - 2 * tt); h11 = tt**2 * (tt - 1)
      w(j0 - 1) = -0.5_wp * h10
      w(j0) = h00 - 0.5_wp * h11
      w(j0 + 1) = h01 + 0.5_wp * h10
      w(j0 + 2) = 0.5_wp * h11
    end if
    s = sum(w * d)
    t = j0 + tt
  end subroutine cubic_minimum

  !> Part of strip i in the stretch between the split positions xl < xh (in strip units;
  !> -huge / +huge at a run's ends): G(xh - i) - G(xl - i), G the integral of the quadratic
  !> B-spline B2 (support -3/2..3/2, the box of a strip smoothed once). The parts of one strip
  !> in two neighbouring stretches add up to its whole; the part's derivative by a split
  !> position is B2 there, continuous (with the box, the part's slope jumped wherever a
  !> split position crossed a strip's edge: the patches' loads, curvature means and points
  !> kinked).
  pure real(wp) function strip_part(i, xl, xh) result(f)
    integer, intent(in) :: i
    real(wp), intent(in) :: xl, xh
    f = b2_integral(xh - i) - b2_integral(xl - i)
  end function strip_part

  !> G(u) = integral of the quadratic B-spline from -3/2 to u
  pure real(wp) function b2_integral(u) result(g)
    real(wp), intent(in) :: u
    if (u <= -1.5_wp) then
      g = 0
    else if (u <= -0.5_wp) then
      g = (u + 1.5_wp)**3 / 6
    else if (u <= 0.5_wp) then
      g = 0.5_wp + 0.75_wp * u - u**3 / 3
    else if (u < 1.5_wp) then
      g = 1 - (1.5_wp - u)**3 / 6
    else
      g = 1
    end if
  end function b2_integral

  !> Smooth minimum of two positive values, m = (p + q - sqrt((p - q)^2 + (mu (p + q))^2)) / 2
  !> (homogeneous of degree one; (1 - mu) p where p = q, within mu^2 (p + q)^2 / (4 |p - q|)
  !> of min(p, q) away from it) and its derivatives: min(p, q) kinks where the two
  !> peaks of a run are equally deep.
  pure subroutine smooth_min(p, q, m, dm_dp, dm_dq)
    real(wp), intent(in) :: p, q
    real(wp), intent(out) :: m, dm_dp, dm_dq
    real(wp), parameter :: mu = 0.05_wp
    real(wp) :: r
    r = sqrt((p - q)**2 + (mu * (p + q))**2)
    m = 0.5_wp * (p + q - r)
    if (r > 0) then
      dm_dp = 0.5_wp * (1 - ((p - q) + mu**2 * (p + q)) / r)
      dm_dq = 0.5_wp * (1 - (-(p - q) + mu**2 * (p + q)) / r)
    else
      dm_dp = 0.5_wp; dm_dq = 0.5_wp
    end if
  end subroutine smooth_min

  !> Vertex offset (in strips, within +-0.5) of the parabola through delta(k-1..k+1).
  pure real(wp) function peak_offset(delta, k, ilo, ihi) result(x)
    real(wp), contiguous, intent(in) :: delta(:)
    integer, intent(in) :: k, ilo, ihi
    real(wp) :: dm, dp, den
    x = 0
    if (k <= ilo .or. k >= ihi) return
    dm = delta(k - 1); dp = delta(k + 1)
    if (dm == -huge(1.0_wp) .or. dp == -huge(1.0_wp)) return
    den = dm - 2 * delta(k) + dp
    if (den >= 0) return
    x = 0.5_wp * (dm - dp) / den
    x = min(max(x, -0.5_wp), 0.5_wp)
  end function peak_offset

  !> Vertex value of that parabola (= delta(k) at the ends of the window).
  pure real(wp) function refined_peak(delta, k, ilo, ihi) result(v)
    real(wp), contiguous, intent(in) :: delta(:)
    integer, intent(in) :: k, ilo, ihi
    real(wp) :: x
    v = delta(k)
    x = peak_offset(delta, k, ilo, ihi)
    if (x /= 0) v = delta(k) - 0.25_wp * (delta(k - 1) - delta(k + 1)) * x
  end function refined_peak

end module rd_strip_contact
