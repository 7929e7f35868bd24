"""Quasi-static normal contact (`&wheelset normal_contact = 'quasi_static'`, docs/theory.md):
a wheelset's height and roll leave the state and follow their force balance at every
evaluation. Checked against the elastic model of the same deck, which is independent of the
quasi-static solve (it integrates z and roll on the Hertz springs):

- at the quasi-static solution, the elastic model's vertical and roll accelerations of every
  wheelset vanish (the solve balances exactly the loads the equations of motion see);
- the quasi-static model's linearisation equals the static condensation of the elastic
  model's linearisation at that state, A_o,o - A_o,p (A_a,p)^-1 A_a,o (o: the remaining states,
  p: z and roll, a: their accelerations), written here from the two matrices;
- a frozen z or roll on a quasi-static wheelset is refused at its deck line.

The two-axle wagon of docs/first_vehicle.md, at t = 0 on its straight track (relative rates
equal generalized velocities there)."""
import subprocess
from pathlib import Path

import numpy as np
import pytest

from raildyn import Model

REPO = Path(__file__).resolve().parents[2]
WAGON = REPO / "inputs" / "first_wagon.nml"
WHEELSETS = {"w1": "ws1", "w2": "ws2"}
# bodies in deck order with their frozen coordinates (x y z yaw roll pitch), as the deck says
BODIES = [("car", {"x"}), ("ws1", set()), ("ws2", set())]
DOFS = ["x", "y", "z", "yaw", "roll", "pitch"]


def deck(quasi_static: bool) -> str:
    text = f"&include file = '{WAGON}' /\n"
    if quasi_static:
        text += "".join(f"&wheelset name = '{w}', normal_contact = 'quasi_static' /\n" for w in WHEELSETS)
    return text


def free_coordinates(quasi_static: bool) -> list[tuple[str, str]]:
    """(body, dof) of every free coordinate in state order (docs/output.md /state/y)."""
    out = []
    for body, frozen in BODIES:
        held = set(frozen)
        if quasi_static and body in WHEELSETS.values():
            held |= {"z", "roll"}
        out += [(body, d) for d in DOFS if d not in held]
    return out


@pytest.fixture(scope="module")
def models(build_dir):
    qs = Model.from_string(deck(True), base_dir=REPO / "inputs")
    qs.initialize(write_output=False)
    el = Model.from_string(deck(False), base_dir=REPO / "inputs")
    el.initialize(write_output=False)
    # the elastic state at the quasi-static solution: z and roll from the quasi-static model's
    # outputs, their rates zero (relative rates = generalized velocities on straight track)
    coords_qs, coords_el = free_coordinates(True), free_coordinates(False)
    y_qs = qs.state()
    assert y_qs.size == 2 * len(coords_qs)
    value = dict(zip(coords_qs, y_qs[:len(coords_qs)]))
    rate = dict(zip(coords_qs, y_qs[len(coords_qs):]))
    for body in WHEELSETS.values():
        pos = qs.output(f"bodies/{body}/position_track")
        value[(body, "z")], value[(body, "roll")] = pos[2], pos[4]
        rate[(body, "z")] = rate[(body, "roll")] = 0.0
    y_el = np.array([value[c] for c in coords_el] + [rate[c] for c in coords_el])
    assert y_el.size == el.state().size
    el.set_state(y_el)
    yield qs, el, coords_qs, coords_el
    qs.close()
    el.close()


def test_the_solution_balances_the_elastic_equations(models):
    qs, el, _, _ = models
    for body in WHEELSETS.values():
        acc = el.output(f"bodies/{body}/acceleration_track")
        # g = 9.8 m/s^2 is what an unbalanced wheelset would show; the solve is at rounding
        assert abs(acc[2]) < 1e-6, (body, acc)
        assert abs(acc[4]) < 1e-5, (body, acc)
        # the wheel loads carry the wagon (a check that the solution is in contact at all)
        q = [el.output(f"wheelsets/{w}/{s}/wheel")[3] for w, b in WHEELSETS.items() if b == body
             for s in ("left", "right")]
        assert min(q) > 40e3, q


def test_linearisation_is_the_condensed_elastic_one(models):
    qs, el, coords_qs, coords_el = models
    a_qs, a_el = qs.linearize(), el.linearize()
    n_el, n_qs = len(coords_el), len(coords_qs)
    keep = [coords_el.index(c) for c in coords_qs]
    o = keep + [n_el + k for k in keep]
    p = [coords_el.index((b, d)) for b in WHEELSETS.values() for d in ("z", "roll")]
    a = [n_el + k for k in p]
    condensed = a_el[np.ix_(o, o)] - a_el[np.ix_(o, p)] @ np.linalg.solve(a_el[np.ix_(a, p)], a_el[np.ix_(a, o)])
    assert condensed.shape == a_qs.shape == (2 * n_qs, 2 * n_qs)
    # entrywise, relative to each column's size (both are central differences of the RHS, step
    # h_j = 1e-8 max(1, |y_j|), rd_scene_linearization), plus the quasi-static solve's own noise:
    # converged to 1e-13 m/rad (rd_multibody), i.e. accelerations to |A_a,p| 1e-13, which a
    # central difference turns into up to 10 |A_a,p| 1e-13 / (2 h_j) on an entry (factor 10:
    # the two solves of a difference and their propagation to the other rows)
    scale = np.maximum(np.abs(condensed).max(axis=0), 1e-6)
    y_qs = qs.state()
    noise = 10 * np.abs(a_el[np.ix_(a, p)]).max() * 1e-13 / (2 * 1e-8 * np.maximum(1.0, np.abs(y_qs)))
    err = np.abs(a_qs - condensed) / (1e-4 * scale + noise)
    assert err.max() < 1, (err.max(), np.unravel_index(err.argmax(), err.shape))
    # and the condensation is not the trivial part of the elastic matrix: the coupling through
    # z and roll changes the lateral rows
    assert np.abs(a_el[np.ix_(o, o)] - condensed).max() / scale.max() > 1e-3
    lam_qs = np.sort_complex(np.linalg.eigvals(a_qs))
    lam_c = np.sort_complex(np.linalg.eigvals(condensed))
    assert np.allclose(lam_qs, lam_c, rtol=1e-4, atol=1e-3)


def test_frozen_height_is_refused_at_its_line(raildyn_exe, tmp_path):
    path = tmp_path / "frozen.nml"
    path.write_text(deck(False) + "&body name = 'ws1', frozen = 'z' /\n"
                    "&wheelset name = 'w1', normal_contact = 'quasi_static' /\n")
    res = subprocess.run([str(raildyn_exe), "check", str(path)], capture_output=True, text=True, timeout=120)
    assert res.returncode != 0
    err = res.stdout + res.stderr
    assert "frozen.nml:3" in err and "normal_contact" in err and "frozen" in err, err
