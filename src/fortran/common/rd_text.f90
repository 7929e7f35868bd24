!> Numbers as text for messages and output names.
!>
!> Results are fixed-length (call sites trim them): gfortran 12 mishandles two
!> deferred-length function results in one expression, and messages concatenate several.
module rd_text
  use rd_kinds, only: wp, i8
  implicit none
  private
  public :: int_text, real_text, fixed_text, sci_text, lower_case

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

  !> Fixed-point with `decimals` digits after the point (>= 0), left-adjusted, a zero before
  !> the point ("0.086", "-0.24", "12" for decimals = 0): figures printed for readers.
  pure function fixed_text(x, decimals) result(text)
    real(wp), intent(in) :: x
    integer, intent(in) :: decimals
    character(len=32) :: text
    character(len=16) :: edit
    write (edit, '(a,i0,a)') '(f0.', decimals, ')'
    write (text, edit) x
    if (text(1:1) == '.') then
      text = '0' // text
    else if (text(1:2) == '-.') then
      text = '-0' // text(2:)
    end if
    if (decimals == 0) text(len_trim(text):len_trim(text)) = ' '   ! '12.' -> '12'
    if (text(1:1) == '-' .and. verify(trim(text), '-0.') == 0) text = text(2:)   ! no '-0.00'
  end function fixed_text

  !> Scientific notation with `decimals` digits after the point, left-adjusted (call sites
  !> trim): sci_text(x, 5) is Fortran's es.5 edit ("1.23457E-03"); `exponent_digits` as
  !> the Ee suffix (sci_text(x, 16, 3): "1.2345678901234568E-003", full double precision).
  pure function sci_text(x, decimals, exponent_digits) result(text)
    real(wp), intent(in) :: x
    integer, intent(in) :: decimals
    integer, intent(in), optional :: exponent_digits
    character(len=40) :: text
    character(len=24) :: edit
    if (present(exponent_digits)) then
      write (edit, '(a,i0,a,i0,a,i0,a)') '(es', decimals + 8 + exponent_digits, '.', decimals, 'e', &
        exponent_digits, ')'
    else
      write (edit, '(a,i0,a,i0,a)') '(es', decimals + 10, '.', decimals, ')'
    end if
    write (text, edit) x
    text = adjustl(text)
  end function sci_text

  !> ASCII lower case (deck keywords, profile names, method names).
  pure function lower_case(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i, c
    t = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('A') .and. c <= iachar('Z')) t(i:i) = achar(c + 32)
    end do
  end function lower_case
end module rd_text
