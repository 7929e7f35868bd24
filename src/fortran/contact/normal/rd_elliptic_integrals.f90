!> Complete elliptic integrals of the first and second kind, K(e) and E(e), by the
!> arithmetic-geometric mean (Abramowitz & Stegun 17.6). Used by the Hertz solution
!> (oracles.md, Johnson "Contact Mechanics" 4.2) instead of the thesis' printed table.
module rd_elliptic_integrals
  use rd_kinds, only: wp, pi
  implicit none
  private
  public :: elliptic_ke

contains

  !> K(e) and E(e) for the modulus e given through its complement k' = sqrt(1 - e^2)
  !> (0 < k' <= 1). Passing k' rather than e keeps full relative accuracy for very
  !> elongated ellipses (e -> 1), where 1 - e^2 would cancel.
  !> AGM: a0 = 1, b0 = k', c0 = e; K = pi / (2 a_inf),
  !> E = K (1 - sum_{n>=0} 2^(n-1) c_n^2)   (A&S 17.6.3-17.6.4).
  !> Converges quadratically: 5-7 iterations to machine precision for k' >= 1e-12.
  pure subroutine elliptic_ke(kprime, k_first, e_second)
    real(wp), intent(in) :: kprime
    real(wp), intent(out) :: k_first, e_second
    real(wp) :: a, b, c, a_next, weight, sum_c2
    integer :: iter
    a = 1.0_wp
    b = kprime
    ! c0^2 = e^2 = 1 - k'^2 = (1 - k')(1 + k'), written to avoid cancellation
    sum_c2 = 0.5_wp * (1.0_wp - kprime) * (1.0_wp + kprime)
    weight = 0.5_wp
    do iter = 1, 40
      c = 0.5_wp * (a - b)
      a_next = 0.5_wp * (a + b)
      b = sqrt(a * b)
      a = a_next
      weight = 2.0_wp * weight
      sum_c2 = sum_c2 + weight * c * c
      if (abs(c) <= 4.0_wp * epsilon(a) * a) exit   ! a, b may stay 1 ulp apart
    end do
    k_first = pi / (2.0_wp * a)
    e_second = k_first * (1.0_wp - sum_c2)
  end subroutine elliptic_ke
end module rd_elliptic_integrals
