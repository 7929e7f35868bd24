"""Files whose common axis is not time (the track export samples along sigma), and the
quick-look plots (python -m raildyn.plots) on such files and on run files."""

import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from raildyn import Results
from raildyn.plots import plot_channels, plot_track

PYTHON_DIR = str(Path(__file__).resolve().parents[2] / "python")
PNG = b"\x89PNG\r\n\x1a\n"


def track_file(tmp_path):
    """A circle of radius 500 m to the left sampled every 10 m along sigma, written by
    hand: root attribute axis = 'sigma', no /time."""
    path = tmp_path / "track.h5"
    sigma = np.arange(0.0, 801.0, 10.0)
    radius = 500.0
    xyz = np.column_stack([radius * np.sin(sigma / radius), radius * (1 - np.cos(sigma / radius)),
                           0 * sigma])
    with h5py.File(path, "w") as f:
        f.attrs["axis"] = np.bytes_("sigma")
        f.create_group("meta").attrs["status"] = np.bytes_("completed")
        s = f.create_dataset("sigma", data=sigma, maxshape=(None,))
        s.attrs["unit"] = np.bytes_("m")
        for name, data, unit, comps in [("track/position", xyz, "m", "X Y Z"),
                                        ("track/curvature", np.full((sigma.size, 1), 1 / radius),
                                         "1/m", "kappa")]:
            d = f.create_dataset(name, data=data, maxshape=(None, data.shape[1]))
            d.attrs["unit"] = np.bytes_(unit)
            d.attrs["components"] = np.bytes_(comps)
    return path, sigma, xyz


def test_results_with_sigma_axis(tmp_path):
    path, sigma, xyz = track_file(tmp_path)
    with Results(path) as r:
        assert r.axis == "sigma"
        np.testing.assert_array_equal(r.time, sigma)
        assert r.unit("sigma") == "m"
        assert r.channels() == ["track/curvature", "track/position"]
        np.testing.assert_array_equal(r.get("track/position:Y"), xyz[:, 1])


def test_plot_functions_write_png(tmp_path):
    path, *_ = track_file(tmp_path)
    out = plot_track(path, tmp_path / "track.png")
    assert open(out, "rb").read(8) == PNG
    out = plot_channels(path, tmp_path / "ch.png", ["track/curvature:kappa"])
    assert open(out, "rb").read(8) == PNG


def test_plots_command_line(tmp_path, make_results_file):
    env = dict(os.environ, PYTHONPATH=PYTHON_DIR)
    path, *_ = track_file(tmp_path)
    out = tmp_path / "cli_track.png"
    run = subprocess.run([sys.executable, "-m", "raildyn.plots", "track", str(path), str(out)],
                         capture_output=True, text=True, env=env, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "RuntimeWarning" not in run.stderr
    assert out.read_bytes()[:8] == PNG
    t = np.linspace(0, 1, 21)
    run_file = make_results_file("run.h5", t, {"bodies/a/x": (np.column_stack([t, -t]), "m", "u v", "")})
    out = tmp_path / "cli_run.png"
    run = subprocess.run([sys.executable, "-m", "raildyn.plots", "channels", str(run_file), str(out)],
                         capture_output=True, text=True, env=env, timeout=60)
    assert run.returncode == 0, run.stderr
    assert out.read_bytes()[:8] == PNG
    bad = subprocess.run([sys.executable, "-m", "raildyn.plots", "channels", str(tmp_path / "none.h5"),
                          str(out)], capture_output=True, text=True, env=env, timeout=60)
    assert bad.returncode == 1 and "raildyn.plots:" in bad.stderr
