!> FASTSIM (Kalker 1982, "A fast algorithm for the simplified theory of rolling contact";
!> thesis 3.6.3, eqs. 3.44-3.57) with three flexibilities
!>   L1 = 8a/(3 G C11), L2 = 8a/(3 G C22), L3 = pi a sqrt(a/b) / (4 G C23)   (eq. 3.57)
!> (the thesis' eq. 3.56 spin term should read pi a^3 b phi / (4 L3); 3.57 is right).
!>
!> The ellipse is cut into ny strips along y; each strip is marched from its leading edge
!> x = +a_j (traction zero) towards the trailing edge in nx elements. Tractions ON THE
!> WHEEL grow in adhesion as dp_x = -(xi/L1 - phi y/L3) ds, dp_y = -(eta/L2 + phi x/L3) ds
!> (slip w = (xi - phi y, eta + phi x), eq. 3.45; ds the marched distance), and are
!> clipped to the traction bound mu p(x, y) where they exceed it (eqs. 3.52-3.53).
!> Half-step start: tractions are evaluated at element centres (first step ds = dx/2, the
!> x-dependent slip at the middle of each step), which makes the march exact for the
!> linear adhesion field and removes the O(1/n) error of the textbook march (oracles.md).
!> Traction bound: parabolic p = 2N/(pi a b)(1 - x^2/a^2 - y^2/b^2) (Kalker's choice,
!> default) or elliptic (Hertz) p = 3N/(2 pi a b) sqrt(1 - x^2/a^2 - y^2/b^2).
!> Spin moment Mz = sum (x p_y - y p_x) dA from the traction field. No allocation.
!>
!> Smooth clip (saturation_width w > 0; w = 0 is Kalker's sharp one): the clip |p| -> min(|p|, g)
!> of each element has a kink where the element enters slip, and the sum of those kinks makes
!> the forces piecewise smooth in the creepages, the load and the ellipse (many small kinks,
!> docs/performance.md "Contact smoothness"). With w > 0 the clip is min's C1 (Huber) blend
!> over u = |p|/g in [1 - w, 1 + w]: |p| -> g (u - (u - 1 + w)^2 / (4 w)), never above
!> min(|p|, g) and equal to it outside the band; the forces become C1. Fully sliding and fully
!> adhering elements are unchanged; in partial slip the traction is at most w/4 of the bound
!> lower.
module rd_creep_fastsim
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_creep_law, only: creep_law_t, creep_patch_t, creepage_t, creep_force_t, &
                          creep_law_options_t, patch_is_loaded
  use rd_kalker_coefficients, only: kalker_coefficients
  implicit none
  private
  public :: creep_fastsim_t, creep_fastsim_build

  integer, parameter, public :: BOUND_PARABOLIC = 1, BOUND_ELLIPTIC = 2

  type, extends(creep_law_t) :: creep_fastsim_t
    integer :: nx = 20
    integer :: ny = 20
    integer :: bound = BOUND_PARABOLIC
    real(wp) :: saturation_width = 0.0_wp
  contains
    procedure :: compute => fastsim_compute
    procedure :: name => fastsim_name
  end type creep_fastsim_t

contains

  subroutine creep_fastsim_build(options, law, error)
    type(creep_law_options_t), intent(in) :: options
    class(creep_law_t), allocatable, intent(out) :: law
    type(error_t), allocatable, intent(out) :: error
    type(creep_fastsim_t) :: fastsim
    if (options%grid_nx < 1 .or. options%grid_ny < 1 .or. options%grid_nx > 100000 &
        .or. options%grid_ny > 100000) then
      call make_error(error, RD_ERR_INPUT, 'fastsim: grid must be between 1 and 100000 elements per direction')
      return
    end if
    if (.not. (options%saturation_width >= 0.0_wp .and. options%saturation_width <= 0.5_wp)) then
      call make_error(error, RD_ERR_INPUT, 'fastsim: saturation width must be in [0, 0.5]')
      return
    end if
    fastsim%saturation_width = options%saturation_width
    fastsim%nx = options%grid_nx
    fastsim%ny = options%grid_ny
    select case (trim(adjustl(options%bound)))
    case ('parabolic', ''); fastsim%bound = BOUND_PARABOLIC
    case ('elliptic'); fastsim%bound = BOUND_ELLIPTIC
    case default
      call make_error(error, RD_ERR_INPUT, 'fastsim: traction bound "' // trim(options%bound) // &
                      '" unknown; expected ''parabolic'' or ''elliptic''')
      return
    end select
    allocate (law, source=fastsim)
  end subroutine creep_fastsim_build

  pure subroutine fastsim_compute(self, patch, creep, force)
    class(creep_fastsim_t), intent(in) :: self
    type(creep_patch_t), intent(in) :: patch
    type(creepage_t), intent(in) :: creep
    type(creep_force_t), intent(out) :: force
    ! Strips are independent: they are marched side by side in blocks of `lanes`, so the
    ! inner loop runs across strips (no loop-carried dependency, SIMD-friendly) while the
    ! scratch stays fixed-size on the stack (no allocation); the last block may be partial.
    integer, parameter :: lanes = 16
    real(wp) :: c11, c22, c23, c33, a, b, g, l1, l2, l3, p_scale, dy, inv_a2, rate_eta, rate_spin
    real(wp) :: half, step, x, rel, bound, t, scale, fx, fy, mz, w, u, blend, band_divisor
    real(wp), dimension(lanes) :: y, rel_y, aj, dx, rate_x, px, py, sx, sy, sm
    integer :: i, j, lane, first, nl
    logical :: elliptic, smooth
    if (.not. patch_is_loaded(patch)) return
    a = patch%a
    b = patch%b
    g = patch%shear_modulus
    call kalker_coefficients(a / b, patch%poisson, c11, c22, c23, c33)
    l1 = 8.0_wp * a / (3.0_wp * g * c11)
    l2 = 8.0_wp * a / (3.0_wp * g * c22)
    l3 = pi * a * sqrt(a / b) / (4.0_wp * g * c23)
    elliptic = self%bound == BOUND_ELLIPTIC
    w = self%saturation_width
    smooth = w > 0.0_wp
    band_divisor = merge(4.0_wp * w, 1.0_wp, smooth)   ! (1 where w = 0: the blend is unused)
    if (elliptic) then
      p_scale = patch%friction * 1.5_wp * patch%normal_force / (pi * a * b)
    else
      p_scale = patch%friction * 2.0_wp * patch%normal_force / (pi * a * b)
    end if
    dy = 2.0_wp * b / self%ny
    inv_a2 = 1.0_wp / (a * a)
    rate_eta = creep%eta / l2
    rate_spin = creep%phi / l3
    fx = 0.0_wp; fy = 0.0_wp; mz = 0.0_wp
    do first = 1, self%ny, lanes
      nl = min(lanes, self%ny - first + 1)
      do lane = 1, nl
        j = first + lane - 1
        y(lane) = -b + (j - 0.5_wp) * dy
        rel_y(lane) = max(0.0_wp, 1.0_wp - (y(lane) / b)**2)
        aj(lane) = a * sqrt(rel_y(lane))
        dx(lane) = 2.0_wp * aj(lane) / self%nx
        rate_x(lane) = creep%xi / l1 - rate_spin * y(lane)
      end do
      px = 0.0_wp; py = 0.0_wp; sx = 0.0_wp; sy = 0.0_wp; sm = 0.0_wp
      do i = 1, self%nx
        half = merge(0.5_wp, 1.0_wp, i == 1)     ! half-step start: first centre at dx/2
        do lane = 1, nl
          x = aj(lane) - (i - 0.5_wp) * dx(lane)
          step = half * dx(lane)
          ! adhesion increment over the step (slip evaluated at the step's middle x + step/2)
          px(lane) = px(lane) - rate_x(lane) * step
          py(lane) = py(lane) - (rate_eta + rate_spin * (x + 0.5_wp * step)) * step
          rel = max(0.0_wp, rel_y(lane) - x * x * inv_a2)
          bound = p_scale * merge(sqrt(rel), rel, elliptic)
          ! slip where |p| exceeds the bound: back onto it, direction kept (eqs. 3.52-3.53);
          ! written branch-free, so that the loop across strips vectorizes (scale = 1 in
          ! adhesion). t is floored at sqrt(tiny): where p = 0, u ~ 1e-154 / bound is below
          ! the band, as |p| / bound.
          t = sqrt(max(px(lane)**2 + py(lane)**2, tiny(1.0_wp)))
          scale = min(1.0_wp, bound / t)
          ! smooth clip: u = |p| / bound where it can be in the band (u < 1 + w <= 1.5),
          ! else at most 2 (no overflow where bound ~ 0); the blend is used in the band only
          u = t / max(bound, 0.5_wp * t)
          blend = (u - (u - 1.0_wp + w)**2 / band_divisor) / u
          scale = merge(blend, scale, smooth .and. bound > 0.0_wp .and. u > 1.0_wp - w .and. u < 1.0_wp + w)
          px(lane) = px(lane) * scale
          py(lane) = py(lane) * scale
          sx(lane) = sx(lane) + px(lane)
          sy(lane) = sy(lane) + py(lane)
          sm(lane) = sm(lane) + x * py(lane)
        end do
      end do
      ! Mz = sum (x p_y - y p_x) dA
      fx = fx + sum(sx(1:nl) * dx(1:nl))
      fy = fy + sum(sy(1:nl) * dx(1:nl))
      mz = mz + sum((sm(1:nl) - y(1:nl) * sx(1:nl)) * dx(1:nl))
    end do
    force%fx = fx * dy
    force%fy = fy * dy
    force%mz = mz * dy
  end subroutine fastsim_compute

  pure function fastsim_name(self) result(name)
    class(creep_fastsim_t), intent(in) :: self
    character(len=:), allocatable :: name
    character(len=24) :: grid
    write (grid, '(i0,"x",i0)') self%nx, self%ny
    if (self%bound == BOUND_ELLIPTIC) then
      name = 'fastsim ' // trim(grid) // ' elliptic bound'
    else
      name = 'fastsim ' // trim(grid) // ' parabolic bound'
    end if
    if (self%saturation_width > 0.0_wp) then
      write (grid, '(f0.3)') self%saturation_width
      name = name // ', smooth clip w = ' // trim(grid)
    end if
  end function fastsim_name
end module rd_creep_fastsim
