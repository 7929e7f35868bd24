"""Campaigns that can be trusted when resumed (issue 13, items 12 and 13): a run is reused
only when nothing it depends on changed (files at any include depth, the runner), Ctrl-C
stops cleanly, and failures, missing channels and damaged files are reported with a message
while summary.csv survives. Categories: pytest -m campaign_cache, -m campaign_errors."""
import csv
import json
import math
import os
import signal
import subprocess
import time
from pathlib import Path

import h5py
import pytest

from raildyn import campaign as cp

REPO = Path(__file__).resolve().parents[2]

#: base.nml -> body.nml -> spring.nml: the damping that the metric measures sits two
#: includes below the campaign's base deck
BASE = """&simulation title = 'nested', t_end = {t_end}, speed = 10.0, gravity = 0.0,
            equilibrium = 'none' /
&solver method = 'bdf', rtol = 1e-9, atol = 1e-12{solver} /
&output interval = 0.002 /
&include file = 'parts/body.nml' /
"""
BODY = """&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 10.0, izz = 10.0,
      position = 0.0, 0.0, 1.0, velocity = 0.0, 0.0, 0.1, frozen = 'x', 'y', 'yaw', 'roll', 'pitch' /
&include file = 'spring.nml' /
"""
SPRING = """&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass',
      point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, {damping} /
"""
CAMPAIGN = """name = "nested"
deck = "base.nml"
output = "runs"
jobs = 2
raildyn = "{exe}"

[sweep]
"body[mass].mass" = [500.0, 1000.0]

[[metrics]]
name = "decay"
channel = "{channel}"
reduce = "growth_rate"
"""


def make_campaign(tmp_path, exe, damping=400.0, t_end=4.0, solver="",
                  channel="bodies/mass/position_track:z"):
    (tmp_path / "parts").mkdir(exist_ok=True)
    (tmp_path / "base.nml").write_text(BASE.format(t_end=t_end, solver=solver))
    (tmp_path / "parts" / "body.nml").write_text(BODY)
    (tmp_path / "parts" / "spring.nml").write_text(SPRING.format(damping=damping))
    path = tmp_path / "c.toml"
    path.write_text(CAMPAIGN.format(exe=exe, channel=channel))
    return path


def run(path):
    """Run the campaign; (states printed per run, summary rows)."""
    lines = []
    summary = cp.run_campaign(cp.load_campaign(path), progress=lines.append)
    with open(summary) as f:
        return [line.rsplit(": ", 1)[1] for line in lines], list(csv.DictReader(f))


def damping_decay(rows, damping):
    """Free vibration of a damped oscillator decays like exp(-c t / (2 m))."""
    for row in rows:
        assert float(row["decay"]) == pytest.approx(-damping / (2 * float(row["body[mass].mass"])),
                                                    rel=0.02), row


