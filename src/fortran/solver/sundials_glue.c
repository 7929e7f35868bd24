/*
 * sundials_glue.c -- the small C layer between raildyn's Fortran integrators
 * (rd_integrator.f90) and the SUNDIALS C API (CVODE, ARKODE/ERKStep).
 *
 * Why C and not SUNDIALS' Fortran 2003 modules: Debian 12's CMake config for the
 * Fortran modules is broken, and the C API survives the SUNDIALS 6 -> 7 renames
 * with a handful of version macros (below). The Fortran side only sees an opaque
 * handle (one per integrator, so two integrators never share state) and calls
 * the rd_glue_* functions through bind(C) interfaces.
 *
 * The right-hand side and the optional Jacobian (analytic, or coloured difference
 * quotients) are computed by two bind(C) Fortran procedures (rd_solver_rhs_callback,
 * rd_solver_jac_callback in rd_sundials_glue.f90). They receive the `user` pointer given at creation, which
 * points to the Fortran wrapper object holding the ode_system_t. Return codes
 * follow SUNDIALS: 0 ok, > 0 recoverable (retry with a smaller step), < 0 fatal.
 *
 * Linear algebra: Debian's SUNDIALS is built without SUNLinSol_LapackDense, so
 * this file provides a custom SUNLinearSolver (type DIRECT) that factors the
 * dense Newton matrix M = I - gamma J with LAPACK dgetrf and solves with dgetrs.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_types.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <arkode/arkode_erkstep.h>

#if SUNDIALS_VERSION_MAJOR >= 7
#include <sundials/sundials_errors.h>
#define RD_SUN_COMM_NULL SUN_COMM_NULL
#else
#define RD_SUN_COMM_NULL NULL
#endif

#ifndef SUNLS_LUFACT_FAIL
#define SUNLS_LUFACT_FAIL 808
#endif
#ifndef SUNLS_MEM_FAIL
#define SUNLS_MEM_FAIL -803
#endif

/* Method identifiers shared with rd_integrator.f90 (glue_method_* parameters). */
enum { RD_GLUE_BDF = 1, RD_GLUE_ADAMS = 2, RD_GLUE_ERK = 3 };

#define RD_GLUE_MSG_LEN 1024

/* Fortran callbacks (rd_integrator.f90). Arrays are contiguous, length n. */
extern int rd_solver_rhs_callback(double t, const double *y, double *ydot, int64_t n,
                                  void *user);
extern int rd_solver_jac_callback(double t, const double *y, const double *fy,
                                  double *jac, int64_t n, double h, const double *ewt,
                                  double *work1, double *work2, void *user);

/* LAPACK (column-major, 32-bit integers as in Debian's reference/OpenBLAS LAPACK). */
extern void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv,
                    int *info);
extern void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info,
                    size_t trans_len);

typedef struct {
  int method;
  int64_t n;
  SUNContext ctx;
  void *mem;              /* CVODE or ERKStep memory */
  N_Vector y;             /* SUNDIALS' working state */
  N_Vector abstol;        /* per-component absolute tolerances (optional) */
  SUNMatrix A;            /* dense Newton matrix (BDF only) */
  SUNLinearSolver LS;     /* custom LAPACK dense solver (BDF only) */
  SUNNonlinearSolver NLS; /* fixed-point iteration (Adams only) */
  void *user;             /* Fortran wrapper object */
  char msg[RD_GLUE_MSG_LEN]; /* last error text reported by SUNDIALS */
  /* ERK only: the last accepted step (for the retry of a recoverable RHS failure, see
   * erk_evolve), whether the last RHS call failed recoverably, the retries so far, and
   * the counters of the ERKStep runs before such a retry's restart */
  N_Vector y_accepted;
  double t_accepted;
  int rhs_recoverable;
  long retries;
  long erk_banked[3]; /* steps, RHS evaluations, error-test failures */
} rd_glue_t;

/* ------------------------------------------------------------------------- */
/* Custom dense LAPACK linear solver                                          */
/* ------------------------------------------------------------------------- */

