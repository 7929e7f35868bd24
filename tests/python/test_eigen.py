"""`raildyn eigen` and the C API's rd_linearize (Model.linearize) against closed forms.

The deck tests/decks/eigen_chain.nml is a fixed-free chain of three equal masses m joined by
equal springs k and dampers c (only x free): K = k T with T the tridiagonal fixed-free matrix,
whose eigenvalues are 4 sin^2((2j - 1) pi / (2 (2n + 1))) (j = 1..n), and C = (c/k) K, so the
modes are undamped modes with zeta_j = (c/k) w_j / 2. The matrices are written here from the
deck's numbers, not from anything raildyn computes."""
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import raildyn
from raildyn.stability import mode_from_json, read_root_locus

REPO = Path(__file__).resolve().parents[2]
CHAIN = REPO / "tests" / "decks" / "eigen_chain.nml"
M, K, C, N = 100.0, 1.0e4, 20.0, 3          # the deck's mass, stiffness, damping, masses


def runner(exe, *args, expect=0, cwd=None):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=120,
                         cwd=cwd)
    assert res.returncode == expect, res.stdout + res.stderr
    return res


def eigen_json(exe, *args, cwd=None):
    return json.loads(runner(exe, "eigen", *args, "--json", cwd=cwd).stdout)


def chain_modes():
    """(w_j, zeta_j) of the chain in closed form."""
    w = [2 * math.sqrt(K / M) * math.sin((2 * j - 1) * math.pi / (2 * (2 * N + 1))) for j in range(1, N + 1)]
    return [(wj, C / K * wj / 2) for wj in w]


def chain_matrix():
    """[[0, I], [-K/m, -C/m]] of the chain, rows and columns (x1..x3, v1..v3)."""
    t = 2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1)
    t[-1, -1] = 1.0
    a = np.zeros((2 * N, 2 * N))
    a[:N, N:] = np.eye(N)
    a[N:, :N] = -K / M * t
    a[N:, N:] = -C / M * t
    return a


@pytest.mark.parametrize("speed", [0.0, 10.0, 55.0])
def test_chain_modes_in_closed_form(raildyn_exe, tmp_path, speed):
    """Every mode: frequency, damping ratio, real and imaginary part to 1e-7 of the closed
    form, at any running speed (the chain has no speed-dependent force); least damped first."""
    out = eigen_json(raildyn_exe, CHAIN, "--speed", speed, cwd=tmp_path)
    assert out["speed"] == speed and out["states"] == 6
    assert out["kept_states"] == ["m1.x", "m2.x", "m3.x", "m1.nu_x", "m2.nu_x", "m3.nu_x"]
    modes = [mode_from_json(m) for m in out["modes"]]
    assert len(modes) == N
    assert [m.damping_ratio for m in modes] == sorted(m.damping_ratio for m in modes)
    for mode, (w, zeta) in zip(modes, chain_modes()):        # zeta grows with w
        assert mode.imag == pytest.approx(w * math.sqrt(1 - zeta ** 2), rel=1e-7)
        assert mode.real == pytest.approx(-zeta * w, rel=1e-7)
        assert mode.damping_ratio == pytest.approx(zeta, rel=1e-7)
        assert mode.frequency_hz == pytest.approx(w * math.sqrt(1 - zeta ** 2) / (2 * math.pi), rel=1e-7)
        assert not mode.neutral
    assert list(tmp_path.iterdir()) == []             # eigen writes no results file


def test_chain_dominant_coordinates(raildyn_exe):
    """Participation = share of the kinetic energy (equal masses: the squared mode shape,
    normalised). The fixed-free chain's mode j has shape sin((2j - 1) i pi / (2n + 1))."""
    out = eigen_json(raildyn_exe, CHAIN)
    for j, mode in enumerate(out["modes"], start=1):
        shape = np.array([math.sin((2 * j - 1) * i * math.pi / (2 * N + 1)) for i in range(1, N + 1)])
        share = shape ** 2 / np.sum(shape ** 2)
        order = np.argsort(-share)
        listed = [d for d in mode["dominant"]]
        assert [d["body"] for d in listed] == [f"m{i + 1}" for i in order if share[i] >= 0.05][:3]
        assert all(d["dof"] == "x" for d in listed)
        for d in listed:
            assert d["share"] == pytest.approx(share[int(d["body"][1:]) - 1], rel=1e-7)


