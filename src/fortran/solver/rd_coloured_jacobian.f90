!> Coloured (grouped) finite-difference Jacobians for the BDF Newton matrix
!> (Curtis, Powell & Reid 1974, "On the estimation of sparse Jacobian matrices").
!>
!> The caller states the sparsity as groups of columns and, per column, the rows that
!> column may touch (its possible non-zeros). Columns of one group have pairwise disjoint
!> row sets, so one right-hand-side call perturbs all of them at once and every
!> difference f_i(y + sum_k inc_k e_k) - f_i(y) belongs to the single column of the group
!> whose row set holds i. A Jacobian costs one RHS call per group instead of one per state.
!> Entries outside the stated rows are exactly zero.
!>
!> Increments are those of CVODE's dense difference quotient (SUNDIALS 6.4
!> cvLsDenseDQJac, CVODE guide section "Dense difference quotient Jacobian"):
!>   inc_j = max(sqrt(uround) |y_j|, min_inc / ewt_j),
!>   min_inc = 1000 |h| uround n ||f(t, y)||_WRMS(ewt)   (1 if that norm is 0),
!> with ewt_j = 1 / (rtol |y_j| + atol_j) CVODE's error weights and h its current step, so
!> a coloured Jacobian equals CVODE's own column by column (up to round-off) when the
!> stated sparsity is right.
!>
!> This module holds the pattern and the arithmetic; the RHS calls go through
!> rhs_context_t%evaluate_coloured_jacobian (rd_rhs_context), which owns the failure
!> convention.
module rd_coloured_jacobian
  use rd_kinds, only: wp
  use rd_error, only: error_t, make_error, RD_ERR_INPUT
  use rd_text, only: int_text
  implicit none
  private
  public :: jacobian_sparsity_t, build_jacobian_sparsity, dq_minimum_increment, dq_increment

  !> CVODE's MIN_INC_MULT (cvode_ls.c).
  real(wp), parameter :: min_inc_mult = 1000.0_wp

  !> Column groups and per-column row sets (compressed, 1-based), fixed after build.
  type :: jacobian_sparsity_t
    integer :: n = 0                        !< state size (square Jacobian n x n)
    integer :: n_groups = 0                 !< RHS calls per Jacobian
    integer, allocatable :: group_start(:)  !< (n_groups + 1): group g = group_columns(group_start(g):group_start(g+1)-1)
    integer, allocatable :: group_columns(:) !< (n) every column once, group after group
    integer, allocatable :: row_start(:)    !< (n + 1): column j may touch rows(row_start(j):row_start(j+1)-1)
    integer, allocatable :: rows(:)         !< row indices, ascending within a column
    !> Absolute floor on the increments (state units), 0 = CVODE's rule alone. A system whose
    !> right-hand side solves an inner equation (quasi-static coordinates, rd_multibody) is
    !> smooth only down to that solve's rounding, ~1e-11 m/s^2 on a wheelset's acceleration;
    !> CVODE's rule can perturb by 1e-15, where that noise swamps the derivative.
    real(wp) :: min_increment = 0
  contains
    procedure :: in_pattern
  end type jacobian_sparsity_t

