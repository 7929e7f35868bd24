"""A campaign run as a Slurm job array on a real single-node Slurm cluster started for the
test on loopback (tests/python/support/slurm_single_node.sh): `raildyn campaign run
--executor slurm --submit` submits the array, waits for it, and the summary holds every run's
result, checked against the closed form distance = speed * t_end. The cluster is the
`slurm` fixture of conftest.py."""
import csv
import os

import pytest

from raildyn import campaign as cp


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
