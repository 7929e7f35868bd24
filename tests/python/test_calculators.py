"""Contact calculators, from Python (ctypes over libraildyn) and from the command line
(`raildyn hertz`, `raildyn creep`), against the closed forms and CONTACT values of
validation/reference/oracles.md."""
import json
import os
import subprocess
from pathlib import Path

import pytest

from raildyn import calculators

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def exe():
    return Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"


def cli(exe, *args):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=60)
    return res


# oracles.md worked example: r = 0.46 m wheel on a 300 mm rail crown, 100 kN, E 210 GPa, nu 0.28
WORKED = dict(a=7.19e-3, b=5.41e-3, p0=1227e6, approach=105e-6, stiffness=1.43e9)


def test_hertz_worked_example_python():
    h = calculators.hertz((1 / 0.46, 0.0, 0.0, 1 / 0.3), normal_force=1e5, young_modulus=210e9,
                          poisson=0.28)
    for key, value in WORKED.items():
        assert h[key] == pytest.approx(value, rel=0.005), key
    # the inverse: the approach gives the force back
    back = calculators.hertz((1 / 0.46, 0.0, 0.0, 1 / 0.3), penetration=h["approach"],
                             young_modulus=210e9, poisson=0.28)
    assert back["normal_force"] == pytest.approx(1e5, rel=1e-9)


def test_hertz_worked_example_cli(exe):
    res = cli(exe, "hertz", "--wheel-radius", 0.46, "--rail-radius", 0.3, "--normal-force", 1e5,
              "--young", 210e9, "--poisson", 0.28)
    assert res.returncode == 0, res.stderr
    h = json.loads(res.stdout)
    for key, value in WORKED.items():
        assert h[key] == pytest.approx(value, rel=0.005), key


# CONTACT reference (oracles.md): a = 6 mm, b = 4 mm, N = 50 kN, G = 82 GPa, nu = 0.28, mu = 0.3
PATCH = dict(a=0.006, b=0.004, normal_force=5e4, shear_modulus=82e9, poisson=0.28, friction=0.3)
FASTSIM_ROWS = [  # xi, eta, phi [1/m], Fx, Fy [N], Mz [N m]
    (1e-5, 0, 0, -92.80, 0, 0),
    (1e-3, 0, 0, -7454, 0, 0),
    (0, 1e-3, 0, 0, -7001, 8.086),
    (0, 0, 0.1, 0, -1989, -3.337),
]


@pytest.mark.parametrize("row", FASTSIM_ROWS)
def test_fastsim_against_contact(row):
    xi, eta, phi, fx, fy, mz = row
    f = calculators.creep("fastsim", xi=xi, eta=eta, phi=phi, grid=100, **PATCH)
    scale = max(abs(fx), abs(fy))
    assert f["fx"] == pytest.approx(fx, abs=0.02 * scale)
    assert f["fy"] == pytest.approx(fy, abs=0.02 * scale)
    if mz:
        assert f["mz"] == pytest.approx(mz, rel=0.02)


def test_creep_cli_matches_python(exe):
    res = cli(exe, "creep", "--law", "polach", "--a", 0.006, "--b", 0.004, "--normal-force", 5e4,
              "--shear-modulus", 82e9, "--poisson", 0.28, "--friction", 0.3, "--xi", 1e-3,
              "--eta", 1e-3, "--spin", 0.1)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    ref = calculators.creep("polach", xi=1e-3, eta=1e-3, phi=0.1, **PATCH)
    for k in ("fx", "fy", "mz"):
        assert out[k] == pytest.approx(ref[k], rel=1e-12, abs=1e-9)
    # saturation: far into sliding the resultant is mu N for every law
    for law in ("linear", "fastsim", "polach"):
        if law == "linear":
            continue  # plain linear theory does not saturate (its saturated variant does)
        f = calculators.creep(law, xi=0.5, **PATCH)
        assert abs(f["fx"]) == pytest.approx(0.3 * 5e4, rel=0.01), law


def test_creep_cli_bad_usage(exe):
    res = cli(exe, "creep", "--law", "magic", "--a", 0.006, "--b", 0.004, "--normal-force", 1e4)
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "magic" in res.stderr
    res = cli(exe, "creep", "--law", "fastsim", "--a", 0.006)
    assert res.returncode == 2 and "required" in res.stderr
