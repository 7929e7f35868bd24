"""A first vehicle without traps (docs/first_vehicle.md): the shipped two-axle wagon runs; a
body whose x is free and falls behind its track frame gets a warning (closed form: a constant
longitudinal force F on a free body moves it by F t^2 / (2 m)); `raildyn check` prints the
masses, static wheel loads, conicity, the cant deficiency of every curve and what the static
equilibrium moved, each checked against an independent formulation here."""
import math
import re
import subprocess
from pathlib import Path

import h5py
import pytest

REPO = Path(__file__).resolve().parents[2]
WAGON = REPO / "inputs" / "first_wagon.nml"
G = 9.80665


def run(exe, *args, expect=0):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=600)
    assert res.returncode == expect, res.stdout + res.stderr
    return res


def test_the_first_wagon_runs_without_warnings(raildyn_exe, tmp_path):
    out = run(raildyn_exe, "run", WAGON, "-o", tmp_path / "wagon.h5").stdout
    assert "completed t = 6 s, 601 output steps" in out
    assert "warning" not in out and "note" not in out, out
    with h5py.File(tmp_path / "wagon.h5", "r") as f:
        assert f["meta"].attrs["status"] == b"completed"
        # it ran into the curve: the last track frame of the car body lies in the 600 m curve
        assert f["track/frames/1/curvature"][-1, 0] == pytest.approx(1 / 600.0)
        # the leading wheelset steers outwards (to the right, -y) in the left-hand curve
        assert f["bodies/ws1/position_track"][-1, 1] < -1e-3


def test_check_of_the_first_wagon(raildyn_exe):
    out = run(raildyn_exe, "check", WAGON).stdout
    masses = {"car": 20000.0, "ws1": 1300.0, "ws2": 1300.0}
    total = sum(masses.values())
    m = re.search(r"masses: car ([\d.]+) kg, ws1 ([\d.]+) kg, ws2 ([\d.]+) kg; total ([\d.]+) kg, "
                  r"weight ([\d.]+) kN", out)
    assert m, out
    assert [float(v) for v in m.groups()[:3]] == list(masses.values())
    assert float(m.group(4)) == total
    assert float(m.group(5)) == pytest.approx(total * G / 1e3, abs=0.01)
    # a symmetric vehicle on level straight track: each wheel carries a quarter of the weight
    loads = [float(q) for q in re.findall(r"(?:left|right) ([\d.]+) kN", out.split("static wheel loads Q:")[1]
                                          .splitlines()[0])]
    assert len(loads) == 4
    for q in loads:
        assert q == pytest.approx(total * G / 4e3, rel=2e-3)
    # S1002 on 60E1 at 1:40, centred: the conicity is of the order 0.1-0.3 (measured here)
    # (the line that starts with "conicity": the checkout's path may contain the word too)
    lam = [float(x) for x in re.findall(r"w\d ([\d.]+)", out.split("\nconicity")[1].splitlines()[0])]
    assert len(lam) == 2 and lam[0] == pytest.approx(lam[1], rel=1e-6) and 0.05 < lam[0] < 0.5, out
    # the curve of the deck: 40 m straight + 30 m clothoid, then 200 m of R 600 m, cant 80 mm
    m = re.search(r"sigma (\d+)-(\d+) m: R (\d+) m left, cant (\d+) mm; V ([\d.]+) m/s at entry "
                  r"\(t = ([\d.]+) s\): unbalanced lateral acceleration ([\d.]+) m/s\^2, cant deficiency "
                  r"(-?\d+) mm", out)
    assert m, out
    assert (int(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))) == (70, 270, 600, 80)
    v, R, h, s = 20.0, 600.0, 0.08, 1.5
    assert float(m.group(6)) == pytest.approx((70 - 10) / v, abs=0.01)   # start_sigma 10 m
    phi = math.asin(h / s)
    a_q = v ** 2 / R * math.cos(phi) - G * math.sin(phi)
    assert float(m.group(7)) == pytest.approx(a_q, abs=1e-3)
    assert int(m.group(8)) == round(1e3 * s * a_q / G)
    assert abs(int(m.group(8)) - 1e3 * (s * v ** 2 / (G * R) - h)) < 1.0   # small-angle form
    assert "equilibrium (preload) moved the bodies" in out and "warning" not in out, out


KNIFE_EDGE = """&simulation t_end = 1.0, speed = 10.0, equilibrium = 'solve' /
&segment type = 'straight', length = 100.0 /
&body name = 'ws1', mass = 1500.0, ixx = 800.0, iyy = 100.0, izz = 800.0,
      position = 0.0, 0.0, {z} /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = {conicity}, creep_law = 'linear' /
&element name = 'hold', type = 'spring_damper', body2 = 'ws1', point1 = 0.0, 0.0, 0.45,
      stiffness = 1e6, 1e6, 0.0 /
"""


