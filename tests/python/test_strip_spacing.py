"""&wheelset strip_spacing (issue 14 item 3: the fidelity map runs online strips at two
spacings): the arc-length spacing of the resampled wheel points and rail lines of the profile
contact. Checked against the closed form of a conical wheel (conicity 0.05) touching a circular
rail head (R 0.3 m, no inclination), tests/python/test_reference_radius.py's geometry: at
centred rigid contact the normal is tilted by atan(lam), the rail touches at
Y = Y_c - R sin(atan(lam)) and the wheel rolls on r = r_tape - lam s there. The contact point
found by the strips moves towards the closed form as the spacing shrinks (measured: 194, 5.8,
2.0, 1.0 um off at 0.4, 0.2, 0.1, 0.05 mm), so a spacing that does not reach the strips fails.
"""
import math
import subprocess

import h5py
import pytest

from test_reference_radius import (GAUGE, cone_on_circle_height,
                                   cone_on_circle_rolling_radius, deck, write_cone_and_circle)

LAM, RADIUS = 0.05, 0.3


def first_patch(exe, folder, spacing):
    """Patch 1 of the left wheel at t = 0 (both wheels 0.1 um into their rails)."""
    z = cone_on_circle_height(LAM, RADIUS) - 1e-7
    name = f"s{spacing:g}"
    (folder / f"{name}.nml").write_text(deck(f"wheel_profile = 'cone.txt', rail_profile = 'circle.txt', "
                                             f"strip_spacing = {spacing}", track="rail_inclination = 0.0", z=z))
    res = subprocess.run([str(exe), "run", str(folder / f"{name}.nml"), "-o", str(folder / f"{name}.h5"), "-q"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    with h5py.File(folder / f"{name}.h5", "r") as f:
        ds = f["wheelsets/w1/left/patch1"]
        comps = ds.attrs["components"]
        comps = (comps.decode() if isinstance(comps, bytes) else comps).split()
        return dict(zip(comps, ds[0]))


def test_finer_strips_converge_to_the_closed_form_contact(raildyn_exe, tmp_path):
    write_cone_and_circle(tmp_path, LAM, RADIUS)
    y_centre = GAUGE / 2 + math.sqrt(RADIUS**2 - (RADIUS - 0.014)**2)
    y_contact = y_centre - RADIUS * math.sin(math.atan(LAM))
    r_contact = cone_on_circle_rolling_radius(LAM, RADIUS)
    err = {}
    for spacing in (4e-4, 2e-4, 1e-4, 5e-5):
        p = first_patch(raildyn_exe, tmp_path, spacing)
        assert p["kind"] == 1.0
        err[spacing] = abs(p["rail_point_y"] - y_contact)
        # within one strip of the closed form at every spacing; the rolling radius follows
        assert err[spacing] <= spacing, (spacing, err)
        assert p["rolling_radius"] == pytest.approx(r_contact, abs=LAM * spacing + 1e-7)
        assert p["contact_angle"] == pytest.approx(-math.atan(LAM), abs=2.0 * spacing / 0.1)
    # finer strips, closer contact: 0.05 mm at least 20 times closer than 0.4 mm, and no
    # spacing worse than a coarser one by more than rounding
    assert err[5e-5] < err[4e-4] / 20, err
    assert err[1e-4] < err[2e-4] < err[4e-4], err


def test_strip_spacing_outside_its_range_is_refused(raildyn_exe, tmp_path):
    (tmp_path / "bad.nml").write_text(deck("wheel_profile = 's1002', rail_profile = '60e1', strip_spacing = 1e-6"))
    res = subprocess.run([str(raildyn_exe), "check", str(tmp_path / "bad.nml")], capture_output=True, text=True,
                         timeout=60)
    assert res.returncode == 1
    assert "strip_spacing" in res.stderr + res.stdout and "bad.nml:" in res.stderr + res.stdout
