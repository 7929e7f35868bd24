!> Profile files: SIMPACK `.prw` (wheel) / `.prr` (rail) and plain y-z tables.
!>
!> SIMPACK: header keys `type` (0 rail, 1 wheel), `units.len.f` (file units per metre),
!> `mirror.y`, `mirror.z`, `inversion`, `shift.y`, `shift.z`, `rotate` (in `units.ang.f`
!> units), points between `point.begin` and `point.end` (`!` starts a comment). In SIMPACK
!> profile coordinates z points down, which for a wheel is the radius increase F; so the
!> wheel maps to (s, F) = (y, z) and the rail to (y, -z) (see validation/reference/profiles/README.md).
!> Tables: two (or three, the third ignored) numbers per line separated by blanks, tabs or
!> commas; `#` or `!` start comments; metres unless a comment states `units: mm` (or cm, m);
!> columns are already in our conventions (wheel: s, F; rail: y field-positive, z up).
module rd_profile_io
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use rd_text, only: lower_case, int_text, real_text
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, error_context, RD_ERR_INPUT, RD_ERR_IO
  use rd_line_reader, only: read_line
  use rd_profile, only: profile_t, PROFILE_WHEEL, PROFILE_RAIL, validate_profile, profile_kind_name
  implicit none
  private
  public :: read_profile_file, write_profile_table, write_profile_simpack

  integer, parameter :: max_line = 1024

