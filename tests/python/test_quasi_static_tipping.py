"""A hunting wheelset tipping over its flange contact on rigid track (issue 14 item 5): the
Manchester V1 vehicle (S1002/60E1, quasi-static normal contact, FASTSIM with the smooth clip)
at 100 m/s on straight RIGID track, 1.25 times its linear critical speed, after a lateral
pulse on wheelset 1 (bench/extremes' past-critical scene before it moved to flexible track).
The leading wheelsets hunt from flange to flange; each flange hit pushes the wheelset's axle
load onto one wheel and the other one lifts.

Oracle: the tipping limit of a wheelset in closed form (bench/extremes/tipping.py evaluates it per
output sample). Take moments about the loaded wheel's
contact point of the forces that act at the wheelset centre (its weight and the suspension's
vertical forces, resultant W, at the lateral distance y_c of that point from the centre; the
lateral forces that hold it against the flange, resultant F, at its height r above it): the
other wheel keeps a load as long as F r < W y_c, and with that wheel off the rail the contact
carries Q = W and Y = F, so it lifts at

    Y / Q = y_c / r = |wheel_point_y| / |wheel_point_z| of the loaded patch

(1.50 for the flange face of an S1002 wheel at r = 0.473 m, y_c = 0.711 m). The suspension's roll
moment and the contact forces' own moments move the point a few per cent (measured: the lifts
happen at 0.94-0.97 of it). Checked: the run completes; the left and the right wheel of
wheelset 1 each lift at least once; at every output sample with a wheel of a wheelset off its
rail the other wheel's Y/Q lies within 0.85-1.0 of its tipping limit (a wheel lost by the
contact search, or thrown off by a spurious force, would show any Y/Q); at every sample with
both wheels on the rail no wheel's Y/Q exceeds its limit.

The same scene with the energy-consistent strip force (strip_normal_force = 'potential') to
0.6 s: it ended in a solver failure at 0.456 s (quasi-static normal contact did not converge
with the left wheel about to lift: the damped Newton iteration stalled on a kink of that force;
the step-limited continuation of rd_multibody now takes over there) and now completes.
"""
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "bench" / "extremes"))
from rigid_track import deck_text  # noqa: E402  (bench/extremes/rigid_track.py's past-critical deck)
from tipping import lift_ratios, wheel_series  # noqa: E402  (the closed form, per output sample)
EXE = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"
#: the Manchester vehicle with quasi-static normal contact on rigid track (rigid_track.py's case)
RIGID_MANCHESTER = ("manchester", "quasi_static", None, False)


def run(tmp_path, name, t_end, wheelset_overrides):
    deck = tmp_path / f"{name}.nml"
    deck.write_text(deck_text(RIGID_MANCHESTER, t_end, wheelset=wheelset_overrides))
    out = tmp_path / f"{name}.h5"
    res = subprocess.run([str(EXE), "run", str(deck), "-o", str(out), "--quiet"], capture_output=True, text=True,
                         timeout=900)
    return res, out


def test_wheel_lifts_at_the_tipping_limit_of_the_flange_contact(tmp_path):
    res, out = run(tmp_path, "table", 1.0, "contact_geometry = 'table'")
    assert res.returncode == 0, res.stderr
    with h5py.File(out, "r") as f:
        sides = {s: wheel_series(f, "w1", s) for s in ("left", "right")}
        for s in ("left", "right"):
            assert sides[s][0].any(), f"the {s} wheel of wheelset 1 never lifts: the scene no longer tests tipping"
        ratio = lift_ratios(f)
        lifts = ratio.size
        assert np.all((ratio > 0.85) & (ratio <= 1.0)), ratio
        for ws in f["wheelsets"]:
            series = {s: wheel_series(f, ws, s) for s in ("left", "right")}
            both = ~series["left"][0] & ~series["right"][0]
            for s in ("left", "right"):
                _, yq, limit = series[s]
                assert np.all(yq[both] <= limit[both]), (ws, s, (yq[both] / limit[both]).max())
    assert lifts >= 4


def test_potential_strip_force_completes_through_the_first_lift(tmp_path):
    res, out = run(tmp_path, "potential", 0.6,
                   "contact_geometry = 'strips', strip_normal_force = 'potential'")
    assert res.returncode == 0, res.stderr
    with h5py.File(out, "r") as f:
        assert f["time"][-1] >= 0.6 - 1e-9
        lost, _, _ = wheel_series(f, "w1", "left")
        assert lost.any()
