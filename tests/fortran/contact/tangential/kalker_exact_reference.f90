!> Test oracle: Kalker's exact theory of steady rolling contact on a Hertzian ellipse
!> (Kalker 1990, "Three-dimensional elastic bodies in rolling contact", ch. 2-5; the
!> method of CONTACT), written independently of the creep laws under test so that they
!> can be judged where no published table exists (elongated flange patches, large spin).
!>
!> Model: two quasi-identical elastic half-spaces (wheel and rail of one material, so
!> the normal and tangential problems decouple), Hertzian pressure p_n on the ellipse,
!> piecewise-constant tractions p (ON THE WHEEL) on a regular nx x ny grid.
!> - Relative surface displacement u = sum_J K(I - J) p_J with the Cerruti kernel of
!>   the combined bodies (Johnson 1985, eq. 3.86a, doubled for two half-spaces):
!>   u_x = 1/(pi G) [((1-nu)/r + nu x^2/r^3) p_x + nu x y/r^3 p_y], u_y likewise; the
!>   element integrals are closed forms (int int 1/r = X asinh(Y/|X|) + Y asinh(X/|Y|),
!>   int int x^2/r^3 = Y asinh(X/|Y|), int int y^2/r^3 = X asinh(Y/|X|), int int xy/r^3 = -r).
!> - Steady rolling, material entering at x = +a: slip s = w - du/dx with the rigid slip
!>   w = (xi - phi y, eta + phi x) (the conventions of docs/conventions.md and eq. 3.45);
!>   du/dx is the upwind difference (u(x + dx) - u(x))/dx, as in CONTACT.
!> - Coulomb: |p| <= mu p_n; stick where s = 0, slip where p = -mu p_n s/|s|.
!> Solved as the projection equation p = Proj_{|p| <= mu p_n}(p - r s(p)) (equivalent to
!> the stick and slip conditions for any r > 0; stick: s = 0, slip: p on the bound and
!> opposite to s) by semismooth Newton steps with a dense Jacobian (LAPACK dgesv) and
!> residual-halving damping. Checked in test_creep_spin_exact against CONTACT's exact
!> rows of oracles.md before it is used as a reference.
module kalker_exact_reference
  use rd_kinds, only: wp, pi
  implicit none
  private
  public :: kalker_exact_forces, scene_patch_count, scene_name, scene, scene_grid, scene_is_flange

  !> Contact patches of the TGV profile scenes (inputs/tgv_profile_fastsim.nml and
  !> tgv_profile_polach.nml, window means t = 15-18 s of wheelsets/w1/<side>/patch1 in the runs
  !> of 2026-11-21; G = 84 GPa, nu = 0.25, mu = 0.45): a, b [m], N [N], xi, eta, phi [1/m], and
  !> the grid (nx, ny) of the exact solution. Shared by the tests that judge laws on them.
  integer, parameter :: scene_patch_count = 4
  character(len=*), parameter :: scene_name(scene_patch_count) = [character(len=24) :: &
    'flange, Polach run', 'flange, FASTSIM run', 'tread, Polach run', 'tread, FASTSIM run']
  real(wp), parameter :: scene(6, scene_patch_count) = reshape([ &
    8.16e-3_wp, 2.22e-3_wp, 70976.0_wp, -6.80e-3_wp, 2.36e-3_wp, 0.990_wp, &
    8.40e-3_wp, 1.73e-3_wp, 70110.0_wp, -4.88e-3_wp, 2.06e-3_wp, 0.839_wp, &
    6.11e-3_wp, 4.61e-3_wp, 61809.0_wp, 2.61e-3_wp, 2.10e-3_wp, -0.020_wp, &
    6.10e-3_wp, 4.70e-3_wp, 62452.0_wp, 3.36e-3_wp, 1.90e-3_wp, -0.020_wp], [6, scene_patch_count])
  integer, parameter :: scene_grid(2, scene_patch_count) = reshape([40, 10, 40, 10, 20, 20, 20, 20], &
                                                                   [2, scene_patch_count])
  logical, parameter :: scene_is_flange(scene_patch_count) = [.true., .true., .false., .false.]

