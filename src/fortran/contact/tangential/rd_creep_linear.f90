!> Kalker's linear theory (thesis eqs. 3.39-3.43, with the thesis' typos corrected:
!> f22 uses C33, and the matrix of eq. 3.43 gives Mz = +G (ab)^1.5 C23 eta - G (ab)^2 C33 phi):
!>   Fx = -G a b C11 xi
!>   Fy = -G a b C22 eta - G (ab)^1.5 C23 phi
!>   Mz =  G (ab)^1.5 C23 eta - G (ab)^2 C33 phi
!> optionally saturated after Shen, Hedrick & Elkins (1983): the tangential resultant is
!> scaled by f(u) = 1 - u/3 + u^2/27 for u <= 3 and 1/u beyond, u = |F_lin| / (mu N), so
!> |F| -> mu N; the spin moment is scaled by the same factor (a common, documented choice).
module rd_creep_linear
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_creep_law, only: creep_law_t, creep_patch_t, creepage_t, creep_force_t, &
                          creep_law_options_t, patch_is_loaded
  use rd_kalker_coefficients, only: kalker_coefficients
  implicit none
  private
  public :: creep_linear_t, creep_linear_build, linear_creep_forces, shen_hedrick_elkins_factor

  integer, parameter, public :: SATURATION_NONE = 0, SATURATION_SHE = 1

  type, extends(creep_law_t) :: creep_linear_t
    integer :: saturation = SATURATION_NONE
  contains
    procedure :: compute => linear_compute
    procedure :: name => linear_name
  end type creep_linear_t

contains

  subroutine creep_linear_build(options, law, error)
    type(creep_law_options_t), intent(in) :: options
    class(creep_law_t), allocatable, intent(out) :: law
    type(error_t), allocatable, intent(out) :: error
    type(creep_linear_t) :: linear
    select case (trim(adjustl(options%saturation)))
    case ('none', ''); linear%saturation = SATURATION_NONE
    case ('shen_hedrick_elkins'); linear%saturation = SATURATION_SHE
    case default
      call make_error(error, RD_ERR_INPUT, 'linear creep law: saturation "' // trim(options%saturation) // &
                      '" unknown; expected ''none'' or ''shen_hedrick_elkins''')
      return
    end select
    allocate (law, source=linear)
  end subroutine creep_linear_build

  pure subroutine linear_compute(self, patch, creep, force)
    class(creep_linear_t), intent(in) :: self
    type(creep_patch_t), intent(in) :: patch
    type(creepage_t), intent(in) :: creep
    type(creep_force_t), intent(out) :: force
    real(wp) :: f, limit
    if (.not. patch_is_loaded(patch)) return
    call linear_creep_forces(patch, creep, force)
    if (self%saturation == SATURATION_SHE) then
      limit = patch%friction * patch%normal_force
      f = shen_hedrick_elkins_factor(hypot(force%fx, force%fy), limit)
      force%fx = f * force%fx
      force%fy = f * force%fy
      force%mz = f * force%mz
    end if
  end subroutine linear_compute

  !> The unsaturated linear forces (also used by FASTSIM's and Polach's references).
  pure subroutine linear_creep_forces(patch, creep, force)
    type(creep_patch_t), intent(in) :: patch
    type(creepage_t), intent(in) :: creep
    type(creep_force_t), intent(out) :: force
    real(wp) :: c11, c22, c23, c33, gab, sqrt_ab
    call kalker_coefficients(patch%a / patch%b, patch%poisson, c11, c22, c23, c33)
    gab = patch%shear_modulus * patch%a * patch%b
    sqrt_ab = sqrt(patch%a * patch%b)
    force%fx = -gab * c11 * creep%xi
    force%fy = -gab * (c22 * creep%eta + sqrt_ab * c23 * creep%phi)
    force%mz = gab * sqrt_ab * (c23 * creep%eta - sqrt_ab * c33 * creep%phi)
  end subroutine linear_creep_forces

  !> Shen-Hedrick-Elkins scale factor F'/F for a linear resultant f_lin and limit mu N.
  elemental function shen_hedrick_elkins_factor(f_lin, limit) result(factor)
    real(wp), intent(in) :: f_lin, limit
    real(wp) :: factor, u
    if (limit <= 0.0_wp) then
      factor = 0.0_wp
      return
    end if
    u = f_lin / limit
    if (u <= 3.0_wp) then
      factor = 1.0_wp - u / 3.0_wp + u * u / 27.0_wp
    else
      factor = 1.0_wp / u
    end if
  end function shen_hedrick_elkins_factor

  pure function linear_name(self) result(name)
    class(creep_linear_t), intent(in) :: self
    character(len=:), allocatable :: name
    if (self%saturation == SATURATION_SHE) then
      name = 'linear (Shen-Hedrick-Elkins saturation)'
    else
      name = 'linear'
    end if
  end function linear_name
end module rd_creep_linear
