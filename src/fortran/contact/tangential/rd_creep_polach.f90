!> Polach's creep force model (Polach 1999, "A fast wheel-rail forces calculation computer
!> code", VSD Suppl. 33; Polach 2000, Wear 241; thesis 3.6.4, eqs. 3.58-3.72) with the
!> 2005 extension for large creepage (Polach 2005, Wear 258: k_A, k_S and a friction
!> coefficient falling with the slip velocity). Corrections to the thesis:
!> - eq. 3.61 must read F = 2 mu N/pi (eps/(1 + eps^2) + atan(eps)) (the thesis drops the
!>   square: with eps/(1+eps) the force would tend to (1 + 2/pi) mu N);
!> - eq. 3.70 must read C = 3G/(8a) sqrt((C11 xi/s)^2 + (C22 eta/s)^2) (square lost);
!> - eq. 3.72 forces are in Polach's sign (same sign as the creepage); forces ON THE WHEEL
!>   are their negatives (Kalker/CONTACT convention, docs/conventions.md).
!> With spin, s_C = sqrt(xi^2 + eta_C^2) with eta_C = eta + phi a when that increases
!> |eta| (eq. 3.65) sets the magnitude (eps) and the split Fx = F xi/s_C, Fy = F eta/s_C;
!> the weights of C stay those of the translational creepage s = sqrt(xi^2 + eta^2)
!> (eq. 3.70 with the translational creepage of eq. 3.63): only then is Fx = -G a b C11 xi
!> in the linear range whatever the spin (weighting with eta_C/s_C, as done here before,
!> mixed C22 into Fx).
!> Known limitation of the published model (docs/theory_contact_mechanics.md): on an
!> elongated, spinning flange patch the split by s_C (phi a dominating eta) rotates the
!> force towards y_c; against Kalker's exact theory the resultant stays within a few %,
!> but Fx is about 30 % low and Fy 15-40 % high (test_creep_spin_exact).
!> Polach gives no spin moment: Mz here is the linear Mz (C23, C33) scaled by the ratio of
!> the Polach resultant to the linear resultant (saturation of the tangential force), and
!> the unscaled linear Mz when there is no translational force. Say so when comparing.
module rd_creep_polach
  use rd_kinds, only: wp, pi
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_creep_law, only: creep_law_t, creep_patch_t, creepage_t, creep_force_t, &
                          creep_law_options_t, patch_is_loaded
  use rd_kalker_coefficients, only: kalker_coefficients
  implicit none
  private
  public :: creep_polach_t, creep_polach_build

  type, extends(creep_law_t) :: creep_polach_t
    real(wp) :: k_a = 1.0_wp              !< reduction of the slope in the adhesion area
    real(wp) :: k_s = 1.0_wp              !< reduction in the slip area
    real(wp) :: friction_ratio = 1.0_wp   !< A = mu_inf / mu_0
    real(wp) :: friction_decay = 0.0_wp   !< B [s/m]
  contains
    procedure :: compute => polach_compute
    procedure :: name => polach_name
  end type creep_polach_t

