"""Outputs a user asks for (docs/output.md): the solver statistics in the completion line of
`raildyn run`, checked against the counts a fixed-step method must take (closed form) and
against what the results file keeps in /meta/solver."""
import re
import subprocess

import h5py
import pytest

# A box hanging on a vertical spring-damper under a moving track frame: cheap, no contact.
OSCILLATOR = """&simulation title = 'oscillator', t_end = {t_end}, speed = 10.0, equilibrium = 'none' /
&solver method = '{method}', fixed_step = {h}, rtol = 1e-8, atol = 1e-10 /
&output interval = {interval} {output} /
&segment type = 'straight', length = 1000.0 /
&body name = 'box', mass = 100.0, ixx = 10.0, iyy = 10.0, izz = 10.0, position = 0.0, 0.0, 0.5,
      velocity = 0.0, 0.0, 0.2 /
&element name = 'hanger', type = 'spring_damper', body2 = 'box', point1 = 0.0, 0.0, 0.5,
      stiffness = 1e5, 1e5, 4e4, damping = 50.0, 50.0, 50.0 /
"""


def oscillator_deck(tmp_path, name="osc", t_end=0.1, method="rk4", h=1e-3, interval=0.01, output=""):
    deck = tmp_path / f"{name}.nml"
    deck.write_text(OSCILLATOR.format(t_end=t_end, method=method, h=h, interval=interval, output=output))
    return deck


def run(exe, *args, expect=0):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=120)
    assert res.returncode == expect, res.stdout + res.stderr
    return res


SOLVER_LINE = re.compile(r"solver: (\d+) steps, (\d+) RHS calls \((\d+) for Jacobians\), "
                         r"(\d+) error-test failures, (\d+) Newton failures")


def test_completion_line_counts_fixed_steps(raildyn_exe, tmp_path):
    # rk4 with h = 1 ms to 0.1 s: 100 steps of 4 RHS calls, never a failure
    deck = oscillator_deck(tmp_path)
    out = run(raildyn_exe, "run", deck, "-o", tmp_path / "osc.h5").stdout
    m = SOLVER_LINE.search(out)
    assert m, out
    steps, rhs, rhs_jac, err_fail, newton_fail = map(int, m.groups())
    assert (steps, rhs, rhs_jac, err_fail, newton_fail) == (100, 400, 0, 0, 0)


def test_completion_line_matches_meta_solver(raildyn_exe, tmp_path):
    deck = oscillator_deck(tmp_path, method="bdf")
    out = run(raildyn_exe, "run", deck, "-o", tmp_path / "osc.h5").stdout
    m = SOLVER_LINE.search(out)
    assert m, out
    steps, rhs, rhs_jac, err_fail, newton_fail = map(int, m.groups())
    with h5py.File(tmp_path / "osc.h5", "r") as f:
        s = f["meta/solver"].attrs
        assert steps == s["n_steps"] > 0
        assert rhs == s["n_rhs"] + s["n_rhs_jacobian"]
        assert rhs_jac == s["n_rhs_jacobian"]
        assert err_fail == s["n_error_fail"]
        assert newton_fail == s["n_newton_fail"]