@pytest.mark.campaign_cache
def test_check_json_lists_every_file_read(tmp_path, raildyn_exe):
    """`raildyn check --json` names the deck, nested includes and the input files a deck
    names (not analytic profile keywords, not the results file)."""
    make_campaign(tmp_path, raildyn_exe)
    proc = subprocess.run([str(raildyn_exe), "check", "base.nml", "--json"], cwd=tmp_path,
                          capture_output=True, text=True)
    answer = json.loads(proc.stdout)
    assert proc.returncode == 0 and answer["status"] == "ok" and answer["exit_code"] == 0
    assert [Path(tmp_path, f).resolve() for f in answer["input_files"]] == \
        [tmp_path / "base.nml", tmp_path / "parts" / "body.nml", tmp_path / "parts" / "spring.nml"]
    assert answer["version"] == subprocess.run([str(raildyn_exe), "version"], capture_output=True,
                                               text=True).stdout.split()[1]
    # a repository deck with an irregularity file, its wheel and rail profiles keywords
    deck = REPO / "inputs" / "tgv_wheelset_irregular.nml"
    answer = json.loads(subprocess.run([str(raildyn_exe), "check", str(deck), "--json"],
                                       capture_output=True, text=True).stdout)
    files = [Path(f).resolve() for f in answer["input_files"]]
    irregularity = [line for line in deck.read_text().splitlines() if "irregularity_file" in line]
    assert files[0] == deck and len(irregularity) == 1
    named = irregularity[0].split("irregularity_file")[1].split("'")[1]
    assert (deck.parent / named).resolve() in files
    assert not any(f.name in ("s1002", "60e1", "54e1") or f.suffix == ".h5" for f in files)
    # profile files named in an override of a deck that includes three more decks
    profiles = REPO / "inputs" / "profiles"
    (tmp_path / "profiles.nml").write_text(
        f"&include file = '{REPO / 'inputs' / 'tgv_profile_fastsim.nml'}' /\n"
        f"&wheelset name = 'w1', wheel_profile = '{profiles / 's1002.prw'}', "
        f"rail_profile = '{profiles / '60e1.prr'}' /\n")
    answer = json.loads(subprocess.run([str(raildyn_exe), "check", "profiles.nml", "--json"],
                                       cwd=tmp_path, capture_output=True, text=True).stdout)
    files = [Path(tmp_path, f).resolve() for f in answer["input_files"]]
    assert answer["status"] == "ok" and files[:2] == [tmp_path / "profiles.nml",
                                                      REPO / "inputs" / "tgv_profile_fastsim.nml"]
    assert files[-2:] == [profiles / "s1002.prw", profiles / "60e1.prr"]
    assert all(f.is_file() for f in files) and len(files) == len(set(files)) > 4
    # a deck that does not check: status error with the message, files read so far listed
    (tmp_path / "parts" / "spring.nml").write_text("&element name = 'spring', typo = 1 /\n")
    proc = subprocess.run([str(raildyn_exe), "check", "base.nml", "--json"], cwd=tmp_path,
                          capture_output=True, text=True)
    answer = json.loads(proc.stdout)
    assert proc.returncode == 1 and answer["status"] == "error" and "typo" in answer["message"]
    # names that JSON must escape read back unchanged
    odd = tmp_path / 'od"d\\x'
    odd.mkdir()
    (odd / "b.nml").write_text("&body name = 'b', mass = 1.0, ixx = 1.0, iyy = 1.0, izz = 1.0 /\n")
    (tmp_path / "top.nml").write_text("&simulation t_end = 1.0, speed = 1.0 /\n"
                                      "&segment type = 'straight', length = 100.0 /\n"
                                      "&include file = 'od\"d\\x/b.nml' /\n")
    proc = subprocess.run([str(raildyn_exe), "check", "top.nml", "--json"], cwd=tmp_path,
                          capture_output=True, text=True)
    assert json.loads(proc.stdout)["input_files"] == ["top.nml", 'od"d\\x/b.nml']


@pytest.mark.campaign_cache
def test_edit_two_includes_down_reruns(tmp_path, raildyn_exe):
    path = make_campaign(tmp_path, raildyn_exe)
    states, rows = run(path)
    assert states == ["ok", "ok"]
    damping_decay(rows, 400.0)
    states, rows = run(path)
    assert states == ["reused", "reused"]
    # the damping sits in a file included by a file included by the base deck
    (tmp_path / "parts" / "spring.nml").write_text(SPRING.format(damping=800.0))
    states, rows = run(path)
    assert states == ["ok", "ok"]
    damping_decay(rows, 800.0)


@pytest.mark.campaign_cache
def test_edited_survey_file_reruns(tmp_path, raildyn_exe):
    """An input file that is not a deck (here the track's survey points): straight along x,
    then along y = 0.1 x; the track frame ends at arc length V t_end on that line."""
    def survey(slope):
        (tmp_path / "survey.txt").write_text(
            "# x y z superelevation\n" + "".join(f"{x} {slope * x} 0 0\n" for x in range(0, 401, 20)))
    survey(0.0)
    (tmp_path / "track.nml").write_text("&simulation t_end = 2.0, speed = 10.0 /\n"
                                        "&output interval = 0.5 /\n&track survey_file = 'survey.txt' /\n")
    path = tmp_path / "c.toml"
    path.write_text(f'name = "survey"\ndeck = "track.nml"\noutput = "runs"\nraildyn = "{raildyn_exe}"\n'
                    '[sweep]\n"simulation.speed" = [10.0, 20.0]\n'
                    '[[metrics]]\nname = "y_end"\nchannel = "track/frames/1/position:Y"\nreduce = "final"\n')
    states, rows = run(path)
    assert states == ["ok", "ok"] and [float(r["y_end"]) for r in rows] == [0.0, 0.0]
    survey(0.1)
    states, rows = run(path)
    assert states == ["ok", "ok"]
    for row in rows:
        arc = 2.0 * float(row["simulation.speed"])
        assert float(row["y_end"]) == pytest.approx(arc * math.sin(math.atan(0.1)), rel=1e-9)


