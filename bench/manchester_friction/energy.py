#!/usr/bin/env python3
"""Work per cycle of wheelset 1's forces in the friction-0.6 flange cycle
(docs/theory_flange_chatter.md section 12; issue 12 item 2 asks for the energy balance).

The balance (`balance`): the work per cycle of each force group on each coordinate of
wheelset 1, the generalized force times the coordinate's rate with the rate's mean over the
cycles removed (the steady drift of x and of the spin deviation would otherwise count the
steady sliding: mean force times mean rate), i.e. what each group gives to (> 0) or takes from
(< 0) the oscillation. Groups: the normal and the creep forces (with the spin moment) of each
wheel, rebuilt in the track frame from the patch slots (normal along (0, sin g, cos g), creep
along x_c and y_c = (0, cos g, -sin g), docs/conventions.md; the rebuilt sum is checked against
the wheel's Y and Q), the two primary suspension elements (force on the wheelset, fixed frame,
turned into the track frame by the track heading, at the axle points (0, +-1, 0)) and gravity
on the height. Generalized forces: track-frame force components on x, y, z; the moment about
the wheelset centre on roll (X), spin (Y) and yaw (Z), a small-angle reading of the angular
coordinates (yaw ~ 15 mrad). The free coordinates' rates are the output's; the quasi-static
height and roll (no rate in the state) are differentiated from the samples. A closed balance
gives, per free coordinate, the sum of the groups = the change of the oscillation's kinetic
energy, and per quasi-static coordinate a sum of zero (massless: its forces balance at every
instant); the residuals are printed (the frame's inertial and gyroscopic terms are left out).

The earlier accounting (`analyse`, kept for comparison), per wheel:

Runs friction_06.nml of this folder to T_END with samples every 0.2 ms (about 36 per cycle of
the 135-139 Hz cycle; wheelsets, patches, bodies and elements only: ~480 MB) unless --results names such a
file, and prints, over the whole cycles in [T0, T_END] (cycles counted by the upward zero
crossings of wheelset 1's lateral shift about its mean):
- the creep forces' work per cycle, v (Fx xi + Fy eta + Mz phi) dt
  (the creep law's slip velocity; always <= 0: the forces oppose the slip), and its part on the
  fluctuation of the slip, with the creepages' means over the window removed (the work of the
  force fluctuations on the slip fluctuations: what the creep forces take from, or give to, the
  cycle), split into longitudinal, lateral and spin;
- the loop work of the normal force, -sum N d(delta) over steps in which the patch keeps its
  kind (section 3: non-zero only where the normal force field is not conservative). This
  assumes that the force acts along the gradient of the penetration; the strips apply it at
  the centroid of the virtual-penetration region (section 3, part 2), so it is not the work
  the force does; the balance above is;
- the cycle's energy scale, 1/2 m v^2 of wheelset 1's lateral velocity amplitude;
- the rates of the quasi-static coordinates (height z and roll, from the sampled positions): the
  creepages leave them out (docs/theory.md "Quasi-static normal contact": the implicit rate
  dz/dt is neglected), and the lateral creepage's own fluctuation, for comparison.

    python3 bench/manchester_friction/energy.py [--build DIR] [--results FILE] [--t0 9.6] [--t-end 10.0]
        [--extra "&solver rtol = 1e-7, atol = 1e-10, atol_velocity = 1e-7 /"]
"""
import argparse
import os
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
#: Manchester wheelset mass [kg] (inputs/vehicles/manchester_v1.nml)
WHEELSET_MASS = 1813.0
#: Manchester wheelset moments of inertia about x, y (axle), z [kg m^2]
WHEELSET_INERTIA = (1120.0, 112.0, 1120.0)
#: primary suspension elements on wheelset 1 and their lateral axle points [m]
PRIMARY = (("prim1l", 1.0), ("prim1r", -1.0))
GRAVITY = 9.81
#: coordinates of the balance: free (in the integrator's state) and quasi-static
FREE = ("x", "y", "yaw", "spin")
QUASI_STATIC = ("z", "roll")


