"""`raildyn profile-scan` writes the contact table to HDF5 (layout of docs/output.md, axis =
lateral shift), CSV and a plot; checked for the mirror symmetry of a symmetric wheelset
(independent of the numbers themselves) and for agreement between the three outputs. Its
EN 15302 conicities, conicity CSV and plot, and the contact-point drawing."""
import json
import os
import re
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


def test_profile_scan_en15302_conicity_and_contact_plot(raildyn_exe, tmp_path):
    """S1002 / 60E1: EN 15302 conicities next to the harmonic one. Checked: the printed values
    equal the conicity CSV's; for this symmetric pair (Delta r odd) the regression, centred on
    the motion's middle (0), equals the harmonic linearisation, an independent formulation;
    the integration method equals `raildyn conicity` on the scan's own Delta r column; the
    drawing's profile curves put the centred wheelset's contact point on both the wheel and
    the rail curve (rigid contact, lowered 5 um)."""
    pytest.importorskip("matplotlib")
    res = subprocess.run([str(raildyn_exe), "profile-scan", "--ymax", "0.008", "--step", "0.0002",
                          "--amplitude", "0.002", "--amplitude", "0.004", "--csv", str(tmp_path / "s.csv"),
                          "--conicity-plot", str(tmp_path / "c.png"), "--contact-plot", str(tmp_path / "p.png")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    printed = re.findall(r"equivalent conicity at amplitude\s+([\d.]+) mm:\s+([\d.]+) \(harmonic\); EN 15302 "
                         r"integration\s+([\d.]+), regression\s+([\d.]+)", res.stdout)
    assert [float(p[0]) for p in printed] == [2.0, 4.0], res.stdout
    con = np.genfromtxt(tmp_path / "c.csv", delimiter=",", names=True)
    assert con.dtype.names == ("amplitude_m", "harmonic", "integration", "regression", "wavelength_m")
    assert np.allclose(con["amplitude_m"], np.arange(1, 81) * 1e-4, rtol=0, atol=1e-15)
    for a_mm, harmonic, integration, regression in printed:
        row = con[np.argmin(abs(con["amplitude_m"] - float(a_mm) / 1000))]
        assert [row["harmonic"], row["integration"], row["regression"]] == pytest.approx(
            [float(harmonic), float(integration), float(regression)], abs=1e-4)
    # (the harmonic value's midpoint rule, 2000 points across the table's kinks, is good to about
    # 1e-5: 1.3e-5 measured at 7.1 mm; the regression is exact for the linear pieces)
    assert np.allclose(con["regression"], con["harmonic"], rtol=3e-5, atol=0)
    # the integration method from the scan's Delta r through `raildyn conicity`
    scan = np.genfromtxt(tmp_path / "s.csv", delimiter=",", names=True)
    np.savetxt(tmp_path / "dr.csv", np.c_[scan["y_m"], scan["delta_r_m"]], delimiter=",", fmt="%.17g")
    centre = len(scan) // 2
    e0 = 0.5 * (scan["left_p1_y_rail_m"][centre] - scan["right_p1_y_rail_m"][centre])
    amps = con["amplitude_m"][9::10]
    out = subprocess.run([str(raildyn_exe), "conicity", "--delta-r", str(tmp_path / "dr.csv"), "--r0", "0.46",
                          "--e0", repr(e0), "--amplitudes", ",".join(map(repr, amps)), "--json"],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert np.allclose(got["conicity"], con["integration"][9::10], rtol=1e-12)
    assert np.allclose(got["wavelength"], con["wavelength_m"][9::10], rtol=1e-12)
    # the drawing: both plots written, and the curves meet at the centred contact points
    assert (tmp_path / "c.png").stat().st_size > 10000 and (tmp_path / "p.png").stat().st_size > 10000
    curves = np.genfromtxt(tmp_path / "p_profiles.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    r = raildyn.Results(tmp_path / "p.h5")
    for side in ("left", "right"):
        wheel = curves[(curves["side"] == side) & (curves["surface"] == "wheel")]
        rail = curves[(curves["side"] == side) & (curves["surface"] == "rail")]
        rail = rail[np.argsort(rail["y_m"])]
        s_wheel, y_rail = r.get(f"scan/{side}/patch1")[centre, [0, 2]]
        order = np.argsort(wheel["profile_coordinate_m"])
        yw = np.interp(s_wheel, wheel["profile_coordinate_m"][order], wheel["y_m"][order])
        zw = np.interp(s_wheel, wheel["profile_coordinate_m"][order], wheel["z_m"][order])
        zr = np.interp(y_rail, rail["y_m"], rail["z_m"])
        assert abs(yw - y_rail) < 2e-4 and abs(zw - zr) < 2e-5, (side, yw, y_rail, zw, zr)
