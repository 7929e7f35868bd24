"""Parametric campaigns (raildyn.campaign): decks with overrides, local runs, metrics checked
against closed forms, resume, Slurm job-array script, bad campaign files."""
import csv
import json
import os
from pathlib import Path

import numpy as np
import pytest

from raildyn import campaign as cp

REPO = Path(__file__).resolve().parents[2]

BASE = """! damped spring-mass carried along a straight track
&simulation title = 'campaign base', t_end = 4.0, speed = 10.0, gravity = 0.0,
            equilibrium = 'none' /
&solver method = 'bdf', rtol = 1e-9, atol = 1e-12 /
&output interval = 0.002 /
&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 10.0, izz = 10.0,
      position = 0.0, 0.0, 1.0, velocity = 0.0, 0.0, 0.1, frozen = 'x', 'y', 'yaw', 'roll', 'pitch' /
&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass',
      point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, 400.0 /
"""

CAMPAIGN = """name = "mass_sweep"
deck = "base.nml"
output = "runs"
jobs = 2
{extra}
[sweep]
"simulation.speed" = [5.0, 10.0]
"body[mass].mass" = [500.0, 1000.0]

[[metrics]]
name = "distance"
channel = "vehicle/distance"
reduce = "final"

[[metrics]]
name = "decay"
channel = "bodies/mass/position_track:z"
reduce = "growth_rate"
"""


@pytest.fixture
def campaign_file(tmp_path, build_dir):
    (tmp_path / "base.nml").write_text(BASE)
    path = tmp_path / "c.toml"
    path.write_text(CAMPAIGN.format(extra=f'raildyn = "{(build_dir / "bin" / "raildyn").resolve()}"'))
    return path


def test_override_deck_text(tmp_path):
    text = cp.override_deck(tmp_path / "base.nml", {"simulation.speed": 20.0,
                                                      "body[car].mass": 3, "body[car].frozen": ["x", "y"],
                                                      "wheelset[w1].creep_law": "polach"})
    assert "&include file = '" in text
    assert "&simulation speed = 20.0 /" in text
    assert "&body name = 'car', mass = 3, frozen = 'x', 'y' /" in text
    assert "&wheelset name = 'w1', creep_law = 'polach' /" in text


def test_campaign_runs_and_metrics(campaign_file):
    camp = cp.load_campaign(campaign_file)
    summary = cp.run_campaign(camp, progress=lambda *_: None)
    with open(summary) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4
    for row in rows:
        assert row["exit_code"] == "0", row
        v, m = float(row["simulation.speed"]), float(row["body[mass].mass"])
        assert float(row["distance"]) == pytest.approx(v * 4.0, rel=1e-12)
        # free vibration of a damped oscillator decays like exp(-c t / (2 m))
        assert float(row["decay"]) == pytest.approx(-400.0 / (2 * m), rel=0.02)
    # each run's deck says what differs
    deck = (camp.output / "run0003" / "deck.nml").read_text()
    assert "&body name = 'mass', mass = 1000.0 /" in deck
    # resume: nothing runs again
    lines = []
    cp.run_campaign(camp, progress=lines.append)
    assert all("reused" in l for l in lines), lines
    # an edited base deck runs again
    base = campaign_file.parent / "base.nml"
    base.write_text(BASE.replace("t_end = 4.0", "t_end = 2.0"))
    lines = []
    cp.run_campaign(camp, progress=lines.append)
    assert not any("reused" in l for l in lines), lines


def test_variants_and_speed_replaced_by_a_law(tmp_path, raildyn_exe):
    """A campaign of explicit variants (how raildyn critical-speed runs its probes): a speed
    law in the run deck replaces the base deck's constant speed, and a constant speed
    replaces a base deck's law (docs/input_reference.md "Includes and overrides"). Distances
    against the closed form: the integral of the piecewise-linear speed."""
    (tmp_path / "base.nml").write_text(BASE)
    (tmp_path / "law.nml").write_text(BASE.replace("speed = 10.0,", "speed_times = 0.0, 4.0, "
                                                   "speed_values = 2.0, 6.0,"))
    law = {"simulation.speed_times": [0.0, 2.0, 4.0], "simulation.speed_values": [10.0, 10.0, 20.0]}
    for base, variants, distances in (("base.nml", [law, {"simulation.t_end": 3.0}], [50.0, 30.0]),
                                      ("law.nml", [{"simulation.speed": 5.0}, {}], [20.0, 16.0])):
        camp = cp.Campaign(path=tmp_path / base, name="variants", deck=tmp_path / base,
                           output=tmp_path / ("runs_" + base), jobs=2, exe=raildyn_exe, variants=variants,
                           metrics=[cp.Metric("distance", "vehicle/distance", "final")])
        with open(cp.run_campaign(camp, progress=lambda *_: None)) as f:
            rows = list(csv.DictReader(f))
        assert [r["exit_code"] for r in rows] == ["0", "0"], rows
        assert [float(r["distance"]) for r in rows] == pytest.approx(distances, rel=1e-9)
        assert list(rows[0])[1:1 + len(camp.parameter_names())] == camp.parameter_names()


