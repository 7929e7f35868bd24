"""Contact tables in a scene (`&wheelset contact_geometry = 'table'`): the TGV 001 vehicle
with S1002 / 60E1 profiles (inputs/tgv_profile_fastsim.nml), 6 s (straight track and the
start of the transition), run once on the online strips and once on tables of them.

Oracle: the strip run (the model the tables tabulate, at other poses than the nodes).
Bounds: the differences measured when the tables were introduced (0.54 mm lateral shift,
0.46 kN lateral and 0.64 kN vertical wheel force, on 64-68 kN wheel loads), rounded up; they
come from the table's interpolation and its one patch per slot (docs/theory_contact_geometry.md
section 10). The four wheelsets share one table: one file in the cache directory, which the
test points to its own tmp_path (RAILDYN_CACHE_DIR)."""
import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
EXE = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"
WHEELSETS = ("w1", "w2", "w3", "w4")


def run(tmp_path, name, extra, cache):
    deck = tmp_path / f"{name}.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'tgv_profile_fastsim.nml'}' /\n"
                    "&simulation t_end = 6.0 /\n" + extra)
    env = dict(os.environ, RAILDYN_CACHE_DIR=str(cache))
    res = subprocess.run([str(EXE), "run", str(deck), "-o", str(tmp_path / f"{name}.h5"), "--quiet"],
                         capture_output=True, text=True, timeout=600, env=env)
    assert res.returncode == 0, res.stderr
    return h5py.File(tmp_path / f"{name}.h5", "r")


def test_scene_on_tables_follows_the_strips(tmp_path):
    cache = tmp_path / "cache"
    tables = "".join(f"&wheelset name = '{w}', contact_geometry = 'table' /\n" for w in WHEELSETS)
    strips = run(tmp_path, "strips", "", cache)
    assert not cache.exists() or not any(cache.iterdir()), "the strip run builds no table"
    table = run(tmp_path, "tables", tables, cache)
    assert len(list(cache.glob("contact-table-*.bin"))) == 1, "one table for four equal wheelsets"
    for ws in ("ws1", "ws2", "ws3", "ws4"):
        ys, yt = strips[f"bodies/{ws}/position_track"][:, 1], table[f"bodies/{ws}/position_track"][:, 1]
        assert np.all(np.isfinite(yt))
        assert np.abs(ys - yt).max() < 0.7e-3, ws
    for w in WHEELSETS:
        for side in ("left", "right"):
            fs, ft = strips[f"wheelsets/{w}/{side}/wheel"][()], table[f"wheelsets/{w}/{side}/wheel"][()]
            assert np.abs(fs[:, 2] - ft[:, 2]).max() < 550.0, (w, side, "Y")
            assert np.abs(fs[:, 3] - ft[:, 3]).max() < 750.0, (w, side, "Q")
            assert fs[:, 3].min() > 50e3 and ft[:, 3].min() > 50e3
    # a second run reads the cached table and gives bit for bit the same results
    again = run(tmp_path, "again", tables, cache)
    assert np.array_equal(again["bodies/ws1/position_track"][()], table["bodies/ws1/position_track"][()])


def test_table_geometry_needs_profile_contact(tmp_path):
    deck = tmp_path / "bad.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'tgv_vehicle_straight.nml'}' /\n"
                    "&wheelset name = 'w1', contact_geometry = 'tables' /\n")
    res = subprocess.run([str(EXE), "check", str(deck)], capture_output=True, text=True, timeout=120)
    assert res.returncode == 1
    assert "contact_geometry" in res.stderr and "strips" in res.stderr and "bad.nml" in res.stderr