def run(exe: Path, work: Path, t_end: float, extra: str = "") -> Path:
    deck = work / "energy.nml"
    deck.write_text(f"&include file = '{HERE / 'friction_06.nml'}' /\n&simulation t_end = {t_end} /\n"
                    "&output interval = 0.0002, groups = 'wheelsets', 'patches', 'bodies', 'elements' /\n"
                    f"{extra}\n")
    out = work / "energy.h5"
    subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"], check=True)
    return out


def _read(path: Path, t0: float, t_end: float, balance_series: bool = False) -> dict:
    """Wheelset 1's series in [t0, t_end]: time, position, velocity, patches (and, for the
    balance, the heading, the wheel resultants and the primary elements' forces)."""
    with h5py.File(path, "r") as f:
        t = f["time"][...]
        m = (t >= t0) & (t <= t_end + 1e-9)
        d = {"t": t[m], "pos": f["bodies/ws1/position_track"][m], "vel": f["bodies/ws1/velocity_track"][m],
             "patches": {side: [f[f"wheelsets/w1/{side}/patch{j}"][m] for j in range(1, 5)]
                         for side in ("left", "right")}}
        if balance_series:
            d["heading"] = f["bodies/ws1/angles_fixed"][m][:, 0] - d["pos"][:, 3]
            d["wheels"] = {side: f[f"wheelsets/w1/{side}/wheel"][m] for side in ("left", "right")}
            d["primary"] = [(f[f"elements/{name}/force_fixed"][m], ly) for name, ly in PRIMARY]
    return d


def analyse(path: Path, t0: float, t_end: float) -> dict:
    d = _read(path, t0, t_end)
    tt, pos, vel, patches = d["t"], d["pos"], d["vel"], d["patches"]
    sel, n = _cycles(tt, pos[:, 1], t0, t_end)
    ts = tt[sel]

    def per_cycle(q):
        q = q[sel]
        return float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(ts))) / n

    out = {"cycles": n, "frequency": n / (ts[-1] - ts[0]), "wheels": {}}
    for side, slots in patches.items():
        w = {"creep": 0.0, "creep_on_fluctuation": [0.0, 0.0, 0.0], "normal_loop": 0.0, "kinds": set()}
        for p in slots:
            kind = p[:, 0]
            if not (kind[sel] > 0).any():
                continue
            w["kinds"] |= set(int(k) for k in np.unique(kind[sel]) if k > 0)
            v, fx, fy, mz = p[:, 22], p[:, 6], p[:, 7], p[:, 8]
            xi, eta, phi = p[:, 3], p[:, 4], p[:, 5]
            on = kind > 0
            w["creep"] += per_cycle(np.where(on, v * (fx * xi + fy * eta + mz * phi), 0.0))
            for k, (force, creep) in enumerate(((fx, xi), (fy, eta), (mz, phi))):
                w["creep_on_fluctuation"][k] += per_cycle(np.where(on, v * force * (creep - creep[sel & on].mean()), 0.0))
            idx = np.where(sel)[0]
            keep = (kind[idx][1:] == kind[idx][:-1]) & (kind[idx][1:] > 0)
            dw = -0.5 * (p[idx, 2][1:] + p[idx, 2][:-1]) * np.diff(p[idx, 1])
            w["normal_loop"] += float(dw[keep].sum()) / n
            w["slip_lateral_amplitude"] = float(np.std((v * eta)[sel]) * np.sqrt(2.0))
        out["wheels"][side] = w
    vy = vel[sel, 1]
    out["lateral_velocity_amplitude"] = float(vy.max() - vy.min()) / 2
    out["energy_scale"] = 0.5 * WHEELSET_MASS * out["lateral_velocity_amplitude"] ** 2
    zdot = np.gradient(pos[:, 2], tt)[sel]
    rolldot = np.gradient(pos[:, 4], tt)[sel]
    out["z_rate_amplitude"] = float(zdot.max() - zdot.min()) / 2
    out["roll_rate_amplitude"] = float(rolldot.max() - rolldot.min()) / 2
    return out


def _cycles(tt: np.ndarray, y: np.ndarray, t0: float, t_end: float):
    """Whole cycles of y about its mean (upward zero crossings): selection mask and count."""
    yc = y - y.mean()
    up = np.where((yc[:-1] < 0) & (yc[1:] >= 0))[0]
    if len(up) < 3:
        raise SystemExit(f"fewer than two cycles of wheelset 1 in {t0}-{t_end} s: no cycle to measure")
    sel = np.zeros(len(tt), bool)
    sel[up[0]:up[-1] + 1] = True
    return sel, len(up) - 1