typedef struct {
  int n;
  int *pivots;
  sunindextype last_flag;
} rd_lapack_content_t;

#define LS_CONTENT(S) ((rd_lapack_content_t *)((S)->content))

static SUNLinearSolver_Type rd_ls_gettype(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID rd_ls_getid(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_CUSTOM;
}

static int rd_ls_initialize(SUNLinearSolver S) {
  LS_CONTENT(S)->last_flag = 0;
  return 0;
}

/* LU factorization in place of the dense matrix data (column-major, ldim = n). */
static int rd_ls_setup(SUNLinearSolver S, SUNMatrix A) {
  rd_lapack_content_t *c = LS_CONTENT(S);
  int n = c->n, info = 0;
  dgetrf_(&n, &n, SUNDenseMatrix_Data(A), &n, c->pivots, &info);
  c->last_flag = info;
  /* info > 0: exactly singular pivot -> recoverable, CVODE retries with smaller h. */
  if (info > 0) return SUNLS_LUFACT_FAIL;
  if (info < 0) return SUNLS_MEM_FAIL;
  return 0;
}

static int rd_ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b,
                       sunrealtype tol) {
  (void)tol;
  rd_lapack_content_t *c = LS_CONTENT(S);
  int n = c->n, one = 1, info = 0;
  double *xd = N_VGetArrayPointer(x);
  const double *bd = N_VGetArrayPointer(b);
  if (xd != bd) memcpy(xd, bd, (size_t)n * sizeof(double));
  dgetrs_("N", &n, &one, SUNDenseMatrix_Data(A), &n, c->pivots, xd, &n, &info, 1);
  c->last_flag = info;
  return info == 0 ? 0 : SUNLS_MEM_FAIL;
}

static sunindextype rd_ls_lastflag(SUNLinearSolver S) { return LS_CONTENT(S)->last_flag; }

static int rd_ls_space(SUNLinearSolver S, long int *lenrw, long int *leniw) {
  *lenrw = 0;
  *leniw = 2 + LS_CONTENT(S)->n;
  return 0;
}

static int rd_ls_free(SUNLinearSolver S) {
  if (S == NULL) return 0;
  if (S->content) {
    free(LS_CONTENT(S)->pivots);
    free(S->content);
    S->content = NULL;
  }
  SUNLinSolFreeEmpty(S);
  return 0;
}

static SUNLinearSolver rd_lapack_dense_solver(int n, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == NULL) return NULL;
  S->ops->gettype = rd_ls_gettype;
  S->ops->getid = rd_ls_getid;
  S->ops->initialize = rd_ls_initialize;
  S->ops->setup = rd_ls_setup;
  S->ops->solve = rd_ls_solve;
  S->ops->lastflag = rd_ls_lastflag;
  S->ops->space = rd_ls_space;
  S->ops->free = rd_ls_free;
  rd_lapack_content_t *c = (rd_lapack_content_t *)calloc(1, sizeof(*c));
  if (c == NULL) {
    SUNLinSolFreeEmpty(S);
    return NULL;
  }
  c->n = n;
  c->pivots = (int *)calloc((size_t)(n > 0 ? n : 1), sizeof(int));
  S->content = c;
  if (c->pivots == NULL) {
    rd_ls_free(S);
    return NULL;
  }
  return S;
}

/* ------------------------------------------------------------------------- */
/* Callbacks handed to SUNDIALS                                               */
/* ------------------------------------------------------------------------- */

static int rd_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data) {
  rd_glue_t *g = (rd_glue_t *)user_data;
  int status = rd_solver_rhs_callback(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot),
                                      g->n, g->user);
  g->rhs_recoverable = status > 0;
  return status;
}

/* ERKStep's post-step hook: remember every accepted step. */
static int rd_erk_accepted(sunrealtype t, N_Vector y, void *user_data) {
  rd_glue_t *g = (rd_glue_t *)user_data;
  N_VScale(1.0, y, g->y_accepted);
  g->t_accepted = t;
  return 0;
}

/* The Jacobian callback also gets what CVODE's own difference quotient uses (its current
 * step h and error weights ewt, in tmp1) and two scratch vectors (tmp2, tmp3), so a
 * coloured difference quotient can choose the same increments without allocating. */
