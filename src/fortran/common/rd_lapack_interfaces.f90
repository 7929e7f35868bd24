!> Explicit interfaces of the LAPACK routines the library calls (reference LAPACK, double
!> precision), so that their arguments are checked at compile time; one place for all the
!> modules that solve with them.
module rd_lapack_interfaces
  use rd_kinds, only: wp
  implicit none
  private
  public :: dgbsv, dgelsd, band_put

  interface
    !> Solves A X = B for a band matrix A (kl sub-, ku super-diagonals) by LU with partial
    !> pivoting; ab in LAPACK's band storage with 2 kl + ku + 1 rows.
    subroutine dgbsv(n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
      import :: wp
      integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
      real(wp), intent(inout) :: ab(ldab, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgbsv

    !> Minimum-norm least-squares solution of A X = B (SVD, divide and conquer).
    subroutine dgelsd(m, n, nrhs, a, lda, b, ldb, s, rcond, rank, work, lwork, iwork, info)
      import :: wp
      integer, intent(in) :: m, n, nrhs, lda, ldb, lwork
      real(wp), intent(inout) :: a(lda, *), b(ldb, *)
      real(wp), intent(out) :: s(*), work(*)
      real(wp), intent(in) :: rcond
      integer, intent(out) :: rank, iwork(*), info
    end subroutine dgelsd
  end interface

contains

  !> A(row, col) = v in the band storage of dgbsv (kl sub-, ku super-diagonals)
  pure subroutine band_put(ab, kl, ku, row, col, v)
    real(wp), intent(inout) :: ab(:, :)
    integer, intent(in) :: kl, ku, row, col
    real(wp), intent(in) :: v
    ab(kl + ku + 1 + row - col, col) = v
  end subroutine band_put

end module rd_lapack_interfaces
