"""A whole assessment of a synthetic results file (written with h5py following
docs/output.md) whose every quantity is known by construction, through the Python API and
through `raildyn assess` (JSON, CSV, HTML, errors).

The scene: the vehicle runs at 10 m/s from sigma 50 m for 40 s (output every 25 ms: 40 Hz,
so the 20 Hz force filter has nothing to remove and the forces are used as written). Wheelset
w1 (body ws1) has its track frame at frame_offset 2 m and sits 0.01 m ahead in it: its track
position is s = 52.01 + 10 t. Under it the track is straight to 200 m, a linear transition
to 300 m and a 500 m curve beyond. The wheel columns are set independently of each other
(the assessment reads each column as it is):

- Y/Q left: 0.1 + a triangle of height 0.5 and half-width 4 m at 102.01 m: its 2 m mean peaks
  at 0.1 + 0.5 (1 - 1/8) = 0.5375 there; right: -0.1 throughout.
- sum Y = 5000 + 2000 cos(2 pi (s - 52.01) / 10 m) (1 Hz): the 2 m mean peaks at
  5000 + 2000 sinc(0.2) on a crest; band-passed at 1 +- 2 Hz its rms over 100 m is 2000/sqrt(2).
  Y left/right = sum Y / 2 +- y_d with y_d = 20 kN in the curve (ramped in the transition):
  Y_qst = 22.5 kN / -17.5 kN (the median of the oscillation over whole periods is 0).
- Q left = 60 kN + d + 8 kN triangle at 152.01 m - 30 kN triangle at 120.01 m, Q right =
  60 kN - d, d = 5 kN in the curve: Q0 = 60 kN (Prud'homme 50 kN), Q_max left = the 99.85 %
  value of 1601 samples = the third largest = 60 + 8 (1 - 0.25/4) = 67.5 kN, Q_qst 65 / 55 kN,
  Delta Q/Q left 0.5 at 120.01 m, right 5/60.
- left patch 1: Fx = -2000 N at xi = 0.001, Fy = 3000 N at eta = -0.004 (1 + 4 triangle at
  352.01 m): T gamma 14 N, 62 N at the peak; patch 2 (flange) only in the curve: Fy = -5000 N
  at eta = 0.01, T gamma 50 N. Wheel: 112 N at 352.01 m. RCF index (FI_surf = f - 2 pi a b k /
  (3 Fz), k = 300 MPa): patch 1 Fz = 50 kN, a = 6 mm, b = 4 mm: 0.0721 - 0.3016 < 0; patch 2
  Fz = 10 kN, a = 2 mm, b = 2 mm (1 - 0.5 triangle at 400.01 m): 0.5 - 0.2513 = 0.2487, at
  400.01 m 0.5 - 0.2513 / 4 = 0.43717. The right wheel's slots stay empty.
- sensor 'floor' (specific_force_body, as an accelerometer reads it): lateral 0.5 sin(2 pi t),
  vertical +g: Cc_z = 0, Cc_y = 0.5 |Wd(1 Hz)| / sqrt(2) (its
  largest value includes the filter's switch-on transient, +0.9 %); N_MV needs 5 min: not
  available.
"""
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from raildyn.assess import assess
from raildyn.assess.filters import weighting_response

REPO = Path(__file__).resolve().parents[2]
PATCH = ("kind penetration normal_force xi eta spin creep_force_x creep_force_y spin_moment s_wheel "
         "u_rail wheel_point_x wheel_point_y wheel_point_z rail_point_x rail_point_y rail_point_z "
         "contact_angle rolling_radius semi_axis_a semi_axis_b hertz_warning reference_speed").split()
PATCH_UNITS = "1 m N 1 1 1/m N N N*m m m m m m m m m rad m m m 1 m/s"
WHEEL = "n_patches force_longitudinal force_lateral_Y force_vertical_Q Y_over_Q max_penetration".split()
DECK = """! synthetic deck: only what the assessment reads
&simulation title = 'synthetic assessment scene', speed = 10.0 /
&body name = 'car', mass = 1.0, frame_offset = 0.0 /
&body name = 'ws1', mass = 1.0,
      frame_offset = 2.0 /   ! the wheelset's own frame, 2 m ahead
&wheelset name = 'w1', body = 'ws1', wheel_profile = 'profiles/a/b.txt' /
&body name = 'floor_body', frame = 'ws1', mass = 1.0 /
&sensor name = 'floor', body = 'floor_body', position = 0.0, 0.0, 1.0 /
"""


