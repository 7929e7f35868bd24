#!/usr/bin/env python3
"""Work per cycle of wheelset 1's contact forces in the friction-0.6 flange cycle
(docs/theory_flange_chatter.md section 12; issue 12 item 2 asks for the energy balance).

Runs friction_06.nml of this folder to T_END with samples every 0.2 ms (about 36 per cycle of
the 135-139 Hz cycle; wheelsets, patches and bodies only: ~430 MB) unless --results names such a
file, and prints, over the whole cycles in [T0, T_END] (cycles counted by the upward zero
crossings of wheelset 1's lateral shift about its mean):
- per wheel of wheelset 1: the creep forces' work per cycle, v (Fx xi + Fy eta + Mz phi) dt
  (the creep law's slip velocity; always <= 0: the forces oppose the slip), and its part on the
  fluctuation of the slip, with the creepages' means over the window removed (the work of the
  force fluctuations on the slip fluctuations: what the creep forces take from, or give to, the
  cycle), split into longitudinal, lateral and spin;
- per wheel the loop work of the normal force, -sum N d(delta) over steps in which the patch
  keeps its kind (section 3: non-zero only where the normal force field is not conservative);
- the cycle's energy scale, 1/2 m v^2 of wheelset 1's lateral velocity amplitude;
- the rates of the quasi-static coordinates (height z and roll, from the sampled positions): the
  creepages leave them out (docs/theory.md "Quasi-static normal contact": the implicit rate
  dz/dt is neglected), and the lateral creepage's own fluctuation, for comparison.

    python3 bench/manchester_friction/energy.py [--build DIR] [--results FILE] [--t0 9.6] [--t-end 10.0]
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


def run(exe: Path, work: Path, t_end: float) -> Path:
    deck = work / "energy.nml"
    deck.write_text(f"&include file = '{HERE / 'friction_06.nml'}' /\n&simulation t_end = {t_end} /\n"
                    "&output interval = 0.0002, groups = 'wheelsets', 'patches', 'bodies' /\n")
    out = work / "energy.h5"
    subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"], check=True)
    return out


def analyse(path: Path, t0: float, t_end: float) -> dict:
    with h5py.File(path, "r") as f:
        t = f["time"][...]
        m = (t >= t0) & (t <= t_end + 1e-9)
        tt = t[m]
        pos = f["bodies/ws1/position_track"][m]
        vel = f["bodies/ws1/velocity_track"][m]
        patches = {side: [f[f"wheelsets/w1/{side}/patch{j}"][m] for j in range(1, 5)] for side in ("left", "right")}
    yc = pos[:, 1] - pos[:, 1].mean()
    up = np.where((yc[:-1] < 0) & (yc[1:] >= 0))[0]
    if len(up) < 3:
        raise SystemExit(f"fewer than two cycles of wheelset 1 in {t0}-{t_end} s: no cycle to measure")
    n = len(up) - 1
    sel = (tt >= tt[up[0]]) & (tt <= tt[up[-1]])
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", type=Path, default=Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")))
    ap.add_argument("--results", type=Path, default=None, help="a results file of such a run (no new run)")
    ap.add_argument("--t0", type=float, default=9.6)
    ap.add_argument("--t-end", type=float, default=10.0)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="raildyn-energy-") as tmp:
        path = args.results or run(args.build / "bin" / "raildyn", Path(tmp), args.t_end)
        r = analyse(path, args.t0, args.t_end)
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