contains

  !> Build the pattern from the group of each column (1..number of groups, every group
  !> used) and each column's rows (CSR: rows(row_start(j):row_start(j+1)-1)). Refuses a
  !> pattern whose groups are not structurally orthogonal (two columns of one group that
  !> may touch the same row), since that would mix their derivatives silently.
  subroutine build_jacobian_sparsity(sparsity, column_group, row_start, rows, error)
    type(jacobian_sparsity_t), intent(out) :: sparsity
    integer, intent(in) :: column_group(:)
    integer, intent(in) :: row_start(:)
    integer, intent(in) :: rows(:)
    type(error_t), allocatable, intent(out) :: error
    integer :: n, ng, j, g, k, i, fill
    integer, allocatable :: owner(:), count(:)

    n = size(column_group)
    if (n < 1) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: no columns; expected one group per state')
      return
    end if
    if (size(row_start) /= n + 1) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: row_start has ' // trim(int_text(size(row_start))) // &
                      ' entries; expected n + 1 = ' // trim(int_text(n + 1)))
      return
    end if
    if (row_start(1) /= 1 .or. any(row_start(2:) < row_start(:n)) .or. row_start(n + 1) - 1 /= size(rows)) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: row_start is not a non-decreasing ' // &
                      'CSR index from 1 to size(rows) + 1')
      return
    end if
    if (any(rows < 1) .or. any(rows > n)) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: a row index is outside 1..' // trim(int_text(n)))
      return
    end if
    ng = maxval(column_group)
    if (minval(column_group) < 1) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: a column has no group; expected groups >= 1')
      return
    end if
    allocate (count(ng), source=0)
    do j = 1, n
      count(column_group(j)) = count(column_group(j)) + 1
    end do
    if (any(count == 0)) then
      call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: group ' // trim(int_text(findloc(count, 0, dim=1))) // &
                      ' has no column; expected groups numbered 1..number of groups')
      return
    end if
    ! Structural orthogonality: within a group each row belongs to at most one column.
    allocate (owner(n))
    do g = 1, ng
      owner = 0
      do j = 1, n
        if (column_group(j) /= g) cycle
        do k = row_start(j), row_start(j + 1) - 1
          i = rows(k)
          if (owner(i) == j) then
            call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: column ' // trim(int_text(j)) // &
                            ' lists row ' // trim(int_text(i)) // ' twice')
            return
          end if
          if (owner(i) /= 0) then
            call make_error(error, RD_ERR_INPUT, 'jacobian sparsity: columns ' // trim(int_text(owner(i))) // ' and ' // &
                            trim(int_text(j)) // ' of group ' // trim(int_text(g)) // ' may both touch row ' // &
                            trim(int_text(i)) // &
                            '; expected disjoint row sets within a group')
            return
          end if
          owner(i) = j
        end do
      end do
    end do

    sparsity%n = n
    sparsity%n_groups = ng
    allocate (sparsity%group_start(ng + 1), sparsity%group_columns(n))
    sparsity%group_start(1) = 1
    do g = 1, ng
      sparsity%group_start(g + 1) = sparsity%group_start(g) + count(g)
    end do
    count = sparsity%group_start(:ng)   ! next free slot per group
    do j = 1, n
      g = column_group(j)
      fill = count(g)
      sparsity%group_columns(fill) = j
      count(g) = fill + 1
    end do
    sparsity%row_start = row_start
    sparsity%rows = rows
    do j = 1, n
      call sort_ascending(sparsity%rows(row_start(j):row_start(j + 1) - 1))
    end do
  end subroutine build_jacobian_sparsity

  !> True when entry (i, j) may be non-zero.
  pure logical function in_pattern(self, i, j)
    class(jacobian_sparsity_t), intent(in) :: self
    integer, intent(in) :: i, j
    in_pattern = any(self%rows(self%row_start(j):self%row_start(j + 1) - 1) == i)
  end function in_pattern

  !> CVODE's floor on the increments: 1000 |h| uround n ||fy||_WRMS(ewt), or 1 when the
  !> weighted norm of f is zero (cvLsDenseDQJac).
  pure real(wp) function dq_minimum_increment(h, fy, ewt) result(min_inc)
    real(wp), intent(in) :: h
    real(wp), intent(in) :: fy(:), ewt(:)
    real(wp) :: fnorm
    fnorm = sqrt(sum((fy * ewt)**2) / real(size(fy), wp))
    if (fnorm > 0.0_wp) then
      min_inc = min_inc_mult * abs(h) * epsilon(1.0_wp) * real(size(fy), wp) * fnorm
    else
      min_inc = 1.0_wp
    end if
  end function dq_minimum_increment

  !> Increment of column j: max(sqrt(uround) |y_j|, min_inc / ewt_j) (cvLsDenseDQJac), and at
  !> least `floor` (jacobian_sparsity_t%min_increment).
  pure elemental real(wp) function dq_increment(yj, ewtj, min_inc, floor) result(inc)
    real(wp), intent(in) :: yj, ewtj, min_inc
    real(wp), intent(in), optional :: floor
    inc = max(sqrt(epsilon(1.0_wp)) * abs(yj), min_inc / ewtj)
    if (present(floor)) inc = max(inc, floor)
  end function dq_increment

  pure subroutine sort_ascending(a)
    integer, intent(inout) :: a(:)
    integer :: i, j, v
    do i = 2, size(a)
      v = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= v) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = v
    end do
  end subroutine sort_ascending
end module rd_coloured_jacobian
