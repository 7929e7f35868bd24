"""Sensors (&sensor, docs/output.md /sensors): points fixed on bodies, their position and
absolute velocity and acceleration, checked against closed forms written here:

- a body held at rest in the frame of a canted circular curve at constant speed: the point
  turns on a horizontal circle about the curve's vertical axis at the rate V/R, so its
  acceleration is (V/R)^2 times its horizontal distance from that axis, towards it (the
  V^2/R of the curve plus the offsets' terms), seen in the canted track frame;
- a body spinning in yaw at a constant rate on straight track under an accelerating frame:
  centripetal acceleration -omega^2 r in the body, the frame's dV/dt along the track;
- deck errors name file:line, the group and the parameter; the channel group `sensors`
  selects them; the C API lists their channels.
"""
import math
import subprocess

import h5py
import numpy as np
import pytest

import raildyn

G = 9.81
G_DEFAULT = 9.80665      # &simulation gravity's default

CURVE = """&simulation title = 'sensor in a curve', t_end = 0.5, speed = {V}, equilibrium = 'none',
      start_sigma = 100.0, gravity = {g} /
&solver method = 'rk4', fixed_step = 1e-3 /
&output interval = 0.1 {output} /
&segment type = 'clothoid', length = 50.0, radius = {R}, side = 'left', cant = {cant} /
&segment type = 'curve', length = 500.0, radius = {R}, side = 'left', cant = {cant} /
&body name = 'car', mass = 1000.0, ixx = 100.0, iyy = 100.0, izz = 100.0,
      position = 0.0, {yb}, {zb}, frozen = 'y', 'z', 'yaw', 'roll', 'pitch' /
&sensor name = 'floor', body = 'car', position = {x0}, {y0}, {z0} /
"""


def run(exe, *args, expect=0):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=120)
    assert res.returncode == expect, res.stdout + res.stderr
    return res


def curve_deck(tmp_path, output="", **kw):
    values = dict(V=30.0, R=400.0, cant=0.12, yb=0.2, zb=1.5, x0=7.0, y0=-1.1, z0=0.4, g=G)
    values.update(kw)
    deck = tmp_path / "curve.nml"
    deck.write_text(CURVE.format(output=output, **values))
    return deck, values


def test_point_at_rest_in_a_canted_curve(raildyn_exe, tmp_path):
    deck, p = curve_deck(tmp_path)
    run(raildyn_exe, "run", deck, "-o", tmp_path / "c.h5")
    V, R = p["V"], p["R"]
    phi = -math.asin(p["cant"] / 1.5)          # left-hand curve: the right (outer) rail is raised
    X, Y, Z = p["x0"], p["yb"] + p["y0"], p["zb"] + p["z0"]
    ell = Y * math.cos(phi) - Z * math.sin(phi)    # horizontal offset towards the centre
    w = V / R
    a_track = [-w**2 * X, w**2 * (R - ell) * math.cos(phi), -w**2 * (R - ell) * math.sin(phi)]
    v_track = [w * (R - ell), w * X * math.cos(phi), -w * X * math.sin(phi)]
    # gravity (0, 0, -g) in track components: (0, -g sin phi, -g cos phi)
    f_body = [a_track[0], a_track[1] + G * math.sin(phi), a_track[2] + G * math.cos(phi)]
    with h5py.File(tmp_path / "c.h5", "r") as f:
        s = f["sensors/floor"]
        n = len(f["time"])
        assert n == 6
        np.testing.assert_allclose(s["position_track"][:], np.tile([X, Y, Z], (n, 1)), atol=1e-12)
        np.testing.assert_allclose(s["velocity_track"][:], np.tile(v_track, (n, 1)), rtol=0, atol=1e-10)
        np.testing.assert_allclose(s["acceleration_track"][:], np.tile(a_track, (n, 1)), rtol=0, atol=1e-10)
        # the body does not turn in its frame: body components are the track ones
        np.testing.assert_allclose(s["acceleration_body"][:], s["acceleration_track"][:], atol=1e-12)
        np.testing.assert_allclose(s["velocity_body"][:], s["velocity_track"][:], atol=1e-12)
        np.testing.assert_allclose(s["specific_force_body"][:], np.tile(f_body, (n, 1)), rtol=0, atol=1e-10)
        # the curve's V^2/R, here 2.25 m/s^2, dominates the lateral acceleration
        assert s["acceleration_track"][0, 1] == pytest.approx(V**2 / R, rel=0.01)
        assert s["acceleration_track"].attrs["unit"] == b"m/s^2"
        assert s["specific_force_body"].attrs["components"] == b"fx fy fz"
        # the fixed-frame position lies on the horizontal circle of radius sqrt((R-ell)^2+X^2)
        pf = s["position_fixed"][:]
        origin, heading = f["track/frames/1/position"][:], f["track/frames/1/angles"][:, 0]
        centre = origin[:, :2] + R * np.c_[-np.sin(heading), np.cos(heading)]
        radius = np.hypot(pf[:, 0] - centre[:, 0], pf[:, 1] - centre[:, 1])
        np.testing.assert_allclose(radius, math.hypot(R - ell, X), rtol=1e-9)