contains

  !> The points in metres, with the file line of each: finite, and strictly monotonic in
  !> y in one direction or the other (validate_profile reverses a decreasing profile);
  !> errors name the file line (validate_profile, which has no lines, names points).
  subroutine check_point_lines(path, y, z, lines, error)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: y(:), z(:)
    integer, intent(in) :: lines(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: i, n
    real(wp) :: direction
    n = size(y)
    do i = 1, n
      if (.not. (ieee_is_finite(y(i)) .and. ieee_is_finite(z(i)))) then
        call make_error(error, RD_ERR_INPUT, trim(path) // ':' // trim(int_text(lines(i))) // &
          ': coordinate not finite; expected finite numbers')
        return
      end if
    end do
    if (n < 2) return
    direction = sign(1.0_wp, y(n) - y(1))
    do i = 2, n
      if (.not. (direction * (y(i) - y(i - 1)) > 0)) then
        call make_error(error, RD_ERR_INPUT, trim(path) // ':' // trim(int_text(lines(i))) // &
          ': lateral coordinate ' // trim(real_text(y(i))) // ' m does not ' // &
          trim(merge('increase', 'decrease', direction > 0)) // ' from the point at line ' // &
          trim(int_text(lines(i - 1))) // ' (' // trim(real_text(y(i - 1))) // ' m); expected a graph ' // &
          'z(y): strictly monotonic y, no overhangs or repeated points')
        return
      end if
    end do
  end subroutine check_point_lines

  !> Read a profile file (SIMPACK if it contains `point.begin`, else a table) into metres.
  subroutine read_profile_file(path, kind, profile, error)
    character(len=*), intent(in) :: path
    integer, intent(in) :: kind            !< PROFILE_WHEEL or PROFILE_RAIL (expected)
    type(profile_t), intent(out) :: profile
    type(error_t), allocatable, intent(out) :: error
    integer :: unit, ios
    character(len=max_line) :: line
    logical :: is_simpack
    open (newunit=unit, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot open ' // profile_kind_name(kind) // ' profile file ' // trim(path))
      return
    end if
    is_simpack = .false.
    do
      read (unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(adjustl(line), 'point.begin') == 1) then
        is_simpack = .true.
        exit
      end if
    end do
    rewind (unit)
    profile%kind = kind
    profile%source = trim(path)
    if (is_simpack) then
      call read_simpack(unit, path, kind, profile, error)
    else
      call read_table(unit, path, profile, error)
    end if
    close (unit)
    if (allocated(error)) return
    call validate_profile(profile, error)
  end subroutine read_profile_file

  subroutine read_simpack(unit, path, kind, profile, error)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: path
    integer, intent(in) :: kind
    type(profile_t), intent(inout) :: profile
    type(error_t), allocatable, intent(out) :: error
    character(len=max_line) :: line, key, val
    integer :: ios, nline, eq, n, ftype, mirror_y, mirror_z, inversion, block_line
    logical :: in_points, in_header
    real(wp) :: ufac, afac, shift_y, shift_z, rot, a, b, c, yy, zz
    real(wp), allocatable :: ybuf(:), zbuf(:)
    integer, allocatable :: lbuf(:)
    character(len=300) :: msg

    ufac = 1; afac = 1; shift_y = 0; shift_z = 0; rot = 0
    ftype = -1; mirror_y = 0; mirror_z = 0; inversion = 0
    in_points = .false.; in_header = .false.
    allocate (ybuf(256), zbuf(256), lbuf(256))
    n = 0; nline = 0; block_line = 0
    do
      call read_line(unit, path, nline, line, ios, error)
      if (allocated(error)) return
      if (ios /= 0) exit
      call strip_comment(line, '!')
      line = adjustl(line)
      if (len_trim(line) == 0) cycle
      if (in_points) then
        if (index(line, 'point.end') == 1) then
          in_points = .false.
          cycle
        end if
        if (.not. parse_numbers(line, a, b, c)) then
          write (msg, '(a,":",i0,a)') trim(path), nline, &
            ': malformed profile point (expected two numbers "y z"): "' // trim(line) // '"'
          call make_error(error, RD_ERR_INPUT, trim(msg))
          return
        end if
        n = n + 1
        if (n > size(ybuf)) call grow(ybuf, zbuf, lbuf)
        ybuf(n) = a; zbuf(n) = b; lbuf(n) = nline
        cycle
      end if
      if (index(line, 'point.begin') == 1) then
        if (block_line > 0) then
          call make_error(error, RD_ERR_INPUT, trim(path) // ':' // trim(int_text(nline)) // &
            ': a second point.begin (the first at line ' // trim(int_text(block_line)) // &
            '); expected one point block per profile')
          return
        end if
        in_points = .true.; block_line = nline
        cycle
      end if
      if (index(line, 'header.begin') == 1) in_header = .true.
      if (index(line, 'header.end') == 1) in_header = .false.
      eq = index(line, '=')
      if (eq == 0) cycle
      key = adjustl(line(:eq - 1))
      val = adjustl(line(eq + 1:))
      select case (trim(key))
      case ('type')          ! the profile type lives in the header (spline.type is the data file type)
        if (in_header) call read_int(val, ftype)
      case ('units.len.f')
        call read_real(val, ufac)
      case ('units.ang.f')
        call read_real(val, afac)
      case ('mirror.y')
        call read_int(val, mirror_y)
      case ('mirror.z')
        call read_int(val, mirror_z)
      case ('inversion')
        call read_int(val, inversion)
      case ('shift.y')
        call read_real(val, shift_y)
      case ('shift.z')
        call read_real(val, shift_z)
      case ('rotate')
        call read_real(val, rot)
      end select
      if (ios /= 0) then
        write (msg, '(a,":",i0,a)') trim(path), nline, ': cannot read the value of ' // trim(key)
        call make_error(error, RD_ERR_INPUT, trim(msg))
        return
      end if
    end do
    if (in_points) then
      call make_error(error, RD_ERR_INPUT, trim(path) // ': point.begin without point.end')
      return
    end if
    if (ftype == 0 .and. kind == PROFILE_WHEEL .or. ftype == 1 .and. kind == PROFILE_RAIL) then
      call make_error(error, RD_ERR_INPUT, trim(path) // ': header type = ' // trim(merge('0 (rail) ', '1 (wheel)', ftype == 0)) &
        // ' but a ' // profile_kind_name(kind) // ' profile is expected')
      return
    end if
    if (.not. (ufac > 0)) then
      call make_error(error, RD_ERR_INPUT, trim(path) // ': units.len.f must be > 0 (file length units per metre)')
      return
    end if
    ! SIMPACK pre-processing order: shift, rotate, mirror, inversion, then units
    rot = rot / afac
    block
      integer :: i
      do i = 1, n
        yy = ybuf(i) + shift_y; zz = zbuf(i) + shift_z
        a = cos(rot) * yy - sin(rot) * zz
        b = sin(rot) * yy + cos(rot) * zz
        if (mirror_y == 1) a = -a
        if (mirror_z == 1) b = -b
        ybuf(i) = a / ufac
        zbuf(i) = b / ufac
      end do
    end block
    if (inversion == 1 .and. n > 0) then
      ybuf(1:n) = ybuf(n:1:-1); zbuf(1:n) = zbuf(n:1:-1); lbuf(1:n) = lbuf(n:1:-1)
    end if
    call check_point_lines(path, ybuf(1:n), zbuf(1:n), lbuf(1:n), error)
    if (allocated(error)) return
    profile%y = ybuf(1:n)
    if (kind == PROFILE_WHEEL) then
      profile%z = zbuf(1:n)          ! z down = radius increase F
    else
      profile%z = -zbuf(1:n)         ! z down -> z up
    end if
  contains
    subroutine read_int(text, v)
      character(len=*), intent(in) :: text
      integer, intent(inout) :: v
      read (text, *, iostat=ios) v
    end subroutine read_int
    subroutine read_real(text, v)
      character(len=*), intent(in) :: text
      real(wp), intent(inout) :: v
      read (text, *, iostat=ios) v
    end subroutine read_real
  end subroutine read_simpack

  subroutine read_table(unit, path, profile, error)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: path
    type(profile_t), intent(inout) :: profile
    type(error_t), allocatable, intent(out) :: error
    character(len=max_line) :: line, lower
    integer :: ios, nline, n, p
    real(wp) :: a, b, c, factor
    real(wp), allocatable :: ybuf(:), zbuf(:)
    integer, allocatable :: lbuf(:)
    character(len=300) :: msg
    allocate (ybuf(256), zbuf(256), lbuf(256))
    factor = 1; n = 0; nline = 0
    do
      call read_line(unit, path, nline, line, ios, error)
      if (allocated(error)) return
      if (ios /= 0) exit
      p = scan(line, '#!')
      if (p > 0) then
        lower = lower_case(line(p + 1:))
        if (index(lower, 'units') > 0 .or. index(lower, 'unit:') > 0 .or. index(lower, 'unit =') > 0) then
          if (index(lower, 'mm') > 0) then
            factor = 1.0e-3_wp
          else if (index(lower, 'cm') > 0) then
            factor = 1.0e-2_wp
          else if (index(lower, ' m') > 0 .or. index(lower, ':m') > 0 .or. index(lower, '=m') > 0) then
            factor = 1
          end if
        end if
        line(p:) = ' '
      end if
      if (len_trim(line) == 0) cycle
      if (.not. parse_numbers(line, a, b, c)) then
        write (msg, '(a,":",i0,a)') trim(path), nline, &
          ': malformed line (expected two numbers "y z", blank or comma separated): "' // trim(adjustl(line)) // '"'
        call make_error(error, RD_ERR_INPUT, trim(msg))
        return
      end if
      n = n + 1
      if (n > size(ybuf)) call grow(ybuf, zbuf, lbuf)
      ybuf(n) = a; zbuf(n) = b; lbuf(n) = nline
    end do
    profile%y = ybuf(1:n) * factor
    profile%z = zbuf(1:n) * factor
    call check_point_lines(path, profile%y, profile%z, lbuf(1:n), error)
  end subroutine read_table

  !> Two or three numbers (commas or blanks); false if fewer than two or junk.
  logical function parse_numbers(line, a, b, c) result(ok)
    character(len=*), intent(in) :: line
    real(wp), intent(out) :: a, b, c
    character(len=len(line)) :: work
    character(len=len(line)) :: tok(4)   ! as long as the line: a long number is never cut
    integer :: i, ntok, ios, p, q
    work = line
    do i = 1, len(work)
      if (work(i:i) == ',' .or. work(i:i) == char(9) .or. work(i:i) == ';') work(i:i) = ' '
    end do
    ntok = 0
    p = 1
    do while (p <= len_trim(work))
      if (work(p:p) == ' ') then
        p = p + 1
        cycle
      end if
      q = index(work(p:), ' ')
      if (q == 0) then
        q = len_trim(work) + 1
      else
        q = p + q - 1
      end if
      ntok = ntok + 1
      if (ntok > 3) then
        ok = .false.
        return
      end if
      tok(ntok) = work(p:q - 1)
      p = q
    end do
    ok = ntok >= 2
    a = 0; b = 0; c = 1
    if (.not. ok) return
    read (tok(1), *, iostat=ios) a
    if (ios == 0) read (tok(2), *, iostat=ios) b
    if (ios == 0 .and. ntok == 3) read (tok(3), *, iostat=ios) c
    ok = ios == 0 .and. verify(trim(tok(1)), '0123456789+-.eEdD') == 0 &
         .and. verify(trim(tok(2)), '0123456789+-.eEdD') == 0
  end function parse_numbers

  subroutine strip_comment(line, mark)
    character(len=*), intent(inout) :: line
    character(len=1), intent(in) :: mark
    integer :: p
    p = index(line, mark)
    if (p > 0) line(p:) = ' '
  end subroutine strip_comment

  subroutine grow(a, b, lines)
    real(wp), allocatable, intent(inout) :: a(:), b(:)
    integer, allocatable, intent(inout) :: lines(:)
    a = [a, a]
    b = [b, b]
    lines = [lines, lines]
  end subroutine grow

  !> Write a plain y-z table in metres with a header comment (our conventions).
  subroutine write_profile_table(path, profile, header, error)
    character(len=*), intent(in) :: path
    type(profile_t), intent(in) :: profile
    character(len=*), intent(in) :: header(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: unit, ios, i
    open (newunit=unit, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot write profile table ' // trim(path))
      return
    end if
    do i = 1, size(header)
      write (unit, '(a)') '# ' // trim(header(i))
    end do
    write (unit, '(a)') '# units: m'
    if (profile%kind == PROFILE_WHEEL) then
      write (unit, '(a)') '# columns: s (lateral from the tape circle, + field side), F (radius increase)'
    else
      write (unit, '(a)') '# columns: y (lateral, + field side), z (up)'
    end if
    do i = 1, size(profile%y)
      write (unit, '(es24.16,1x,es24.16)') profile%y(i), profile%z(i)
    end do
    close (unit)
  end subroutine write_profile_table

  !> Write a SIMPACK profile (millimetres, no mirroring or inversion; z down).
  subroutine write_profile_simpack(path, profile, comment, error)
    character(len=*), intent(in) :: path
    type(profile_t), intent(in) :: profile
    character(len=*), intent(in) :: comment(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: unit, ios, i
    real(wp) :: zf
    open (newunit=unit, file=path, status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      call make_error(error, RD_ERR_IO, 'cannot write profile file ' // trim(path))
      return
    end if
    do i = 1, size(comment)
      write (unit, '(a)') '! ' // trim(comment(i))
    end do
    write (unit, '(a)') '  header.begin'
    write (unit, '(a)') '    version       =  1'
    write (unit, '(a,i0,a)') '    type          =  ', merge(1, 0, profile%kind == PROFILE_WHEEL), &
      '                       ! 0=rail profile, 1=wheel profile'
    write (unit, '(a)') '  header.end'
    write (unit, '(a)') '  spline.begin'
    write (unit, '(a)') '    mirror.y       =  0'
    write (unit, '(a)') '    mirror.z       =  0'
    write (unit, '(a)') '    inversion      =  0'
    write (unit, '(a)') '    units.len.f    = +1.000000000000000e+03   ! lengths in mm'
    write (unit, '(a)') '    units.ang.f    = +1.000000000000000e+00'
    write (unit, '(a)') '    point.begin'
    do i = 1, size(profile%y)
      zf = profile%z(i)
      if (profile%kind == PROFILE_RAIL) zf = -zf
      write (unit, '(es22.14,2x,es22.14)') 1000 * profile%y(i), 1000 * zf
    end do
    write (unit, '(a)') '    point.end'
    write (unit, '(a)') '  spline.end'
    close (unit)
  end subroutine write_profile_simpack

end module rd_profile_io
