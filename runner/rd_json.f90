!> JSON text for the runner's machine-readable answers (`raildyn check --json`, `raildyn
!> eigen --json`, `raildyn conicity --json`): strings escaped as RFC 8259 requires, so that any
!> path or message reads back unchanged; numbers with 17 significant digits, so that they read
!> back exactly.
module rd_json
  use rd_kinds, only: wp
  use rd_text, only: sci_text
  implicit none
  private
  public :: json_string, json_real

contains

  !> `text` as a JSON string literal (quotes, backslashes and control bytes escaped).
  pure function json_string(text) result(json)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: json
    character(len=*), parameter :: hex = '0123456789abcdef'
    integer :: i, code
    json = '"'
    do i = 1, len(text)
      code = iachar(text(i:i))
      select case (code)
      case (34); json = json // '\"'
      case (92); json = json // '\\'
      case (10); json = json // '\n'
      case (13); json = json // '\r'
      case (9); json = json // '\t'
      case (0:8, 11:12, 14:31, 127)
        json = json // '\u00' // hex(code / 16 + 1:code / 16 + 1) // hex(mod(code, 16) + 1:mod(code, 16) + 1)
      case default; json = json // text(i:i)
      end select
    end do
    json = json // '"'
  end function json_string

  !> `x` as a JSON number (17 significant digits); null when not finite (JSON has no NaN).
  pure function json_real(x) result(json)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: json
    if (x /= x .or. abs(x) > huge(x)) then
      json = 'null'
    else
      json = trim(sci_text(x, 16, 3))
    end if
  end function json_real
end module rd_json
