"""Outputs a user asks for (docs/output.md): the solver statistics in the completion line of
`raildyn run`, checked against the counts a fixed-step method must take (closed form) and
against what the results file keeps in /meta/solver."""
import re
import subprocess

import h5py
import pytest

# A box hanging on a vertical spring-damper under a moving track frame: cheap, no contact.
OSCILLATOR = """&simulation title = 'oscillator', t_end = {t_end}, speed = 10.0, equilibrium = 'none' /
&solver method = '{method}', {solver} /
&output interval = {interval} {output} /
&segment type = 'straight', length = 1000.0 /
&body name = 'box', mass = 100.0, ixx = 10.0, iyy = 10.0, izz = 10.0, position = 0.0, 0.0, 0.5,
      velocity = 0.0, 0.0, 0.2 /
&element name = 'hanger', type = 'spring_damper', body2 = 'box', point1 = 0.0, 0.0, 0.5,
      stiffness = 1e5, 1e5, 4e4, damping = 50.0, 50.0, 50.0 /
"""


def oscillator_deck(tmp_path, name="osc", t_end=0.1, method="rk4", h=1e-3, interval=0.01, output=""):
    deck = tmp_path / f"{name}.nml"
    # each method's own parameters (rk4 reads no tolerances, the others no fixed step)
    solver = f"fixed_step = {h}" if method == "rk4" else "rtol = 1e-8, atol = 1e-10"
    deck.write_text(OSCILLATOR.format(t_end=t_end, method=method, solver=solver, interval=interval,
                                      output=output))
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


def datasets(path):
    names = []
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    return set(names)


# A knife-edge wheelset resting on the rails: the contact groups (wheelsets, patches).
WHEELSET = """&simulation title = 'rest', t_end = 0.02, speed = 5.0, equilibrium = 'none' /
&output interval = 0.005 {output} /
&segment type = 'straight', length = 100.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, 0.44999, frozen = 'x', 'y', 'yaw', 'roll' /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = 0.05, creep_law = 'linear' /
"""


def test_output_groups_select_the_written_series(raildyn_exe, tmp_path):
    full, part = tmp_path / "full.h5", tmp_path / "part.h5"
    run(raildyn_exe, "run", oscillator_deck(tmp_path, "full"), "-o", full)
    run(raildyn_exe, "run", oscillator_deck(tmp_path, "part", output=", groups = 'bodies', 'state'"),
        "-o", part)
    every = datasets(full)
    # the default writes every group
    assert {n.split("/")[0] for n in every} == {"time", "meta", "vehicle", "track", "bodies",
                                                "elements", "state"}
    kept = datasets(part)
    assert kept == {n for n in every if n.split("/")[0] in ("time", "meta", "bodies", "state")}
    with h5py.File(full, "r") as a, h5py.File(part, "r") as b:
        for name in kept - {"meta/deck_text"}:
            assert (a[name][...] == b[name][...]).all(), name
            assert dict(a[name].attrs) == dict(b[name].attrs), name
        # the results file keeps the solver statistics whatever the selection
        assert b["meta/solver"].attrs["n_steps"] == a["meta/solver"].attrs["n_steps"]


def test_patches_are_their_own_group(raildyn_exe, tmp_path):
    deck = tmp_path / "ws.nml"
    deck.write_text(WHEELSET.format(output=", groups = 'wheelsets'"))
    run(raildyn_exe, "run", deck, "-o", tmp_path / "ws.h5")
    kept = datasets(tmp_path / "ws.h5") - {"time", "meta/deck_text"}
    assert kept == {"wheelsets/w1/summary", "wheelsets/w1/rail_offsets",
                    "wheelsets/w1/left/wheel", "wheelsets/w1/right/wheel"}
    deck.write_text(WHEELSET.format(output=", groups = 'patches'"))
    run(raildyn_exe, "run", deck, "-o", tmp_path / "ws.h5")
    kept = datasets(tmp_path / "ws.h5") - {"time", "meta/deck_text"}
    assert kept == {f"wheelsets/w1/{side}/patch{j}" for side in ("left", "right") for j in range(1, 5)}


def test_unknown_output_group_names_the_deck_line(raildyn_exe, tmp_path):
    deck = oscillator_deck(tmp_path, output=", groups = 'bodies', 'contact'")
    err = run(raildyn_exe, "check", deck, expect=1).stderr
    assert "osc.nml:3" in err and "groups" in err and "'contact'" in err, err


def test_state_series_is_the_body_coordinates_and_rates(raildyn_exe, tmp_path):
    # on straight track the generalized velocities are the relative rates (rd_multibody)
    run(raildyn_exe, "run", oscillator_deck(tmp_path), "-o", tmp_path / "osc.h5")
    with h5py.File(tmp_path / "osc.h5", "r") as f:
        y = f["state/y"]
        comps = y.attrs["components"].decode().split()
        dofs = ["x", "y", "z", "yaw", "roll", "pitch"]
        assert comps == [f"box.{d}" for d in dofs] + [f"box.nu_{d}" for d in dofs]
        assert y.attrs["unit"].decode().split() == ["m"] * 3 + ["rad"] * 3 + ["m/s"] * 3 + ["rad/s"] * 3
        assert (y[:, :6] == f["bodies/box/position_track"][...]).all()
        assert abs(y[:, 6:] - f["bodies/box/velocity_track"][...]).max() < 1e-12


def read_csv(path):
    import numpy as np
    lines = path.read_text().splitlines()
    return lines[0].split(","), np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def test_export_writes_one_csv_per_series_with_the_files_units(raildyn_exe, tmp_path):
    run(raildyn_exe, "run", oscillator_deck(tmp_path), "-o", tmp_path / "osc.h5")
    out = run(raildyn_exe, "export", tmp_path / "osc.h5", "--csv", tmp_path / "csv").stdout
    with h5py.File(tmp_path / "osc.h5", "r") as f:
        series = []
        f.visititems(lambda n, o: series.append(n) if isinstance(o, h5py.Dataset)
                     and o.ndim == 2 else None)
        assert f"{len(series)} CSV files" in out
        files = {str(p.relative_to(tmp_path / "csv"))[:-4] for p in (tmp_path / "csv").rglob("*.csv")}
        assert files == set(series)
        for name in series:
            header, table = read_csv(tmp_path / "csv" / f"{name}.csv")
            comps = f[name].attrs["components"].decode().split()
            units = f[name].attrs["unit"].decode().split()
            units = units * len(comps) if len(units) == 1 else units
            assert header == ["time [s]"] + [f"{c} [{u}]" for c, u in zip(comps, units)], name
            assert (table[:, 0] == f["time"][...]).all()
            assert (table[:, 1:] == f[name][...]).all(), name     # 17 digits: exact doubles


def test_export_refuses_a_series_without_units(raildyn_exe, tmp_path, make_results_file):
    import numpy as np
    path = make_results_file("bare.h5", [0.0, 0.1],
                             {"bodies/b/position_track": (np.zeros((2, 2)), "m m m", "x y", "")})
    res = run(raildyn_exe, "export", path, "--csv", tmp_path / "csv", expect=1)
    assert "bodies/b/position_track" in res.stderr and "'m m m'" in res.stderr, res.stderr
    res = run(raildyn_exe, "export", tmp_path / "missing.h5", "--csv", tmp_path / "csv", expect=4)
    assert "missing.h5: no such file" in res.stderr
