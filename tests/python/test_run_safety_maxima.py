"""The running-safety maxima on the completion line of `raildyn run` (rd_safety_maxima,
docs/output.md "Completion line"): checked against a closed form (a wheelset at rest carries
Q = m g / 2 per wheel; its Prud'homme limit is 10 kN + 2 Q0 / 3) and against an independent
evaluation of the results file written here (2 m centred sliding means of the records' linear
interpolant integrated with numpy's trapezoid rule on each window's own points; the track
position from the file's frame sigma and body x; Q0 the median of the wheels' mean load)."""
import re
import subprocess

import h5py
import numpy as np
import pytest

WHEELSET = """&simulation title = 'ws', t_end = {t_end}, speed = {speed}, equilibrium = 'solve' /
&output interval = {interval} /
&segment type = 'straight', length = 100.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, {y0}, 0.45, frozen = {frozen} /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = 0.05, creep_law = 'linear' /
&element name = 'guide', type = 'spring_damper', body2 = 'ws1', point1 = 0.0, 0.0, 0.45,
      point2 = 0.0, 0.0, 0.0, stiffness = 0.0, 2e5, 0.0, damping = 0.0, 2e3, 0.0 /
"""
LINE = re.compile(r"running safety \(EN 14363, unfiltered records, 2 m sliding means along the track; "
                  r"raildyn assess: the full set\): max Y/Q (-?[\d.]+) \((\w+) (left|right) at (-?[\d.]+) m; "
                  r"limit 0\.8\); max \|sum Y\| ([\d.]+) kN \((\w+) at (-?[\d.]+) m\) = (\d+) % of its "
                  r"Prud'homme limit ([\d.]+) kN; max Q ([\d.]+) kN \((\w+) (left|right) at (-?[\d.]+) m\)$",
                  re.M)
G = 9.80665


def run(exe, tmp_path, **kw):
    values = dict(t_end=1.0, speed=20.0, y0=0.003, frozen="'x'", interval=0.005)
    values.update(kw)
    deck = tmp_path / "ws.nml"
    deck.write_text(WHEELSET.format(**values))
    res = subprocess.run([str(exe), "run", str(deck), "-o", str(tmp_path / "ws.h5")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr
    return res.stdout


def close(printed, value, decimals):
    return abs(float(printed) - value) <= 0.5 * 10.0**-decimals + 1e-9


def sliding_mean_max(s, y, length=2.0):
    """Largest centred sliding mean and its centre, each window integrated on its own points."""
    best, at = -np.inf, None
    for c in s[(s - length / 2 >= s[0]) & (s + length / 2 <= s[-1])]:
        a, b = c - length / 2, c + length / 2
        x = np.concatenate([[a], s[(s > a) & (s < b)], [b]])
        mean = np.trapz(np.interp(x, s, y), x) / length
        if mean > best:
            best, at = mean, c
    return best, at


def test_wheelset_at_rest_closed_form(raildyn_exe, tmp_path):
    out = run(raildyn_exe, tmp_path, speed=5.0, y0=0.0, frozen="'x', 'y', 'yaw', 'roll'")
    m = LINE.search(out)
    assert m, out
    q0 = 1500.0 * G / 2                     # each wheel carries half the weight
    assert close(m.group(10), q0 / 1e3, 1), out
    assert close(m.group(9), (10e3 + 2 * q0 / 3) / 1e3, 1), out
    assert close(m.group(5), 0.0, 1) and m.group(8) == "0", out


def test_oscillating_wheelset_against_the_results_file(raildyn_exe, tmp_path):
    out = run(raildyn_exe, tmp_path)
    m = LINE.search(out)
    assert m, out
    with h5py.File(tmp_path / "ws.h5", "r") as f:
        s = f["track/frames/1/sigma"][:, 0] + f["bodies/ws1/position_track"][:, 0]
        wheel = {side: f[f"wheelsets/w1/{side}/wheel"][:] for side in ("left", "right")}
    yq = {side: sliding_mean_max(s, wheel[side][:, 4]) for side in wheel}
    side = max(yq, key=lambda k: yq[k][0])
    assert (m.group(2), m.group(3)) == ("w1", side), out
    assert close(m.group(1), yq[side][0], 3) and close(m.group(4), yq[side][1], 1), (out, yq)
    sum_y = wheel["left"][:, 2] + wheel["right"][:, 2]
    hi, at_hi = sliding_mean_max(s, sum_y)
    lo, at_lo = sliding_mean_max(s, -sum_y)
    best, at = (hi, at_hi) if hi >= lo else (lo, at_lo)
    q0 = np.median(0.5 * (wheel["left"][:, 3] + wheel["right"][:, 3]))
    limit = 10e3 + 2 * q0 / 3
    assert close(m.group(5), best / 1e3, 1) and close(m.group(7), at, 1), (out, best, at)
    assert close(m.group(9), limit / 1e3, 1) and close(m.group(8), 100 * best / limit, 0), out
    q = {k: wheel[k][:, 3] for k in wheel}
    qside = max(q, key=lambda k: q[k].max())
    assert m.group(12) == qside and close(m.group(10), q[qside].max() / 1e3, 1), out
    assert close(m.group(13), s[np.argmax(q[qside])], 1), out
    # the oscillation is there: a flat result would not test the windows
    assert best > 300.0 and yq[side][0] > 0.03, (best, yq)


def test_no_window_without_track_covered(raildyn_exe, tmp_path):
    out = run(raildyn_exe, tmp_path, t_end=0.1, speed=0.0, y0=0.0, frozen="'x', 'y', 'yaw', 'roll'")
    assert re.search(r"running safety \(.*\): no 2 m window: the wheelsets covered 0\.00 m of track; "
                     r"max Q [\d.]+ kN \(w1 (left|right) at 0\.0 m\)$", out, re.M), out


def test_equals_raildyn_assess_where_it_does_not_filter(raildyn_exe, tmp_path):
    """At 40 Hz output raildyn assess takes the forces as written (no 20 Hz low pass): its
    Y/Q and sum Y (same windows, positions and Q0) are the completion line's."""
    from raildyn.assess import assess
    m = LINE.search(run(raildyn_exe, tmp_path, t_end=2.0, interval=0.025))
    assert m
    a = assess(tmp_path / "ws.h5")
    assert any("forces used as written" in n for n in a.notes), a.notes
    yq = max((q for q in a.find("Y/Q") if q.value is not None), key=lambda q: q.value)
    assert (m.group(2), m.group(3)) == (yq.wheelset, yq.side)
    assert close(m.group(1), yq.value, 3) and close(m.group(4), yq.position, 1), (m.group(0), yq)
    (sy,) = a.find("sum_Y", wheelset="w1")
    assert close(m.group(5), abs(sy.value) / 1e3, 1) and close(m.group(7), sy.position, 1), (m.group(0), sy)
    assert close(m.group(9), sy.limit / 1e3, 1), (m.group(0), sy)
