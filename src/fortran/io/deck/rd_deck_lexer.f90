!> Tokens of the namelist deck syntax, each with its line number.
!>
!> The lexer never fails: an unterminated string becomes a TK_UNTERMINATED
!> token so the parser, which knows the group and parameter being read, can
!> report it with full context. Comments (`!` outside strings) and white
!> space are dropped; string escapes (a doubled quote) are decoded.
module rd_deck_lexer
  use rd_deck_text, only: to_lower
  implicit none
  private
  public :: token_t, tokenize
  public :: TK_GROUP, TK_END, TK_WORD, TK_STRING, TK_EQUALS, TK_COMMA, TK_LPAREN, TK_RPAREN, &
            TK_UNTERMINATED, TK_EOF

  integer, parameter :: TK_GROUP = 1        !< &name (text = lower-case name)
  integer, parameter :: TK_END = 2          !< / or &end
  integer, parameter :: TK_WORD = 3         !< bare word: number, logical, name, repeat 'n*'
  integer, parameter :: TK_STRING = 4       !< quoted string (text = decoded content)
  integer, parameter :: TK_EQUALS = 5
  integer, parameter :: TK_COMMA = 6
  integer, parameter :: TK_LPAREN = 7
  integer, parameter :: TK_RPAREN = 8
  integer, parameter :: TK_UNTERMINATED = 9 !< string without its closing quote on the line
  integer, parameter :: TK_EOF = 10

  type :: token_t
    integer :: kind = TK_EOF
    integer :: line = 0
    character(len=:), allocatable :: text
    logical :: glued = .false.   !< no white space before this token
  end type token_t

  character(len=*), parameter :: word_stop = ' ,/=()!&''"' // achar(9) // achar(10) // achar(13)

contains

  subroutine tokenize(text, tokens, ntok)
    character(len=*), intent(in) :: text
    type(token_t), allocatable, intent(out) :: tokens(:)
    integer, intent(out) :: ntok
    integer :: i, n, line, j, nbuf
    character :: c, q
    character(len=:), allocatable :: buf
    logical :: glued, closed

    allocate (tokens(64))
    ntok = 0
    n = len(text); i = 1; line = 1; glued = .false.
    do while (i <= n)
      c = text(i:i)
      select case (c)
      case (' ', achar(9), achar(13))
        i = i + 1; glued = .false.
      case (achar(10))
        i = i + 1; line = line + 1; glued = .false.
      case ('!')
        do while (i <= n)
          if (text(i:i) == achar(10)) exit
          i = i + 1
        end do
      case ('&', '$')
        j = i + 1
        do while (j <= n)
          if (index(word_stop, text(j:j)) > 0) exit
          j = j + 1
        end do
        if (to_lower(text(i + 1:j - 1)) == 'end') then
          call push(TK_END, '&end')
        else
          call push(TK_GROUP, to_lower(text(i + 1:j - 1)))
        end if
        i = j
      case ('/')
        call push(TK_END, '/'); i = i + 1
      case ('=')
        call push(TK_EQUALS, '='); i = i + 1
      case (',')
        call push(TK_COMMA, ','); i = i + 1
      case ('(')
        call push(TK_LPAREN, '('); i = i + 1
      case (')')
        call push(TK_RPAREN, ')'); i = i + 1
      case ('''', '"')
        ! decoded into a buffer of the line's length (not grown per character: a
        ! megabyte-long value must cost linear time)
        q = c; closed = .false.
        j = index(text(i + 1:), achar(10))
        if (j == 0) then
          j = n + 1
        else
          j = i + j
        end if
        allocate (character(len=j - i) :: buf)
        nbuf = 0
        j = i + 1
        do while (j <= n)
          if (text(j:j) == achar(10)) exit
          if (text(j:j) == q) then
            if (j < n) then
              if (text(j + 1:j + 1) == q) then
                nbuf = nbuf + 1; buf(nbuf:nbuf) = q; j = j + 2; cycle
              end if
            end if
            closed = .true.; exit
          end if
          nbuf = nbuf + 1; buf(nbuf:nbuf) = text(j:j); j = j + 1
        end do
        if (closed) then
          call push(TK_STRING, buf(1:nbuf)); i = j + 1
        else
          call push(TK_UNTERMINATED, q // buf(1:nbuf)); i = j
        end if
        deallocate (buf)
      case default
        j = i
        do while (j <= n)
          if (index(word_stop, text(j:j)) > 0) exit
          j = j + 1
        end do
        call push(TK_WORD, text(i:j - 1)); i = j
      end select
    end do
    ! EOF padding: the parser looks up to three tokens ahead (name(k) =)
    call push(TK_EOF, ''); call push(TK_EOF, ''); call push(TK_EOF, ''); call push(TK_EOF, '')

  contains

    subroutine push(kind, t)
      integer, intent(in) :: kind
      character(len=*), intent(in) :: t
      type(token_t), allocatable :: grown(:)
      if (ntok == size(tokens)) then
        allocate (grown(2 * size(tokens)))
        grown(1:ntok) = tokens(1:ntok)
        call move_alloc(grown, tokens)
      end if
      ntok = ntok + 1
      tokens(ntok)%kind = kind
      tokens(ntok)%line = line
      tokens(ntok)%text = t
      tokens(ntok)%glued = glued
      glued = .true.
    end subroutine push
  end subroutine tokenize
end module rd_deck_lexer