SPIN = """&simulation title = 'spinning body', t_end = 0.95, speed_times = 0.0, 1.0,
      speed_values = 10.0, 12.0, equilibrium = 'none', gravity = {g} /
&solver method = 'rk4', fixed_step = 1e-3 /
&output interval = 0.05 /
&segment type = 'straight', length = 500.0 /
&body name = 'disc', mass = 50.0, ixx = 5.0, iyy = 5.0, izz = 8.0, position = 0.0, 0.0, 1.0,
      angular_rate = {omega}, 0.0, 0.0, frozen = 'x', 'y', 'z', 'roll', 'pitch' /
&sensor name = 'rim', body = 'disc', position = {x0}, {y0}, {z0} /
"""


def test_point_on_a_body_spinning_in_yaw(raildyn_exe, tmp_path):
    omega, x0, y0, z0 = 2.0, 0.6, 0.25, -0.1
    deck = tmp_path / "spin.nml"
    deck.write_text(SPIN.format(omega=omega, x0=x0, y0=y0, z0=z0, g=G))
    run(raildyn_exe, "run", deck, "-o", tmp_path / "s.h5")
    with h5py.File(tmp_path / "s.h5", "r") as f:
        t = f["time"][:]
        s = f["sensors/rim"]
        psi = omega * t
        c, sn = np.cos(psi), np.sin(psi)
        xr, yr = x0 * c - y0 * sn, x0 * sn + y0 * c      # the point relative to the CG, track axes
        V = 10.0 + 2.0 * t
        np.testing.assert_allclose(s["position_track"][:], np.c_[xr, yr, 1.0 + z0 + 0 * t], atol=1e-9)
        np.testing.assert_allclose(s["velocity_track"][:], np.c_[V - omega * yr, omega * xr, 0 * t], atol=1e-9)
        np.testing.assert_allclose(s["acceleration_track"][:],
                                   np.c_[2.0 - omega**2 * xr, -omega**2 * yr, 0 * t], atol=1e-9)
        # in the body: the centripetal -omega^2 r, and the frame's dV/dt turned into body axes
        np.testing.assert_allclose(s["acceleration_body"][:],
                                   np.c_[2.0 * c - omega**2 * x0, -2.0 * sn - omega**2 * y0, 0 * t], atol=1e-9)
        np.testing.assert_allclose(s["specific_force_body"][:],
                                   np.c_[2.0 * c - omega**2 * x0, -2.0 * sn - omega**2 * y0, G + 0 * t], atol=1e-9)


