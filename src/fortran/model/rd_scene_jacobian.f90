!> The sparsity of a scene's Jacobian, for the coloured difference quotients of the BDF
!> integrator (rd_coloured_jacobian).
!>
!> The bodies are Lagrangian, each in its own track frame, without constraints
!> (thesis 4.2-4.6): the generalized mass matrix is block diagonal per body, so the
!> derivatives of body b's states (its rates and accelerations, rd_multibody) depend only
!> on b's own states and on the states of whatever shares a force with b:
!>  - a force element couples body1, body2 (0 = ground: the track frame, no state) and its
!>    own internal states (series dampers: their rates depend on both bodies);
!>  - a wheelset contact acts on its wheelset from that wheelset's kinematics (rigid rails
!>    fixed in the track frame, thesis 4.7); with rail bodies (flexible track) each wheel's
!>    force also depends on its rail body's (y, z) and rates and acts on it, so the contact
!>    couples the wheelset with each rail body (the two rails only through the wheelset:
!>    the left wheel's geometry sees the left rail only, rd_contact_geometry);
!>  - external loads act on one body, from its own frames; the run-time override loads of
!>    the C API do not depend on the state at all; gravity and the track frames' motion
!>    (speed law) depend on time only.
!> A provider of another type cannot state its coupling, so the scene then falls back to
!> the dense Jacobian (`dense_reason`).
!>
!> Graph: the nodes are the bodies (deck order) followed by the elements that have
!> internal states; two nodes are adjacent when one force couples them. A column of node
!> a may touch the rows of every node adjacent to a (and a's own), so two nodes may be
!> perturbed in the same RHS call only when no node is adjacent to both (distance > 2).
!> Greedy distance-2 colouring in deck order (Gebremedhin, Manne & Pothen 2005, "What
!> color is your Jacobian?"); a colour with nodes of at most m states gives m column
!> groups (one state of each node per group). Manchester vehicle 1 (car, 2 bogies,
!> 4 wheelsets): {car}, {bogie1, ws3}, {bogie2, ws1}, {ws2, ws4} -> 4 x 12 = 48 RHS calls
!> per Jacobian instead of 84.
module rd_scene_jacobian
  use rd_kinds, only: wp
  use rd_error, only: error_t, error_context
  use rd_multibody, only: multibody_t
  use rd_coloured_jacobian, only: jacobian_sparsity_t, build_jacobian_sparsity
  use rd_text, only: int_text
  implicit none
  private
  public :: body_coupling_t, multibody_coupling, distance2_colouring, coupling_sparsity, &
            scene_jacobian_sparsity

  !> The coupling graph of a multibody system.
  type :: body_coupling_t
    integer :: n_nodes = 0                   !< the bodies (nodes 1..number of bodies), then the elements with states
    logical, allocatable :: adjacent(:, :)   !< (n_nodes, n_nodes), symmetric, true on the diagonal
    integer, allocatable :: state_start(:)   !< (n_nodes + 1): node a owns states(state_start(a):state_start(a+1)-1)
    integer, allocatable :: states(:)        !< state indices (q slots, then nu slots, then element states)
    !> Allocated when some force provider cannot state its coupling: use a dense Jacobian.
    character(len=:), allocatable :: dense_reason
  end type body_coupling_t

contains

  !> The coupling graph of `mbs` (after its elements and providers were added).
  subroutine multibody_coupling(mbs, coupling)
    type(multibody_t), intent(in) :: mbs
    type(body_coupling_t), intent(out) :: coupling
    integer :: nb, ne, e, i, j, k, n, node, b1, b2, fill
    integer, allocatable :: element_node(:), pairs(:, :)
    logical :: known

    nb = mbs%body_count()
    ne = mbs%element_count()
    allocate (element_node(ne), source=0)
    node = nb
    do e = 1, ne
      if (mbs%elements(e)%e%state_count() > 0) then
        node = node + 1
        element_node(e) = node
      end if
    end do
    coupling%n_nodes = node
    allocate (coupling%adjacent(node, node), source=.false.)
    do i = 1, node
      coupling%adjacent(i, i) = .true.
    end do
    do e = 1, ne
      b1 = mbs%elements(e)%e%body1
      b2 = mbs%elements(e)%e%body2
      if (b1 > 0) call link(b1, b2)
      if (element_node(e) > 0) then
        call link(element_node(e), b2)
        if (b1 > 0) call link(element_node(e), b1)
      end if
    end do
    do i = 1, size(mbs%providers)
      call mbs%providers(i)%p%coupled_bodies(pairs, known)
      if (.not. known) coupling%dense_reason = 'force provider ' // trim(int_text(i)) // &
                                               ' does not state which bodies it couples'
      do j = 1, size(pairs, 2)
        call link(pairs(1, j), pairs(2, j))
      end do
    end do

    ! states of each node, in the order of rd_multibody's layout
    allocate (coupling%state_start(node + 1), coupling%states(mbs%state_size()))
    fill = 0
    do i = 1, nb
      coupling%state_start(i) = fill + 1
      do j = 1, 6
        k = mbs%free_slot(i, j)
        if (k == 0) cycle
        fill = fill + 1
        coupling%states(fill) = k
      end do
      do j = 1, 6
        k = mbs%free_slot(i, j)
        if (k == 0) cycle
        fill = fill + 1
        coupling%states(fill) = mbs%nfree + k
      end do
    end do
    do e = 1, ne
      if (element_node(e) == 0) cycle
      coupling%state_start(element_node(e)) = fill + 1
      n = mbs%elements(e)%e%state_count()
      k = 2 * mbs%nfree + mbs%el_state_start(e)
      coupling%states(fill + 1:fill + n) = [(k + j, j = 0, n - 1)]
      fill = fill + n
    end do
    coupling%state_start(node + 1) = fill + 1
  contains
    subroutine link(a, b)
      integer, intent(in) :: a, b
      coupling%adjacent(a, b) = .true.
      coupling%adjacent(b, a) = .true.
    end subroutine link
  end subroutine multibody_coupling

  !> Greedy distance-2 colouring in node order: node a gets the smallest colour not used
  !> by a node within distance 2 (a node adjacent to both). colour(a) in 1..n_colours.
  pure subroutine distance2_colouring(adjacent, colour, n_colours)
    logical, intent(in) :: adjacent(:, :)
    integer, intent(out) :: colour(:)
    integer, intent(out) :: n_colours
    logical :: used(size(adjacent, 1) + 1)
    integer :: a, c, n

    n = size(adjacent, 1)
    colour = 0
    n_colours = 0
    do a = 1, n
      used = .false.
      do c = 1, a - 1
        if (any(adjacent(:, a) .and. adjacent(:, c))) used(colour(c)) = .true.
      end do
      colour(a) = findloc(used, .false., dim=1)
      n_colours = max(n_colours, colour(a))
    end do
  end subroutine distance2_colouring

  !> Column groups and row sets for a state of size n from the coupling graph: colour the
  !> nodes, then group m of colour c holds the m-th state of every node of colour c.
  !> Without stated coupling (dense_reason) every column is its own group with all rows.
  subroutine coupling_sparsity(coupling, n, sparsity, error)
    type(body_coupling_t), intent(in) :: coupling
    integer, intent(in) :: n
    type(jacobian_sparsity_t), intent(out) :: sparsity
    type(error_t), allocatable, intent(out) :: error
    integer :: colour(coupling%n_nodes), n_colours, c, a, b, m, width, group, j, k
    integer :: column_group(n), row_start(n + 1)
    integer, allocatable :: rows(:)

    if (allocated(coupling%dense_reason) .or. coupling%n_nodes == 0) then
      column_group = [(j, j = 1, n)]
      row_start = [(1 + (j - 1) * n, j = 1, n + 1)]
      rows = [((k, k = 1, n), j = 1, n)]
      call build_jacobian_sparsity(sparsity, column_group, row_start, rows, error)
      return
    end if
    call distance2_colouring(coupling%adjacent, colour, n_colours)
    column_group = 0
    group = 0
    do c = 1, n_colours
      width = 0
      do a = 1, coupling%n_nodes
        if (colour(a) == c) width = max(width, node_size(a))
      end do
      do m = 1, width
        group = group + 1
        do a = 1, coupling%n_nodes
          if (colour(a) /= c .or. node_size(a) < m) cycle
          column_group(coupling%states(coupling%state_start(a) + m - 1)) = group
        end do
      end do
    end do
    ! rows of a column of node a: the states of every node adjacent to a
    allocate (rows(0))
    row_start(1) = 1
    do j = 1, n
      a = node_of_state(j)
      do b = 1, coupling%n_nodes
        if (coupling%adjacent(a, b)) &
          rows = [rows, coupling%states(coupling%state_start(b):coupling%state_start(b + 1) - 1)]
      end do
      row_start(j + 1) = size(rows) + 1
    end do
    call build_jacobian_sparsity(sparsity, column_group, row_start, rows, error)
    if (allocated(error)) call error_context(error, 'scene jacobian sparsity')
  contains
    pure integer function node_size(a)
      integer, intent(in) :: a
      node_size = coupling%state_start(a + 1) - coupling%state_start(a)
    end function node_size
    pure integer function node_of_state(j)
      integer, intent(in) :: j
      integer :: a
      node_of_state = 0
      do a = 1, coupling%n_nodes
        if (any(coupling%states(coupling%state_start(a):coupling%state_start(a + 1) - 1) == j)) then
          node_of_state = a
          return
        end if
      end do
    end function node_of_state
  end subroutine coupling_sparsity

  !> The coloured-Jacobian sparsity of `mbs`. `dense_reason` is allocated (and the
  !> sparsity left empty) when the coupling is unknown: the caller keeps CVODE's dense
  !> difference quotients then.
  subroutine scene_jacobian_sparsity(mbs, sparsity, dense_reason, error)
    type(multibody_t), intent(in) :: mbs
    type(jacobian_sparsity_t), intent(out) :: sparsity
    character(len=:), allocatable, intent(out) :: dense_reason
    type(error_t), allocatable, intent(out) :: error
    type(body_coupling_t) :: coupling
    call multibody_coupling(mbs, coupling)
    if (allocated(coupling%dense_reason)) then
      dense_reason = coupling%dense_reason
      return
    end if
    call coupling_sparsity(coupling, mbs%state_size(), sparsity, error)
    ! quasi-static coordinates are solved to rounding (~1 ulp of z ~ 0.46 m: 5.6e-17 m, i.e.
    ! ~3e-11 m/s^2 on the wheelset); increments of 1e-10 (m, rad, m/s, rad/s) keep that noise
    ! below 1e-6 of the Hertz terms' derivatives and the truncation error ~1e-10 m / 50 um
    if (mbs%has_quasi_static) sparsity%min_increment = 1.0e-10_wp
  end subroutine scene_jacobian_sparsity
end module rd_scene_jacobian
