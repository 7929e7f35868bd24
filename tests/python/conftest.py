"""Shared pytest fixtures: the package on sys.path, the build directory, and a writer of
results files with the layout of docs/output.md built directly with h5py (independent of
the Fortran writer)."""

import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
if str(REPO / "python") not in sys.path:
    sys.path.insert(0, str(REPO / "python"))


def load_script(rel: str, name: str):
    """A script of the repository (bench/...) imported as module `name` (registered in
    sys.modules: dataclasses look their module up)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(name, REPO / rel)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="session")
def build_dir() -> Path:
    """Build tree: $RAILDYN_BUILD_DIR (ctest sets it) or <repo>/build."""
    return Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build"))


@pytest.fixture(scope="session")
def raildyn_exe(build_dir) -> Path:
    """The runner of the build tree (a test that needs it fails if it was not built)."""
    exe = build_dir / "bin" / "raildyn"
    if not exe.exists():
        pytest.fail(f"raildyn executable not built: {exe}")
    return exe


def write_layout_file(path, time, series, root_attrs=None, meta_attrs=None, solver=None,
                      deck_text=None):
    """Write a results file by hand following docs/output.md.

    series: {path: (data (n, ncomp), unit, components, description)}.
    """
    import h5py
    import numpy as np

    with h5py.File(path, "w", libver="latest") as f:
        attrs = {"format": np.bytes_("raildyn-results"), "format_version": np.int64(1)}
        attrs.update(root_attrs or {})
        for k, v in attrs.items():
            f.attrs[k] = np.bytes_(v) if isinstance(v, str) else v
        meta = f.create_group("meta")
        for k, v in (meta_attrs or {}).items():
            meta.attrs[k] = np.bytes_(v) if isinstance(v, str) else v
        sol = meta.create_group("solver")
        for k, v in (solver or {}).items():
            sol.attrs[k] = v
        if deck_text is not None:
            meta["deck_text"] = np.bytes_(deck_text)
        t = f.create_dataset("time", data=np.asarray(time, float), maxshape=(None,), chunks=True)
        t.attrs["unit"] = np.bytes_("s")
        t.attrs["components"] = np.bytes_("time")
        for name, (data, unit, components, description) in series.items():
            data = np.asarray(data, float)
            d = f.create_dataset(name, data=data, maxshape=(None, data.shape[1]), chunks=True)
            d.attrs["unit"] = np.bytes_(unit)
            d.attrs["components"] = np.bytes_(components)
            d.attrs["description"] = np.bytes_(description)
    return path


@pytest.fixture
def make_results_file(tmp_path):
    """Factory: make_results_file(name, time, series, **attrs) -> path."""
    def make(name, time, series, **kwargs):
        return write_layout_file(tmp_path / name, time, series, **kwargs)
    return make


def free_port():
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def slurm(tmp_path):
    """A real single-node Slurm cluster on loopback for one test (support/slurm_single_node.sh:
    munged, slurmctld and slurmd under a temporary folder); yields the environment that
    points Slurm's clients at it (SLURM_CONF). Its daemons are stopped by their PIDs."""
    import shutil
    import signal
    import subprocess
    import tempfile
    import time
    for tool in ("slurmctld", "slurmd", "sbatch", "munged"):
        if not (shutil.which(tool) or Path("/usr/sbin", tool).exists()):
            pytest.fail(f"{tool} not installed (scripts/setup.sh installs Slurm for the tests)")
    if os.geteuid() != 0:
        pytest.fail("the single-node Slurm of this test needs root")
    # munged runs as user 'munge': its directory must be reachable for it (pytest's own
    # temporary directories are private to root)
    d = Path(tempfile.mkdtemp(prefix="raildyn-slurm-", dir="/tmp"))
    d.chmod(0o755)
    start = subprocess.run(["bash", str(Path(__file__).resolve().parent / "support" / "slurm_single_node.sh"),
                            str(d / "c"), str(free_port()), str(free_port())], capture_output=True, text=True,
                           timeout=60)
    assert start.returncode == 0, start.stdout + start.stderr
    d = d / "c"
    env = dict(os.environ, SLURM_CONF=str(d / "slurm.conf"))
    deadline = time.time() + 30
    while time.time() < deadline:
        out = subprocess.run(["sinfo", "-h", "-o", "%T"], env=env, capture_output=True, text=True)
        if out.stdout.strip() in ("idle", "mixed", "allocated"):
            break
        time.sleep(0.5)
    else:
        pytest.fail(f"slurm did not come up: {out.stdout} {out.stderr}")
    yield env
    for pid_file in (d / "slurmd.pid", d / "slurmctld.pid", d / "munge" / "munged.pid"):
        try:
            os.kill(int(pid_file.read_text().split()[0]), signal.SIGTERM)
        except (OSError, ValueError):
            pass
    shutil.rmtree(d.parent, ignore_errors=True)
