"""`raildyn critical-speed` against a linear wheelset model derived here, and the bracket
theory puts the nonlinear methods in (docs/theory_stability.md section 3).

The linear model of the conical wheelset on knife-edge rails (tests/decks/knife_edge_wheelset.nml)
in its lateral shift y and yaw psi, written from rigid-body kinematics and Kalker's linear law:

- knife-edge roll kinematics: the rails are lines at +-e0, the wheels cones of slope
  lam = tan(d); a lateral shift y rolls the wheelset by phi = s y, s = lam / (e0 - r0 lam)
  (the left rail point lies on the cone at e0 - y - r0 phi, so sin(phi) = (r_L - r_R)/(2 e0)),
  and the rolling radii are r0 +- lam_e y with lam_e = lam e0 / (e0 - r0 lam);
- longitudinal creepages -+(lam_e y / r0 + e0 psi'/V): yaw moment -2 f11 e0 (lam_e y/r0 + e0 psi'/V);
- lateral creepage of the contact point, whose lateral velocity is y' + r0 phi' along the
  track plus e0 phi' sin(d) in the tilted contact plane: eta = (kap y'/V - psi) / cos(d),
  kap = e0 / (e0 - r0 lam); the two creep forces give -2 f22 (kap y'/V - psi) along Y_T;
- load transfer: the lateral creep forces act at the rails, a lever m_c = e0 sin d + r0 cos d
  below the centre of mass; the roll balance (quasi-static) shifts N_L - N_R by
  -m_c F_contact / ell, ell = e0 cos d - r0 sin d, whose inclined normals (-sin d each) add
  sin(d) m_c / (ell cos d) of the creep force to it;
- gravitational stiffness: the normal forces N0 turned by the roll (-2 N0 cos(d) s y) and the
  load transfer of the moved normals (-sin(d) 2 N0 (cos d + m_c s) y / ell);
- springs: 2 k_y laterally, 2 k_x d^2 in yaw; masses m and izz.
Left out: the gyroscopic terms (iyy = 10 kg m^2 in the deck), the roll inertia of the
quasi-static roll (ixx s^2 / m ~ 1 %), terms of order lam^2 (1 %). The creep coefficients
f11, f22 (per wheel) and the wheel load N0 are measured from the wheels' own outputs through
the C API (creep force over creepage for a small spin and lateral rate), not taken from the
linearisation. Dropping the roll kinematics (kap = 1, lam_e = lam) moves the model's critical
speed by 0.4 %, the load transfer by 0.5 %: the tolerances below (0.25 %) tell them apart."""
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import raildyn
from raildyn.stability import peaks_after_speed_change

REPO = Path(__file__).resolve().parents[2]
DECKS = REPO / "tests" / "decks"
WHEELSET = DECKS / "knife_edge_wheelset.nml"
HUNTING = DECKS / "knife_edge_wheelset_hunting.nml"
M, IZZ, LAM, E0, R0, KX, KY, D = 1500.0, 800.0, 0.1, 0.75, 0.45, 1.0e6, 1.0e6, 1.0   # the deck's numbers


def critical_speed(exe, deck, *args, expect=0, cwd=None):
    res = subprocess.run([str(exe), "critical-speed", str(deck), *map(str, args), "--json"],
                         capture_output=True, text=True, timeout=600, cwd=cwd)
    assert res.returncode == expect, res.stdout + res.stderr
    return json.loads(res.stdout) if expect == 0 else res


def measured_contact(speed):
    """f11, f22 [N] per wheel and N0 [N] at the static equilibrium, from the patch outputs
    (creep force / creepage) after a small spin rate and a small lateral rate."""
    with raildyn.Model.from_file(WHEELSET) as model:
        model.initialize(write_output=False)
        model.set_input("speed", speed)
        y0 = model.state()
        nfree = y0.size // 2            # x y z yaw roll pitch, then their rates

        def patches(y):
            model.set_state(y)
            return [model.output(f"wheelsets/w/{side}/patch1") for side in ("left", "right")]
        base = patches(y0)
        f = {}
        # slot in the rates: pitch (spin), y; patch columns: xi, creep_force_x / eta, creep_force_y
        for slot, (creep, force), key in ((5, (3, 6), "f11"), (1, (4, 7), "f22")):
            y = y0.copy()
            y[nfree + slot] += 1e-3
            moved = patches(y)
            f[key] = -np.mean([(p[force] - b[force]) / (p[creep] - b[creep]) for p, b in zip(moved, base)])
        return f["f11"], f["f22"], 0.5 * (base[0][2] + base[1][2])


