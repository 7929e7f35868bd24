"""`raildyn conicity --delta-r FILE --r0 R0 --e0 E0 [--amplitudes ...] --json` (EN 15302
equivalent conicity of a given Delta r function) against an oracle written here: the
kinematic wheelset equation y'' = -Delta r(y) / (2 e0 r0) integrated along the track with
RK4 from a turning point, its wavelength L turned into a conicity with Klingel's formula
lambda = e0 r0 (2 pi / L)^2, its amplitude = half the peak-to-peak motion; the regression
method against a least-squares line through Delta r sampled along a harmonic motion over the
same range. The table is asymmetric, curved and has Delta r(0) /= 0. Also the JSON interface,
the pure cone and the error messages (file and line, exit status)."""
import json
import subprocess

import numpy as np
import pytest

R0, E0 = 0.46, 0.75


def conicity(exe, *args, cwd=None):
    return subprocess.run([str(exe), "conicity", *map(str, args)], capture_output=True, text=True,
                          timeout=60, cwd=cwd)


def write_table(path, y, dr):
    path.write_text("".join(f"{a!r},{b!r}\n" for a, b in zip(y, dr)))
    return path


def curved_table():
    """Rows every 0.1 mm on [-12, 11] mm: Delta r = 0.4 mm + 0.3 y + 900 y^3 + 4 y^2 (zero near
    -1.3 mm, steeper to the right than to the left)."""
    y = np.round(np.arange(-0.012, 0.011 + 1e-9, 0.0001), 12)
    return y, 0.0004 + 0.3 * y + 900 * y**3 + 4 * y**2


def kinematic_oracle(y_tab, dr_tab, y_start, r0=R0, e0=E0, steps=40000):
    """Integrate y'' = -Delta r(y) / (2 e0 r0) from the turning point y_start (y' = 0) through
    one full period with RK4 in x; the period ends where y' crosses zero from + to - again
    (located by linear interpolation). Returns (wavelength, y_min, y_max)."""
    def acc(y):
        return -np.interp(y, y_tab, dr_tab) / (2 * e0 * r0)

    # a first pass with a coarse step estimates the wavelength, which sets the fine step
    wavelength = None
    for n in (2000, steps):
        h = (wavelength or 100.0) / n
        y, v, x = y_start, 0.0, 0.0
        y_min = y_start
        crossed_down = False
        while True:
            k1y, k1v = v, acc(y)
            k2y, k2v = v + 0.5 * h * k1v, acc(y + 0.5 * h * k1y)
            k3y, k3v = v + 0.5 * h * k2v, acc(y + 0.5 * h * k2y)
            k4y, k4v = v + h * k3v, acc(y + h * k3y)
            y_new = y + h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y)
            v_new = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
            y_min = min(y_min, y_new)
            if v < 0 <= v_new:
                crossed_down = True          # passed the left turning point
            if crossed_down and v > 0 >= v_new:
                wavelength = x + h * v / (v - v_new)
                break
            y, v, x = y_new, v_new, x + h
    return wavelength, y_min, y_start


def test_conicity_against_the_kinematic_wheelset(raildyn_exe, tmp_path):
    y_tab, dr_tab = curved_table()
    path = write_table(tmp_path / "dr.csv", y_tab, dr_tab)
    for y_start in (0.0015, 0.004, 0.008):
        wavelength, y_min, y_max = kinematic_oracle(y_tab, dr_tab, y_start)
        amplitude = 0.5 * (y_max - y_min)
        res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", repr(amplitude),
                       "--json")
        assert res.returncode == 0, res.stderr
        out = json.loads(res.stdout)
        lam_ode = E0 * R0 * (2 * np.pi / wavelength) ** 2
        print(f"A = {amplitude * 1e3:.4f} mm: ODE {lam_ode:.6f}, raildyn {out['conicity'][0]:.6f}, "
              f"regression {out['conicity_regression'][0]:.6f}")
        assert out["conicity"][0] == pytest.approx(lam_ode, rel=1e-6)
        assert out["wavelength"][0] == pytest.approx(wavelength, rel=1e-6)
        # regression over the motion's range, weighted by a harmonic motion's residence time
        theta = 2 * np.pi * (np.arange(200000) + 0.5) / 200000
        ys = 0.5 * (y_max + y_min) + amplitude * np.sin(theta)
        slope = np.polyfit(ys, np.interp(ys, y_tab, dr_tab), 1)[0]
        assert out["conicity_regression"][0] == pytest.approx(slope / 2, rel=1e-6)
    # the table is curved: the conicity grows with the amplitude, and the two methods differ
    # (by far more than the tolerance above: 4e-5 at 6 mm, nearly the same for a smooth table)
    res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.001,0.006", "--json")
    out = json.loads(res.stdout)
    assert out["conicity"][1] > out["conicity"][0] + 0.01
    assert abs(out["conicity"][1] - out["conicity_regression"][1]) > 1e-5