def test_sensor_channel_group_and_c_api_names(raildyn_exe, tmp_path):
    deck, _ = curve_deck(tmp_path, output=", groups = 'sensors'")
    run(raildyn_exe, "run", deck, "-o", tmp_path / "only.h5")
    names = []
    with h5py.File(tmp_path / "only.h5", "r") as f:
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    series = ["position_track", "position_fixed", "velocity_track", "acceleration_track",
              "velocity_body", "acceleration_body", "specific_force_body"]
    assert set(names) == {"time", "meta/deck_text"} | {f"sensors/floor/{q}" for q in series}
    with raildyn.Model.from_file(deck) as m:
        m.initialize(write_output=False)
        assert [n for n in m.output_names() if n.startswith("sensors/")] == [f"sensors/floor/{q}" for q in series]
        assert m.output("sensors/floor/position_track") == pytest.approx([7.0, 0.2 - 1.1, 1.5 + 0.4])


@pytest.mark.parametrize("line, expected", [
    ("&sensor name = 'floor', body = 'roof', position = 0.0, 0.0, 0.0 /", ["body", "'roof'"]),
    ("&sensor name = 'a/b', body = 'car', position = 0.0, 0.0, 0.0 /", ["name", "'/'"]),
    ("&sensor name = 'floor', body = 'car' /", ["position"]),
    ("&sensor name = 'floor', body = 'car', position = 1.0, 2.0 /", ["position", "3"]),
])
def test_bad_sensors_name_the_deck_line(raildyn_exe, tmp_path, line, expected):
    deck, _ = curve_deck(tmp_path)
    text = deck.read_text().splitlines()
    text[-1] = line                           # the sensor is the deck's line 9
    deck.write_text("\n".join(text) + "\n")
    err = run(raildyn_exe, "check", deck, expect=1).stderr
    assert "curve.nml:9" in err and "sensor" in err, err
    for word in expected:
        assert word in err, err
    assert err.count("\n") <= 2, err


def test_two_sensors_with_one_name_are_refused(raildyn_exe, tmp_path):
    deck, _ = curve_deck(tmp_path)
    deck.write_text(deck.read_text() + "&sensor name = 'floor', body = 'car', position = 0.0, 0.0, 0.0 /\n")
    err = run(raildyn_exe, "check", deck, expect=1).stderr
    assert "curve.nml:10" in err and "floor" in err, err


WHEELSET = """&simulation title = 'axle box sensor', t_end = 0.2, speed = 20.0, equilibrium = 'solve' /
&output interval = 0.01 /
&segment type = 'straight', length = 100.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, 0.45, frozen = 'x', 'y', 'yaw', 'roll' /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = 0.05, creep_law = 'linear' /
&sensor name = 'axle_box', body = 'ws1', position = 0.3, 1.0, 0.1 /
"""


def test_a_wheelset_sensor_does_not_turn_with_the_wheel(raildyn_exe, tmp_path):
    """On a wheelset the point is fixed in the axle-box frame: rolling at V / r0 = 44 rad/s
    (9 turns in 0.2 s) it stays at the same offset from the wheelset's centre, moving with it
    at V along the track."""
    deck = tmp_path / "ws.nml"
    deck.write_text(WHEELSET)
    run(raildyn_exe, "run", deck, "-o", tmp_path / "ws.h5")
    with h5py.File(tmp_path / "ws.h5", "r") as f:
        q = f["bodies/ws1/position_track"][:]
        qd = f["bodies/ws1/velocity_track"][:]
        qdd = f["bodies/ws1/acceleration_track"][:]
        s = f["sensors/axle_box"]
        n = len(f["time"])
        # only z (and the spin) move: the point is the centre plus the fixed offset
        np.testing.assert_allclose(s["position_track"][:], q[:, :3] + [0.3, 1.0, 0.1], atol=1e-12)
        np.testing.assert_allclose(s["velocity_track"][:], np.c_[20.0 + 0 * qd[:, 0], 0 * qd[:, 0], qd[:, 2]],
                                   atol=1e-12)
        np.testing.assert_allclose(s["acceleration_track"][:], np.c_[0 * qdd[:, 0], 0 * qdd[:, 0], qdd[:, 2]],
                                   atol=1e-9)
        np.testing.assert_allclose(s["specific_force_body"][:, 2], qdd[:, 2] + G_DEFAULT, atol=1e-9)
        assert n == 21