def tri(s, centre, half_width):
    return np.clip(1.0 - np.abs(s - centre) / half_width, 0.0, None)


def write_scene(make_results_file, name="scene.h5", with_sensor=True, rows=1601, without=()):
    dt = 0.025
    t = np.arange(rows) * dt
    distance = 50.0 + 10.0 * t
    frame2 = distance + 2.0
    s = frame2 + 0.01
    kappa = np.where(frame2 < 200, 0.0, np.where(frame2 < 300, (frame2 - 200) / 100 / 500, 1 / 500))
    ramp = np.clip((frame2 - 200) / 100, 0.0, 1.0)          # transition share
    sum_y = 5000 + 2000 * np.cos(2 * np.pi * (s - 52.01) / 10.0)
    y_d = 20e3 * ramp
    d = 5e3 * ramp
    q_left = 60e3 + d + 8e3 * tri(s, 152.01, 4) - 30e3 * tri(s, 120.01, 4)
    q_right = 60e3 - d
    yq_left = 0.1 + 0.5 * tri(s, 102.01, 4)
    zeros = np.zeros_like(t)

    def wheel(y, q, yq):
        return np.column_stack([zeros + 1, zeros, y, q, yq, zeros])

    def patch(**cols):
        return np.column_stack([cols.get(c, zeros) for c in PATCH])

    in_curve = kappa >= 1 / 500 - 1e-15
    series = {
        "vehicle/speed": (np.full((t.size, 1), 10.0), "m/s", "V", "running speed"),
        "vehicle/distance": (distance[:, None], "m", "sigma", "arc length"),
        "track/frames/1/sigma": (distance[:, None], "m", "sigma", "frame 1"),
        "track/frames/1/curvature": (np.zeros((t.size, 1)), "1/m", "kappa", "frame 1"),
        "track/frames/2/sigma": (frame2[:, None], "m", "sigma", "frame 2"),
        "track/frames/2/curvature": (kappa[:, None], "1/m", "kappa", "frame 2"),
        "bodies/ws1/position_track": (np.column_stack([zeros + 0.01] + [zeros] * 5), "m m m rad rad rad",
                                      "x y z yaw roll pitch", "wheelset"),
        "wheelsets/w1/left/wheel": (wheel(sum_y / 2 + y_d, q_left, yq_left), "1 N N N 1 m", " ".join(WHEEL), "left"),
        "wheelsets/w1/right/wheel": (wheel(sum_y / 2 - y_d, q_right, zeros - 0.1), "1 N N N 1 m", " ".join(WHEEL),
                                     "right"),
        "wheelsets/w1/left/patch1": (patch(kind=zeros + 1, creep_force_x=zeros - 2000, xi=zeros + 0.001,
                                           creep_force_y=zeros + 3000,
                                           eta=-0.004 * (1 + 4 * tri(s, 352.01, 4)), normal_force=zeros + 50e3,
                                           semi_axis_a=zeros + 6e-3, semi_axis_b=zeros + 4e-3),
                                     PATCH_UNITS, " ".join(PATCH), "p1"),
        "wheelsets/w1/left/patch2": (patch(kind=np.where(in_curve, 2.0, 0.0), creep_force_y=zeros - 5000,
                                           eta=zeros + 0.01, normal_force=np.where(in_curve, 10e3, 0.0),
                                           semi_axis_a=2e-3 * (1 - 0.5 * tri(s, 400.01, 4)),
                                           semi_axis_b=2e-3 * (1 - 0.5 * tri(s, 400.01, 4))),
                                     PATCH_UNITS, " ".join(PATCH), "p2"),
        "wheelsets/w1/right/patch1": (patch(), PATCH_UNITS, " ".join(PATCH), "p1"),
        "wheelsets/w1/right/patch2": (patch(), PATCH_UNITS, " ".join(PATCH), "p2"),
    }
    for series_name in without:
        del series[series_name]
    if with_sensor:
        # an accelerometer's reading: +g vertically (docs/output.md /sensors specific_force_body)
        series["sensors/floor/specific_force_body"] = (
            np.column_stack([zeros, 0.5 * np.sin(2 * np.pi * t), zeros + 9.80665]), "m/s^2", "fx fy fz", "floor")
        # the point 1.5 m ahead of its body's frame origin (x of position_track)
        series["sensors/floor/position_track"] = (np.column_stack([zeros + 1.5, zeros, zeros + 1.0]), "m",
                                                  "x y z", "floor")
    return make_results_file(name, t, series, meta_attrs={"status": "completed"},
                             root_attrs={"title": "synthetic assessment scene"}, deck_text=DECK)


