"""A campaign run as a Slurm job array on a real single-node Slurm cluster started for the
test on loopback (tests/python/support/slurm_single_node.sh): `raildyn campaign run
--executor slurm --submit` submits the array, waits for it, and the summary holds every run's
result, checked against the closed form distance = speed * t_end."""
import csv
import os
import shutil
import signal
import socket
import subprocess
import time
from pathlib import Path

import pytest

from raildyn import campaign as cp

HERE = Path(__file__).resolve().parent


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def slurm(tmp_path):
    for tool in ("slurmctld", "slurmd", "sbatch", "munged"):
        if not (shutil.which(tool) or Path("/usr/sbin", tool).exists()):
            pytest.fail(f"{tool} not installed (scripts/setup.sh installs Slurm for the tests)")
    if os.geteuid() != 0:
        pytest.fail("the single-node Slurm of this test needs root")
    # munged runs as user 'munge': its directory must be reachable for it (pytest's own
    # temporary directories are private to root)
    import tempfile
    d = Path(tempfile.mkdtemp(prefix="raildyn-slurm-", dir="/tmp"))
    d.chmod(0o755)
    start = subprocess.run(["bash", str(HERE / "support" / "slurm_single_node.sh"), str(d / "c"),
                            str(free_port()), str(free_port())], capture_output=True, text=True,
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


def test_campaign_as_slurm_job_array(tmp_path, slurm, build_dir):
    (tmp_path / "base.nml").write_text("&simulation title = 'slurm', t_end = 1.5, speed = 10.0 /\n"
                                       "&output interval = 0.1 /\n")
    (tmp_path / "c.toml").write_text(
        'name = "slurm_sweep"\ndeck = "base.nml"\noutput = "runs"\nexecutor = "slurm"\n'
        f'raildyn = "{(build_dir / "bin" / "raildyn").resolve()}"\n'
        '[sweep]\n"simulation.speed" = [5.0, 10.0, 20.0, 40.0]\n'
        '[[metrics]]\nname = "distance"\nchannel = "vehicle/distance"\nreduce = "final"\n')
    old = dict(os.environ)
    os.environ.update(slurm)
    try:
        rc = cp.main(["run", str(tmp_path / "c.toml"), "--submit"])
    finally:
        os.environ.clear()
        os.environ.update(old)
    assert rc == 0
    with open(tmp_path / "runs" / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4
    for row in rows:
        assert row["exit_code"] == "0", row
        assert float(row["distance"]) == pytest.approx(float(row["simulation.speed"]) * 1.5)
    assert len(list((tmp_path / "runs").glob("slurm-*_*.out"))) == 4
