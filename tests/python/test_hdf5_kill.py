"""A writer process killed with SIGKILL half-way leaves a readable results file holding
at least every step up to its last flush (SWMR, docs/output.md).

The demo (tests/fortran/io/hdf5/hdf5_writer_demo.f90) writes row k = (0.01 k | k, sin(0.1 k),
-2 k | 1000 + k) slowly for ever and prints "flushed <n>" after each flush; the expected
values are recomputed here from that closed form."""

import os
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from raildyn import Results


@pytest.fixture(scope="module")
def demo(build_dir):
    exe = Path(build_dir) / "tests" / "hdf5_writer_demo"
    if not exe.is_file():
        pytest.skip(f"{exe} not built (cmake --build <build> --target hdf5_writer_demo; "
                    "set RAILDYN_BUILD_DIR)")
    return exe


def expected_rows(n):
    k = np.arange(n, dtype=float)
    return 0.01 * k, np.column_stack([k, np.sin(0.1 * k), -2.0 * k]), (1000.0 + k)[:, None]


def run_and_kill(demo, path, flush_every, buffer_steps, min_flushes, sleep_ms=1):
    """Start the demo, wait for min_flushes flush reports, SIGKILL it; return the last
    flushed row count it reported."""
    proc = subprocess.Popen([str(demo), str(path), str(flush_every), str(buffer_steps),
                             str(sleep_ms), "0"], stdout=subprocess.PIPE, text=True)
    flushed, reports = 0, 0
    deadline = time.monotonic() + 30.0
    try:
        while reports < min_flushes:
            line = proc.stdout.readline()
            assert line, f"demo ended early with status {proc.poll()}"
            if line.startswith("flushed "):
                flushed = int(line.split()[1])
                reports += 1
            assert time.monotonic() < deadline, "demo too slow"
        # SWMR allows readers while the writer runs: the rows flushed so far are there.
        with Results(path) as live:
            assert live.n_steps >= flushed and live.status == "running"
            t, pos, _ = expected_rows(live.n_steps)
            np.testing.assert_array_equal(live.time, t)
            np.testing.assert_allclose(live.get("bodies/demo/position"), pos, rtol=0, atol=1e-15)
        # Kill between flushes: after a few more unflushed steps were buffered or written.
        time.sleep(0.003 * flush_every * sleep_ms / 2)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)
        # Flush reports printed after our last read but before the kill also count.
        for line in proc.stdout.read().splitlines():
            if line.startswith("flushed "):
                flushed = int(line.split()[1])
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        proc.stdout.close()
    assert proc.returncode == -signal.SIGKILL
    return flushed


@pytest.mark.parametrize("flush_every,buffer_steps", [(10, 4), (7, 7), (25, 100)])
def test_killed_writer_leaves_readable_file(demo, tmp_path, flush_every, buffer_steps):
    path = tmp_path / "killed.h5"
    flushed = run_and_kill(demo, path, flush_every, buffer_steps, min_flushes=5)
    assert flushed >= 5 * flush_every

    # Raw h5py (SWMR read mode, the documented way to open a killed run's file).
    with h5py.File(path, "r", swmr=True) as f:
        n_time = f["time"].shape[0]
        assert n_time >= flushed
        assert f["bodies/demo/position"].shape[1] == 3
        assert f["meta"].attrs["status"] == b"running"
        t, pos, force = expected_rows(flushed)
        np.testing.assert_array_equal(f["time"][:flushed], t)
        np.testing.assert_allclose(f["bodies/demo/position"][:flushed], pos, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(f["wheelsets/ws1/left/normal_force"][:flushed], force)

    # The package reader opens it too and sees complete, correct rows only.
    with Results(path) as r:
        n = r.n_steps
        assert n >= flushed
        t, pos, force = expected_rows(n)
        np.testing.assert_array_equal(r.time, t)
        np.testing.assert_allclose(r.get("bodies/demo/position"), pos, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(r.get("wheelsets/ws1/left/normal_force"), force)
        assert r.metadata["status"] == "running"
        assert r.metadata["title"] == "hdf5_writer_demo"
        assert r.deck_text == "&run t_end = 1 /"


def test_completed_demo_file(demo, tmp_path):
    """A run that ends normally: status completed, exact row count, metadata."""
    path = tmp_path / "done.h5"
    steps = 53   # not a multiple of the buffer nor of flush_every
    out = subprocess.run([str(demo), str(path), "10", "4", "0", str(steps)],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[-1] == f"closed {steps}"
    with h5py.File(path, "r") as f:   # closed cleanly: plain read mode works
        assert f["time"].shape == (steps,)
        assert f["bodies/demo/position"].shape == (steps, 3)
        assert f["wheelsets/ws1/left/normal_force"].shape == (steps, 1)
    with Results(path) as r:
        t, pos, force = expected_rows(steps)
        np.testing.assert_array_equal(r.time, t)
        np.testing.assert_allclose(r.get("bodies/demo/position"), pos, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(r.get("wheelsets/ws1/left/normal_force:N"), force[:, 0])
        assert r.channels() == ["bodies/demo/position", "wheelsets/ws1/left/normal_force"]
        assert r.unit("bodies/demo/position") == "m"
        assert r.units("bodies/demo/position") == ["m", "m", "m"]
        assert r.components("bodies/demo/position") == ["x", "y", "z"]
        assert r.unit("time") == "s"
        meta = r.metadata
        assert meta["status"] == "completed"
        assert meta["n_steps"] == steps
        assert meta["end_time"] == pytest.approx(0.01 * (steps - 1), rel=1e-15)
        assert meta["format"] == "raildyn-results"


def test_reader_attached_while_the_run_finishes(demo, tmp_path):
    """A monitoring reader holds the file (SWMR read, shared lock) while the writer
    closes: the writer still records status 'completed' and all rows."""
    path = tmp_path / "watched.h5"
    steps = 200
    proc = subprocess.Popen([str(demo), str(path), "10", "4", "2", str(steps)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert line.startswith("flushed "), line + proc.stderr.read()
        with Results(path) as watcher:
            assert watcher.status == "running" and watcher.n_steps >= int(line.split()[1])
            out, err = proc.communicate(timeout=60)   # the writer closes while we watch
            assert proc.returncode == 0, err
            assert out.splitlines()[-1] == f"closed {steps}"
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    with Results(path) as r:
        assert r.status == "completed"
        assert r.n_steps == steps and r.metadata["n_steps"] == steps
        t, pos, _ = expected_rows(steps)
        np.testing.assert_array_equal(r.time, t)
        np.testing.assert_allclose(r.get("bodies/demo/position"), pos, rtol=0, atol=1e-15)