static int rd_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *user_data,
                  N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) {
  rd_glue_t *g = (rd_glue_t *)user_data;
  sunrealtype h = 0.0;
  if (CVodeGetCurrentStep(g->mem, &h) != 0) return -1;
  if (CVodeGetErrWeights(g->mem, tmp1) != 0) return -1;
  return rd_solver_jac_callback(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                                SUNDenseMatrix_Data(J), g->n, h, N_VGetArrayPointer(tmp1),
                                N_VGetArrayPointer(tmp2), N_VGetArrayPointer(tmp3), g->user);
}

/* Keep SUNDIALS' error text for the caller instead of printing it on stderr. */
#if SUNDIALS_VERSION_MAJOR >= 7
static void rd_err_handler(int line, const char *func, const char *file, const char *msg,
                           SUNErrCode err_code, void *err_user_data, SUNContext sunctx) {
  (void)line;
  (void)file;
  (void)err_code;
  (void)sunctx;
  rd_glue_t *g = (rd_glue_t *)err_user_data;
  snprintf(g->msg, RD_GLUE_MSG_LEN, "%s: %s", func ? func : "?", msg ? msg : "");
}
#else
static void rd_err_handler(int error_code, const char *module, const char *function,
                           char *msg, void *eh_data) {
  rd_glue_t *g = (rd_glue_t *)eh_data;
  if (error_code > 0) return; /* warnings (e.g. t + h == t) are not failures */
  snprintf(g->msg, RD_GLUE_MSG_LEN, "%s: %s: %s", module ? module : "?",
           function ? function : "?", msg ? msg : "");
}
#endif

static void rd_glue_note(rd_glue_t *g, const char *what, int flag) {
  snprintf(g->msg, RD_GLUE_MSG_LEN, "%s failed (flag %d)", what, flag);
}

/* ------------------------------------------------------------------------- */
/* Public glue API (bind(C) interfaces in rd_integrator.f90)                  */
/* ------------------------------------------------------------------------- */

void rd_glue_destroy(void *handle) {
  rd_glue_t *g = (rd_glue_t *)handle;
  if (g == NULL) return;
  if (g->mem) {
    if (g->method == RD_GLUE_ERK)
      ERKStepFree(&g->mem);
    else
      CVodeFree(&g->mem);
  }
  if (g->NLS) SUNNonlinSolFree(g->NLS);
  if (g->LS) SUNLinSolFree(g->LS);
  if (g->A) SUNMatDestroy(g->A);
  if (g->abstol) N_VDestroy(g->abstol);
  if (g->y_accepted) N_VDestroy(g->y_accepted);
  if (g->y) N_VDestroy(g->y);
  if (g->ctx) SUNContext_Free(&g->ctx);
  free(g);
}

/* Create an integrator for n states at (t0, y0). Returns NULL on failure with a
 * message in msg (length msglen, NUL-terminated). */
