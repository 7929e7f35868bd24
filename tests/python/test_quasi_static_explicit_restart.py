"""An explicit integrator's restart on quasi-static normal contact (issue 14 item 5): the flange
climb scene of bench/extremes (Manchester V1, S1002/60E1 contact tables with FASTSIM, R 80 m at
2 m/s, friction 0.6, 120 kN outwards on wheelset 1 from 0.5 s), run with erk (ARKODE's
Dormand-Prince) until it stops.

After the load's onset a stage of an explicit step can reach a state where the quasi-static
solve of a wheelset's height and roll does not converge; the glue then restarts from the last
accepted step with a quarter of the step (sundials_glue.c, erk_evolve). That restart's first
evaluation is the accepted step's state, which its last stage solved. Before, the solve
started there from the failed stages' solutions (ahead in time, off the solution) and did not
converge either: the run ended in a solver failure (exit 2, ARK_RHSFUNC_FAIL) at 0.5015 s for
some output intervals (the published extremes matrix: 0.01 s; here also 0.002 s, which an
eight-entry history of solutions still failed). Now the solve starts at the accepted step's own
solution (rd_multibody, solve_quasi_static).

Oracle: the scene's physics, reached by an independent integrator: BDF (CVODE) on the same deck
ends in the documented stop (exit 3) on wheelset 1, a derailment at 0.578 s; erk must end in the
same stop at the same time within 0.01 s, at every output interval, and never in a solver failure.
"""
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EXE = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"


def run(tmp_path, method, interval):
    scene = REPO / "bench" / "extremes" / "scenes" / "manchester__flange_climb.nml"
    deck = tmp_path / f"climb_{method}_{interval:g}.nml"
    levels = "".join(f"&wheelset name = 'w{k}', contact_geometry = 'table', creep_law = 'fastsim' /\n"
                     for k in range(1, 5))
    deck.write_text(f"&include file = {str(scene)!r} /\n{levels}"
                    f"&solver method = '{method}' /\n"
                    f"&output interval = {interval!r} /\n")
    out = tmp_path / f"climb_{method}_{interval:g}.h5"
    res = subprocess.run([str(EXE), "run", str(deck), "-o", str(out), "--quiet"], capture_output=True, text=True,
                         timeout=600)
    return res


def stop_time(stderr: str) -> float:
    """The time in the contact's stop reason ('wheelset contact 1, right wheel, t = ... s:')."""
    head = stderr.split("wheelset contact 1, ", 1)[1]
    return float(head.split("t = ", 1)[1].split(" s", 1)[0])


@pytest.fixture(scope="module")
def bdf_stop(tmp_path_factory):
    res = run(tmp_path_factory.mktemp("bdf"), "bdf", 0.01)
    assert res.returncode == 3, res.stderr
    assert "derailment" in res.stderr, res.stderr
    return stop_time(res.stderr)


@pytest.mark.parametrize("interval", [0.01, 0.002])
def test_erk_reaches_the_physics_stop_of_bdf(tmp_path, bdf_stop, interval):
    res = run(tmp_path, "erk", interval)
    assert "did not converge" not in res.stderr, res.stderr
    assert res.returncode == 3, res.stderr
    assert "wheelset contact 1, " in res.stderr and "derailment" in res.stderr, res.stderr
    assert abs(stop_time(res.stderr) - bdf_stop) < 0.01, (stop_time(res.stderr), bdf_stop)
