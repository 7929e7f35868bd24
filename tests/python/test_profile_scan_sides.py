"""Per-side profiles through the command line: `raildyn profile-scan --wheel-right /
--rail-right` and `&wheelset wheel_profile_right / rail_profile_right` in a scene.
Oracles independent of the numbers: naming the left profiles again on the right changes
nothing (CSV identical to the plain scan; scene outputs bit for bit those of today's deck),
and swapping the left and right rails mirrors the scan (delta_r(y) = -delta_r'(-y), roll
odd, patch counts swapped); the closed-form check of delta_r(0) is
tests/fortran/contact/geometry/test_side_profiles.f90 (d)."""
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np

import raildyn

REPO = Path(__file__).resolve().parents[2]
EXE = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"
SCAN = ["profile-scan", "--ymax", "0.006", "--step", "0.001", "--amplitude", "0.004"]


def run(*args):
    return subprocess.run([str(EXE), *SCAN, *args], capture_output=True, text=True, timeout=120)


def test_explicit_same_right_profiles_change_nothing(tmp_path):
    a = run("--csv", str(tmp_path / "a.csv"))
    b = run("--wheel-right", "s1002", "--rail-right", "60e1", "--csv", str(tmp_path / "b.csv"))
    assert a.returncode == 0 and b.returncode == 0, a.stderr + b.stderr
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert "right wheel s1002, rail 60e1" in b.stdout


def test_swapped_rails_mirror_the_scan(tmp_path):
    a = run("--rail-right", "54e1", "--h5", str(tmp_path / "a.h5"))
    b = run("--rail", "54e1", "--rail-right", "60e1", "--h5", str(tmp_path / "b.h5"))
    assert a.returncode == 0 and b.returncode == 0, a.stderr + b.stderr
    ra, rb = raildyn.Results(tmp_path / "a.h5"), raildyn.Results(tmp_path / "b.h5")
    assert ra.metadata["rail_profile"] == "60e1" and ra.metadata["rail_profile_right"] == "54e1"
    dra, drb = ra.get("scan/delta_r")[:, 0], rb.get("scan/delta_r")[:, 0]
    n0 = len(dra) // 2
    assert abs(dra[n0]) > 1e-4, "different rails: rolling-radius difference at y = 0"
    assert np.allclose(dra, -drb[::-1], atol=1e-9)
    roll_a, roll_b = ra.get("scan/pose")[:, 2], rb.get("scan/pose")[:, 2]
    assert abs(roll_a[n0]) > 1e-6 and np.allclose(roll_a, -roll_b[::-1], atol=1e-9)
    assert np.array_equal(ra.get("scan/left/n_patches")[:, 0], rb.get("scan/right/n_patches")[::-1, 0])


def test_right_profile_usage_errors(tmp_path):
    res = run("--wheel-right")
    assert res.returncode == 2 and "--wheel-right expects a value" in res.stderr
    res = run("--rail-right", str(tmp_path / "missing.prr"))
    assert res.returncode == 1 and "missing.prr" in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1
    res = run("--rail-precant-right", "0.5")
    assert res.returncode == 2 and "--rail-precant-right" in res.stderr


def _float_datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()])
                     if isinstance(o, h5py.Dataset) and o.dtype.kind == "f" else None)
    return out


def test_scene_with_explicit_same_right_profiles_is_unchanged(tmp_path):
    """TGV 001 with profile contact, 0.3 s: wheelset w1 names S1002 / 60E1 again on the right
    and every float output equals today's deck bit for bit; a different right rail (54E1)
    changes w1's right wheel."""
    inc = f"&include file = '{REPO / 'inputs' / 'tgv_profile_fastsim.nml'}' /\n&simulation t_end = 0.3 /\n"
    decks = {"base": inc,
             "same": inc + "&wheelset name = 'w1', wheel_profile_right = 's1002', rail_profile_right = '60e1' /\n",
             "other": inc + "&wheelset name = 'w1', rail_profile_right = '54e1' /\n"}
    out = {}
    for name, text in decks.items():
        (tmp_path / f"{name}.nml").write_text(text)
        res = subprocess.run([str(EXE), "run", str(tmp_path / f"{name}.nml"), "-o", str(tmp_path / f"{name}.h5"),
                              "--quiet"], capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr
        out[name] = _float_datasets(tmp_path / f"{name}.h5")
    assert out["base"].keys() == out["same"].keys()
    for key, value in out["base"].items():
        assert np.array_equal(value, out["same"][key]), key
    assert not np.array_equal(out["base"]["wheelsets/w1/right/wheel"], out["other"]["wheelsets/w1/right/wheel"])
