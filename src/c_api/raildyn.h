/*
 * raildyn C API: create a scene from a deck, step it, read outputs, set inputs.
 *
 * Handles are opaque (NEKO style): an integer that names a Fortran model object.
 * There is no module-global simulation state: any number of models may live in one
 * process. Every call returns an integer status (RD_OK = 0 on success); after a
 * failure the message is available per handle with rd_error_message().
 *
 * A host survives any call:
 *  - Handles are unique for the life of the process: a destroyed handle is never issued
 *    again, and every call with it (or with any value that no create call returned)
 *    returns RD_ERR_HANDLE; rd_error_message() then says which of the two it is.
 *  - A NULL pointer argument returns RD_ERR_INPUT (message on the handle, naming the
 *    argument), never a crash. Array arguments may be NULL when their size is 0; output
 *    buffers need a length >= 1. rd_create_*() with handle == NULL creates nothing.
 *  - A failed rd_initialize() leaves the model as created (nothing built, a results file
 *    it opened closed with the failure recorded): it may be called again.
 *  - A failed rd_advance() ends the run: the results file is closed with /meta status
 *    "failed: <message>", as `raildyn run` records it; rd_advance(), rd_set_input() and
 *    rd_initialize() then return RD_ERR_HANDLE with that message (create a new model to
 *    run again); queries still answer with the last valid state.
 *  - Threads: the library takes no locks. The table of handles is process-wide and
 *    HDF5 is usually built without thread safety: a threaded host serialises its calls.
 * All quantities are SI (docs/conventions.md); names of outputs are listed in
 * docs/output.md and by rd_output_name().
 */
#ifndef RAILDYN_H
#define RAILDYN_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef int64_t rd_handle;

/* Status codes (mirror src/fortran/common/rd_error.f90). */
enum {
  RD_OK = 0,
  RD_ERR_INPUT = 1,    /* bad deck, profile file or argument */
  RD_ERR_RUNTIME = 2,  /* integrator failure, NaN in the state */
  RD_ERR_PHYSICS = 3,  /* derailment, wheel lift-off beyond limits */
  RD_ERR_IO = 4,       /* cannot read or write a file */
  RD_ERR_INTERNAL = 5, /* an invariant of the code broke */
  RD_ERR_HANDLE = 6    /* invalid handle or call order */
};

/* Library version as "MAJOR.MINOR.PATCH" (static storage). */
const char *rd_version(void);

/* Create a model from a deck file, or from deck text (relative paths in the text are
 * resolved against base_dir; NULL or "" means the current directory). On failure a
 * handle is still returned when possible, so that rd_error_message() can explain;
 * destroy it afterwards. *handle is 0 if no handle could be made. */
int rd_create_from_file(const char *deck_path, rd_handle *handle);
int rd_create_from_string(const char *deck_text, const char *base_dir, rd_handle *handle);

/* Build the scene (track, bodies, elements, contact), set the initial state,
 * open the results file (write_output = 1) and write step 0. The results file is the deck's
 * &output file (relative to the deck), or else <deck stem>.h5 in the host's working directory. */
int rd_initialize(rd_handle handle, int write_output);

/* Integrate up to time t_target [s] (>= current time); outputs are written at the
 * deck's output interval on the way. The integrator may step beyond t_target and
 * interpolate it (advancing in many small chunks costs no steps); rd_set_input() and
 * rd_set_state() restart it at the current time, where the change takes effect. */
int rd_advance(rd_handle handle, double t_target);

/* Current simulated time [s]. */
int rd_get_time(rd_handle handle, double *time);

/* State vector of the integrator (free coordinates, their rates, internal states). */
int rd_get_state_size(rd_handle handle, int *size);
int rd_get_state(rd_handle handle, double *state, int size);

/* Replace the state at the current time (after rd_initialize; the integrator restarts
 * there). size must be the state size (rd_get_state_size), values finite: otherwise
 * RD_ERR_INPUT and nothing changes. Layout: docs/output.md, /state/y. */
int rd_set_state(rd_handle handle, const double *state, int size);

/* A restart: before rd_initialize, start the run at time [s] from state instead of the
 * deck's initial state (the static setup still runs: element free lengths and preloads are
 * part of the model). The first output row is (time, state); later rows follow the deck's
 * output grid. Size and finiteness checked as rd_set_state; RD_ERR_HANDLE after
 * rd_initialize. */
int rd_set_start(rd_handle handle, double time, const double *state, int size);

/* The linearised equations of motion about the current time and state: the n x n matrix
 * A = df/dy of the state equation y' = f(t, y), n = rd_get_state_size(), rows and columns
 * in the layout of the state (docs/output.md, /state/y), by central differences of the
 * right-hand side (docs/theory_stability.md), at the running speed in force (the deck's
 * law or rd_set_input "speed"). Row-major: matrix[i * n + j] = d f_i / d y_j (0-based).
 * size must be n * n: otherwise RD_ERR_INPUT and nothing is written. After rd_initialize
 * (RD_ERR_HANDLE before); the model's time and state do not change. Its eigenvalues are the
 * modes `raildyn eigen` reports. */
int rd_linearize(rd_handle handle, double *matrix, int size);

/* Named outputs at the current time: count, names, sizes, values (the state at that time,
 * also when the results file holds interval means, &output mean_samples). */
int rd_output_count(rd_handle handle, int *count);
int rd_output_name(rd_handle handle, int index /* 1-based */, char *name, int name_len);
int rd_output_size(rd_handle handle, const char *name, int *size);
int rd_get_output(rd_handle handle, const char *name, double *values, int size);

/* Set a named input, effective from the current time on. Known inputs:
 *   "speed"                          [m/s]  running speed V (overrides the deck's law)
 *   "body/<name>/external_force"     6 values, force [N] and moment [N m] at the centre of
 *                                     mass, fixed-frame components */
int rd_set_input(rd_handle handle, const char *name, const double *values, int size);

/* Flush and close the output file; the model can still be queried. */
int rd_finalize(rd_handle handle);

/* Message of the last failure on this handle ("" if none); NUL-terminated, truncated
 * to message_len - 1 characters. For an invalid handle: RD_ERR_HANDLE and why it is
 * invalid (destroyed, or never created). Reading it leaves the handle's message as is. */
int rd_error_message(rd_handle handle, char *message, int message_len);

/* The run's notes so far, one per line ("" if none): wheels without contact in some output
 * samples, with their share and the largest sampled vertical force (the lines `raildyn run`
 * prints after "note:", kept in the results file's /meta attribute "notes").
 * NUL-terminated, truncated to notes_len - 1 characters. */
int rd_run_notes(rd_handle handle, char *notes, int notes_len);

/* Free everything the handle owns. An output still open (no rd_finalize()) is closed with
 * /meta status "completed" if the deck's t_end was reached, else "stopped". The handle is
 * invalid from then on (RD_ERR_HANDLE), also for a second rd_destroy(). */
int rd_destroy(rd_handle handle);

#ifdef __cplusplus
}
#endif
#endif /* RAILDYN_H */