@pytest.mark.campaign_cache
def test_new_runner_reruns(tmp_path, raildyn_exe):
    """The runner is part of what a run depends on: another build (here the same program
    with one byte appended, which still runs) makes every run stale."""
    exe = tmp_path / "raildyn"
    exe.write_bytes(raildyn_exe.read_bytes())
    exe.chmod(0o755)
    path = make_campaign(tmp_path, exe)
    assert run(path)[0] == ["ok", "ok"]
    assert run(path)[0] == ["reused", "reused"]
    with open(exe, "ab") as f:
        f.write(b"\0")
    assert run(path)[0] == ["ok", "ok"]


@pytest.mark.campaign_errors
def test_damaged_results_rerun_on_resume(tmp_path, raildyn_exe, capsys):
    """A run recorded as completed whose results file is cut short runs again, never
    silently: a notice naming the file and the fault before it runs, the damaged file kept
    beside the new one, the reason in status.json; the summary then has its metric."""
    path = make_campaign(tmp_path, raildyn_exe)
    run(path)
    results = tmp_path / "runs" / "run0001" / "results.h5"
    cut = results.read_bytes()[:1000]
    results.write_bytes(cut)
    notices = []
    lines = []
    summary = cp.run_campaign(cp.load_campaign(path), progress=lines.append, notice=notices.append)
    assert [line.rsplit(": ", 1)[1] for line in lines] == [
        "reused", "ok, run again because its results file was damaged or incomplete"]
    assert len(notices) == 1 and "run0001" in notices[0] and str(results) in notices[0]
    assert "damaged, cannot be read" in notices[0] and "running it again" in notices[0]
    assert (results.parent / "results.h5.damaged").read_bytes() == cut
    status = json.loads((results.parent / "status.json").read_text())
    assert str(results) in status["rerun_reason"] and status["exit_code"] == 0
    with open(summary) as f:
        damping_decay(list(csv.DictReader(f)), 400.0)
    # resumed once more: nothing to say, both reused
    assert run(path)[0] == ["reused", "reused"]


@pytest.mark.campaign_errors
def test_incomplete_or_missing_results_rerun_on_resume_with_a_notice(tmp_path, raildyn_exe, capsys):
    """From the command line: a results file that reads but whose run did not complete, and
    one that is gone, each give one notice line on stderr (no traceback) and run again;
    summary.csv is written with both metrics."""
    path = make_campaign(tmp_path, raildyn_exe)
    assert cp.main(["run", str(path)]) == 0
    capsys.readouterr()
    first = tmp_path / "runs" / "run0000" / "results.h5"
    second = tmp_path / "runs" / "run0001" / "results.h5"
    with h5py.File(first, "r+") as f:
        f["meta"].attrs["status"] = "running"
    second.unlink()
    assert cp.main(["run", str(path)]) == 0
    err = capsys.readouterr().err
    assert "Traceback" not in err
    notices = sorted(l for l in err.splitlines() if l.startswith("raildyn campaign: run000"))
    assert len(notices) == 2, err
    assert str(first) in notices[0] and "incomplete" in notices[0] and "'running'" in notices[0]
    assert str(second) in notices[1] and "missing" in notices[1]
    with open(tmp_path / "runs" / "summary.csv") as f:
        damping_decay(list(csv.DictReader(f)), 400.0)