void *rd_glue_create(int method, int64_t n, double t0, const double *y0, void *user,
                     char *msg, int msglen) {
  rd_glue_t *g = (rd_glue_t *)calloc(1, sizeof(*g));
  int flag = 0;
  if (g == NULL) {
    snprintf(msg, (size_t)msglen, "out of memory");
    return NULL;
  }
  g->method = method;
  g->n = n;
  g->user = user;
  if (SUNContext_Create(RD_SUN_COMM_NULL, &g->ctx) != 0) {
    snprintf(msg, (size_t)msglen, "SUNContext_Create failed");
    free(g);
    return NULL;
  }
#if SUNDIALS_VERSION_MAJOR >= 7
  SUNContext_ClearErrHandlers(g->ctx);
  SUNContext_PushErrHandler(g->ctx, rd_err_handler, g);
#endif
  g->y = N_VNew_Serial((sunindextype)n, g->ctx);
  if (g->y == NULL) {
    snprintf(msg, (size_t)msglen, "N_VNew_Serial(%lld) failed", (long long)n);
    rd_glue_destroy(g);
    return NULL;
  }
  memcpy(N_VGetArrayPointer(g->y), y0, (size_t)n * sizeof(double));

  if (method == RD_GLUE_BDF || method == RD_GLUE_ADAMS) {
    g->mem = CVodeCreate(method == RD_GLUE_BDF ? CV_BDF : CV_ADAMS, g->ctx);
    if (g->mem == NULL) {
      snprintf(msg, (size_t)msglen, "CVodeCreate failed");
      rd_glue_destroy(g);
      return NULL;
    }
#if SUNDIALS_VERSION_MAJOR < 7
    CVodeSetErrHandlerFn(g->mem, rd_err_handler, g);
#endif
    flag = CVodeInit(g->mem, rd_rhs, t0, g->y);
    if (flag == 0) flag = CVodeSetUserData(g->mem, g);
    if (flag == 0 && method == RD_GLUE_BDF) {
      /* Modified Newton with a dense Jacobian, factored by LAPACK. */
      g->A = SUNDenseMatrix((sunindextype)n, (sunindextype)n, g->ctx);
      g->LS = rd_lapack_dense_solver((int)n, g->ctx);
      if (g->A == NULL || g->LS == NULL)
        flag = -1;
      else
        flag = CVodeSetLinearSolver(g->mem, g->LS, g->A);
    } else if (flag == 0) {
      /* Adams: functional (fixed-point) iteration, no Jacobian (non-stiff use). */
      g->NLS = SUNNonlinSol_FixedPoint(g->y, 0, g->ctx);
      if (g->NLS == NULL)
        flag = -1;
      else
        flag = CVodeSetNonlinearSolver(g->mem, g->NLS);
    }
  } else if (method == RD_GLUE_ERK) {
    g->mem = ERKStepCreate(rd_rhs, t0, g->y, g->ctx);
    if (g->mem == NULL) {
      snprintf(msg, (size_t)msglen, "ERKStepCreate failed");
      rd_glue_destroy(g);
      return NULL;
    }
#if SUNDIALS_VERSION_MAJOR < 7
    ERKStepSetErrHandlerFn(g->mem, rd_err_handler, g);
#endif
    flag = ERKStepSetUserData(g->mem, g);
    /* Dormand-Prince 5(4), 7 stages, FSAL (Dormand & Prince 1980). */
    if (flag == 0) flag = ERKStepSetTableNum(g->mem, ARKODE_DORMAND_PRINCE_7_4_5);
    g->y_accepted = N_VClone(g->y);
    if (g->y_accepted == NULL) flag = -1;
    else rd_erk_accepted(t0, g->y, g);
    if (flag == 0) flag = ERKStepSetPostprocessStepFn(g->mem, rd_erk_accepted);
  } else {
    snprintf(msg, (size_t)msglen, "unknown glue method id %d", method);
    rd_glue_destroy(g);
    return NULL;
  }
  if (flag != 0) {
    snprintf(msg, (size_t)msglen, "setting up the integrator failed (flag %d)%s%s", flag,
             g->msg[0] ? ": " : "", g->msg);
    rd_glue_destroy(g);
    return NULL;
  }
  return g;
}

/* Scalar or per-component tolerances (atol_vec may be NULL). */
int rd_glue_set_tolerances(void *handle, double rtol, double atol, const double *atol_vec) {
  rd_glue_t *g = (rd_glue_t *)handle;
  int flag;
  if (atol_vec != NULL) {
    if (g->abstol == NULL) g->abstol = N_VNew_Serial((sunindextype)g->n, g->ctx);
    if (g->abstol == NULL) return -1;
    memcpy(N_VGetArrayPointer(g->abstol), atol_vec, (size_t)g->n * sizeof(double));
    flag = g->method == RD_GLUE_ERK ? ERKStepSVtolerances(g->mem, rtol, g->abstol)
                                    : CVodeSVtolerances(g->mem, rtol, g->abstol);
  } else {
    flag = g->method == RD_GLUE_ERK ? ERKStepSStolerances(g->mem, rtol, atol)
                                    : CVodeSStolerances(g->mem, rtol, atol);
  }
  if (flag != 0) rd_glue_note(g, "setting the tolerances", flag);
  return flag;
}