def _rotation(yaw: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """Wheelset intermediate frame -> track frame, Rz(yaw) Rx(roll) (docs/conventions.md)."""
    c, s, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
    one, zero = np.ones_like(yaw), np.zeros_like(yaw)
    rz = np.stack([np.stack([c, -s, zero], -1), np.stack([s, c, zero], -1), np.stack([zero, zero, one], -1)], -2)
    rx = np.stack([np.stack([one, zero, zero], -1), np.stack([zero, cr, -sr], -1), np.stack([zero, sr, cr], -1)], -2)
    return rz @ rx


def balance(path: Path, t0: float, t_end: float) -> dict:
    """Work per cycle of each force group on each coordinate of wheelset 1 (module docstring)."""
    d = _read(path, t0, t_end, balance_series=True)
    tt, pos, vel, patches = d["t"], d["pos"], d["vel"], d["patches"]
    heading, wheels, primary = d["heading"], d["wheels"], d["primary"]
    sel, n = _cycles(tt, pos[:, 1], t0, t_end)
    ts = tt[sel]
    rate = {"x": vel[:, 0], "y": vel[:, 1], "yaw": vel[:, 3], "spin": vel[:, 5],
            "z": np.gradient(pos[:, 2], tt), "roll": np.gradient(pos[:, 4], tt)}

    def per_cycle(q):
        q = q[sel]
        return float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(ts))) / n

    # the means by the same trapezoid rule as the work, so that a constant force does no work
    means = {k: per_cycle(v) * n / (ts[-1] - ts[0]) for k, v in rate.items()}
    rate = {k: v - means[k] for k, v in rate.items()}
    rot = _rotation(pos[:, 3], pos[:, 4])

    def work(force, moment):
        gen = {"x": force[:, 0], "y": force[:, 1], "z": force[:, 2],
               "roll": moment[:, 0], "spin": moment[:, 1], "yaw": moment[:, 2]}
        return {k: per_cycle(gen[k] * rate[k]) for k in FREE + QUASI_STATIC}

    groups, rebuild = {}, {}
    for side, slots in patches.items():
        fn, ft, mn, mt = (np.zeros((len(tt), 3)) for _ in range(4))
        for p in slots:
            on = p[:, 0] > 0
            g = p[:, 17]
            normal = np.stack([0 * g, np.sin(g), np.cos(g)], -1)
            lateral = np.stack([0 * g, np.cos(g), -np.sin(g)], -1)
            arm = np.einsum("nij,nj->ni", rot, p[:, 11:14])
            f_n = np.where(on, p[:, 2], 0.0)[:, None] * normal
            f_t = np.where(on, p[:, 6], 0.0)[:, None] * np.array([1.0, 0.0, 0.0]) \
                + np.where(on, p[:, 7], 0.0)[:, None] * lateral
            fn += f_n
            ft += f_t
            mn += np.cross(arm, f_n)
            mt += np.cross(arm, f_t) + np.where(on, p[:, 8], 0.0)[:, None] * normal
        w = wheels[side]
        rebuild[side] = float(max(np.max(np.abs(fn[:, 1] + ft[:, 1] - w[:, 2])),
                                  np.max(np.abs(fn[:, 2] + ft[:, 2] - w[:, 3]))))
        groups[f"{side} normal"] = work(fn, mn)
        groups[f"{side} creep"] = work(ft, mt)
    fs, ms = np.zeros((len(tt), 3)), np.zeros((len(tt), 3))
    c, s = np.cos(heading), np.sin(heading)
    for force_fixed, ly in primary:
        f_track = np.stack([c * force_fixed[:, 0] + s * force_fixed[:, 1],
                            -s * force_fixed[:, 0] + c * force_fixed[:, 1], force_fixed[:, 2]], -1)
        fs += f_track
        ms += np.cross(np.einsum("nij,j->ni", rot, np.array([0.0, ly, 0.0])), f_track)
    groups["suspension"] = work(fs, ms)
    groups["gravity"] = work(np.stack([0 * tt, 0 * tt, -WHEELSET_MASS * GRAVITY + 0 * tt], -1), np.zeros((len(tt), 3)))
    i0, i1 = np.where(sel)[0][[0, -1]]
    kinetic = {}
    for k, col, mass in (("x", 0, WHEELSET_MASS), ("y", 1, WHEELSET_MASS),
                         ("yaw", 3, WHEELSET_INERTIA[2]), ("spin", 5, WHEELSET_INERTIA[1])):
        v = vel[:, col]
        mean = means[k]
        kinetic[k] = (0.5 * mass * (v[i1] ** 2 - v[i0] ** 2) - mass * mean * (v[i1] - v[i0])) / n
    residual = {k: sum(g[k] for g in groups.values()) - kinetic.get(k, 0.0) for k in FREE + QUASI_STATIC}
    return {"cycles": n, "frequency": n / (ts[-1] - ts[0]), "groups": groups, "kinetic": kinetic,
            "residual": residual, "rebuild_error": rebuild}


