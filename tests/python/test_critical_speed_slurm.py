"""`raildyn critical-speed --backend slurm`: the probe runs of the bisection and of the ramp
as Slurm job arrays on a real single-node cluster (the `slurm` fixture of conftest.py),
through the campaign machinery (raildyn.stability.run_probes -> raildyn.campaign). The same
probes run by the local process pool give the same answer bit for bit, the array's tasks
leave their Slurm logs, and the answers hold the physics the local tests check: the
bisection of the knife-edge wheelset (linear creep, a lateral pulse) brackets its linear
critical speed, which tests/python/test_critical_speed.py checks against a model derived
there."""
import json
import os
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DECKS = REPO / "tests" / "decks"


def critical_speed(exe, deck, *args, env=None):
    res = subprocess.run([str(exe), "critical-speed", str(deck), *map(str, args), "--json"],
                         capture_output=True, text=True, timeout=900, env=env)
    assert res.returncode == 0, res.stdout + res.stderr
    return json.loads(res.stdout)


def test_bisection_and_ramp_probes_as_slurm_job_arrays(tmp_path, slurm, raildyn_exe):
    env = dict(os.environ, **slurm)
    pulsed = tmp_path / "pulsed.nml"
    pulsed.write_text(f"&include file = '{DECKS / 'knife_edge_wheelset.nml'}' /\n"
                      "&external_force body = 'ws', frame = 'track', force = 0.0, 2000.0, 0.0, "
                      "t_start = 0.1, t_end = 0.15 /\n")
    common = ["--method", "bisection", "--speeds", "70,90", "--resolution", "1", "--jobs", "2",
              "--t-end", "3", "--t-from", "0.5", "--channel", "bodies/ws/position_track:y"]
    local = critical_speed(raildyn_exe, pulsed, *common, "--work", tmp_path / "local")
    on_slurm = critical_speed(raildyn_exe, pulsed, *common, "--backend", "slurm", "--work", tmp_path / "slurm",
                              env=env)
    assert on_slurm["probes"] == local["probes"]
    assert on_slurm["critical_speed"] == local["critical_speed"] and on_slurm["resolution"] <= 1
    rounds = sorted((tmp_path / "slurm").glob("bisection*"))
    assert len(rounds) >= 2
    for r in rounds:      # one job array per round, one task (and log) per probe
        assert (r / "campaign.sbatch").is_file()
        assert len(list(r.glob("slurm-*_*.out"))) == len(list(r.glob("run*/")))
    linear = critical_speed(raildyn_exe, pulsed, "--method", "linear", "--speeds", "70,90", "--resolution", "0.05")
    a, b = on_slurm["bracket"]
    assert a - linear["resolution"] <= linear["critical_speed"] <= b + linear["resolution"]

    ramp = ["--method", "ramp", "--speeds", "60,100", "--hold", "3", "--duration", "16,32", "--jobs", "2"]
    hunting = DECKS / "knife_edge_wheelset_hunting.nml"
    local = critical_speed(raildyn_exe, hunting, *ramp, "--work", tmp_path / "ramp_local")
    on_slurm = critical_speed(raildyn_exe, hunting, *ramp, "--backend", "slurm", "--work", tmp_path / "ramp_slurm",
                              env=env)
    assert on_slurm["probes"] == local["probes"] and on_slurm["critical_speed"] == local["critical_speed"]
    assert len(list((tmp_path / "ramp_slurm" / "ramps").glob("slurm-*_*.out"))) == 2
