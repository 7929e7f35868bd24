/*
 * raildyn contact mechanics calculators: stateless C functions over the Fortran core
 * (Hertz patch, creep forces of one patch). SI units; frames and signs as
 * docs/conventions.md: x along the rolling direction, y lateral in the contact plane,
 * forces and moment ON THE WHEEL in contact-frame components, spin creepage in 1/m.
 * Every function returns 0 on success and 1 (RD_ERR_INPUT) for bad input, a NULL pointer
 * argument included; outputs are then left untouched. Thread-safe (no global state).
 */
#ifndef RAILDYN_CALCULATORS_H
#define RAILDYN_CALCULATORS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Load kinds for rd_hertz_patch. */
enum { RD_HERTZ_GIVEN_FORCE = 0, RD_HERTZ_GIVEN_PENETRATION = 1 };

/* Warning bits reported by rd_hertz_patch (mirror src/fortran/contact/normal/rd_hertz.f90). */
enum {
  RD_HERTZ_WARN_CLAMPED_ROLLING = 1, /* relative curvature along x <= minimum: clamped */
  RD_HERTZ_WARN_CLAMPED_LATERAL = 2, /* relative curvature along y <= minimum: clamped */
  RD_HERTZ_WARN_ELONGATED = 4,       /* a/b outside [0.1, 10] */
  RD_HERTZ_WARN_BAD_INPUT = 8        /* NaN/Inf input */
};

/* Hertz contact patch, same material for wheel and rail.
 * curvatures[4] = {kappa_wheel_x, kappa_wheel_y, kappa_rail_x, kappa_rail_y} [1/m],
 * signed (convex > 0). young_modulus [Pa], poisson_ratio in [0, 0.5).
 * load_kind RD_HERTZ_GIVEN_FORCE: load = normal force [N];
 * RD_HERTZ_GIVEN_PENETRATION: load = approach [m] (<= 0 gives an empty patch).
 * Outputs: semi-axes a (rolling direction) and b [m], normal force [N], approach [m],
 * peak pressure p0 [Pa], normal stiffness dN/d(approach) [N/m], warning bits. */
int rd_hertz_patch(const double curvatures[4], double young_modulus, double poisson_ratio,
                   int load_kind, double load, double *a, double *b, double *normal_force,
                   double *approach, double *p0, double *stiffness, int *warning);

/* Creep forces of one elliptic patch by the named law: "linear", "fastsim" or "polach".
 * a, b [m]; normal_force [N]; G [Pa]; nu; mu; xi, eta [-]; phi [1/m];
 * grid = FASTSIM elements per direction (ignored by the other laws; <= 0 means 20).
 * Outputs fx, fy [N], mz [N m] on the wheel, contact frame. */
int rd_creep_forces(const char *law, double a, double b, double normal_force, double G,
                    double nu, double mu, double xi, double eta, double phi, int grid,
                    double *fx, double *fy, double *mz);

#ifdef __cplusplus
}
#endif

#endif /* RAILDYN_CALCULATORS_H */