def test_failed_run_is_reported(campaign_file, tmp_path):
    text = campaign_file.read_text().replace('[500.0, 1000.0]', '[-1.0]')
    campaign_file.write_text(text)
    camp = cp.load_campaign(campaign_file)
    summary = cp.run_campaign(camp, progress=lambda *_: None)
    with open(summary) as f:
        rows = list(csv.DictReader(f))
    assert all(r["exit_code"] == "1" for r in rows)
    assert "mass" in rows[0]["error"] and "deck.nml" in rows[0]["error"]


def test_slurm_array_script(campaign_file):
    camp = cp.load_campaign(campaign_file)
    camp.slurm_options = ["--time=00:10:00"]
    assert cp.run_campaign(camp, executor="slurm", progress=lambda *_: None) is None
    script = (camp.output / "campaign.sbatch").read_text()
    assert "#SBATCH --array=0-3" in script
    assert "#SBATCH --time=00:10:00" in script
    runs = (camp.output / "runs.txt").read_text().split()
    assert len(runs) == 4 and all(Path(r, "deck.nml").exists() for r in runs)
    # a task runs exactly like the local executor
    rc = cp.main(["task", str(cp.find_raildyn(camp)), runs[0]])
    assert rc == 0
    assert json.loads(Path(runs[0], "status.json").read_text())["exit_code"] == 0


@pytest.mark.parametrize("text, words", [
    ('name = "x"\n', "'deck' is required"),
    ('name = "x"\ndeck = "nope.nml"\n', "not found"),
    ('name = "x"\ndeck = "base.nml"\n[sweep]\n"simulation speed" = [1.0]\n', "group.parameter"),
    ('name = "x"\ndeck = "base.nml"\n[sweep]\n"simulation.speed" = 3.0\n', "non-empty list"),
    ('name = "x"\ndeck = "base.nml"\n[sweep]\n"simulation.speed" = [nan]\n', "finite"),
    ('name = "x"\ndeck = "base.nml"\n[[metrics]]\nname="a"\nchannel="b"\nreduce="median"\n', "reduce"),
    ('name = "x"\ndeck = "base.nml"\nexecuter = "local"\n', "unknown entry"),
])
def test_bad_campaign_files(tmp_path, text, words):
    (tmp_path / "base.nml").write_text(BASE)
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(cp.CampaignError) as e:
        cp.load_campaign(p)
    assert words in str(e.value) and "bad.toml" in str(e.value)


def test_explicit_runner_must_exist(tmp_path, build_dir):
    """A campaign's 'raildyn' that is not an executable is an error naming it and the file,
    never replaced by another runner (raildyn.executable, shared with the validation harness)."""
    (tmp_path / "base.nml").write_text(BASE)
    path = tmp_path / "c.toml"
    path.write_text(CAMPAIGN.format(extra='raildyn = "no/such/raildyn"'))
    with pytest.raises(cp.CampaignError) as e:
        cp.find_raildyn(cp.load_campaign(path))
    assert "no/such/raildyn" in str(e.value) and "c.toml" in str(e.value)
    assert "is not an executable file" in str(e.value)
    path.write_text(CAMPAIGN.format(extra=f'raildyn = "{(build_dir / "bin" / "raildyn").resolve()}"'))
    assert cp.find_raildyn(cp.load_campaign(path)) == (build_dir / "bin" / "raildyn").resolve()


def test_runner_campaign_command(campaign_file):
    """`raildyn campaign run` hands over to the Python package and returns its status."""
    import subprocess
    camp = cp.load_campaign(campaign_file)
    exe = cp.find_raildyn(camp)
    res = subprocess.run([str(exe), "campaign", "run", str(campaign_file), "--jobs", "1"],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert (camp.output / "summary.csv").exists()
    bad = campaign_file.parent / "bad.toml"
    bad.write_text('name = "x"\n')
    res = subprocess.run([str(exe), "campaign", "run", str(bad)], capture_output=True, text=True)
    assert res.returncode == 1 and "'deck' is required" in res.stderr


@pytest.mark.parametrize("path", sorted(REPO.glob("validation/**/*.toml")), ids=lambda p: p.name)
def test_repository_campaigns_make_valid_decks(path, tmp_path, raildyn_exe):
    """Every campaign shipped in the repository loads, and the deck of each of its runs passes
    `raildyn check` (the override groups name parameters the runner knows, with valid values)."""
    import subprocess
    c = cp.load_campaign(path)
    assert c.deck.is_file() and c.runs() and c.metrics
    for k, params in enumerate(c.runs()):
        deck = tmp_path / f"run{k}.nml"
        deck.write_text(cp.override_deck(c.deck, params))
        proc = subprocess.run([str(raildyn_exe), "check", str(deck)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout + proc.stderr
