!> multibody%quasi_static_balance (the residual that solve_quasi_static drives to zero, at a
!> pose of the caller's choosing; bench/contact_chatter/study_quasi_static_balance maps it),
!> on the acceptance deck inputs/manchester_v1_tc1.nml at t = 0 (straight track):
!>  (a) at the solution of the right-hand side's solve the residual is zero to the solve's
!>      tolerance (1e-13 m, rad, on a contact stiffness of ~1e6 1/s^2: below 1e-5 m/s^2);
!>  (b) against an independent path: the residual is the height and roll accelerations with the
!>      rates of height and roll at zero. The same deck with elastic normal contact has height
!>      and roll in its state; with the same pose (wheelset 1 lowered by 20 um and rolled by
!>      0.1 mrad, the others at their balance) and those rates zero, its right-hand side's z''
!>      and roll'' of every wheelset equal the residual to rounding (1e-9 of the residual's
!>      scale), and the residual of the moved wheelset is not small (it would pass a procedure
!>      that returned zeros otherwise).
program test_scene_quasi_static_balance
  use rd_kinds, only: wp
  use rd_error, only: error_t
  use rd_test_support, only: check, stop_on, test_summary, file_text
  use rd_scene, only: scene_t
  use rd_multibody, only: multibody_t
  use rd_body_spec, only: DOF_Z, DOF_ROLL
  implicit none

  character(len=:), allocatable :: qs_text, el_text
  type(scene_t), target :: qs_scene, el_scene
  type(error_t), allocatable :: error
  type(multibody_t), pointer :: qs, el
  real(wp), allocatable :: y(:), ydot(:), zr(:, :), r(:, :), yel(:), ydot_el(:)
  real(wp) :: scale, worst
  integer :: ib, dof, nb, k, ws(4)

  qs_text = file_text('inputs/manchester_v1_tc1.nml')
  el_text = "&include file = 'manchester_v1_tc1.nml' /"
  do k = 1, 4
    el_text = el_text // new_line('a') // "&wheelset name = 'w" // achar(48 + k) // "', normal_contact = 'elastic' /"
  end do
  call qs_scene%load_string(qs_text, 'inputs', error)
  if (.not. allocated(error)) call qs_scene%build(error)
  if (.not. allocated(error)) call qs_scene%initialize(.false., error)
  call stop_on(error, 'the acceptance deck')
  call el_scene%load_string(el_text, 'inputs', error)
  if (.not. allocated(error)) call el_scene%build(error)
  if (.not. allocated(error)) call el_scene%initialize(.false., error)
  call stop_on(error, 'the acceptance deck with elastic normal contact')
  qs => qs_scene%system()
  el => el_scene%system()
  nb = qs%body_count()
  ws = [(k, k = nb - 3, nb)]     ! the four wheelsets are the last bodies of the deck
  call check(all([(any(qs%bodies(ws(k))%quasi_static), k = 1, 4)]), 'the deck''s wheelsets are quasi-static')
  allocate (y(qs%state_size()), ydot(qs%state_size()), zr(2, nb), r(2, nb))
  call qs_scene%get_state(y, error); call stop_on(error, 'state')

  ! (a) at the right-hand side's solution
  call qs%rhs(0.0_wp, y, ydot, error); call stop_on(error, 'rhs')
  zr = reshape([(qs%bodies(ib)%q0([DOF_Z, DOF_ROLL]), ib = 1, nb)], [2, nb])
  call qs%quasi_static_balance(0.0_wp, y, zr, r, error); call stop_on(error, 'balance at the solution')
  write (*, '(a, es10.2)') '(a) largest residual at the solve''s solution [m/s^2, rad/s^2]: ', maxval(abs(r(:, ws)))
  call check(maxval(abs(r(:, ws))) < 1.0e-5_wp, '(a) the residual vanishes at the solve''s solution')

  ! (b) the moved pose, through the elastic model's right-hand side
  zr(1, ws(1)) = zr(1, ws(1)) - 2.0e-5_wp
  zr(2, ws(1)) = zr(2, ws(1)) + 1.0e-4_wp
  call qs%quasi_static_balance(0.0_wp, y, zr, r, error); call stop_on(error, 'balance at the moved pose')
  allocate (yel(el%state_size()), ydot_el(el%state_size()))
  call check(el%body_count() == nb .and. el%state_size() - 2 * el%nfree == qs%state_size() - 2 * qs%nfree, &
             '(b) the elastic deck has the same bodies and element states')
  yel = 0
  do ib = 1, nb
    do dof = 1, 6
      if (el%free_slot(ib, dof) == 0) cycle
      if (qs%free_slot(ib, dof) > 0) then
        ! straight track at t = 0: the rates are the generalized velocities (no frame rotation)
        yel(el%free_slot(ib, dof)) = y(qs%free_slot(ib, dof))
        yel(el%nfree + el%free_slot(ib, dof)) = y(qs%nfree + qs%free_slot(ib, dof))
      else if (dof == DOF_Z) then
        yel(el%free_slot(ib, dof)) = zr(1, ib)
      else if (dof == DOF_ROLL) then
        yel(el%free_slot(ib, dof)) = zr(2, ib)
      else
        call check(.false., '(b) a coordinate free in the elastic deck only is z or roll')
      end if
    end do
  end do
  yel(2 * el%nfree + 1:) = y(2 * qs%nfree + 1:)
  call el%rhs(0.0_wp, yel, ydot_el, error); call stop_on(error, 'elastic rhs')
  scale = maxval(abs(r(:, ws)))
  worst = 0
  do k = 1, 4
    worst = max(worst, abs(ydot_el(el%nfree + el%free_slot(ws(k), DOF_Z)) - r(1, ws(k))), &
                abs(ydot_el(el%nfree + el%free_slot(ws(k), DOF_ROLL)) - r(2, ws(k))))
  end do
  write (*, '(a, 2es11.3, a, es10.2)') '(b) wheelset 1 moved: residual z'''', roll'''' = ', r(:, ws(1)), &
    '; largest difference from the elastic rhs: ', worst
  call check(scale > 10.0_wp, '(b) the moved wheelset is far from its balance (residual above 10 m/s^2)')
  call check(worst <= 1.0e-9_wp * scale, '(b) the residual equals the elastic model''s z'''' and roll''''')
  call qs_scene%destroy()
  call el_scene%destroy()
  call test_summary('test_scene_quasi_static_balance')
end program test_scene_quasi_static_balance