def model_eigenvalue(speed, f11, f22, n0):
    """Least-stable eigenvalue of the (y, psi) model of the module docstring."""
    d = math.atan(LAM)
    sd, cd = math.sin(d), math.cos(d)
    s = LAM / (E0 - R0 * LAM)
    lam_e, kap = LAM * E0 / (E0 - R0 * LAM), E0 / (E0 - R0 * LAM)
    ell, m_c = E0 * cd - R0 * sd, E0 * sd + R0 * cd
    transfer = 1 + sd * m_c / (cd * ell)
    k_gravity = -2 * n0 * cd * s - sd * 2 * n0 * (cd + m_c * s) / ell
    K = np.array([[2 * KY - k_gravity, -2 * transfer * f22],
                  [2 * f11 * E0 * lam_e / R0, 2 * KX * D ** 2]])
    C = np.array([[2 * transfer * f22 * kap / speed, 0.0],
                  [0.0, 2 * f11 * E0 ** 2 / speed]])
    Minv = np.diag([1 / M, 1 / IZZ])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    ev = np.linalg.eigvals(A)
    return ev[np.argmax(ev.real)]


@pytest.fixture(scope="module")
def linear(raildyn_exe):
    return critical_speed(raildyn_exe, WHEELSET, "--method", "linear", "--speeds", "20,200",
                          "--resolution", "0.02")


def test_linear_critical_speed_and_hunting_frequency(linear):
    """raildyn's linear critical speed and hunting frequency equal the model's to 0.25 %."""
    f11, f22, n0 = measured_contact(linear["critical_speed"])
    lo, hi = 20.0, 200.0
    assert model_eigenvalue(lo, f11, f22, n0).real < 0 < model_eigenvalue(hi, f11, f22, n0).real
    while hi - lo > 1e-3:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if model_eigenvalue(mid, f11, f22, n0).real > 0 else (mid, hi)
    frequency = abs(model_eigenvalue(hi, f11, f22, n0).imag) / (2 * math.pi)
    assert linear["resolution"] <= 0.02
    assert linear["critical_speed"] == pytest.approx(lo, rel=2.5e-3)
    assert linear["mode"]["frequency_hz"] == pytest.approx(frequency, rel=2.5e-3)
    assert [d["body"] + "." + d["dof"] for d in linear["mode"]["dominant"]][:2] == ["ws.y", "ws.yaw"]
    assert linear["bracket"][0] <= linear["critical_speed"] <= linear["bracket"][1]


def hunting_after_speed_change(speed, hold_speed=100.0, hold=3.0, after=20.0):
    """Half-cycle peaks of the wheelset's lateral shift over ``after`` seconds at ``speed``,
    starting from the limit cycle reached at ``hold_speed``."""
    return peaks_after_speed_change(HUNTING, speed, hold_speed, hold, after)


