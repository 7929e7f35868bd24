!> The `raildyn` command: one executable, one sub-command per task.
!>
!>   raildyn run DECK [-o OUT.h5] [--progress|--quiet]   run a scene
!>   raildyn check DECK [--json]                          validate a deck (and build the scene)
!>   raildyn track DECK [-o OUT.h5] [--step DS] [--csv OUT.csv] [--plot OUT.png]
!>   raildyn profile-scan ...                             wheel-rail contact characteristics
!>   raildyn eigen DECK [--speed V | --speeds ...] ...    linear modes, root locus
!>   raildyn conicity --delta-r FILE --r0 R0 --e0 E0      EN 15302 conicity of a Delta r table
!>   raildyn export RESULTS.h5 --csv DIR                  one CSV per series (raildyn.export)
!>   raildyn assess RESULTS.h5 [--json] [--csv DIR] [--html DIR]   EN 14363 / EN 12299 (raildyn.assess)
!>   raildyn hertz ... / raildyn creep ...                contact calculators
!>   raildyn version | help
!>
!> Exit status: 0 success; otherwise the error class of docs/conventions (1 input,
!> 2 runtime, 3 physics limit, 4 i/o, 5 internal); bad usage gives 1 with a usage line.
program raildyn
  use rd_runner_commands, only: run_command
  implicit none
  integer :: nargs, i, status
  character(len=:), allocatable :: args(:)
  integer :: maxlen, l

  nargs = command_argument_count()
  maxlen = 1
  do i = 1, nargs
    call get_command_argument(i, length=l)
    maxlen = max(maxlen, l)
  end do
  allocate (character(len=maxlen) :: args(nargs))
  do i = 1, nargs
    call get_command_argument(i, args(i))
  end do
  call run_command(args, status)
  if (status /= 0) call exit(status)
end program raildyn
