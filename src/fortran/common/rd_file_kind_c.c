/* The kind of a file system entry, for rd_file_kind (Fortran's INQUIRE cannot tell a
 * directory, a FIFO or a device from a regular file). */
#include <sys/stat.h>

/* 0: does not exist (or cannot be examined), 1: regular file, 2: directory, 3: other
 * (FIFO, device, socket). Symbolic links are followed. */
int rd_file_kind_c(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return 0;
    if (S_ISREG(st.st_mode)) return 1;
    if (S_ISDIR(st.st_mode)) return 2;
    return 3;
}
