"""Independent linear formulations for the TGV cases: steady curving and lateral stability
of the wheelset, bogie and vehicle in the lateral/yaw plane (knife-edge contact)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

#: TGV 001 bogie data used by the linear steady-curving model (same numbers as
#: inputs/vehicles/tgv001_bogie.nml, kept in sync by tests/python/test_validation_rules.py):
#: wheelset and bogie frame masses (table 5.8), primary kx, ky per spring (table 5.4), primary
#: spring lateral semi-spacing dp and semi-wheelbase l (deck ASSUMPTIONs), r0, e0, cone slope
#: (table 5.7).
TGV_BOGIE = dict(m_w=1500.0, m_b=3020.0, kx=3.90e7, ky=7.85e6, dp=1.0, l=1.5, r0=0.45, e0=0.75,
                 lam=0.10033)
#: Complete TGV 001 (inputs/vehicles/tgv001_vehicle.nml): car body mass (table 5.1), secondary
#: kx, ky per spring (table 5.6) at +-ds laterally, bogie pivots at +-pivot (deck ASSUMPTIONs).
TGV_VEHICLE = dict(m_c=43200.0, kx_s=1.73e5, ky_s=1.73e5, ds=1.0, pivot=9.35)


@dataclass
class PlanarBody:
    name: str
    x: float                 #: longitudinal position of its track frame in the vehicle [m]
    mass: float
    wheelset: bool = False


@dataclass
class PlanarSpring:
    body_a: str
    body_b: str
    x: float                 #: longitudinal position of the attachment in the vehicle [m]
    k_lat: float             #: total lateral stiffness [N/m]
    k_yaw: float             #: total yaw stiffness (sum of kx d^2) [N m/rad]


def steady_curving(bodies: Sequence[PlanarBody], springs: Sequence[PlanarSpring], f11: float, f22: float,
                   radius: float, a_q: float, r0: float, e0: float, lam: float) -> dict[str, tuple[float, float]]:
    """Quasi-static curving of a vehicle with conical wheelsets, linear creep and linear
    springs, in the lateral/yaw plane (the classical linear model, e.g. Wickens 2003 ch. 6;
    Iwnicki (ed.) 2006, Handbook of Railway Vehicle Dynamics, ch. 8). Every body is written in
    its own track frame at x_b, like raildyn's bodies: y to the left, yaw nose left, left-hand
    curve (curvature 1/radius > 0). A point of body b at vehicle position X lies, in the track
    frame at X, at y_b + psi_b (X - x_b) - (X - x_b)^2 / (2R) with yaw psi_b - (X - x_b)/R
    (the track bends towards the curve centre and its tangent turns). Wheelsets:

    - longitudinal creepages xi_L,R = -+(e0/R + lam y/r0): yaw moment -2 f11 e0 (e0/R + lam y/r0);
    - lateral creepage eta = -psi: lateral force 2 f22 psi (spin neglected: it cancels between
      the wheels of a cone);

    and the uncompensated lateral acceleration a_q = V^2/R cos(phi) - g sin|phi| loads every
    mass (-m a_q along y). Returns {body: (y, psi)} [m, rad]."""
    kap = 1.0 / radius
    idx = {b.name: i for i, b in enumerate(bodies)}
    n = 2 * len(bodies)
    A = np.zeros((n, n))
    rhs = np.zeros(n)
    for i, b in enumerate(bodies):
        rhs[2 * i] += b.mass * a_q
        if b.wheelset:
            A[2 * i, 2 * i + 1] += 2 * f22
            A[2 * i + 1, 2 * i] += -2 * f11 * e0 * lam / r0
            rhs[2 * i + 1] += 2 * f11 * e0 * e0 * kap

    def disp(b: PlanarBody, X: float):
        """(coefficients of y, psi; constant) of the lateral displacement and of the yaw at X."""
        d = X - b.x
        return (1.0, d, -kap * d * d / 2), (0.0, 1.0, -kap * d)

    for s in springs:
        ib = idx[s.body_b]
        (ly_b, lp_b, lc_b), (_, yp_b, yc_b) = disp(bodies[ib], s.x)
        # relative lateral displacement delta = d_b - d_a, relative yaw theta = th_b - th_a;
        # 'ground' is body b's own track frame (conventions.md), fixed: d_a = th_a = 0
        dcoef = {(ib, 0): ly_b, (ib, 1): lp_b}
        tcoef = {(ib, 1): yp_b}
        dconst, tconst = lc_b, yc_b
        pairs = [(ib, -1.0)]
        if s.body_a != "ground":
            ia = idx[s.body_a]
            (ly_a, lp_a, lc_a), (_, yp_a, yc_a) = disp(bodies[ia], s.x)
            dcoef.update({(ia, 0): -ly_a, (ia, 1): -lp_a})
            tcoef[(ia, 1)] = -yp_a
            dconst -= lc_a
            tconst -= yc_a
            pairs.append((ia, 1.0))
        # body b: force -k delta, moment (X - x_b)(-k delta) - k_yaw theta; body a: opposite
        for body, sgn in pairs:
            lever = s.x - bodies[body].x
            for (j, c), v in dcoef.items():
                A[2 * body, 2 * j + c] += sgn * s.k_lat * v
                A[2 * body + 1, 2 * j + c] += sgn * s.k_lat * lever * v
            for (j, c), v in tcoef.items():
                A[2 * body + 1, 2 * j + c] += sgn * s.k_yaw * v
            rhs[2 * body] -= sgn * s.k_lat * dconst
            rhs[2 * body + 1] -= sgn * (s.k_lat * lever * dconst + s.k_yaw * tconst)
    u = np.linalg.solve(A, rhs)
    return {b.name: (float(u[2 * i]), float(u[2 * i + 1])) for i, b in enumerate(bodies)}


def tgv_planar_model(kind: str, p: dict | None = None) -> tuple[list[PlanarBody], list[PlanarSpring]]:
    """The TGV 001 single wheelset on its primary springs to the track frame ('wheelset',
    inputs/tgv_wheelset.nml), bogie ('bogie', bogie centre at 0) or complete vehicle
    ('vehicle', car body centre at 0) for ``steady_curving`` / ``lateral_stability``, from
    TGV_BOGIE (or the bogie data ``p``) and TGV_VEHICLE."""
    p, q = p or TGV_BOGIE, TGV_VEHICLE
    if kind == "wheelset":
        return ([PlanarBody("ws1", 0.0, p["m_w"], wheelset=True)],
                [PlanarSpring("ground", "ws1", 0.0, 2 * p["ky"], 2 * p["kx"] * p["dp"] ** 2)])
    if kind not in ("bogie", "vehicle"):
        raise ValueError(f"tgv_planar_model: kind {kind!r}; expected 'wheelset', 'bogie' or 'vehicle'")
    vehicle = kind == "vehicle"
    centres = (q["pivot"], -q["pivot"]) if vehicle else (0.0,)
    bodies, springs = [], []
    k = 0
    for j, xc in enumerate(centres, start=1):
        bodies.append(PlanarBody(f"bogie{j}", xc, p["m_b"]))
        for dx in (p["l"], -p["l"]):
            k += 1
            bodies.append(PlanarBody(f"ws{k}", xc + dx, p["m_w"], wheelset=True))
            springs.append(PlanarSpring(f"bogie{j}", f"ws{k}", xc + dx, 2 * p["ky"], 2 * p["kx"] * p["dp"] ** 2))
        if vehicle:
            springs.append(PlanarSpring("car", f"bogie{j}", xc, 2 * q["ky_s"], 2 * q["kx_s"] * q["ds"] ** 2))
    if vehicle:
        bodies.append(PlanarBody("car", 0.0, q["m_c"]))
    return bodies, springs


#: Number of wheelsets of each planar model.
PLANAR_WHEELSETS = {"wheelset": 1, "bogie": 2, "vehicle": 4}

#: Yaw inertias [kg m2] of the TGV 001 bodies (tables 5.1, 5.8), for the linear stability model.
TGV_YAW_INERTIA = dict(wheelset=799.35, bogie=4063.712, car=2.43e6)
#: TGV secondary lateral damping per spring [N s/m] (table 5.6).
TGV_SECONDARY_CY = 3.5e4
#: Wheelset spin inertia Iyy [kg m2] (table 5.8) and the primary vertical stiffness kz [N/m] and
#: damping cz [N s/m] per spring (table 5.4) at +-dp: the roll restraint of the wheelsets by the
#: bogie frame in the knife-edge terms of ``lateral_stability``. The single-wheelset deck
#: (inputs/tgv_wheelset.nml) has no vertical springs.
TGV_WHEELSET_IYY = 93.75
TGV_PRIMARY_VERTICAL = dict(kz=9.75e5, cz=1.08e4)


@dataclass
class KnifeEdgeContact:
    """The straight-running contact state the knife-edge terms of ``lateral_stability`` need,
    per wheel: Kalker coefficients f11 = G a b C11, f22 = G a b C22 [N], f23 = G (ab)^1.5 C23
    [N m] (thesis eqs. 3.39-3.43) and the normal force N0 [N] of the centred wheelset."""
    f11: float
    f22: float
    f23: float = 0.0
    normal_force: float | None = None      #: None: the static wheel load of the model's masses


def _static_normal_force(kind: str) -> float:
    """Normal force [N] per wheel of a centred wheelset from the masses it carries (Q / cos d,
    spin forces' vertical share neglected): the wheelset, half a bogie frame and for the vehicle
    a quarter of the car body; the single-wheelset deck adds the vehicle's axle load."""
    p, q = TGV_BOGIE, TGV_VEHICLE
    if kind == "wheelset":
        w = p["m_w"] + (q["m_c"] + 2 * p["m_b"]) / 4
    else:
        w = p["m_w"] + p["m_b"] / 2 + (q["m_c"] / 4 if kind == "vehicle" else 0.0)
    return 0.5 * w * STANDARD_GRAVITY / math.cos(math.atan(p["lam"]))


def knife_edge_wheelset_terms(contact: KnifeEdgeContact, speed: float, roll_stiffness: float = 0.0,
                              roll_damping: float = 0.0, iyy: float = TGV_WHEELSET_IYY,
                              p: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Linear lateral force F and yaw moment M on one conical wheelset on knife-edge rails
    (wheels: cones of slope lam = tan d, rails: lines at +-e0), F = -(K q + C q'), q = (y, psi),
    as (K, C), each 2x2 (rows F, M). Derived to first order for rigid contacts (the Hertz
    approach, ~3e-5 m, is neglected against the geometry) and quasi-static roll, every term from
    the rigid-body kinematics of the cone and Kalker's linear law (thesis 3.6, 5.3.3):

    - roll follows the lateral shift: the left rail point lies on the cone at axial coordinate
      e0 - y - r0 phi, so sin(phi) ~ (r_L - r_R)/(2 e0) gives phi = s y, s = lam/(e0 - r0 lam),
      and the rolling radii r_L,R = r0 +- lam_e y with lam_e = lam e0/(e0 - r0 lam) (the
      classical cone model has phi = 0 and lam_e = lam; here +6% for the TGV);
    - longitudinal creepages -+(lam_e y/r0 + e0 psi'/V): yaw moment -2 f11 e0 (lam_e y/r0 + e0 psi'/V);
    - lateral creepage of the wheel's material point, (y' + r0 phi') cos d + e0 phi' sin d in the
      contact plane, minus psi (cos d + lam sin d) from the yawed spin (the contact point sits
      r0 lam psi ahead of the wheel's lowest point): eta = (kap y'/V - psi)/cos d, kap = e0/(e0 - r0 lam);
      on the track's Y axis the lateral creep forces give F_cr = -2 f22 (kap y'/V - psi);
    - load transfer: the roll balance of the wheelset, ell (N_L - N_R) + m_c (Fy_L + Fy_R) +
      M_0 = -Iyy Omega psi' (gyroscopic, Omega = V/r0), with ell = e0 cos d - r0 sin d the lever
      of a normal force and m_c = e0 sin d + r0 cos d that of a lateral creep force (contact
      frame) about the centre of mass, and M_0 = -2 N0 (cos d + m_c s) y - k_roll s y - c_roll s y'
      the moment of the unchanged normal forces moved by y and phi and of the primary vertical
      springs (bogie frame roll neglected). N_L - N_R acts laterally through the inclined
      normals (-sin d each) and through the spin force of the cone, Fs = f23 sin(d)/r0 per wheel
      (outwards), which grows with the load (f23 ~ (ab)^1.5 ~ N): g = Fs/N0 - sin d per newton;
    - the normal forces turned by the roll: -2 N0 cos(d) s y;
    - spin creepages (omega . n / V_ref, thesis 3.6.1.3) sum to (sin d/r0)(lam_e y/r0 + e0 psi'/V)
      + 2 psi' cos(d)/V over the two wheels (lateral force -f23 cos d times that) and give the spin
      moments 2 f23 (kap y'/V - psi); the yaw-rate gyroscopic moment is -Iyy Omega s y'.

    f33 terms (~1e-5 of the others) are left out. With f23 = 0 and N0 = 0 (and the kinematic
    factors set to 1) this is the classical model of Wickens / Iwnicki's handbook ch. 7."""
    p = p or TGV_BOGIE
    e0, r0, lam = p["e0"], p["r0"], p["lam"]
    d = math.atan(lam)
    sd, cd = math.sin(d), math.cos(d)
    f11, f22, f23 = contact.f11, contact.f22, contact.f23
    n0 = contact.normal_force or 0.0
    s = lam / (e0 - r0 * lam)
    lam_e = lam * e0 / (e0 - r0 * lam)
    kap = e0 / (e0 - r0 * lam)
    ell = e0 * cd - r0 * sd
    m_c = e0 * sd + r0 * cd
    g = (f23 * sd / r0 / n0 if n0 > 0 else 0.0) - sd
    omega = speed / r0
    Fq, Fv = np.zeros((2, 2)), np.zeros((2, 2))          # F = Fq q + Fv q'
    cr_q, cr_v = np.array([0.0, 2 * f22]), np.array([-2 * f22 * kap / speed, 0.0])
    Fq[0] += cr_q
    Fv[0] += cr_v
    # load transfer N_L - N_R = dq q + dv q' and its lateral force g (N_L - N_R)
    dq = (-m_c * cr_q / cd + np.array([2 * n0 * (cd + m_c * s) + roll_stiffness * s, 0.0])) / ell
    dv = (-m_c * cr_v / cd + np.array([roll_damping * s, -iyy * omega])) / ell
    Fq[0] += g * dq
    Fv[0] += g * dv
    Fq[0, 0] += -2 * n0 * cd * s
    # spin creep: lateral forces and spin moments
    Fq[0, 0] += -cd * f23 * sd / r0 * lam_e / r0
    Fv[0, 1] += -cd * f23 * (sd / r0 * e0 / speed + 2 * cd / speed)
    Fv[1, 0] += 2 * f23 * kap / speed
    Fq[1, 1] += -2 * f23
    # longitudinal creep and gyroscopic yaw moment
    Fq[1, 0] += -2 * f11 * e0 * lam_e / r0
    Fv[1, 1] += -2 * f11 * e0 ** 2 / speed
    Fv[1, 0] += -iyy * omega * s
    return -Fq, -Fv


def lateral_stability(kind: str, f11: float | KnifeEdgeContact, f22: float | None = None,
                      speed: float = 0.0) -> complex:
    """Least-damped eigenvalue [1/s] of the linear lateral/yaw dynamics of the TGV wheelset,
    bogie or vehicle on straight track, with the bodies and springs of ``tgv_planar_model``:
    body masses and yaw inertias, springs between attachment points (lateral k at lever
    X - x_b, yaw k), secondary lateral dampers, and per wheelset the knife-edge contact of
    ``knife_edge_wheelset_terms`` (Wickens 1965 / Iwnicki's handbook ch. 7 extended by the
    knife-edge roll kinematics, load transfer, spin creep and gyroscopic terms, which shift the
    growth rate of the TGV bogie by more than its size: docs/validation.md). ``f11`` is either
    a KnifeEdgeContact or f11 [N] with ``f22`` [N] (then f23 = 0 and the static wheel load).
    Real part > 0: the motion grows (hunting)."""
    if isinstance(f11, KnifeEdgeContact):
        contact = f11
    elif f22 is None:
        raise ValueError("lateral_stability: f22 missing; expected f11, f22 [N] or a KnifeEdgeContact")
    else:
        contact = KnifeEdgeContact(float(f11), float(f22))
    if contact.normal_force is None:
        contact = KnifeEdgeContact(contact.f11, contact.f22, contact.f23, _static_normal_force(kind))
    if not speed > 0:
        raise ValueError(f"lateral_stability: speed {speed!r} m/s; expected > 0")
    p = TGV_BOGIE
    roll_k = roll_c = 0.0
    if kind != "wheelset":        # wheelset deck: ground springs without kz (its header)
        roll_k = 2 * TGV_PRIMARY_VERTICAL["kz"] * p["dp"] ** 2
        roll_c = 2 * TGV_PRIMARY_VERTICAL["cz"] * p["dp"] ** 2
    kw, cw = knife_edge_wheelset_terms(contact, speed, roll_k, roll_c)
    bodies, springs = tgv_planar_model(kind)
    n = 2 * len(bodies)
    M, C, K = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    idx = {b.name: i for i, b in enumerate(bodies)}
    for i, b in enumerate(bodies):
        M[2 * i, 2 * i] = b.mass
        kind_b = "wheelset" if b.wheelset else ("car" if b.name == "car" else "bogie")
        M[2 * i + 1, 2 * i + 1] = TGV_YAW_INERTIA[kind_b]
        if b.wheelset:
            K[2 * i:2 * i + 2, 2 * i:2 * i + 2] += kw
            C[2 * i:2 * i + 2, 2 * i:2 * i + 2] += cw
    for s in springs:
        ib = idx[s.body_b]
        d = np.zeros(n)      # relative lateral displacement at the attachment: d . q
        d[2 * ib], d[2 * ib + 1] = 1.0, s.x - bodies[ib].x
        r = np.zeros(n)      # relative yaw
        r[2 * ib + 1] = 1.0
        if s.body_a != "ground":          # ground: body b's track frame, fixed
            ia = idx[s.body_a]
            d[2 * ia], d[2 * ia + 1] = -1.0, -(s.x - bodies[ia].x)
            r[2 * ia + 1] = -1.0
        K += s.k_lat * np.outer(d, d) + s.k_yaw * np.outer(r, r)
        if s.body_a == "car":
            C += 2 * TGV_SECONDARY_CY * np.outer(d, d)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    ev = np.linalg.eigvals(A)
    return complex(ev[int(np.argmax(ev.real))])


def linear_critical_speed(kind: str, f11: float | KnifeEdgeContact, f22: float | None = None, lo: float = 1.0,
                          hi: float = 300.0) -> float:
    """Lowest speed [m/s] at which ``lateral_stability`` turns unstable (scan, then bisection
    to 0.01 m/s); inf if stable up to ``hi``. Arguments as ``lateral_stability``."""
    grid = np.linspace(lo, hi, 300)
    unstable = [v for v in grid if lateral_stability(kind, f11, f22, v).real > 0]
    if not unstable:
        return math.inf
    b = unstable[0]
    a = grid[max(int(np.searchsorted(grid, b)) - 1, 0)]
    if lateral_stability(kind, f11, f22, a).real > 0:
        return float(a)
    while b - a > 0.01:
        m = 0.5 * (a + b)
        if lateral_stability(kind, f11, f22, m).real > 0:
            b = m
        else:
            a = m
    return 0.5 * (a + b)


def steady_curving_bogie(f11: float, f22: float, radius: float, a_q: float, p: dict | None = None) -> dict:
    """``steady_curving`` of the TGV bogie (or the bogie data ``p``): y1, psi1, y2, psi2, yb, psib."""
    p = {**TGV_BOGIE, **(p or {})}
    s = steady_curving(*tgv_planar_model("bogie", p), f11, f22, radius, a_q, p["r0"], p["e0"], p["lam"])
    return dict(y1=s["ws1"][0], psi1=s["ws1"][1], y2=s["ws2"][0], psi2=s["ws2"][1],
                yb=s["bogie1"][0], psib=s["bogie1"][1])


#: Gravity of the decks (&simulation gravity default = rd_kinds standard_gravity) [m/s^2].
STANDARD_GRAVITY = 9.80665

#: Designed track curve (inputs/tracks/tgv_designed_track.nml): radius, cant, cant base.
TGV_CURVE = dict(radius=1000.0, cant=0.050, cant_base=1.5)