def render_balance(b: dict) -> str:
    cols = FREE + QUASI_STATIC
    lines = [f"balance per cycle [J] ({b['cycles']} cycles, {b['frequency']:.1f} Hz): > 0 gives energy to the "
             "oscillation of wheelset 1",
             f"{'group':14s}" + "".join(f"{c:>9s}" for c in cols) + f"{'free':>9s}{'quasi-st':>9s}{'all':>9s}"]
    for name, g in b["groups"].items():
        free, qs = sum(g[c] for c in FREE), sum(g[c] for c in QUASI_STATIC)
        lines.append(f"{name:14s}" + "".join(f"{g[c]:9.4f}" for c in cols) + f"{free:9.4f}{qs:9.4f}{free + qs:9.4f}")
    lines.append(f"{'kinetic change':14s}" + "".join(f"{b['kinetic'].get(c, 0.0):9.4f}" for c in cols))
    lines.append(f"{'residual':14s}" + "".join(f"{b['residual'][c]:9.4f}" for c in cols))
    lines.append("rebuilt wheel forces against the wheel series: largest difference "
                 + ", ".join(f"{side} {e:.1e} N" for side, e in b["rebuild_error"].items()))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", type=Path, default=Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")))
    ap.add_argument("--results", type=Path, default=None, help="a results file of such a run (no new run)")
    ap.add_argument("--t0", type=float, default=9.6)
    ap.add_argument("--t-end", type=float, default=10.0)
    ap.add_argument("--extra", default="", help="deck lines added to the run (e.g. tighter &solver tolerances)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="raildyn-energy-") as tmp:
        path = args.results or run(args.build / "bin" / "raildyn", Path(tmp), args.t_end, args.extra)
        r = analyse(path, args.t0, args.t_end)
        b = balance(path, args.t0, args.t_end)
    print(render_balance(b))
    print("the earlier accounting (module docstring):")
    print(f"{r['cycles']} cycles in {args.t0}-{args.t_end} s, {r['frequency']:.1f} Hz; wheelset 1's lateral velocity "
          f"amplitude {r['lateral_velocity_amplitude']:.4f} m/s, 1/2 m v^2 = {r['energy_scale']:.3f} J")
    for side, w in r["wheels"].items():
        cx, cy, cs = w["creep_on_fluctuation"]
        print(f"{side} wheel (patch kinds {sorted(w['kinds'])}), per cycle: creep work {w['creep']:.3f} J; on the slip "
              f"fluctuation {cx + cy + cs:.4f} J (longitudinal {cx:.4f}, lateral {cy:.4f}, spin {cs:.4f}); normal "
              f"loop work {w['normal_loop']:.4f} J; lateral slip velocity fluctuation amplitude "
              f"{w.get('slip_lateral_amplitude', float('nan')):.4f} m/s")
    print(f"quasi-static coordinates' rates, left out of the creepages: dz/dt amplitude {r['z_rate_amplitude']:.4f} m/s, "
          f"droll/dt amplitude {r['roll_rate_amplitude']:.4f} rad/s (times the wheel's 0.7 m lever arm: "
          f"{0.7 * r['roll_rate_amplitude']:.4f} m/s)")


if __name__ == "__main__":
    main()
