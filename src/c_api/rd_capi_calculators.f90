!> C-callable contact mechanics calculators (src/c_api/raildyn_calculators.h): a Hertz
!> patch and the creep forces of one patch. Stateless; status 0 ok, 1 bad input (also a
!> NULL pointer argument: pointers are taken as C pointers and checked before use).
module rd_capi_calculators
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_null_char, c_ptr, &
                                         c_associated, c_f_pointer
  use rd_kinds, only: wp
  use rd_error, only: error_t, RD_OK, RD_ERR_INPUT
  use rd_hertz, only: hertz_params_t, hertz_patch_t, build_hertz, hertz_from_force, hertz_from_penetration
  use rd_creep_law, only: creep_law_t, creep_patch_t, creepage_t, creep_force_t, creep_law_options_t, &
                          validate_patch
  use rd_creep_factory, only: build_creep_law
  implicit none
  private
  public :: rd_hertz_patch, rd_creep_forces

  integer, parameter :: max_name = 64

contains

  !> All pointer arguments given (not NULL).
  logical function all_given(pointers)
    type(c_ptr), intent(in) :: pointers(:)
    integer :: i
    all_given = .true.
    do i = 1, size(pointers)
      if (.not. c_associated(pointers(i))) all_given = .false.
    end do
  end function all_given

  !> Store a result through a checked C pointer.
  subroutine put(pointer, value)
    type(c_ptr), intent(in) :: pointer
    real(c_double), intent(in) :: value
    real(c_double), pointer :: target_value
    call c_f_pointer(pointer, target_value)
    target_value = value
  end subroutine put

  function rd_hertz_patch(curvatures_c, young_modulus, poisson_ratio, load_kind, load, a, b, normal_force, &
                          approach, p0, stiffness, warning_c) result(status) bind(C, name='rd_hertz_patch')
    type(c_ptr), value :: curvatures_c, a, b, normal_force, approach, p0, stiffness, warning_c
    real(c_double), value :: young_modulus, poisson_ratio, load
    integer(c_int), value :: load_kind
    integer(c_int) :: status
    real(c_double), pointer :: curvatures(:)
    integer(c_int), pointer :: warning
    type(hertz_params_t) :: params
    type(hertz_patch_t) :: patch
    type(error_t), allocatable :: error
    status = RD_ERR_INPUT
    if (.not. all_given([curvatures_c, a, b, normal_force, approach, p0, stiffness, warning_c])) return
    call c_f_pointer(curvatures_c, curvatures, [4])
    call c_f_pointer(warning_c, warning)
    if (load_kind /= 0 .and. load_kind /= 1) return
    call build_hertz(params, error, young_wheel=real(young_modulus, wp), poisson_wheel=real(poisson_ratio, wp))
    if (allocated(error)) return
    if (load_kind == 0) then
      call hertz_from_force(params, real(curvatures, wp), real(load, wp), patch)
    else
      call hertz_from_penetration(params, real(curvatures, wp), real(load, wp), patch)
    end if
    if (iand(patch%warning, 8) /= 0) return     ! HERTZ_WARN_BAD_INPUT: NaN/Inf given
    call put(a, patch%a)
    call put(b, patch%b)
    call put(normal_force, patch%normal_force)
    call put(approach, patch%approach)
    call put(p0, patch%p0)
    call put(stiffness, patch%stiffness)
    warning = patch%warning
    status = RD_OK
  end function rd_hertz_patch

  function rd_creep_forces(law_c, a, b, normal_force, g, nu, mu, xi, eta, phi, grid, fx, fy, mz) &
      result(status) bind(C, name='rd_creep_forces')
    type(c_ptr), value :: law_c, fx, fy, mz
    real(c_double), value :: a, b, normal_force, g, nu, mu, xi, eta, phi
    integer(c_int), value :: grid
    integer(c_int) :: status
    character(kind=c_char), pointer :: law(:)
    character(len=max_name) :: name
    type(creep_patch_t) :: patch
    type(creepage_t) :: creep
    type(creep_force_t) :: force
    type(creep_law_options_t) :: options
    class(creep_law_t), allocatable :: creep_law
    type(error_t), allocatable :: error
    integer :: i
    status = RD_ERR_INPUT
    if (.not. all_given([law_c, fx, fy, mz])) return
    call c_f_pointer(law_c, law, [max_name])     ! read up to its NUL, at most max_name bytes
    name = ''
    do i = 1, max_name
      if (law(i) == c_null_char) exit
      name(i:i) = law(i)
    end do
    if (i > max_name) return                  ! not a terminated short name
    patch = creep_patch_t(a=a, b=b, normal_force=normal_force, shear_modulus=g, poisson=nu, friction=mu)
    creep%xi = xi; creep%eta = eta; creep%phi = phi
    call validate_patch(patch, creep, error)
    if (allocated(error)) return
    if (grid > 0) then
      options%grid_nx = grid; options%grid_ny = grid
    end if
    call build_creep_law(name, options, creep_law, error)
    if (allocated(error)) return
    call creep_law%compute(patch, creep, force)
    call put(fx, force%fx)
    call put(fy, force%fy)
    call put(mz, force%mz)
    status = RD_OK
  end function rd_creep_forces
end module rd_capi_calculators
