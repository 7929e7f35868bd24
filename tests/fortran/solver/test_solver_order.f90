!> Convergence order of the fixed-step methods: on the harmonic oscillator (closed form
!> x = cos(w t)) the global error at T must fall by 2^p when the step is halved:
!> ratio ~16 for rk4 (p = 4), ~4 for heun (p = 2).
program test_solver_order
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_integrator, only: integrator_t, integrator_settings_t
  use rd_solver_test_problems, only: oscillator_t, report
  use rd_test_support, only: check, test_summary
  implicit none

  call order_of('rk4', 16.0_wp)
  call order_of('heun', 4.0_wp)
  call test_summary('test_solver_order')

contains

  subroutine order_of(method, expected_ratio)
    character(len=*), intent(in) :: method
    real(wp), intent(in) :: expected_ratio
    real(wp) :: err(4), ratio
    integer :: i
    real(wp), parameter :: h0 = 8.0e-3_wp

    do i = 1, size(err)
      err(i) = global_error(method, h0 / 2.0_wp**(i - 1))
    end do
    write (*, '(a)') 'oscillator w = 2 pi to T = 2 s, method ' // method
    do i = 1, size(err)
      call report('  h = ' // trim(real_text(h0 / 2.0_wp**(i - 1))) // ' s: error', err(i))
    end do
    do i = 2, size(err)
      ratio = err(i - 1) / err(i)
      call report('  error ratio on halving h', ratio)
      ! Within 6 % of 2^p: the next term of the error expansion is O(h) smaller.
      call check(abs(ratio - expected_ratio) < 0.06_wp * expected_ratio, &
                 method // ': error ratio on halving the step is not 2^order')
    end do
  end subroutine order_of

  function global_error(method, h) result(err)
    character(len=*), intent(in) :: method
    real(wp), intent(in) :: h
    real(wp) :: err
    type(oscillator_t), target :: osc
    type(integrator_t) :: integ
    type(integrator_settings_t) :: s
    type(error_t), allocatable :: error
    real(wp) :: y(2), ye(2)
    integer :: i

    s%method = method
    s%fixed_step = h
    call integ%build(osc, 0.0_wp, [1.0_wp, 0.0_wp], s, error)
    call check(.not. allocated(error), method // ' build')
    do i = 1, 10
      call integ%advance(0.2_wp * i, y, error)
      call check(.not. allocated(error), method // ' advance')
    end do
    ye = osc%exact(2.0_wp, [1.0_wp, 0.0_wp])
    err = max(abs(y(1) - ye(1)), abs(y(2) - ye(2)) / osc%omega)
    call integ%destroy()
  end function global_error

  function real_text(x) result(s)
    real(wp), intent(in) :: x
    character(len=16) :: s
    write (s, '(es9.2)') x
  end function real_text
end program test_solver_order
