"""The runner on track-only scenes: run, track export, exit codes, progress, and a run killed
half-way leaving a readable file (issue: foundation, items 5 and 6)."""
import os
import re
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

import raildyn


TC1 = """! Manchester track case 1, vehicle reference only
&simulation title = 'TC1 track', t_end = {t_end}, speed = 4.4 /
&output interval = {interval}, flush_every = {flush} /
&segment type = 'straight', length = 50.0 /
&segment type = 'clothoid', length = 30.0, radius = 150.0, side = 'left', cant = 0.100 /
&segment type = 'curve', length = 60.0, radius = 150.0, side = 'left', cant = 0.100 /
"""


def deck(tmp_path, t_end=30.0, interval=0.1, flush=50):
    p = tmp_path / "tc1.nml"
    p.write_text(TC1.format(t_end=t_end, interval=interval, flush=flush))
    return p


def test_run_writes_track_frames(raildyn_exe, tmp_path):
    d = deck(tmp_path)
    res = subprocess.run([raildyn_exe, "run", d, "-o", tmp_path / "r.h5"], capture_output=True,
                         text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert res.stderr == "", "no progress output when not on a terminal"
    r = raildyn.Results(tmp_path / "r.h5")
    assert r.metadata["status"] == "completed"
    assert "TC1 track" in r.deck_text
    t = r.time
    assert np.allclose(t, np.arange(301) * 0.1)
    sigma = r.get("vehicle/distance")[:, 0]
    assert np.allclose(sigma, 4.4 * t)
    # heading at the end of the transition (sigma = 80) is L/(2R); the vehicle is in the
    # curve after 80 / 4.4 s: heading grows by 1/R per metre.
    ang = r.get("track/frames/1/angles")
    i = t > 80 / 4.4
    expected = 30.0 / 300.0 + (sigma[i] - 80.0) / 150.0
    assert np.allclose(ang[i, 0], expected, atol=1e-9)
    # left curve: cant raises the right rail -> negative cant angle
    assert np.allclose(ang[i, 2], -np.arcsin(0.1 / 1.5), atol=1e-12)
    assert r.unit("track/frames/1/position") == "m"
    w = r.get("track/frames/1/angular_velocity")
    assert np.allclose(w[i, 2], 4.4 / 150.0 * np.cos(np.arcsin(0.1 / 1.5)), rtol=1e-9)


def test_default_output_in_working_directory(raildyn_exe, tmp_path):
    """Without -o and without &output file the results go to the working directory, named
    after the deck (not next to the deck: its folder may be read-only); a results file the
    deck names stays relative to the deck."""
    decks, work = tmp_path / "decks", tmp_path / "work"
    decks.mkdir()
    work.mkdir()
    d = deck(decks, t_end=1.0)
    res = subprocess.run([raildyn_exe, "run", d], capture_output=True, text=True, timeout=60, cwd=work)
    assert res.returncode == 0, res.stderr
    assert (work / "tc1.h5").exists() and not (decks / "tc1.h5").exists()
    named = decks / "named.nml"
    named.write_text(f"&include file = '{Path(d).name}' /\n&output file = 'out/named.h5' /\n")
    (decks / "out").mkdir()
    res = subprocess.run([raildyn_exe, "run", named], capture_output=True, text=True, timeout=60, cwd=work)
    assert res.returncode == 0, res.stderr
    assert (decks / "out" / "named.h5").exists()


def test_track_export(raildyn_exe, tmp_path):
    d = deck(tmp_path)
    res = subprocess.run([raildyn_exe, "track", d, "-o", tmp_path / "t.h5", "--step", "0.5",
                          "--csv", tmp_path / "t.csv"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    r = raildyn.Results(tmp_path / "t.h5")
    sigma = r.time
    assert sigma[0] == 0 and abs(sigma[-1] - 140.0) < 1e-9
    kappa = r.get("track/curvature")[:, 0]
    assert np.allclose(kappa[sigma <= 50], 0)
    assert np.allclose(kappa[sigma >= 80], 1 / 150)
    ramp = (sigma > 50) & (sigma < 80)
    assert np.allclose(kappa[ramp], (sigma[ramp] - 50) / 30 / 150)
    csv = np.loadtxt(tmp_path / "t.csv", delimiter=",", comments="#", skiprows=2)
    assert csv.shape == (len(sigma), 9)
    assert np.allclose(csv[:, 7], kappa)


def test_track_plot(raildyn_exe, tmp_path):
    pytest.importorskip("matplotlib")
    d = deck(tmp_path)
    res = subprocess.run([raildyn_exe, "track", d, "-o", tmp_path / "t.h5", "--plot",
                          tmp_path / "t.png"], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "t.png").stat().st_size > 1000


def test_killed_run_leaves_readable_file(raildyn_exe, tmp_path):
    """SIGKILL a long run half-way: every step up to the last flush is readable."""
    d = deck(tmp_path, t_end=1.0e7, interval=0.001, flush=100)
    out = tmp_path / "k.h5"
    proc = subprocess.Popen([raildyn_exe, "run", d, "-o", out], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)
    try:
        deadline = time.time() + 30
        n = 0
        while time.time() < deadline and n < 2000:
            time.sleep(0.2)
            try:
                n = len(raildyn.Results(out).time)
            except Exception:
                n = 0
        assert proc.poll() is None, "the run should still be going"
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    r = raildyn.Results(out)
    t = r.time
    assert len(t) >= 2000
    assert np.allclose(np.diff(t), 0.001)
    sigma = r.get("vehicle/distance")[:, 0]
    assert np.allclose(sigma, 4.4 * t)
    assert r.metadata["status"] == "running"


def test_progress_on_a_terminal(raildyn_exe, tmp_path):
    """On a terminal a long run shows simulated time, fraction done and speed vs real time."""
    import pty
    d = deck(tmp_path, t_end=100.0, interval=0.01, flush=1000)
    pid, fd = pty.fork()
    if pid == 0:  # child: stderr is the pty
        os.execv(str(raildyn_exe), [str(raildyn_exe), "run", str(d), "-o", str(tmp_path / "p.h5")])
    chunks = []
    try:
        while True:
            try:
                data = os.read(fd, 4096)
            except OSError:
                break
            if not data:
                break
            chunks.append(data)
    finally:
        _, status = os.waitpid(pid, 0)
    text = b"".join(chunks).decode(errors="replace")
    assert os.WEXITSTATUS(status) == 0, text
    assert "real time" in text and "%" in text and "t = " in text, text


def test_progress_shows_the_integrators_steps(raildyn_exe, tmp_path):
    """The progress line's last 'N steps, h = H s' are the integrator's counts that the
    results file records at the end (/meta/solver n_steps, h_last)."""
    import pty
    repo = Path(__file__).resolve().parents[2]
    d = tmp_path / "wheelset.nml"
    d.write_text(f"&include file = '{repo / 'inputs' / 'tgv_wheelset.nml'}' /\n&simulation t_end = 2.0 /\n")
    pid, fd = pty.fork()
    if pid == 0:  # child: stderr is the pty
        os.execv(str(raildyn_exe), [str(raildyn_exe), "run", str(d), "-o", str(tmp_path / "w.h5")])
    chunks = []
    try:
        while True:
            try:
                data = os.read(fd, 4096)
            except OSError:
                break
            if not data:
                break
            chunks.append(data)
    finally:
        _, status = os.waitpid(pid, 0)
    text = b"".join(chunks).decode(errors="replace")
    assert os.WEXITSTATUS(status) == 0, text
    steps, h = re.findall(r"(\d+) steps, h = +([0-9.E+-]+) s", text)[-1]
    with h5py.File(tmp_path / "w.h5", "r") as f:
        solver = dict(f["meta/solver"].attrs)
    assert int(steps) == int(solver["n_steps"]) > 0, (steps, solver)
    assert float(h) == pytest.approx(float(solver["h_last"]), rel=0.06), (h, solver)