def test_check_conicity_and_equilibrium_moves_of_a_knife_edge_wheelset(raildyn_exe, tmp_path):
    deck = tmp_path / "ke.nml"
    deck.write_text(KNIFE_EDGE.format(z=0.45, conicity=0.05))
    out = run(raildyn_exe, "check", deck).stdout
    # knife-edge wheels are cones of slope 0.05: r = r0 +- 0.05 y, so (dr(+y) - dr(-y)) / 4y = 0.05
    assert re.search(r"conicity .*: w1 0\.0500\b", out), out
    assert "curves: none" in out
    assert "warning" not in out
    assert re.search(r"moved the bodies from the deck's positions by: ws1 -?0\.\d\d mm \(z\)", out), out


def test_check_warns_when_the_equilibrium_moves_a_body_far(raildyn_exe, tmp_path):
    # the wagon's leading wheelset placed at z = 0 instead of its rolling radius 0.46 m: the
    # static solve lifts it onto the rails, 0.46 m, which passed silently before
    text = WAGON.read_text()
    wrong = "position = 0.0, 0.0, 0.0, frame_offset = 3.0"
    assert text.count("position = 0.0, 0.0, 0.46, frame_offset = 3.0") == 1
    deck = tmp_path / "wrong.nml"
    deck.write_text(text.replace("position = 0.0, 0.0, 0.46, frame_offset = 3.0", wrong))
    out = run(raildyn_exe, "check", deck).stdout
    m = re.search(r"warning: the equilibrium moved ws1 by ([\d.]+) m in z \(more than 0.05 m\)", out)
    assert m, out
    assert float(m.group(1)) == pytest.approx(0.46, abs=2e-3)
    # the deck as shipped: every body within a millimetre of its deck position
    out = run(raildyn_exe, "check", WAGON).stdout
    moves = re.findall(r"(\w+) (-?[\d.]+) mm \((?:x|y|z)\)", out.split("moved the bodies")[1])
    assert [b for b, _ in moves] == ["car", "ws1", "ws2"] and all(abs(float(d)) < 1 for _, d in moves), out


# A box on a vertical spring under a moving frame, x free, pushed back by a constant force:
# x(t) = -F t^2 / (2 m) relative to its frame (straight level track, no other x force).
PUSHED = """&simulation t_end = {t_end}, speed = 10.0, equilibrium = 'none' /
&solver method = 'rk4', fixed_step = 1e-3 /
&output interval = 0.01 /
&segment type = 'straight', length = 1000.0 /
&body name = 'box', mass = 100.0, ixx = 10.0, iyy = 10.0, izz = 10.0, position = 0.0, 0.0, 0.5,
      frozen = 'y', 'yaw', 'roll', 'pitch' /
&element name = 'hanger', type = 'spring_damper', body2 = 'box', point1 = 0.0, 0.0, 0.5,
      stiffness = 0.0, 0.0, 4e4, damping = 0.0, 0.0, 100.0 /
&external_force body = 'box', frame = 'track', force = -2.0, 0.0, 0.0 /
"""


@pytest.mark.parametrize("t_end, warned", [(2.0, False), (3.0, True)])
def test_a_body_falling_behind_its_frame_is_warned(raildyn_exe, tmp_path, t_end, warned):
    deck = tmp_path / "pushed.nml"
    deck.write_text(PUSHED.format(t_end=t_end))
    out = run(raildyn_exe, "run", deck, "-o", tmp_path / "pushed.h5").stdout
    behind = 2.0 * t_end ** 2 / (2 * 100.0)        # 0.04 m at 2 s, 0.09 m at 3 s; limit 0.05 m
    m = re.search(r"warning: body box moved ([\d.]+) m behind its track frame \(x free; more than 0.05 m\)", out)
    assert bool(m) == warned, out
    with h5py.File(tmp_path / "pushed.h5", "r") as f:
        notes = f["meta"].attrs.get("notes", b"").decode()
        assert ("body box moved" in notes) == warned
        assert f["bodies/box/position_track"][-1, 0] == pytest.approx(-behind, rel=1e-6)
    if warned:
        assert float(m.group(1)) == pytest.approx(behind, abs=1e-3)


def test_the_first_wagon_with_a_free_car_body_is_warned(raildyn_exe, tmp_path):
    deck = tmp_path / "free.nml"
    text = WAGON.read_text()
    assert text.count("frozen = 'x'") == 1
    deck.write_text(text.replace(", frozen = 'x'", ""))
    out = run(raildyn_exe, "run", deck, "-o", tmp_path / "free.h5").stdout
    assert re.search(r"warning: body car moved 0\.\d+ m behind its track frame", out), out