def test_ramp_extrapolates_to_where_hunting_ends(raildyn_exe, linear, tmp_path):
    """With saturating creep forces and a flange stop the wheelset hunts on a bounded cycle.
    Constant-speed runs started on that cycle place the end of hunting (the nonlinear
    critical speed) within 0.5 m/s of the linear critical speed: the cycle goes on 0.5 m/s
    above it and dies 0.5 m/s below it (measured: it lives at 80.85 m/s, dies at 80.82 m/s;
    linear 80.95 m/s). Each ramp reads below that by its lag, the faster the lower; the
    extrapolation of two ramp rates to a zero rate (docs/theory_stability.md section 5a)
    lands within that 0.5 m/s, which neither ramp does alone."""
    hunting_linear = critical_speed(raildyn_exe, HUNTING, "--method", "linear", "--speeds", "20,200")
    # saturation and flange stop leave the centred state's linearisation as it is
    assert hunting_linear["critical_speed"] == pytest.approx(linear["critical_speed"], abs=0.6)
    v_lin = linear["critical_speed"]
    _, peaks = hunting_after_speed_change(v_lin + 0.5)
    assert peaks.size > 200 and peaks[-5:].min() > 0.9 * peaks[5:10].max()      # goes on
    _, peaks = hunting_after_speed_change(v_lin - 0.5)
    assert peaks[-1] < 0.5 * peaks[0]                                            # dies out
    ramp = critical_speed(raildyn_exe, HUNTING, "--method", "ramp", "--speeds", "60,100", "--hold", "3",
                          "--duration", "32,64", "--jobs", "2", "--work", tmp_path)
    fast, slow = (p["critical_speed"] for p in ramp["probes"])
    assert [p["duration"] for p in ramp["probes"]] == [32.0, 64.0]
    assert fast < slow < v_lin - 0.5                        # each ramp lags, the faster more
    assert abs(ramp["critical_speed"] - v_lin) < 0.5        # the extrapolation does not
    assert ramp["resolution"] < 1.0
    assert slow < ramp["bracket"][0] < ramp["critical_speed"] < ramp["bracket"][1]   # above the slow one
    assert ramp["mode"]["dominant"][0]["body"] == "ws" and ramp["mode"]["dominant"][0]["dof"] == "y"
    assert ramp["mode"]["measured_frequency_hz"] == pytest.approx(linear["mode"]["frequency_hz"], rel=0.1)


def test_tgv_bogie_nonlinear_below_linear(raildyn_exe, tmp_path):
    """TGV 001 bogie (Kalker linear creep, knife edges): the bisection on disturbed runs and
    the root locus bracket each other as theory says, the nonlinear critical speed not above
    the linear one, and with this nearly linear model (no saturation, no flange) close to it."""
    deck = REPO / "inputs" / "tgv_bogie_straight_40.nml"
    lin = critical_speed(raildyn_exe, deck, "--method", "linear", "--speeds", "30,45", "--resolution", "0.25")
    bis = critical_speed(raildyn_exe, deck, "--method", "bisection", "--speeds", "30,45", "--resolution", "1",
                         "--jobs", "2", "--t-end", "8", "--work", tmp_path)
    assert bis["critical_speed"] - bis["resolution"] <= lin["critical_speed"] + lin["resolution"]
    assert bis["critical_speed"] + bis["resolution"] >= 0.95 * lin["critical_speed"]
    assert lin["mode"]["dominant"][0]["dof"] == "y"
    assert bis["mode"]["measured_frequency_hz"] == pytest.approx(lin["mode"]["frequency_hz"], rel=0.1)
    growing = [p for p in bis["probes"] if p["growth_rate"] > 0]
    decaying = [p for p in bis["probes"] if p["growth_rate"] <= 0]
    assert max(p["speed"] for p in decaying) < min(p["speed"] for p in growing)


def test_bracket_without_a_crossing(raildyn_exe):
    stable = critical_speed(raildyn_exe, WHEELSET, "--method", "linear", "--speeds", "10,50")
    assert stable["critical_speed"] is None and "stable up to 50 m/s" in stable["note"]
    unstable = critical_speed(raildyn_exe, WHEELSET, "--method", "linear", "--speeds", "100,150")
    assert unstable["critical_speed"] is None and "unstable already at 100 m/s" in unstable["note"]


@pytest.mark.parametrize("args, words", [
    (["--method", "sideways"], "invalid choice: 'sideways'"),
    (["--method", "linear", "--speeds", "50,10"], "0 <= LO < HI"),
    (["--method", "linear", "--resolution", "0"], "--resolution expects a speed > 0"),
])
def test_usage_errors(raildyn_exe, args, words):
    res = critical_speed(raildyn_exe, WHEELSET, *args, expect=1)
    assert words in res.stderr and res.stdout == ""