/* Step limits; a zero value keeps SUNDIALS' default (no limit / automatic). */
int rd_glue_set_limits(void *handle, double max_step, double min_step, double init_step,
                       long max_num_steps, int max_order) {
  rd_glue_t *g = (rd_glue_t *)handle;
  int flag = 0;
  if (g->method == RD_GLUE_ERK) {
    if (flag == 0) flag = ERKStepSetMaxStep(g->mem, max_step);
    if (flag == 0) flag = ERKStepSetMinStep(g->mem, min_step);
    if (flag == 0) flag = ERKStepSetInitStep(g->mem, init_step);
    if (flag == 0) flag = ERKStepSetMaxNumSteps(g->mem, max_num_steps);
  } else {
    if (flag == 0) flag = CVodeSetMaxStep(g->mem, max_step);
    if (flag == 0) flag = CVodeSetMinStep(g->mem, min_step);
    if (flag == 0) flag = CVodeSetInitStep(g->mem, init_step);
    if (flag == 0) flag = CVodeSetMaxNumSteps(g->mem, max_num_steps);
    if (flag == 0 && max_order > 0) flag = CVodeSetMaxOrd(g->mem, max_order);
  }
  if (flag != 0) rd_glue_note(g, "setting the step limits", flag);
  return flag;
}

/* BDF: at most max_age steps between two Jacobian evaluations (CVODE's msbj, default 51);
 * CVODE evaluates it sooner after a Newton convergence failure with an old one. */
int rd_glue_set_jacobian_age(void *handle, long max_age) {
  rd_glue_t *g = (rd_glue_t *)handle;
  if (g->method != RD_GLUE_BDF) return 0;
  int flag = CVodeSetJacEvalFrequency(g->mem, max_age);
  if (flag != 0) rd_glue_note(g, "CVodeSetJacEvalFrequency", flag);
  return flag;
}

/* Use the Fortran Jacobian callback instead of CVODE's difference quotients. */
int rd_glue_use_jacobian(void *handle) {
  rd_glue_t *g = (rd_glue_t *)handle;
  if (g->method != RD_GLUE_BDF) return 0;
  int flag = CVodeSetJacFn(g->mem, rd_jac);
  if (flag != 0) rd_glue_note(g, "CVodeSetJacFn", flag);
  return flag;
}

/* Integrate to tout, never stepping past tstop (>= tout; tstop = tout: land exactly on
 * tout). With tstop > tout the method takes its own steps (as far as tstop at most) and
 * y_out is its interpolant at tout: intermediate samples that cost no extra steps. On
 * success y_out gets the solution at *t_reached = tout. On failure *t_reached is the last
 * time the integrator reached and y_out its solution there (interpolated from the
 * method's own history, order 0 = the accepted state), or *valid = 0 if that is not
 * available. */
/* ERKStepEvolve with the retry that ERKStep (SUNDIALS 6) lacks: a right-hand side that
 * fails recoverably (rd_error's retry errors: e.g. the quasi-static contact solve did not
 * converge at a stage's state) ends ERKStep with ARK_UNREC_RHSFUNC_ERR, where CVODE would
 * retry with a smaller step. Do what CVODE does: restart from the last accepted step with a
 * quarter of the step that failed. At most max_retries restarts for one obstacle (CVODE's
 * default limit of convergence failures per step is 10): the count starts again only once an
 * accepted step has passed the time of the last failure, so a failure that no step size
 * avoids (a NaN from some time on) ends after max_retries restarts instead of creeping up to
 * it in ever shorter steps. The restarts' counters are banked (rd_glue_get_stats reports the
 * sums). */
