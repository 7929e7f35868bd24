"""`raildyn profile-scan` writes the contact table to HDF5 (layout of docs/output.md, axis =
lateral shift), CSV and a plot; checked for the mirror symmetry of a symmetric wheelset
(independent of the numbers themselves) and for agreement between the three outputs."""
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import raildyn

REPO = Path(__file__).resolve().parents[2]


def test_profile_scan_outputs(tmp_path):
    pytest.importorskip("matplotlib")
    exe = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"
    res = subprocess.run([str(exe), "profile-scan", "--ymax", "0.008", "--step", "0.0005",
                          "--amplitude", "0.003", "--h5", str(tmp_path / "s.h5"),
                          "--csv", str(tmp_path / "s.csv"), "--plot", str(tmp_path / "s.png")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    r = raildyn.Results(tmp_path / "s.h5")
    y = r.time
    assert np.allclose(y, np.arange(-0.008, 0.008 + 1e-12, 0.0005))
    dr = r.get("scan/delta_r")[:, 0]
    assert np.allclose(dr, -dr[::-1], atol=1e-9), "rolling-radius difference must be odd in y"
    nl = r.get("scan/left/n_patches")[:, 0]
    nr = r.get("scan/right/n_patches")[:, 0]
    assert np.array_equal(nl, nr[::-1])
    gl = r.get("scan/left/patch1")[:, 4]
    gr = r.get("scan/right/patch1")[:, 4]
    assert np.allclose(gl, -gr[::-1], atol=1e-9), "contact angles mirror between the wheels"
    # shifted 8 mm to the right (y < 0) the right wheel flanges (|gamma| > 0.6 rad); centred it does not
    assert abs(gr[0]) > 0.6 and abs(gr[len(y) // 2]) < 0.05
    # the conicity in the file equals the one printed
    printed = float(res.stdout.split("equivalent conicity at amplitude")[1].split(":")[1].split()[0])
    assert float(r.metadata["equivalent_conicity_3.0mm"]) == pytest.approx(printed, abs=1e-4)
    csv = np.genfromtxt(tmp_path / "s.csv", delimiter=",", names=True)
    assert np.allclose(csv["y_m"], y) and np.allclose(csv["delta_r_m"], dr, atol=1e-12)
    assert (tmp_path / "s.png").stat().st_size > 10000
