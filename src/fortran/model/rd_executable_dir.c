/* The directory of the running executable, so that an installed runner finds the Python
   package installed beside it (rd_build_info). Linux: /proc/self/exe with symbolic links
   resolved. Writes the directory (no terminating NUL) and returns its length; 0 when it is
   unknown or longer than capacity: the caller then uses the build tree's package. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

int rd_executable_dir(char *buffer, int capacity) {
  char path[PATH_MAX];
  char *slash;
  size_t length;
  if (realpath("/proc/self/exe", path) == NULL) return 0;
  slash = strrchr(path, '/');
  if (slash == NULL) return 0;
  *slash = '\0';
  length = strlen(path);
  if (length == 0 || length > (size_t)capacity) return 0;
  memcpy(buffer, path, length);
  return (int)length;
}
