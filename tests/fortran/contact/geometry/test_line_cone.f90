!> Line-cone intersection (thesis 4.66-4.71 in quadratic form) and the deepest point of a
!> line inside a cone segment, against brute-force sampling of the cone along the line.
program test_line_cone
  use rd_kinds, only: wp
  use rd_line_cone, only: line_cone_roots, line_cone_max_depth
  use rd_test_support, only: check, fail, test_summary
  implicit none
  integer, parameter :: ncase = 300, nsample = 200001
  real(wp) :: p0(3), d(3), y1, y2, r1, r2, t(2), alpha(2), tb(2), err_root, err_depth, err_alpha
  real(wp) :: psi, phi, f0, f1, ta, tc, tm, t0, rho, py0, a, depth, tau, bdepth, tt, py, r
  integer :: icase, nroot, nb, i, it, nfound, nroots_total
  logical :: found
  real(wp) :: u(8)
  err_root = 0; err_depth = 0; err_alpha = 0; nroots_total = 0; nfound = 0
  call random_seed(put=[(12345 + i, i=1, 64)])
  do icase = 1, ncase
    call random_number(u)
    psi = (u(1) - 0.5_wp) * 0.1_wp              ! yaw up to +-50 mrad
    phi = (u(2) - 0.5_wp) * 0.02_wp
    d = [cos(psi), -sin(psi) * cos(phi), sin(psi) * sin(phi)]
    y1 = 0.70_wp + 0.1_wp * u(3)
    y2 = y1 + 1.0e-4_wp + 0.004_wp * u(4)
    r1 = 0.46_wp + 0.01_wp * (u(5) - 0.5_wp)
    r2 = r1 + (y2 - y1) * 3 * (u(6) - 0.5_wp)   ! slopes from -1.5 (flange) to +1.5
    ! the line passes under the axle at a depth that may or may not cut the cone
    p0 = [0.0_wp, 0.5_wp * (y1 + y2) + 0.01_wp * (u(7) - 0.5_wp), -(0.5_wp * (r1 + r2) - 2.0e-4_wp + 4.0e-4_wp * u(8))]
    call line_cone_roots(p0, d, y1, r1, y2, r2, nroot, t, alpha)
    ! brute force: sign changes of rho(t) - r_lin(p_y(t)) along the line
    nb = 0
    f0 = g(-0.4_wp)
    do i = 1, nsample - 1
      tc = -0.4_wp + 0.8_wp * i / (nsample - 1)
      f1 = g(tc)
      if (f0 * f1 < 0 .and. nb < 2) then
        ta = tc - 0.8_wp / (nsample - 1)
        do it = 1, 60
          tm = 0.5_wp * (ta + tc)
          if (g(ta) * g(tm) <= 0) then
            tc = tm
          else
            ta = tm
          end if
        end do
        nb = nb + 1
        tb(nb) = 0.5_wp * (ta + tc)
        tc = -0.4_wp + 0.8_wp * i / (nsample - 1)
      end if
      f0 = f1
    end do
    if (nb /= nroot) then
      write (*, '(a,i0,a,i0,a,i0)') 'case ', icase, ': roots ', nroot, ' brute force ', nb
      call fail()
      cycle
    end if
    nroots_total = nroots_total + nroot
    do i = 1, nroot
      err_root = max(err_root, abs(t(i) - tb(i)))
      err_alpha = max(err_alpha, abs(alpha(i) - (p0(2) + t(i) * d(2) - y1) / (y2 - y1)))
    end do
    ! deepest point inside the segment: brute force over the part of the line over the segment
    a = hypot(d(1), d(3))
    t0 = -(p0(1) * d(1) + p0(3) * d(3)) / a**2
    rho = hypot(p0(1) + t0 * d(1), p0(3) + t0 * d(3))
    py0 = p0(2) + t0 * d(2)
    call line_cone_max_depth(t0, rho, py0, a, d(2), y1, r1, y2, r2, found, depth, tau)
    bdepth = -huge(1.0_wp)
    ! sample the part of the line over the segment (p_y in [y1, y2]), within 0.5 m of t0
    ta = t0 - 0.5_wp; tc = t0 + 0.5_wp
    if (d(2) /= 0) then
      ta = max(ta, min((y1 - p0(2)) / d(2), (y2 - p0(2)) / d(2)))
      tc = min(tc, max((y1 - p0(2)) / d(2), (y2 - p0(2)) / d(2)))
    end if
    do i = 0, nsample - 1
      tt = ta + (tc - ta) * i / (nsample - 1)
      py = p0(2) + tt * d(2)
      if (py < y1 - 1e-15_wp .or. py > y2 + 1e-15_wp .or. tc < ta) cycle
      r = r1 + (r2 - r1) * (py - y1) / (y2 - y1)
      bdepth = max(bdepth, r - hypot(p0(1) + tt * d(1), p0(3) + tt * d(3)))
    end do
    if (bdepth > -huge(1.0_wp)) then
      nfound = nfound + 1
      if (.not. found) call fail()
      err_depth = max(err_depth, abs(depth - bdepth))
    end if
  end do
  write (*, '(a,i0,a,es10.3,a,es10.3,a,i0,a,es10.3)') 'roots: ', nroots_total, ' max |t - brute| ', err_root, &
    ' m, alpha ', err_alpha, '; depth cases ', nfound, ', max |depth - brute| ', err_depth
  call check(nroots_total > 100, 'enough intersecting cases exercised')
  call check(err_root < 1e-9_wp, 'line-cone roots equal the brute-force crossings')
  call check(err_alpha < 1e-12_wp, 'alpha locates the root on the segment')
  call check(nfound > 100 .and. err_depth < 1e-9_wp, 'deepest point equals brute-force sampling (1e-9 m)')
  call test_summary('test_line_cone')
contains
  real(wp) function g(tq)
    real(wp), intent(in) :: tq
    real(wp) :: pyq
    pyq = p0(2) + tq * d(2)
    g = hypot(p0(1) + tq * d(1), p0(3) + tq * d(3)) - (r1 + (r2 - r1) * (pyq - y1) / (y2 - y1))
  end function g
end program test_line_cone