def one(a, name, **where):
    found = a.find(name, **where)
    assert len(found) == 1, (name, where, [q.label() for q in a.quantities])
    return found[0]


def test_every_quantity_of_the_synthetic_scene(make_results_file):
    a = assess(write_scene(make_results_file))
    assert any("52.01" not in n and "frame_offset 2 m + x of body ws1" in n for n in a.notes)
    assert any("output rate 40 Hz" in n for n in a.notes)

    q = one(a, "Y/Q", wheelset="w1", side="left")
    assert q.value == pytest.approx(0.1 + 0.5 * (1 - 1 / 8), rel=1e-9)
    assert q.position == pytest.approx(102.01, abs=1e-6) and q.limit == 0.8
    assert q.margin == pytest.approx((0.8 - 0.5375) / 0.8, rel=1e-9)
    assert one(a, "Y/Q", side="right").value == pytest.approx(-0.1, rel=1e-12)

    q = one(a, "sum_Y", wheelset="w1")
    assert q.limit == pytest.approx(10e3 + 2 * 60e3 / 3, rel=1e-12)
    # closed form of the continuous cosine; the linear interpolant of 0.25 m samples differs
    # by (2 pi 0.25 / 10)^2 / 12 = 0.2 % of the oscillating part
    assert q.value == pytest.approx(5000 + 2000 * np.sin(0.2 * np.pi) / (0.2 * np.pi), abs=0.002 * 2000)
    assert (q.position - 52.01) / 10.0 == pytest.approx(round((q.position - 52.01) / 10.0), abs=1e-6)

    q = one(a, "sum_Y_rms", wheelset="w1")
    assert q.limit == pytest.approx(25e3, rel=1e-12)
    assert q.value == pytest.approx(2000 / np.sqrt(2), rel=2e-3)
    assert "1.00 +- 2 Hz" in q.clause

    q = one(a, "Q_max", side="left")
    assert q.value == pytest.approx(67.5e3, rel=1e-12) and q.limit == 200e3
    assert min(abs(q.position - 151.76), abs(q.position - 152.26)) < 1e-6     # either sample
    assert one(a, "Q_max", side="right").value == pytest.approx(60e3, rel=1e-12)
    assert one(a, "Q_qst", side="left").value == pytest.approx(65e3, rel=1e-12)
    assert one(a, "Q_qst", side="right").value == pytest.approx(55e3, rel=1e-12)
    assert one(a, "Y_qst", side="left").value == pytest.approx(22.5e3, abs=100)
    assert one(a, "Y_qst", side="right").value == pytest.approx(-17.5e3, abs=100)
    assert "R = 500 m" in one(a, "Y_qst", side="left").clause
    assert 300.0 < one(a, "Q_qst", side="left").position < 452.02
    q = one(a, "DeltaQ/Q", side="left")
    assert q.value == pytest.approx(0.5, rel=1e-12) and q.position == pytest.approx(120.01, abs=1e-6)
    assert one(a, "DeltaQ/Q", side="right").value == pytest.approx(5 / 60, rel=1e-12)

    q = one(a, "T_gamma", side="left", patch=1)
    assert q.value == pytest.approx(2 + 3000 * 0.02, rel=1e-12) and q.position == pytest.approx(352.01, abs=1e-6)
    assert one(a, "T_gamma", side="left", patch=2).value == pytest.approx(50.0, rel=1e-12)
    q = one(a, "T_gamma", side="left", patch=None)
    assert q.value == pytest.approx(112.0, rel=1e-12) and q.position == pytest.approx(352.01, abs=1e-6)
    q = one(a, "RCF_index", side="left")
    k_over_p0 = 2 * np.pi * 2e-3 * 2e-3 * 300e6 / (3 * 10e3) / 4      # the patch area is a quarter at 400.01 m
    assert q.value == pytest.approx(0.5 - k_over_p0, rel=1e-12) and q.position == pytest.approx(400.01, abs=1e-6)
    assert q.limit is None and "k = 300 MPa" in q.clause
    # the wheel's series is its worst patch: the tread patch (below 0) before the curve, the
    # flange patch (0.5 - 0.2513 outside the triangle) in it
    pos, fi = q.series["position"], q.series["value"]
    assert pos[0] == pytest.approx(52.01, abs=1e-6)     # patch 1 loaded from the start
    np.testing.assert_allclose(fi[pos < 300], np.hypot(2000, 3000) / 50e3
                               - 2 * np.pi * 6e-3 * 4e-3 * 300e6 / (3 * 50e3), rtol=1e-12)
    assert np.min(fi[pos > 301]) == pytest.approx(0.5 - 4 * k_over_p0, rel=1e-12)
    assert not one(a, "RCF_index", side="right").available         # no patch ever loaded
    assert not a.find("T_gamma", side="right", patch=1)          # slots that never held a patch
    assert one(a, "T_gamma", side="right", patch=None).value == 0.0

    q = one(a, "N_MV", sensor="floor")
    assert not q.available and "N_MV is taken over 300 s periods" in q.reason
    q = one(a, "Cc", sensor="floor", direction="y")
    steady = 0.5 * abs(weighting_response("Wd", [1.0])[0]) / np.sqrt(2)
    assert steady <= q.value <= 1.01 * steady         # the switch-on transient adds 0.9 %
    assert q.series["value"][-1] == pytest.approx(steady, rel=1e-4)
    assert one(a, "Cc", sensor="floor", direction="x").value == pytest.approx(0.0, abs=1e-12)
    # the constant +g starts no transient: the weightings remove a constant
    assert one(a, "Cc", sensor="floor", direction="z").value == pytest.approx(0.0, abs=1e-12)
    assert any("sensors/floor/specific_force_body" in n and "vehicle/distance + 2 m + x of position_track" in n
               for n in a.notes)
    # its track position: vehicle/distance + the frame offset of its body (shared with ws1) + its
    # x in that frame (docs/output.md /sensors)
    assert q.position == pytest.approx(50.0 + 10.0 * q.series["time"][np.argmax(q.series["value"])] + 2.0 + 1.5)


