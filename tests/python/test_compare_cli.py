"""python -m raildyn.compare: exit status, summary and plots on files with a known answer."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

PYTHON_DIR = str(Path(__file__).resolve().parents[2] / "python")


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    return subprocess.run([sys.executable, "-m", "raildyn.compare", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=60)


def test_cli_pass_and_fail(make_results_file, tmp_path):
    t = np.linspace(0, 1, 51)
    ref = make_results_file("ref.h5", t, {"bodies/a/x": (np.column_stack([t, t ** 2]), "m", "u v", "")})
    same = make_results_file("same.h5", t, {"bodies/a/x": (np.column_stack([t, t ** 2]), "m", "u v", "")})
    # v off by 0.5 % of its range 1: fails at rtol 1e-3, passes at 1e-2
    off = make_results_file("off.h5", t, {"bodies/a/x": (np.column_stack([t, t ** 2 + 5e-3]), "m", "u v", "")})

    ok = run_cli(same, ref)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "2 of 2 channels pass" in ok.stdout
    assert "RuntimeWarning" not in ok.stderr

    bad = run_cli(off, ref, "--rtol", "1e-3", "--plot", tmp_path / "plots")
    assert bad.returncode == 1, bad.stdout + bad.stderr
    assert "bodies/a/x:v" in bad.stdout and "FAIL" in bad.stdout
    assert "bodies/a/x:u" not in bad.stdout          # passing channels hidden by default
    assert list((tmp_path / "plots").glob("*.png"))

    loose = run_cli(off, ref, "--rtol", "1e-2", "--all", "--channel", "bodies/a/x:v")
    assert loose.returncode == 0, loose.stdout + loose.stderr
    assert "1 of 1 channels pass" in loose.stdout