static int erk_evolve(rd_glue_t *g, double tout, double tstop, sunrealtype *tret) {
  const int max_retries = 10;
  int flag, in_a_row = 0;
  sunrealtype t_failed = 0.0;
  for (;;) {
    sunrealtype h = 0.0, t_now = 0.0;
    long v = 0;
    flag = ERKStepSetStopTime(g->mem, tstop);
    g->rhs_recoverable = 0;
    if (flag == 0) flag = ERKStepEvolve(g->mem, tout, g->y, tret, ARK_NORMAL);
    if (flag == ARK_TSTOP_RETURN) flag = ARK_SUCCESS;
    if (flag != ARK_UNREC_RHSFUNC_ERR || !g->rhs_recoverable) return flag;
    if (ERKStepGetCurrentStep(g->mem, &h) != 0 || h == 0.0) return flag;
    if (ERKStepGetCurrentTime(g->mem, &t_now) != 0) t_now = g->t_accepted + h;
    if (in_a_row > 0 && g->t_accepted > t_failed) in_a_row = 0;
    if (++in_a_row > max_retries) return flag;
    t_failed = t_now;
    if (ERKStepGetNumSteps(g->mem, &v) == 0) g->erk_banked[0] += v;
    if (ERKStepGetNumRhsEvals(g->mem, &v) == 0) g->erk_banked[1] += v;
    if (ERKStepGetNumErrTestFails(g->mem, &v) == 0) g->erk_banked[2] += v;
    N_VScale(1.0, g->y_accepted, g->y);
    if (ERKStepReInit(g->mem, rd_rhs, g->t_accepted, g->y) != 0) return flag;
    if (ERKStepSetInitStep(g->mem, 0.25 * h) != 0) return flag;
    g->retries += 1;
  }
}

int rd_glue_advance(void *handle, double tout, double tstop, double *y_out, double *t_reached,
                    int *valid) {
  rd_glue_t *g = (rd_glue_t *)handle;
  sunrealtype tret = 0.0, tcur = 0.0;
  int flag;
  g->msg[0] = '\0';
  *valid = 1;
  if (g->method == RD_GLUE_ERK) {
    flag = erk_evolve(g, tout, tstop, &tret);
    if (flag < 0) {
      /* The output vector is not updated on failure: ask for the state at the time
       * reached. Interpolation needs a step taken and may be unavailable after a failed
       * RHS call (6.4: "Error calling arkInterpEvaluate"); then the caller keeps the
       * previous output. Keep SUNDIALS' message about the real failure. */
      char saved[RD_GLUE_MSG_LEN];
      long nst = 0;
      memcpy(saved, g->msg, sizeof(saved));
      *valid = ERKStepGetNumSteps(g->mem, &nst) == 0 && nst > 0 &&
               ERKStepGetCurrentTime(g->mem, &tcur) == 0 &&
               ERKStepGetDky(g->mem, tcur, 0, g->y) == 0;
      memcpy(g->msg, saved, sizeof(saved));
      if (*valid) tret = tcur;
    }
  } else {
    flag = CVodeSetStopTime(g->mem, tstop);
    if (flag == 0) flag = CVode(g->mem, tout, g->y, &tret, CV_NORMAL);
    if (flag == CV_TSTOP_RETURN) flag = CV_SUCCESS;
    if (flag < 0) {
      char saved[RD_GLUE_MSG_LEN];
      long nst = 0;
      memcpy(saved, g->msg, sizeof(saved));
      *valid = CVodeGetNumSteps(g->mem, &nst) == 0 && nst > 0 &&
               CVodeGetCurrentTime(g->mem, &tcur) == 0 &&
               CVodeGetDky(g->mem, tcur, 0, g->y) == 0;
      memcpy(g->msg, saved, sizeof(saved));
      if (*valid) tret = tcur;
    }
  }
  *t_reached = tret;
  if (*valid) memcpy(y_out, N_VGetArrayPointer(g->y), (size_t)g->n * sizeof(double));
  return flag;
}