contains

  subroutine creep_polach_build(options, law, error)
    type(creep_law_options_t), intent(in) :: options
    class(creep_law_t), allocatable, intent(out) :: law
    type(error_t), allocatable, intent(out) :: error
    type(creep_polach_t) :: polach
    if (.not. (options%polach_ka > 0.0_wp .and. options%polach_ka <= 1.0_wp .and. &
               options%polach_ks > 0.0_wp .and. options%polach_ks <= 1.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'polach: reduction factors k_A, k_S must be in (0, 1]')
      return
    end if
    if (.not. (options%polach_friction_ratio > 0.0_wp .and. options%polach_friction_ratio <= 1.0_wp &
               .and. options%polach_friction_decay >= 0.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'polach: friction ratio A must be in (0, 1] and decay B >= 0 s/m')
      return
    end if
    polach%k_a = options%polach_ka
    polach%k_s = options%polach_ks
    polach%friction_ratio = options%polach_friction_ratio
    polach%friction_decay = options%polach_friction_decay
    allocate (law, source=polach)
  end subroutine creep_polach_build

  pure subroutine polach_compute(self, patch, creep, force)
    class(creep_polach_t), intent(in) :: self
    type(creep_patch_t), intent(in) :: patch
    type(creepage_t), intent(in) :: creep
    type(creep_force_t), intent(out) :: force
    type(creep_force_t) :: linear
    real(wp) :: c11, c22, c23, c33, a, b, g, n, mu, eta_c, s_c, s_t, c_jj, eps, f, k_spin, eps_s, delta, k_m, &
                f_ys, f_lin, f_pol
    if (.not. patch_is_loaded(patch)) return
    a = patch%a
    b = patch%b
    g = patch%shear_modulus
    n = patch%normal_force
    call kalker_coefficients(a / b, patch%poisson, c11, c22, c23, c33)

    eta_c = creep%eta
    if (abs(creep%eta + creep%phi * a) > abs(creep%eta)) eta_c = creep%eta + creep%phi * a   ! eq. 3.65
    s_c = hypot(creep%xi, eta_c)                                                             ! eq. 3.64
    if (s_c <= 0.0_wp) return       ! xi = eta = phi = 0
    ! friction falling with the slip velocity w = V s_C (Polach 2005, eq. 14)
    mu = patch%friction * ((1.0_wp - self%friction_ratio) * exp(-self%friction_decay * patch%rolling_speed * s_c) &
                           + self%friction_ratio)
    if (mu * n <= 0.0_wp) return

    ! gradient of the tangential stress, eps = (2/3) C pi a^2 b s_C / (mu N), C from eq. 3.70
    ! corrected, weighted by the translational creepage s (pure spin: s = 0 and xi = eta = 0,
    ! so F is not used: C = 0 as in Polach's code)
    s_t = hypot(creep%xi, creep%eta)
    c_jj = 0.0_wp
    if (s_t > 0.0_wp) c_jj = hypot(c11 * creep%xi / s_t, c22 * creep%eta / s_t)
    eps = 0.25_wp * g * pi * a * b * c_jj * s_c / (mu * n)
    f = 2.0_wp * mu * n / pi * (self%k_a * eps / (1.0_wp + (self%k_a * eps)**2) + atan(self%k_s * eps))

    ! spin: lateral force F_yS (eqs. 3.66-3.69)
    k_spin = 1.0_wp + 6.3_wp * (1.0_wp - exp(-a / b))
    eps_s = 8.0_wp / 3.0_wp * g * b * sqrt(a * b) * c23 * eta_c / (mu * n * k_spin)
    delta = (eps_s**2 - 1.0_wp) / (eps_s**2 + 1.0_wp)
    k_m = abs(eps_s) * (delta**3 / 3.0_wp - delta**2 / 2.0_wp + 1.0_wp / 6.0_wp) &
          - sqrt((1.0_wp - delta**2)**3) / 3.0_wp
    f_ys = -9.0_wp / 16.0_wp * a * mu * n * k_m * k_spin

    ! eq. 3.72 in Polach's sign, negated: forces on the wheel
    force%fx = -f * creep%xi / s_c
    force%fy = -(f * creep%eta / s_c + f_ys * creep%phi / s_c)

    ! linear forces (thesis eq. 3.43 corrected, as rd_creep_linear) for the Mz scaling
    linear%fx = -g * a * b * c11 * creep%xi
    linear%fy = -g * a * b * (c22 * creep%eta + sqrt(a * b) * c23 * creep%phi)
    linear%mz = g * (a * b)**1.5_wp * (c23 * creep%eta - sqrt(a * b) * c33 * creep%phi)
    f_lin = hypot(linear%fx, linear%fy)
    f_pol = hypot(force%fx, force%fy)
    if (f_lin > 0.0_wp) then
      force%mz = linear%mz * (f_pol / f_lin)
    else
      force%mz = linear%mz
    end if
  end subroutine polach_compute

  pure function polach_name(self) result(name)
    class(creep_polach_t), intent(in) :: self
    character(len=:), allocatable :: name
    if (self%k_a < 1.0_wp .or. self%k_s < 1.0_wp .or. self%friction_ratio < 1.0_wp) then
      name = 'polach (2005 extension)'
    else
      name = 'polach'
    end if
  end function polach_name
end module rd_creep_polach