def test_missing_inputs_are_reported_not_raised(make_results_file):
    """No sensors and a track too short for the 100 m window: those quantities are 'not
    available' with the reason, the others are evaluated; no NaN anywhere in the JSON."""
    path = write_scene(make_results_file, with_sensor=False, rows=321)    # 8 s: 80 m of track
    a = assess(path)
    rms = one(a, "sum_Y_rms", wheelset="w1")
    assert not rms.available and "shorter than the 100 m window" in rms.reason
    assert rms.to_json()["value"] is None and rms.to_json()["limit"] == pytest.approx(25e3)
    assert not one(a, "N_MV").available and "no &sensor in the deck" in one(a, "N_MV").reason
    assert not one(a, "Q_qst", side="left").available
    assert "no circular curve" in one(a, "Q_qst", side="left").reason
    assert one(a, "Y/Q", side="left").available
    text = json.dumps(a.to_json(), allow_nan=False)      # raises on NaN
    assert "NaN" not in text
    # every row names its source, those not available too (docs/assessment.md "Sources")
    assert all(q.source.startswith("secondary: ") for q in a.quantities)
    assert "EN 12299" in one(a, "N_MV").source and "EN 14363" in rms.source


def test_file_without_positions(make_results_file):
    """Without vehicle/distance (&output groups without 'vehicle') no wheelset has a track
    position: every wheelset quantity is listed as not available, with the reason."""
    a = assess(write_scene(make_results_file, without=("vehicle/distance",)))
    wheel = [q for q in a.quantities if q.wheelset == "w1"]
    assert len(wheel) == 2 * 7 + 2 and not any(q.available for q in wheel)
    assert all("no vehicle/distance series" in q.reason for q in wheel)
    assert {q.name for q in wheel} == {"Y/Q", "sum_Y", "sum_Y_rms", "Q_max", "Y_qst", "Q_qst", "DeltaQ/Q",
                                       "T_gamma", "RCF_index"}
    assert one(a, "Cc", sensor="floor", direction="y").available


