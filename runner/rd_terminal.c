/* Terminal detection for the runner's progress line (Fortran has no isatty). */
#include <unistd.h>

int rd_stderr_is_terminal(void) { return isatty(STDERR_FILENO); }
