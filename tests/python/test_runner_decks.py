"""Bad decks fail well (issue: foundation, item 3).

Each case runs the real `raildyn` executable (`check` and `run`) on a small deck written
here and checks: exit status non-zero, exactly one line on stderr naming the deck file, the
line, the group and the parameter and saying what is expected, no Fortran runtime error or
backtrace, and no output file left behind.
"""
import subprocess

import pytest


GOOD_TRACK = """&simulation title = 'ok', t_end = 0.5, speed = 10.0 /
&output interval = 0.1 /
&segment type = 'straight', length = 50.0 /
&segment type = 'clothoid', length = 30.0, radius = 150.0, side = 'left', cant = 0.100 /
&segment type = 'curve', length = 60.0, radius = 150.0, side = 'left', cant = 0.100 /
"""


def run(exe, *args, cwd=None):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=60)


def write(tmp_path, text, name="scene.nml"):
    p = tmp_path / name
    p.write_text(text)
    return p


# (deck text, line of the error, group, parameter, words that must say what is expected)
BAD_DECKS = {
    "misspelled group": (
        GOOD_TRACK.replace("&simulation", "&simulaton"), 1, "simulaton", None, ["simulation"]),
    "unknown group": (
        GOOD_TRACK + "&vehicle name = 'x' /\n", 6, "vehicle", None, ["expected"]),
    "unknown variable": (
        GOOD_TRACK.replace("speed = 10.0", "sped = 10.0"), 1, "simulation", "sped", ["speed"]),
    "wrong type": (
        GOOD_TRACK.replace("t_end = 0.5", "t_end = 'long'"), 1, "simulation", "t_end", ["real"]),
    "malformed number": (
        GOOD_TRACK.replace("length = 60.0", "length = 6O.0"), 5, "segment", "length", ["real"]),
    "missing required": (
        GOOD_TRACK.replace("t_end = 0.5, ", ""), 1, "simulation", "t_end", ["required"]),
    "negative length": (
        GOOD_TRACK.replace("length = 50.0", "length = -50.0"), 3, "segment", "length", ["> 0"]),
    "zero radius": (
        GOOD_TRACK.replace("length = 60.0, radius = 150.0", "length = 60.0, radius = 0.0"),
        5, "segment", "radius", [">= 10"]),
    "curvature change without transition": (
        GOOD_TRACK.replace("&segment type = 'clothoid', length = 30.0, radius = 150.0, "
                           "side = 'left', cant = 0.100 /\n", "")
        .replace("cant = 0.100 /", "/"),
        4, "segment", None, ["transition"]),
    "cant larger than the gauge": (
        GOOD_TRACK.replace("cant = 0.100 /\n&segment type = 'curve'",
                           "cant = 1.600 /\n&segment type = 'curve'")
        .replace("side = 'left', cant = 0.100 /\n", "side = 'left', cant = 1.600 /\n", 1),
        4, "segment", "cant", []),
    "negative mass": (
        GOOD_TRACK + "&body name = 'car', mass = -1000.0, ixx = 1.0, iyy = 1.0, izz = 1.0 /\n",
        6, "body", "mass", ["> 0"]),
    "element with undefined body": (
        GOOD_TRACK + "&body name = 'car', mass = 1000.0, ixx = 1.0, iyy = 1.0, izz = 1.0,"
        " position = 0, 0, 1 /\n"
        "&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'cart',\n"
        "  stiffness = 1e5, 1e5, 1e5 /\n",
        7, "element", "body2", ["car"]),
    "missing profile file": (
        GOOD_TRACK + "&body name = 'ws', mass = 1800.0, ixx = 1100.0, iyy = 100.0, izz = 1100.0,"
        " position = 0, 0, 0.46 /\n"
        "&wheelset name = 'w1', body = 'ws',\n"
        "  wheel_profile = 'no_such_wheel.prw', rail_profile = '60e1' /\n",
        8, "wheelset", "wheel_profile", ["no_such_wheel.prw"]),
}


@pytest.mark.parametrize("case", sorted(BAD_DECKS))
@pytest.mark.parametrize("command", ["check", "run"])
def test_bad_deck_fails_well(raildyn_exe, tmp_path, case, command):
    text, line, group, param, expected_words = BAD_DECKS[case]
    deck = write(tmp_path, text)
    out = tmp_path / "out.h5"
    args = [command, deck] + (["-o", out] if command == "run" else [])
    res = run(raildyn_exe, *args)
    assert res.returncode == 1, (res.returncode, res.stdout, res.stderr)
    lines = [l for l in res.stderr.splitlines() if l.strip()]
    assert len(lines) == 1, res.stderr
    msg = lines[0]
    assert f"scene.nml:{line}:" in msg, msg
    assert f"&{group}" in msg, msg
    if param:
        assert f"'{param}'" in msg, msg
    for w in expected_words:
        assert w in msg, (w, msg)
    for bad in ("Fortran runtime error", "Backtrace", "ERROR STOP", "Error termination"):
        assert bad not in res.stderr + res.stdout
    assert not out.exists(), "a failed deck must not leave an output file"
    assert not (tmp_path / "scene.h5").exists()


def test_good_deck_checks(raildyn_exe, tmp_path):
    deck = write(tmp_path, GOOD_TRACK)
    res = run(raildyn_exe, "check", deck)
    assert res.returncode == 0, res.stderr
    assert "ok" in res.stdout
    assert not (tmp_path / "scene.h5").exists(), "check must not write results"


def test_usage_errors(raildyn_exe, tmp_path):
    assert run(raildyn_exe).returncode == 1
    assert run(raildyn_exe, "frobnicate").returncode == 1
    res = run(raildyn_exe, "run")
    assert res.returncode == 1 and "no deck" in res.stderr
    res = run(raildyn_exe, "check", tmp_path / "absent.nml")
    assert res.returncode != 0 and "absent.nml" in res.stderr
    assert "Fortran runtime error" not in res.stderr