def test_profile_scan_writes_and_reads_the_table(tmp_path):
    """`raildyn profile-scan --table DIR` builds the pair's table into DIR and scans through
    it; a second call finds it (one file, unchanged) and prints the same scan; the scan
    through the table stays within 0.05 mm rolling-radius difference of the strips' scan
    (tread shifts; measured 0.01 mm)."""
    scan = ["profile-scan", "--ymax", "0.004", "--step", "0.001"]
    strips = subprocess.run([str(EXE), *scan, "--csv", str(tmp_path / "s.csv")], capture_output=True, text=True,
                            timeout=300)
    first = subprocess.run([str(EXE), *scan, "--table", str(tmp_path / "tables"), "--csv", str(tmp_path / "t1.csv")],
                           capture_output=True, text=True, timeout=300)
    assert strips.returncode == 0 and first.returncode == 0, strips.stderr + first.stderr
    files = list((tmp_path / "tables").glob("contact-table-*.bin"))
    assert len(files) == 1
    stamp = files[0].stat().st_mtime_ns
    second = subprocess.run([str(EXE), *scan, "--table", str(tmp_path / "tables"), "--csv", str(tmp_path / "t2.csv")],
                            capture_output=True, text=True, timeout=300)
    assert second.returncode == 0, second.stderr
    assert files[0].stat().st_mtime_ns == stamp, "the second scan reads the table, it does not rewrite it"
    assert (tmp_path / "t1.csv").read_bytes() == (tmp_path / "t2.csv").read_bytes()
    assert "through the contact table" in first.stdout
    s = np.genfromtxt(tmp_path / "s.csv", delimiter=",", names=True)
    t = np.genfromtxt(tmp_path / "t1.csv", delimiter=",", names=True)
    assert np.abs(s["delta_r_m"] - t["delta_r_m"]).max() < 5e-5


def test_r80_flange_root_to_face_on_tables(tmp_path):
    """The Manchester vehicle in R 80 m at 8 m/s (bench/extremes/scenes/manchester__r80.nml) on
    tables with the linear law + Shen-Hedrick-Elkins and quasi-static normal contact, to 2.4 s:
    the leading wheelset reaches the flange root / flange face transition of S1002 (y = 6.3-6.4
    mm, yaw 19.5 mrad), where with one table slot for root and face the quasi-static balance had
    no root (the solve did not converge at 2.288 s: exit 2). Now it completes, and follows the
    strip run of the same scene: oracle the online strips with the normal force the tables
    tabulate (strip_normal_force = 'centroid'); bounds the differences measured when
    the face got its own slot (lateral shifts 0.225 mm; wheel forces Y 1.99 kN of 40 kN and Q
    0.81 kN of 70 kN, wheelset 1's flange wheel at 0.72 s), rounded up
    (docs/theory_contact_geometry.md section 10)."""
    scene = REPO / "bench" / "extremes" / "scenes" / "manchester__r80.nml"
    law = "creep_law = 'linear', creep_saturation = 'shen_hedrick_elkins'"
    out = {}
    for geometry in ("table", "strips"):
        deck = tmp_path / f"r80_{geometry}.nml"
        # the strips with the normal force the tables tabulate (the centroid patches; the
        # online default is the distributed force, docs/theory_flange_chatter.md section 14)
        force = ", strip_normal_force = 'centroid'" if geometry == "strips" else ""
        deck.write_text(f"&include file = '{scene}' /\n&simulation t_end = 2.4 /\n" + "".join(
            f"&wheelset name = '{w}', contact_geometry = '{geometry}', {law}{force} /\n" for w in WHEELSETS))
        env = dict(os.environ, RAILDYN_CACHE_DIR=str(tmp_path / "cache"))
        res = subprocess.run([str(EXE), "run", str(deck), "-o", str(tmp_path / f"{geometry}.h5"), "--quiet"],
                             capture_output=True, text=True, timeout=600, env=env)
        assert res.returncode == 0, (geometry, res.stderr[-2000:])
        out[geometry] = h5py.File(tmp_path / f"{geometry}.h5", "r")
    table, strips = out["table"], out["strips"]
    assert table["time"][-1] == strips["time"][-1] == 2.4
    assert table["bodies/ws1/position_track"][:, 1].max() > 6.2e-3, "wheelset 1 reaches the flange"
    for ws in ("ws1", "ws2", "ws3", "ws4"):
        ys, yt = strips[f"bodies/{ws}/position_track"][:, 1], table[f"bodies/{ws}/position_track"][:, 1]
        assert np.all(np.isfinite(yt))
        assert np.abs(ys - yt).max() < 0.3e-3, ws
    for w in WHEELSETS:
        for side in ("left", "right"):
            fs, ft = strips[f"wheelsets/{w}/{side}/wheel"][()], table[f"wheelsets/{w}/{side}/wheel"][()]
            assert np.abs(fs[:, 2] - ft[:, 2]).max() < 2.5e3, (w, side, "Y")
            assert np.abs(fs[:, 3] - ft[:, 3]).max() < 1.0e3, (w, side, "Q")



