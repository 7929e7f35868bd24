"""`&solver jacobian_max_age` (BDF): the most steps between two evaluations of the Newton
matrix's Jacobian, CVODE's msbj (docs/theory_solver.md "Jacobian age"). The TGV vehicle in its
curve (inputs/tgv_vehicle_curve.nml, knife-edge contact), 1 s, with the default and two ages.

Oracle: CVODE's rule. The Jacobian's age is checked where CVODE sets the linear solver up,
which it does at least every 20 steps (its msbp); a setup at least N steps after the last
evaluation evaluates it again. So a run of n steps with an age of N makes at least
n / (N + 20) - 1 evaluations, and with an age of 1 every setup that follows a step evaluates it;
a setup repeated without a step between, for the retry of a failed attempt (an error-test or
a Newton failure, at most one setup each), keeps it: the setups are at most the evaluations
plus the failures. (An empirical "90 % of the setups" held until the rounding changed: 156
evaluations of 175 setups with 58 failures, 2026-11-29.) A larger age than the default makes fewer evaluations, and the motion stays
within the solver's tolerance of the default's (an old Jacobian slows Newton's convergence,
whose test is unchanged): the wheelsets' lateral shifts agree within 20 um (rtol 1e-6 and
atol 1e-8 over 1 s)."""
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
EXE = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("age")
    out = {}
    for age in (None, 1, 1000):
        deck = tmp / f"age_{age}.nml"
        extra = "" if age is None else f"&solver jacobian_max_age = {age} /\n"
        deck.write_text(f"&include file = {str(REPO / 'inputs' / 'tgv_vehicle_curve.nml')!r} /\n"
                        f"&simulation t_end = 1.0 /\n{extra}")
        res = subprocess.run([str(EXE), "run", str(deck), "-o", str(tmp / f"age_{age}.h5"), "--quiet"],
                             capture_output=True, text=True, timeout=600)
        assert res.returncode == 0, res.stderr
        with h5py.File(tmp / f"age_{age}.h5", "r") as f:
            solver = {k: int(v) for k, v in f["meta/solver"].attrs.items() if k.startswith("n_")}
            y = np.array([f[f"bodies/ws{k}/position_track"][:, 1] for k in range(1, 5)])
        out[age] = (solver, y)
    return out


def test_the_default_age_is_51(runs):
    s = runs[None][0]
    assert s["n_jac"] >= s["n_steps"] / (51 + 20) - 1, s
    assert s["n_jac"] < s["n_linear_setups"] / 2, s


def test_an_age_of_one_evaluates_at_every_setup(runs):
    s = runs[1][0]
    assert s["n_linear_setups"] <= s["n_jac"] + s["n_error_fail"] + s["n_newton_fail"], s
    # and not the default age's count (a setup without an evaluation at every other step)
    assert s["n_jac"] > s["n_linear_setups"] / 2, s


def test_an_older_jacobian_makes_fewer_evaluations_and_the_same_motion(runs):
    default, old = runs[None], runs[1000]
    assert old[0]["n_jac"] < default[0]["n_jac"], (old[0], default[0])
    assert old[0]["n_rhs_jacobian"] < default[0]["n_rhs_jacobian"]
    assert np.abs(old[1] - default[1]).max() < 20e-6