def test_dofs_hold_the_other_coordinates(raildyn_exe):
    """--dofs m1 keeps m1.x and its rate; m2 held: m1 between two springs and two dampers,
    w0 = sqrt(2k/m), zeta = 2c / (2 sqrt(2k m))."""
    out = eigen_json(raildyn_exe, CHAIN, "--dofs", "m1")
    assert out["kept_states"] == ["m1.x", "m1.nu_x"]
    (mode,) = out["modes"]
    w0, zeta = math.sqrt(2 * K / M), 2 * C / (2 * math.sqrt(2 * K * M))
    assert mode["damping_ratio"] == pytest.approx(zeta, rel=1e-7)
    assert mode["imag"] == pytest.approx(w0 * math.sqrt(1 - zeta ** 2), rel=1e-7)
    assert eigen_json(raildyn_exe, CHAIN, "--dofs", "x")["kept_states"] == eigen_json(raildyn_exe, CHAIN)["kept_states"]
    assert eigen_json(raildyn_exe, CHAIN, "--dofs", "m3.x,m2")["kept_states"] == ["m2.x", "m3.x", "m2.nu_x", "m3.nu_x"]


def test_model_linearize_is_the_chain_matrix():
    """Model.linearize(): the state-space matrix of the chain (row-major through the C API),
    at the deck's speed and after a speed change; the time and state do not move."""
    with raildyn.Model.from_file(CHAIN) as model:
        with pytest.raises(raildyn.RaildynError) as err:
            model.linearize()
        assert err.value.status == 6 and "initialize" in str(err.value)
        model.initialize(write_output=False)
        before = model.state()
        a = model.linearize()
        assert a.shape == (6, 6)
        np.testing.assert_allclose(a, chain_matrix(), rtol=1e-7, atol=1e-9 * np.abs(chain_matrix()).max())
        model.set_input("speed", 30.0)
        np.testing.assert_allclose(model.linearize(), chain_matrix(), rtol=1e-7, atol=1e-9 * 200)
        assert model.time == 0.0 and np.array_equal(model.state(), before)


def test_rd_linearize_refuses_a_wrong_size():
    """The C call: a buffer size other than n * n is an input error naming the expected size,
    nothing written; a NULL matrix is an input error naming it."""
    import ctypes
    from raildyn.model import load_library
    lib = load_library()
    with raildyn.Model.from_file(CHAIN) as model:
        model.initialize(write_output=False)
        buffer = (ctypes.c_double * 40)(*([7.0] * 40))
        assert lib.rd_linearize(model.handle, buffer, 35) == 1
        message = ctypes.create_string_buffer(512)
        lib.rd_error_message(model.handle, message, 512)
        assert b"expected the state size squared, 6 x 6 = 36" in message.value
        assert list(buffer) == [7.0] * 40
        assert lib.rd_linearize(model.handle, None, 36) == 1
        lib.rd_error_message(model.handle, message, 512)
        assert b"matrix is NULL" in message.value
        assert lib.rd_linearize(model.handle, buffer, 36) == 0