@pytest.mark.parametrize("radius, geometry", [(80.0, "table"), (150.0, "strips"), (200.0, "table")])
def test_static_equilibrium_inside_a_curve_without_cant(tmp_path, radius, geometry):
    """The static equilibrium of the TGV profile vehicle (bench/extremes/tgv_profile_vehicle.nml)
    started 12 m into a curve without cant, on tables or strips. Built at their reference
    height, the wheels touch at zero Hertz approach, without contact stiffness; the static
    solve seats each wheelset on its rails before Newton (rd_static_preload). Without the
    seat, Newton stalled on the wheelset yaws (1.8e3 rad/s^2 in R 80 m) and a wheel reached the
    lift-off limit (exit 3) in each of these cases (R 100, 150, 200 m on both geometries too).
    Oracle: the primary suspension aligns each wheelset with its bogie, so a wheelset yaws
    against its own track frame by about a / R (a = 1.5 m, half the bogie wheelbase), positive
    ahead of its bogie's centre (ws1, ws3), negative behind (measured 3-4 % off: the bogies'
    own yaw and the primaries' longitudinal deflection), and the car body, a chord of the curve
    between its bogies 18.7 m apart, sits inside by about 18.7^2 / (8 R) (measured 2.6-3 % more:
    the bogies' own lateral deflection)."""
    deck = tmp_path / "curve.nml"
    deck.write_text(f"&include file = '{REPO / 'bench' / 'extremes' / 'tgv_profile_vehicle.nml'}' /\n"
                    "&simulation t_end = 1.0, speed = 2.0, start_sigma = 32.0, equilibrium = 'preload' /\n"
                    "&track gauge = 1.435, rail_inclination = 0.025 /\n"
                    f"&segment type = 'clothoid', length = 20.0, radius = {radius}, side = 'right', cant = 0.0 /\n"
                    f"&segment type = 'curve', length = 400.0, radius = {radius}, side = 'right', cant = 0.0 /\n"
                    + "".join(f"&wheelset name = '{w}', contact_geometry = '{geometry}' /\n" for w in WHEELSETS))
    env = dict(os.environ)
    env.setdefault("RAILDYN_CACHE_DIR", str(tmp_path / "cache"))
    res = subprocess.run([str(EXE), "check", str(deck)], capture_output=True, text=True, timeout=600, env=env)
    assert res.returncode == 0, res.stderr
    line = next(li for li in res.stdout.splitlines() if li.startswith("equilibrium"))
    yaw = {ws: float(v) for ws, v in re.findall(r"(ws\d) [-\d.]+ mm \(x\), ([-\d.]+) mrad \(yaw\)", line)}
    assert set(yaw) == {"ws1", "ws2", "ws3", "ws4"}, line
    aligned = 1.5 / radius * 1e3
    for ws, sign in (("ws1", 1), ("ws2", -1), ("ws3", 1), ("ws4", -1)):
        assert abs(yaw[ws] - sign * aligned) < 0.05 * aligned + 0.2, (ws, yaw[ws], sign * aligned)
    chord = 18.7 ** 2 / (8 * radius) * 1e3
    car = float(re.search(r"car ([-\d.]+) mm \(y\)", line).group(1))
    assert abs(car + chord) < 0.03 * chord + 5.0, (car, chord)