@pytest.mark.campaign_errors
def test_missing_channel_keeps_summary(tmp_path, raildyn_exe, capsys):
    path = make_campaign(tmp_path, raildyn_exe, channel="bodies/mass/position_trak:z")
    assert cp.main(["run", str(path)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "Traceback" not in err
    assert "metric 'decay'" in err and "bodies/mass/position_trak:z" in err
    assert "bodies/mass/position_track" in err          # a close name is suggested
    with open(tmp_path / "runs" / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["exit_code"] for r in rows] == ["0", "0"] and all(r["decay"] == "" for r in rows)
    # a damaged results file met by `summary`: a campaign error, the summary still written
    (tmp_path / "runs" / "run0000" / "results.h5").write_bytes(b"not hdf5")
    path.write_text(path.read_text().replace("position_trak", "position_track"))
    assert cp.main(["summary", str(path)]) == 1
    err = capsys.readouterr().err
    assert "run0000/results.h5: cannot read the results file" in err and "Traceback" not in err
    with open(tmp_path / "runs" / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["decay"] == "" and float(rows[1]["decay"]) < 0


@pytest.mark.campaign_errors
def test_failed_run_says_where_and_when(tmp_path, raildyn_exe):
    """The integrator gives up after 20 steps: the row gives the runner's message and the
    simulated time the results file reached; a deck error has its file:line and no time."""
    path = make_campaign(tmp_path, raildyn_exe, solver=", max_num_steps = 20")
    path.write_text(path.read_text().replace("[500.0, 1000.0]", "[-1.0, 1000.0]"))
    _, rows = run(path)
    bad_input, failed = rows
    assert bad_input["exit_code"] == "1" and "deck.nml" in bad_input["error"]
    assert "mass" in bad_input["error"] and bad_input["failed_at"] == ""
    assert failed["exit_code"] == "2" and "CV_TOO_MUCH_WORK" in failed["error"]
    with h5py.File(tmp_path / "runs" / "run0001" / "results.h5") as f:
        assert float(failed["failed_at"]) == f["meta"].attrs["end_time"] > 0
        assert f["meta"].attrs["status"].decode() == "failed: " + failed["error"]
    # the failed run's deck made invalid: its row gives the new error, not the results
    # file of the attempt before
    path.write_text(path.read_text().replace("[-1.0, 1000.0]", "[-1.0, -2.0]"))
    _, rows = run(path)
    assert rows[1]["exit_code"] == "1" and rows[1]["failed_at"] == ""
    assert "deck.nml" in rows[1]["error"] and "CV_TOO_MUCH_WORK" not in rows[1]["error"]


@pytest.mark.campaign_errors
@pytest.mark.parametrize("args", [[], ["frobnicate"], ["run"], ["run", "a.toml", "--jobs", "x"]])
def test_usage_errors_are_not_solver_failures(args, raildyn_exe, tmp_path):
    proc = subprocess.run([str(raildyn_exe), "campaign", *args], capture_output=True, text=True,
                          cwd=tmp_path)
    assert proc.returncode == 1, proc.stderr
    assert "usage:" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.campaign_errors
def test_ctrl_c_stops_cleanly_and_resumes(tmp_path, raildyn_exe):
    """SIGINT to the whole process group, as a terminal's Ctrl-C: one line, exit 130, the
    runs in flight are not recorded; running again completes them."""
    path = make_campaign(tmp_path, raildyn_exe, t_end=400.0)
    proc = subprocess.Popen([str(raildyn_exe), "campaign", "run", str(path)], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    deadline = time.time() + 60
    logs = [tmp_path / "runs" / f"run{i:04d}" / "results.h5" for i in range(2)]
    while not all(p.exists() for p in logs) and time.time() < deadline:
        time.sleep(0.1)
    assert all(p.exists() for p in logs), "the runs did not start"
    time.sleep(0.5)
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert err.strip() == "raildyn campaign: interrupted; rerun to resume"
    assert not any((p.parent / "status.json").exists() for p in logs)
    assert not (tmp_path / "runs" / "summary.csv").exists()
    path.write_text(path.read_text())
    (tmp_path / "base.nml").write_text(BASE.format(t_end=4.0, solver=""))
    states, rows = run(path)
    assert states == ["ok", "ok"]
    damping_decay(rows, 400.0)
