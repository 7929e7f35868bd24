!> Gauss-Legendre nodes and weights on [-1, 1] (Newton on the three-term recurrence,
!> as NR 3rd ed. 4.6 "gauleg"), used at build time only; the results are stored.
module rd_gauss_legendre
  use rd_kinds, only: wp, pi
  implicit none
  private
  public :: gauss_legendre

contains

  !> n-point rule: int_{-1}^{1} f dx ~ sum w(i) f(x(i)), exact for degree 2n-1.
  pure subroutine gauss_legendre(n, x, w)
    integer, intent(in) :: n
    real(wp), intent(out) :: x(n), w(n)
    real(wp) :: z, z_old, p1, p2, p3, dp
    integer :: i, j, iteration
    do i = 1, (n + 1) / 2
      z = cos(pi * (i - 0.25_wp) / (n + 0.5_wp))
      do iteration = 1, 100
        p1 = 1
        p2 = 0
        do j = 1, n
          p3 = p2
          p2 = p1
          p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j
        end do
        dp = n * (z * p1 - p2) / (z * z - 1)
        z_old = z
        z = z_old - p1 / dp
        if (abs(z - z_old) <= 4 * epsilon(1.0_wp)) exit
      end do
      ! recompute the derivative at the converged node for the weight
      p1 = 1
      p2 = 0
      do j = 1, n
        p3 = p2
        p2 = p1
        p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j
      end do
      dp = n * (z * p1 - p2) / (z * z - 1)
      x(i) = -z
      x(n + 1 - i) = z
      w(i) = 2 / ((1 - z * z) * dp * dp)
      w(n + 1 - i) = w(i)
    end do
  end subroutine gauss_legendre
end module rd_gauss_legendre
