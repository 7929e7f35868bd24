!> Numbers as text for messages and output names.
!>
!> Results are fixed-length (call sites trim them): gfortran 12 mishandles two
!> deferred-length function results in one expression, and messages concatenate several.
module rd_text
  use rd_kinds, only: wp, i8
  implicit none
  private
  public :: int_text, real_text

  interface int_text
    module procedure int_text_4, int_text_8
  end interface int_text

contains

  pure function int_text_4(i) result(text)
    integer, intent(in) :: i
    character(len=12) :: text
    write (text, '(i0)') i
  end function int_text_4

  pure function int_text_8(i) result(text)
    integer(i8), intent(in) :: i
    character(len=21) :: text
    write (text, '(i0)') i
  end function int_text_8

  !> Plain decimal with trailing zeros removed (0.002, 150, -0.12), or scientific for
  !> magnitudes below 1e-4 or from 1e7 on.
  pure function real_text(x) result(text)
    real(wp), intent(in) :: x
    character(len=24) :: text
    integer :: last
    if (x == 0) then
      text = '0'
    else if (abs(x) >= 1.0e-4_wp .and. abs(x) < 1.0e7_wp) then
      write (text, '(f0.6)') x
      last = len_trim(text)
      do while (text(last:last) == '0')
        text(last:last) = ' '
        last = last - 1
      end do
      if (text(last:last) == '.') text(last:last) = ' '
      if (text(1:1) == '.') then
        text = '0' // text(1:len(text) - 1)
      else if (text(1:2) == '-.') then
        text = '-0' // text(2:len(text) - 1)
      end if
    else
      write (text, '(es12.5)') x
      text = adjustl(text)
    end if
  end function real_text
end module rd_text
