"""raildyn.Results on files written by hand with h5py following docs/output.md
(the layout contract), independent of the Fortran writer."""

import h5py
import numpy as np
import pytest

from raildyn import Results


@pytest.fixture
def layout_file(make_results_file):
    t = np.linspace(0.0, 1.0, 11)
    pose = np.column_stack([10 * t, 0.001 * np.sin(t), 0.46 + 0 * t, 1e-3 * t, -2e-3 * t, 40 * t])
    force = np.column_stack([1e3 * t, -5e2 * t, 7.5e4 + 0 * t])
    return make_results_file(
        "layout.h5", t,
        {"bodies/car/position_track": (pose, "m m m rad rad rad", "x y z yaw roll pitch",
                                       "car pose in its track frame"),
         "wheelsets/ws1/left/contact_force": (force, "N", "fx fy fz", "contact force"),
         "track/frames/1/sigma": (10 * t[:, None], "m", "sigma", "arc length")},
        root_attrs={"title": "layout test", "raildyn_version": "0.1.0", "deck_file": "x.nml"},
        meta_attrs={"status": "completed", "wall_time": 2.5, "end_time": 1.0,
                    "n_steps": np.int64(11)},
        solver={"n_rhs": np.int64(1234), "h_last": 1e-4},
        deck_text="&run t_end = 1.0 /\n"), t, pose, force


def test_channels_shapes_values(layout_file):
    path, t, pose, force = layout_file
    with Results(path) as r:
        assert r.n_steps == 11
        np.testing.assert_array_equal(r.time, t)
        assert r.time.shape == (11,)
        assert r.channels() == ["bodies/car/position_track", "track/frames/1/sigma",
                                "wheelsets/ws1/left/contact_force"]
        np.testing.assert_array_equal(r.get("bodies/car/position_track"), pose)
        assert r.get("/wheelsets/ws1/left/contact_force").shape == (11, 3)
        np.testing.assert_array_equal(r["bodies/car/position_track:yaw"], pose[:, 3])
        np.testing.assert_array_equal(r.get("time"), t)
        assert "bodies/car/position_track:pitch" in r
        assert "bodies/car/position_track:nope" not in r
        assert len(r.columns()) == 6 + 3 + 1


def test_units_components_description(layout_file):
    path, *_ = layout_file
    with Results(path) as r:
        assert r.unit("bodies/car/position_track") == "m m m rad rad rad"
        assert r.units("bodies/car/position_track") == ["m"] * 3 + ["rad"] * 3
        assert r.unit("bodies/car/position_track:roll") == "rad"
        assert r.units("wheelsets/ws1/left/contact_force") == ["N", "N", "N"]
        assert r.components("bodies/car/position_track") == ["x", "y", "z", "yaw", "roll", "pitch"]
        assert r.description("wheelsets/ws1/left/contact_force") == "contact force"
        assert r.unit("time") == "s"


def test_metadata_and_deck(layout_file):
    path, *_ = layout_file
    with Results(path) as r:
        m = r.metadata
        assert m["version"] == "0.1.0"
        assert m["title"] == "layout test"
        assert m["status"] == "completed" and r.status == "completed"
        assert m["wall_time"] == 2.5
        assert m["n_steps"] == 11
        assert m["solver"] == {"n_rhs": 1234, "h_last": 1e-4}
        assert r.deck_text == "&run t_end = 1.0 /\n"


def test_unknown_channel_and_component(layout_file):
    path, *_ = layout_file
    with Results(path) as r:
        with pytest.raises(KeyError, match="no series"):
            r.get("bodies/bogie/position_track")
        with pytest.raises(KeyError, match="no component"):
            r.get("bodies/car/position_track:w")


def test_ragged_and_unwritten_rows_are_trimmed(make_results_file):
    """A crash can leave /time and the series with different extents, or cells holding
    the NaN fill value: only complete rows are read."""
    t = np.arange(8) * 0.1
    data = np.arange(16, dtype=float).reshape(8, 2)
    path = make_results_file("ragged.h5", t, {"bodies/a/x": (data, "m", "u v", "")})
    with h5py.File(path, "a") as f:
        f["time"].resize((10,))
        f["time"][8:] = [0.8, 0.9]          # time ahead of the series by 2 rows
    with Results(path) as r:
        assert r.n_steps == 8
        assert r.get("bodies/a/x").shape == (8, 2)
    with h5py.File(path, "a") as f:
        f["time"][6] = np.nan               # an unwritten (fill value) time cell
    with Results(path) as r:
        assert r.n_steps == 6
        np.testing.assert_array_equal(r.time, t[:6])
        np.testing.assert_array_equal(r.get("bodies/a/x"), data[:6])


def test_unwritten_series_cells_of_a_running_file(make_results_file):
    """In a live or killed file (status 'running') a series row that HDF5 extended but
    never wrote holds NaN: the rows end there. A closed file is not scanned."""
    t = np.arange(8) * 0.1
    data = np.arange(16, dtype=float).reshape(8, 2)
    data[5, 1] = np.nan
    path = make_results_file("running.h5", t, {"bodies/a/x": (data, "m", "u v", "")},
                             meta_attrs={"status": "running"})
    with Results(path) as r:
        assert r.n_steps == 5
        np.testing.assert_array_equal(r.get("bodies/a/x"), data[:5])
    path = make_results_file("closed.h5", t, {"bodies/a/x": (data, "m", "u v", "")},
                             meta_attrs={"status": "completed"})
    with Results(path) as r:
        assert r.n_steps == 8


def test_not_a_results_file(tmp_path):
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f["x"] = [1.0]
    with pytest.raises(ValueError, match="not a raildyn results file"):
        Results(path)


def test_fortran_writer_file_matches_layout(build_dir, tmp_path):
    """The Fortran writer's file (through the demo) reads like the hand-written one:
    same dataset shapes, attribute names and metadata keys."""
    import subprocess
    exe = build_dir / "tests" / "hdf5_writer_demo"
    if not exe.is_file():
        pytest.skip(f"{exe} not built")
    path = tmp_path / "demo.h5"
    subprocess.run([str(exe), str(path), "5", "3", "0", "12"], check=True, capture_output=True)
    with h5py.File(path, "r") as f:
        for name in ("bodies/demo/position", "wheelsets/ws1/left/normal_force"):
            assert f[name].ndim == 2 and f[name].maxshape[0] is None
            assert {"unit", "components", "description"} <= set(f[name].attrs)
        assert f["time"].shape == (12,) and f["time"].attrs["unit"] == b"s"
        assert {"format", "format_version", "created", "title"} <= set(f.attrs)
        assert {"status", "end_time", "wall_time", "n_steps"} <= set(f["meta"].attrs)
        assert "solver" in f["meta"] and "deck_text" in f["meta"]