contains

  !> Forces (fx, fy) [N] and spin moment mz [N m] on the wheel, contact frame.
  subroutine kalker_exact_forces(a, b, normal_force, shear_modulus, poisson, friction, xi, eta, phi, &
                                 nx, ny, fx, fy, mz, sweeps)
    real(wp), intent(in) :: a, b, normal_force, shear_modulus, poisson, friction, xi, eta, phi
    integer, intent(in) :: nx, ny
    real(wp), intent(out) :: fx, fy, mz
    integer, intent(out), optional :: sweeps
    real(wp) :: dx, dy, kxx(-nx - 1:nx, -ny:ny), kyy(-nx - 1:nx, -ny:ny), kxy(-nx - 1:nx, -ny:ny)
    real(wp) :: xc(0:nx), yc(ny), bound(nx, ny), area, rel, sum_pn
    logical :: inside(nx, ny)
    integer :: ie(nx * ny), je(nx * ny), n, m, k, l, info, sweep
    real(wp), allocatable :: jac(:, :), sys(:, :), p(:), g(:), w(:, :), s(:), res(:), res_try(:), step(:), p_try(:)
    integer, allocatable :: pivot(:)
    real(wp) :: r, z(2), zn, proj(2, 2), res_norm, try_norm, lambda
    integer :: i, j, di, dj

    dx = 2.0_wp * a / nx
    dy = 2.0_wp * b / ny
    area = dx * dy
    do i = 0, nx
      xc(i) = a - (i - 0.5_wp) * dx     ! i = 0: the upwind point just outside the leading edge
    end do
    do j = 1, ny
      yc(j) = -b + (j - 0.5_wp) * dy
    end do
    ! kernel by offset (di, dj) = (i_obs - i_src, j_obs - j_src); x decreases with i
    do dj = -ny, ny
      do di = -nx - 1, nx
        call element_kernel(-di * dx, dj * dy, 0.5_wp * dx, 0.5_wp * dy, shear_modulus, poisson, &
                            kxx(di, dj), kyy(di, dj), kxy(di, dj))
      end do
    end do
    ! Hertz pressure at element centres, rescaled so that the elements carry exactly N
    sum_pn = 0.0_wp
    n = 0
    do j = 1, ny
      do i = 1, nx
        rel = 1.0_wp - (xc(i) / a)**2 - (yc(j) / b)**2
        inside(i, j) = rel > 0.0_wp
        bound(i, j) = merge(sqrt(max(rel, 0.0_wp)), 0.0_wp, inside(i, j))
        sum_pn = sum_pn + bound(i, j) * area
        if (inside(i, j)) then
          n = n + 1
          ie(n) = i; je(n) = j
        end if
      end do
    end do
    bound = friction * normal_force / sum_pn * bound
    m = 2 * n
    allocate (jac(m, m), sys(m, m), p(m), g(n), w(2, n), s(m), res(m), res_try(m), step(m), p_try(m), pivot(m))
    ! d s_k / d p_l = (K(k - l) - K(up(k) - l)) / dx, up(k) the element upwind of k
    do l = 1, n
      do k = 1, n
        di = ie(k) - ie(l); dj = je(k) - je(l)
        jac(2 * k - 1, 2 * l - 1) = (kxx(di, dj) - kxx(di - 1, dj)) / dx
        jac(2 * k, 2 * l) = (kyy(di, dj) - kyy(di - 1, dj)) / dx
        jac(2 * k - 1, 2 * l) = (kxy(di, dj) - kxy(di - 1, dj)) / dx
        jac(2 * k, 2 * l - 1) = jac(2 * k - 1, 2 * l)
      end do
      g(l) = bound(ie(l), je(l))
      w(:, l) = [xi - phi * yc(je(l)), eta + phi * xc(ie(l))]
    end do
    r = 1.0_wp / jac(1, 1)
    p = 0.0_wp
    s = reshape(w, [m])
    call residual(p, res, res_norm)
    do sweep = 1, 200
      if (res_norm <= 1.0e-12_wp * maxval(g)) exit
      ! Jacobian of F(p) = p - Proj(p - r s(p)): stick rows r J; slip rows (I - P) + r P J
      ! with P = g/|z| (I - z z^T/|z|^2), z = p - r s
      do k = 1, n
        z = p(2 * k - 1:2 * k) - r * s(2 * k - 1:2 * k)
        zn = hypot(z(1), z(2))
        if (zn <= g(k)) then
          sys(2 * k - 1:2 * k, :) = r * jac(2 * k - 1:2 * k, :)
        else
          proj(1, 1) = 1.0_wp - z(1)**2 / zn**2
          proj(2, 2) = 1.0_wp - z(2)**2 / zn**2
          proj(1, 2) = -z(1) * z(2) / zn**2
          proj(2, 1) = proj(1, 2)
          proj = g(k) / zn * proj
          sys(2 * k - 1:2 * k, :) = r * matmul(proj, jac(2 * k - 1:2 * k, :))
          sys(2 * k - 1:2 * k, 2 * k - 1:2 * k) = sys(2 * k - 1:2 * k, 2 * k - 1:2 * k) &
                                                   + reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2]) - proj
        end if
      end do
      step = -res
      call dgesv(m, 1, sys, m, pivot, step, m, info)
      if (info /= 0) error stop 'kalker_exact_forces: singular Newton system'
      lambda = 1.0_wp
      do l = 1, 30
        p_try = p + lambda * step
        call residual(p_try, res_try, try_norm)
        if (try_norm < res_norm) exit
        lambda = 0.5_wp * lambda
      end do
      p = p_try
      res = res_try
      res_norm = try_norm
      s = matmul(jac, p)
      do k = 1, n
        s(2 * k - 1:2 * k) = s(2 * k - 1:2 * k) + w(:, k)
      end do
    end do
    fx = 0.0_wp; fy = 0.0_wp; mz = 0.0_wp
    do k = 1, n
      fx = fx + p(2 * k - 1) * area
      fy = fy + p(2 * k) * area
      mz = mz + (xc(ie(k)) * p(2 * k) - yc(je(k)) * p(2 * k - 1)) * area
    end do
    if (present(sweeps)) sweeps = sweep
  contains
    !> F(p) = p - Proj(p - r s(p)) per element, and its largest component
    subroutine residual(pv, f, f_norm)
      real(wp), intent(in) :: pv(:)
      real(wp), intent(out) :: f(:), f_norm
      real(wp) :: sv(size(pv)), zv(2), znv
      integer :: kk
      sv = matmul(jac, pv)
      do kk = 1, n
        sv(2 * kk - 1:2 * kk) = sv(2 * kk - 1:2 * kk) + w(:, kk)
        zv = pv(2 * kk - 1:2 * kk) - r * sv(2 * kk - 1:2 * kk)
        znv = hypot(zv(1), zv(2))
        if (znv > g(kk)) zv = g(kk) / znv * zv
        f(2 * kk - 1:2 * kk) = pv(2 * kk - 1:2 * kk) - zv
      end do
      f_norm = maxval(abs(f))
    end subroutine residual
  end subroutine kalker_exact_forces

  !> Combined-body displacement per unit traction of a rectangle of half-widths hx, hy
  !> whose centre lies at (-xc, -yc) from the observation point.
  pure subroutine element_kernel(xc, yc, hx, hy, g, nu, kxx, kyy, kxy)
    real(wp), intent(in) :: xc, yc, hx, hy, g, nu
    real(wp), intent(out) :: kxx, kyy, kxy
    real(wp) :: i1, ixx, iyy, ixy, x, y, sgn
    integer :: cx, cy
    i1 = 0.0_wp; ixx = 0.0_wp; iyy = 0.0_wp; ixy = 0.0_wp
    do cx = -1, 1, 2
      do cy = -1, 1, 2
        x = xc + cx * hx
        y = yc + cy * hy
        sgn = real(cx * cy, wp)
        i1 = i1 + sgn * (xa(x, y) + xa(y, x))
        ixx = ixx + sgn * xa(y, x)
        iyy = iyy + sgn * xa(x, y)
        ixy = ixy - sgn * hypot(x, y)
      end do
    end do
    kxx = ((1.0_wp - nu) * i1 + nu * ixx) / (pi * g)
    kyy = ((1.0_wp - nu) * i1 + nu * iyy) / (pi * g)
    kxy = nu * ixy / (pi * g)
  contains
    !> x asinh(y/|x|), continuous through x = 0 (limit 0)
    pure real(wp) function xa(p, q)
      real(wp), intent(in) :: p, q
      if (p == 0.0_wp) then
        xa = 0.0_wp
      else
        xa = p * asinh(q / abs(p))
      end if
    end function xa
  end subroutine element_kernel
end module kalker_exact_reference