def test_runner_assess_json_csv_html(make_results_file, raildyn_exe, tmp_path):
    path = write_scene(make_results_file)
    res = subprocess.run([str(raildyn_exe), "assess", str(path), "--json", "--csv", str(tmp_path / "csv"),
                          "--html", str(tmp_path / "html")], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    names = {q["name"] for q in out["quantities"]}
    assert {"Y/Q", "sum_Y", "sum_Y_rms", "Q_max", "Y_qst", "Q_qst", "DeltaQ/Q", "T_gamma", "RCF_index",
            "N_MV", "Cc"} <= names
    for q in out["quantities"]:
        assert {"name", "wheelset", "side", "value", "limit", "unit", "position"} <= set(q)
    yq = next(q for q in out["quantities"] if q["name"] == "Y/Q" and q["side"] == "left")
    assert yq["wheelset"] == "w1" and yq["value"] == pytest.approx(0.5375) and yq["limit"] == 0.8
    assert yq["unit"] == "1" and yq["position"] == pytest.approx(102.01, abs=1e-6)
    n_mv = next(q for q in out["quantities"] if q["name"] == "N_MV")
    assert n_mv["value"] is None and n_mv["limit"] is None and n_mv["reason"]
    rows = (tmp_path / "csv" / "quantities.csv").read_text().splitlines()
    assert rows[0].startswith("name,wheelset,side,patch") and len(rows) == len(out["quantities"]) + 1
    series = np.loadtxt(tmp_path / "csv" / "Y_Q_w1_left.csv", delimiter=",", skiprows=1)
    assert (tmp_path / "csv" / "Y_Q_w1_left.csv").read_text().splitlines()[0] == "position [m],Y/Q [1]"
    assert series[:, 1].max() == pytest.approx(0.5375)
    html = (tmp_path / "html" / "assessment.html").read_text()
    assert html.count("data:image/png;base64,") == len(list((tmp_path / "html").glob("*.png"))) > 5
    assert "not available" in html and "Y/Q w1 left" in html
    # the text table without --json
    res = subprocess.run([str(raildyn_exe), "assess", str(path)], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and "Y/Q w1 left: 0.5375 1 limit 0.8" in res.stdout


def test_runner_assess_errors(raildyn_exe, tmp_path, make_results_file):
    res = subprocess.run([str(raildyn_exe), "assess", str(tmp_path / "none.h5")], capture_output=True, text=True)
    assert res.returncode == 4 and "none.h5: no such file" in res.stderr
    (tmp_path / "text.h5").write_text("not hdf5")
    res = subprocess.run([str(raildyn_exe), "assess", str(tmp_path / "text.h5")], capture_output=True, text=True)
    assert res.returncode == 4 and "Traceback" not in res.stderr
    import h5py
    with h5py.File(tmp_path / "empty.h5", "w"):
        pass
    res = subprocess.run([str(raildyn_exe), "assess", str(tmp_path / "empty.h5")], capture_output=True, text=True)
    assert res.returncode == 1 and "not a raildyn results file" in res.stderr and "Traceback" not in res.stderr
    track = tmp_path / "track.h5"         # a track export: rows along sigma, not a run
    subprocess.run([str(raildyn_exe), "track", str(REPO / "inputs" / "first_wagon.nml"), "-o", str(track)],
                   capture_output=True, check=True, timeout=120)
    res = subprocess.run([str(raildyn_exe), "assess", str(track)], capture_output=True, text=True)
    assert res.returncode == 1 and "only the results of a run can be assessed" in res.stderr
    assert "Traceback" not in res.stderr
    path = write_scene(make_results_file)
    res = subprocess.run([str(raildyn_exe), "assess", str(path), "--prudhomme-alpha", "2"],
                         capture_output=True, text=True)
    assert res.returncode == 1 and "expected 0 < ALPHA <= 1" in res.stderr
    res = subprocess.run([str(raildyn_exe), "assess", str(path), "--shear-yield", "0"],
                         capture_output=True, text=True)
    assert res.returncode == 1 and "expected a shear yield limit k > 0 Pa" in res.stderr


def test_runner_assess_shear_yield(make_results_file, raildyn_exe):
    """--shear-yield sets k of FI_surf: half of it halves the k/p0 term (0.5 - 0.0628 / 2)."""
    res = subprocess.run([str(raildyn_exe), "assess", str(write_scene(make_results_file)), "--json",
                          "--shear-yield", "150e6"], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    q = next(q for q in json.loads(res.stdout)["quantities"] if q["name"] == "RCF_index" and q["side"] == "left")
    assert q["value"] == pytest.approx(0.5 - 2 * np.pi * 2e-3 * 2e-3 * 150e6 / (3 * 10e3) / 4, rel=1e-12)
    assert "k = 150 MPa" in q["clause"]
