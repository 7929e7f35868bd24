"""The ramp method's lag (docs/theory_stability.md section 5a): reproduces its numbers.

On tests/decks/knife_edge_wheelset_hunting.nml (saturating creep, flange stop), ramps from
100 to 60 m/s after a 3 s hold at five rates (raildyn.stability.run_probes, the probes of
`raildyn critical-speed --method ramp`), each read at three thresholds (ramp_reading), the
fit of the readings to v0 - c a^p, and constant-speed runs started on the hunting cycle
(3 s at 100 m/s, then 20 s at the speed: C API set_input "speed") that place the end of
hunting. Run from the repository root with a built runner:

    /usr/bin/python3 bench/critical_speed_ramp/ramp_lag.py [WORK_DIR]
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
from raildyn import stability as st  # noqa: E402
from raildyn.results import Results  # noqa: E402

DECK = REPO / "tests" / "decks" / "knife_edge_wheelset_hunting.nml"
HOLD, V_HI, V_LO = 3.0, 100.0, 60.0
DURATIONS = [8.0, 16.0, 32.0, 64.0, 128.0]
THRESHOLDS = [0.5, 0.25, 0.1]


def from_cycle(speed, after=20.0):
    """Peaks of the lateral shift at 5, 10 and 20 s at ``speed`` after 3 s of hunting at 100 m/s."""
    tp, ap = st.peaks_after_speed_change(DECK, speed, V_HI, HOLD, after)
    return [float(ap[min(np.searchsorted(tp, s), ap.size - 1)]) for s in (0.0, 5.0, 10.0, after)]


def main():
    work = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="ramp_lag_"))
    variants = [{"simulation.speed_times": [0.0, HOLD, HOLD + d], "simulation.speed_values": [V_HI, V_HI, V_LO],
                 "simulation.t_end": HOLD + d} for d in DURATIONS]
    paths = st.run_probes(DECK, variants, work, jobs=2, tag="ramps")
    rates = np.array([(V_HI - V_LO) / d for d in DURATIONS])
    readings = {thr: [] for thr in THRESHOLDS}
    for path in paths:
        with Results(path) as r:
            t, y, v = r.time, r.get("bodies/ws/position_track:y"), r.get("vehicle/speed")[:, 0]
        for thr in THRESHOLDS:
            readings[thr].append(st.ramp_reading(t, y, v, HOLD, thr)["speed"])
    print("rate m/s/s      " + " ".join(f"{a:8.4g}" for a in rates))
    for thr in THRESHOLDS:
        v = np.array(readings[thr])
        fits = []
        for p in np.linspace(0.2, 1.2, 1001):
            X = np.column_stack([np.ones_like(rates), -rates ** p])
            c, *_ = np.linalg.lstsq(X, v, rcond=None)
            fits.append((float(np.sum((X @ c - v) ** 2)), p, c[0]))
        r2, p, v0 = min(fits)
        X = np.column_stack([np.ones_like(rates), -np.sqrt(rates)])
        half = np.linalg.lstsq(X, v, rcond=None)[0][0]
        print(f"threshold {thr:4}: " + " ".join(f"{x:8.3f}" for x in v)
              + f"   best p {p:.2f} (v0 {v0:.2f}, rms {np.sqrt(r2 / v.size):.3f}); p = 1/2: v0 {half:.2f}")
    for speed in (80.0, 80.5, 80.7, 80.78, 80.82, 80.85, 81.0, 81.5):
        peaks = from_cycle(speed)
        print(f"from the cycle at {speed:6.2f} m/s: peak at 0, 5, 10, 20 s " + " ".join(f"{1e3 * x:6.3f}" for x in peaks)
              + " mm")


if __name__ == "__main__":
    main()
