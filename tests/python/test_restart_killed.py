"""A run killed with SIGKILL can be continued: raildyn run --restart reads the killed file (left
flagged open for SWMR writing, rows after its last flush possibly missing) from its last
complete row. Checked against the uninterrupted run: with the fixed-step rk4 and a restart
time on the step grid, the continued rows equal the straight ones to rounding."""
import os
import signal
import subprocess
import time

import h5py
import numpy as np
import pytest

from raildyn import Results

# a lightly damped box on springs, rk4 with a 2 us step: 20 s simulated are 1e7 steps, far
# more wall time than the wait for 20 flushed rows (0.19 s simulated), so it is killed part-way
DECK = """&simulation t_end = {t_end}, speed = 10.0, equilibrium = 'none' /
&solver method = 'rk4', fixed_step = 2e-6 /
&output interval = 0.01, flush_every = 1 /
&segment type = 'straight', length = 10000.0 /
&body name = 'box', mass = 100.0, ixx = 10.0, iyy = 10.0, izz = 10.0, position = 0.0, 0.01, 0.5,
      velocity = 0.0, 0.0, 0.2 /
&element name = 'hanger', type = 'spring_damper', body2 = 'box', point1 = 0.0, 0.0, 0.5,
      stiffness = 1e5, 1e5, 4e4, damping = 5.0, 5.0, 5.0 /
"""


def test_a_killed_run_continues(raildyn_exe, tmp_path):
    deck = tmp_path / "box.nml"
    deck.write_text(DECK.format(t_end=20.0))
    killed = tmp_path / "killed.h5"
    proc = subprocess.Popen([str(raildyn_exe), "run", str(deck), "-o", str(killed), "--quiet"])
    try:
        deadline = time.monotonic() + 60
        rows = 0
        while rows < 20:                       # wait for some flushed rows
            assert proc.poll() is None, "the run ended before it could be killed"
            assert time.monotonic() < deadline
            time.sleep(0.1)
            if killed.exists():
                try:
                    with Results(killed) as r:
                        rows = r.n_steps
                except (OSError, ValueError):
                    rows = 0
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=10)
    with Results(killed) as r:
        assert r.status == "running"           # killed: never closed
        t_last = r.time[-1]
        assert 0.19 <= t_last < 20.0
    t_end = round(t_last + 0.1, 2)
    deck.write_text(DECK.format(t_end=t_end))
    out = subprocess.run([str(raildyn_exe), "run", str(deck), "--restart", str(killed)],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    straight = tmp_path / "straight.h5"
    subprocess.run([str(raildyn_exe), "run", str(deck), "-o", str(straight), "--quiet"], check=True,
                   timeout=300)
    with h5py.File(tmp_path / "killed_restart.h5", "r") as c, h5py.File(straight, "r") as s:
        t_c, t_s = c["time"][...], s["time"][...]
        assert t_c[0] == pytest.approx(t_last, abs=1e-12) and t_c[-1] == pytest.approx(t_end)
        k = np.searchsorted(t_s, t_c[0] - 1e-9)
        np.testing.assert_allclose(t_c, t_s[k:], atol=1e-12)
        y_c, y_s = c["state/y"][...], s["state/y"][k:]
        scale = np.abs(y_s).max(axis=0)
        assert (np.abs(y_c - y_s).max(axis=0) <= 1e-9 * scale + 1e-15).all()
        assert np.ptp(y_s[:, 2]) > 1e-3          # the box moves: the comparison can fail