def test_root_locus_csv_and_plot(raildyn_exe, tmp_path):
    """--speeds: one object with "root_locus"; --csv every mode at every speed (read back by
    raildyn.stability); --plot a PNG (no scratch file left beside it)."""
    out = eigen_json(raildyn_exe, CHAIN, "--speeds", "0,20,40")
    assert [p["speed"] for p in out["root_locus"]] == [0.0, 20.0, 40.0]
    runner(raildyn_exe, "eigen", CHAIN, "--speeds", "0, 20,40", "--csv", tmp_path / "locus.csv",
           "--plot", tmp_path / "locus.png")
    locus = read_root_locus(tmp_path / "locus.csv")
    assert sorted(locus) == [0.0, 20.0, 40.0]
    for (speed, modes), point in zip(sorted(locus.items()), out["root_locus"]):
        assert [m.imag for m in modes] == pytest.approx([p["imag"] for p in point["modes"]], rel=1e-12)
        assert [m.damping_ratio for m in modes] == pytest.approx([p["damping_ratio"] for p in point["modes"]],
                                                                rel=1e-12)
        assert modes[0].dominant[0][0] == "m3" and modes[0].dominant[0][1] == "x"
    assert (tmp_path / "locus.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    runner(raildyn_exe, "eigen", CHAIN, "--speeds", "0,40", "--plot", tmp_path / "only.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["locus.csv", "locus.png", "only.png"]


def test_state_from_a_run_equals_time(raildyn_exe, tmp_path):
    """The TGV wheelset moving after its lateral pulse (knife-edge contact, Kalker creep):
    linearised about the state of a run at t = 0.25 s (--time) or about the same time's row of
    that run's results file (--state FILE:ROW): the same modes."""
    deck = tmp_path / "ws.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'tgv_wheelset.nml'}' /\n"
                    "&simulation t_end = 0.3 /\n&output interval = 0.05 /\n")
    runner(raildyn_exe, "run", deck, "-o", tmp_path / "ws.h5", "--quiet")
    by_time = eigen_json(raildyn_exe, deck, "--time", 0.25, "--dofs", "y,yaw,roll,z")
    by_row = eigen_json(raildyn_exe, deck, "--state", f"{tmp_path / 'ws.h5'}:5", "--dofs", "y,yaw,roll,z")
    assert by_row["time"] == pytest.approx(0.25, abs=1e-12)
    assert "ws.h5" in by_row["linearised_about"] and "t = 0.25" in by_time["linearised_about"]
    assert len(by_time["modes"]) == len(by_row["modes"]) >= 4
    for a, b in zip(by_time["modes"], by_row["modes"]):
        assert a["real"] == pytest.approx(b["real"], rel=1e-5, abs=1e-6)
        assert a["imag"] == pytest.approx(b["imag"], rel=1e-5, abs=1e-6)
    last = eigen_json(raildyn_exe, deck, "--state", tmp_path / "ws.h5")
    assert last["time"] == pytest.approx(0.3, abs=1e-12)


@pytest.mark.parametrize("args, status, words", [
    (["--dofs", "m1.wobble"], 1, "unknown coordinate 'wobble'"),
    (["--dofs", "m9"], 1, "'m9' selects no free coordinate"),
    (["--dofs", "y"], 1, "'y' selects no free coordinate"),
    (["--speed", "-3"], 1, "--speed expects speeds >= 0"),
    (["--speed", "3,4"], 1, "--speed expects one speed"),
    (["--speeds", "3,x"], 1, "got 'x'"),
    (["--time", "1", "--state", "a.h5"], 1, "give --time or --state, not both"),
    (["--state", "absent.h5"], 4, '"absent.h5": no such file'),
    (["--frobnicate"], 1, "unknown option '--frobnicate'"),
])
def test_usage_and_input_errors(raildyn_exe, tmp_path, args, status, words):
    res = runner(raildyn_exe, "eigen", CHAIN, *args, expect=status, cwd=tmp_path)
    assert words in res.stderr and res.stdout == ""


def test_track_alone_is_an_input_error(raildyn_exe, tmp_path):
    deck = tmp_path / "track.nml"
    deck.write_text("&simulation t_end = 1.0, speed = 10.0 /\n&segment type = 'straight', length = 100.0 /\n")
    res = runner(raildyn_exe, "eigen", deck, expect=1)
    assert "no &body: a track alone has no modes to linearise" in res.stderr


def test_state_row_outside_the_file(raildyn_exe, tmp_path):
    runner(raildyn_exe, "run", CHAIN, "-o", tmp_path / "chain.h5", "--quiet")
    res = runner(raildyn_exe, "eigen", CHAIN, "--state", f"{tmp_path / 'chain.h5'}:9999", expect=1)
    assert "no row 9999 in /state/y; expected a row from 0 to 100" in res.stderr
