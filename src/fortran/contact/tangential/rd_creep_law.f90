!> The common interface of all creep laws (tangential contact; thesis 3.6).
!>
!> A creep law turns one contact patch (ellipse a, b, normal force, material, friction)
!> and its creepages into the creep forces and spin moment ON THE WHEEL, in contact-frame
!> components (docs/conventions.md; Kalker/CONTACT sign: Fx = -G a b C11 xi in the linear
!> range). Laws are built by `rd_creep_factory`; parameters are fixed at creation and
!> `compute` is pure and allocation-free, so it can run per patch in the right-hand side.
module rd_creep_law
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_creepage, only: creepage_t
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: creep_law_t, creep_patch_t, creep_force_t, creepage_t, creep_law_options_t
  public :: patch_is_loaded, validate_patch

  !> A contact patch as a creep law sees it: ellipse, load, material, friction, speed (one
  !> patch's path through the types: rd_contact_patch).
  type :: creep_patch_t
    real(wp) :: a = 0.0_wp               !< semi-axis along the rolling direction x_c [m]
    real(wp) :: b = 0.0_wp               !< semi-axis along the lateral direction y_c [m]
    real(wp) :: normal_force = 0.0_wp    !< N [N]
    real(wp) :: shear_modulus = 82.0e9_wp !< combined G [Pa]
    real(wp) :: poisson = 0.28_wp        !< combined nu [-]
    real(wp) :: friction = 0.3_wp        !< (static) friction coefficient mu [-]
    real(wp) :: rolling_speed = 0.0_wp   !< V_ref [m/s]; only laws with slip-velocity friction use it
  end type creep_patch_t

  !> Creep forces on the wheel, contact frame.
  type :: creep_force_t
    real(wp) :: fx = 0.0_wp  !< along x_c [N]
    real(wp) :: fy = 0.0_wp  !< along y_c [N]
    real(wp) :: mz = 0.0_wp  !< spin moment about n [N m]
  end type creep_force_t

  !> Options of all laws in one plain type (each law reads what it needs).
  type :: creep_law_options_t
    integer :: grid_nx = 20                      !< FASTSIM elements per strip
    integer :: grid_ny = 20                      !< FASTSIM strips across the ellipse
    character(len=16) :: bound = 'parabolic'     !< FASTSIM traction bound: 'parabolic' | 'elliptic'
    real(wp) :: saturation_width = 0.0_wp        !< FASTSIM: width w of the smooth clip (0 = Kalker's min)
    character(len=32) :: saturation = 'none'     !< linear: 'none' | 'shen_hedrick_elkins'
    real(wp) :: polach_ka = 1.0_wp               !< Polach 2005 reduction in the adhesion area, k_A
    real(wp) :: polach_ks = 1.0_wp               !< Polach 2005 reduction in the slip area, k_S
    real(wp) :: polach_friction_ratio = 1.0_wp   !< A = mu_inf / mu_0 (1 = no decay)
    real(wp) :: polach_friction_decay = 0.0_wp   !< B [s/m] in mu = mu0((1-A) exp(-B w) + A)
  end type creep_law_options_t

  type, abstract :: creep_law_t
  contains
    procedure(compute_interface), deferred :: compute
    procedure(name_interface), deferred :: name
  end type creep_law_t

  abstract interface
    pure subroutine compute_interface(self, patch, creep, force)
      import :: creep_law_t, creep_patch_t, creepage_t, creep_force_t
      class(creep_law_t), intent(in) :: self
      type(creep_patch_t), intent(in) :: patch
      type(creepage_t), intent(in) :: creep
      type(creep_force_t), intent(out) :: force
    end subroutine compute_interface

    pure function name_interface(self) result(name)
      import :: creep_law_t
      class(creep_law_t), intent(in) :: self
      character(len=:), allocatable :: name
    end function name_interface
  end interface

contains

  !> True when the patch carries load (a, b, N, G > 0, mu >= 0); laws return zero otherwise.
  elemental logical function patch_is_loaded(patch)
    type(creep_patch_t), intent(in) :: patch
    patch_is_loaded = patch%a > 0.0_wp .and. patch%b > 0.0_wp .and. patch%normal_force > 0.0_wp &
                      .and. patch%shear_modulus > 0.0_wp .and. patch%friction >= 0.0_wp
  end function patch_is_loaded

  !> Check user-supplied patch data (calculators, decks); one clear message on failure.
  pure subroutine validate_patch(patch, creep, error)
    type(creep_patch_t), intent(in) :: patch
    type(creepage_t), intent(in) :: creep
    type(error_t), allocatable, intent(out) :: error
    real(wp) :: v(10)
    v = [patch%a, patch%b, patch%normal_force, patch%shear_modulus, patch%poisson, patch%friction, &
         patch%rolling_speed, creep%xi, creep%eta, creep%phi]
    if (.not. all(ieee_is_finite(v))) then
      call make_error(error, RD_ERR_INPUT, 'creep law: inputs must be finite numbers')
    else if (.not. (patch%a > 0.0_wp .and. patch%b > 0.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'creep law: semi-axes a and b must be > 0 m')
    else if (patch%normal_force < 0.0_wp) then
      call make_error(error, RD_ERR_INPUT, 'creep law: normal force must be >= 0 N')
    else if (.not. (patch%shear_modulus > 0.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'creep law: shear modulus must be > 0 Pa')
    else if (.not. (patch%poisson >= 0.0_wp .and. patch%poisson <= 0.5_wp)) then
      call make_error(error, RD_ERR_INPUT, 'creep law: Poisson ratio must be in [0, 0.5]')
    else if (.not. (patch%friction >= 0.0_wp)) then
      call make_error(error, RD_ERR_INPUT, 'creep law: friction coefficient must be >= 0')
    end if
  end subroutine validate_patch
end module rd_creep_law