def test_pure_cone_and_json_interface(raildyn_exe, tmp_path):
    gamma = 0.12
    y = np.round(np.arange(-0.01, 0.01 + 1e-9, 0.0005), 12)
    path = write_table(tmp_path / "cone.csv", y, 2 * gamma * y)
    res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert {"amplitude", "conicity"} <= set(out)
    # default amplitudes: every 0.5 mm up to the table's end
    assert np.allclose(out["amplitude"], np.arange(1, 21) * 0.0005, rtol=0, atol=1e-15)
    assert np.allclose(out["conicity"], gamma, rtol=1e-9)
    assert np.allclose(out["conicity_regression"], gamma, rtol=1e-9)
    assert np.allclose(out["wavelength"], 2 * np.pi * np.sqrt(E0 * R0 / gamma), rtol=1e-9)
    text = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.003")
    assert text.returncode == 0 and "0.12000" in text.stdout


def test_dead_zone_gives_zero_inside(raildyn_exe, tmp_path):
    d, lam = 0.002, 0.1
    y = np.round(np.arange(-0.01, 0.01 + 1e-9, 0.0005), 12)
    path = write_table(tmp_path / "dead.csv", y, 2 * lam * np.sign(y) * np.maximum(np.abs(y) - d, 0))
    res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.001,0.005", "--json")
    out = json.loads(res.stdout)
    assert out["conicity"][0] == 0 and out["conicity_regression"][0] == 0 and out["wavelength"][0] is None
    expect = lam * np.pi**2 / (np.pi + 2 * d / (0.005 - d)) ** 2      # free flight + harmonic halves
    assert out["conicity"][1] == pytest.approx(expect, rel=1e-9)


@pytest.mark.parametrize("content, where, what", [
    ("y,dr\n0,0\n0.001,0.0002\n", ":1:", "is not a number"),
    ("-0.001,-0.0002\n0.001,0.0002\n0.0005,0.0003\n", ":3:", "strictly increasing"),
    ("-0.001,-0.0002\n0.001,0.0002,7\n", ":2:", "3 columns"),
    ("0.001,0.0002\n", "", "at least 2"),
    ("-1,-0.2\n1,0.2\n", ":1:", "millimetres given?"),
    ("-0.001,nan\n0.001,0.0002\n", ":1:", "not finite"),
])
def test_bad_tables_name_file_and_line(raildyn_exe, tmp_path, content, where, what):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--json")
    assert res.returncode == 1, res.stderr
    assert res.stdout == ""
    assert f"{path}{where}" in res.stderr and what in res.stderr, res.stderr


def test_bad_amplitudes_and_usage(raildyn_exe, tmp_path):
    y = np.round(np.arange(-0.004, 0.004 + 1e-9, 0.0005), 12)
    path = write_table(tmp_path / "cone.csv", y, 0.1 * y)
    res = conicity(raildyn_exe, "--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.002,0.005")
    assert res.returncode == 1
    assert str(path) in res.stderr and "largest amplitude it supports is 0.004 m" in res.stderr, res.stderr
    res = conicity(raildyn_exe, "--delta-r", tmp_path / "absent.csv", "--r0", R0, "--e0", E0)
    assert res.returncode == 4 and "absent.csv" in res.stderr
    for args, what in [(["--r0", R0, "--e0", E0], "--delta-r FILE is required"),
                       (["--delta-r", path, "--e0", E0], "--r0 and --e0 are required"),
                       (["--delta-r", path, "--r0", "460", "--e0", E0], "--r0 expects a length in metres"),
                       (["--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.001,x"], "entry 2 'x'"),
                       (["--delta-r", path, "--r0", R0, "--e0", E0, "--amplitudes", "0.001,,0.002"], "entry 2"),
                       (["--delta-r", path, "--r0", R0, "--e0", E0, "--frob"], "unknown option '--frob'")]:
        res = conicity(raildyn_exe, *args)
        assert res.returncode == 1 and what in res.stderr, (args, res.stderr)
        assert res.stderr.splitlines()[-1].startswith("usage: raildyn conicity")