/* Restart from (t0, y0), e.g. after a discontinuity; keeps all settings. */
int rd_glue_reinit(void *handle, double t0, const double *y0) {
  rd_glue_t *g = (rd_glue_t *)handle;
  int flag;
  memcpy(N_VGetArrayPointer(g->y), y0, (size_t)g->n * sizeof(double));
  if (g->method == RD_GLUE_ERK) {
    /* a restart from outside: its own first step, counters and restart point */
    flag = ERKStepSetInitStep(g->mem, 0.0);
    if (flag == 0) flag = ERKStepReInit(g->mem, rd_rhs, t0, g->y);
    g->erk_banked[0] = g->erk_banked[1] = g->erk_banked[2] = 0;
    g->retries = 0;
    rd_erk_accepted(t0, g->y, g);
  } else {
    flag = CVodeReInit(g->mem, t0, g->y);
  }
  if (flag != 0) rd_glue_note(g, "reinit", flag);
  return flag;
}

/* Counters since the last (re)initialisation:
 * counts[0] steps, [1] RHS evaluations by the method, [2] RHS evaluations for the
 * difference-quotient Jacobian, [3] Jacobian evaluations, [4] linear solver setups,
 * [5] error-test failures, [6] nonlinear convergence failures, [7] last order,
 * [8] restarts after a recoverable RHS failure (ERK only, erk_evolve).
 * reals[0] last step size, [1] step size to be tried next, [2] current time. */
int rd_glue_get_stats(void *handle, long *counts, double *reals) {
  rd_glue_t *g = (rd_glue_t *)handle;
  long v = 0;
  int q = 0;
  sunrealtype r = 0.0;
  for (int i = 0; i < 9; ++i) counts[i] = 0;
  for (int i = 0; i < 3; ++i) reals[i] = 0.0;
  if (g->method == RD_GLUE_ERK) {
    if (ERKStepGetNumSteps(g->mem, &v) == 0) counts[0] = g->erk_banked[0] + v;
    if (ERKStepGetNumRhsEvals(g->mem, &v) == 0) counts[1] = g->erk_banked[1] + v;
    if (ERKStepGetNumErrTestFails(g->mem, &v) == 0) counts[5] = g->erk_banked[2] + v;
    counts[7] = 5;
    counts[8] = g->retries;
    if (ERKStepGetLastStep(g->mem, &r) == 0) reals[0] = r;
    if (ERKStepGetCurrentStep(g->mem, &r) == 0) reals[1] = r;
    if (ERKStepGetCurrentTime(g->mem, &r) == 0) reals[2] = r;
  } else {
    if (CVodeGetNumSteps(g->mem, &v) == 0) counts[0] = v;
    if (CVodeGetNumRhsEvals(g->mem, &v) == 0) counts[1] = v;
    if (g->method == RD_GLUE_BDF) {
      if (CVodeGetNumLinRhsEvals(g->mem, &v) == 0) counts[2] = v;
      if (CVodeGetNumJacEvals(g->mem, &v) == 0) counts[3] = v;
    }
    if (CVodeGetNumLinSolvSetups(g->mem, &v) == 0) counts[4] = v;
    if (CVodeGetNumErrTestFails(g->mem, &v) == 0) counts[5] = v;
    if (CVodeGetNumNonlinSolvConvFails(g->mem, &v) == 0) counts[6] = v;
    if (CVodeGetLastOrder(g->mem, &q) == 0) counts[7] = q;
    if (CVodeGetLastStep(g->mem, &r) == 0) reals[0] = r;
    if (CVodeGetCurrentStep(g->mem, &r) == 0) reals[1] = r;
    if (CVodeGetCurrentTime(g->mem, &r) == 0) reals[2] = r;
  }
  return 0;
}

/* Name of a return flag (e.g. "CV_TOO_MUCH_WORK") into buf. */
void rd_glue_flag_name(void *handle, int flag, char *buf, int buflen) {
  rd_glue_t *g = (rd_glue_t *)handle;
  char *name = (g != NULL && g->method == RD_GLUE_ERK) ? ERKStepGetReturnFlagName(flag)
                                                        : CVodeGetReturnFlagName(flag);
  snprintf(buf, (size_t)buflen, "%s", name ? name : "unknown flag");
  free(name);
}

/* The last error text SUNDIALS reported for this integrator ("" if none). */
void rd_glue_last_message(void *handle, char *buf, int buflen) {
  rd_glue_t *g = (rd_glue_t *)handle;
  snprintf(buf, (size_t)buflen, "%s", g->msg);
}
