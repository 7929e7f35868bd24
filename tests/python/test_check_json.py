"""`raildyn check DECK --json` gives the deck as the runner reads it, which the validation
harness uses instead of reading decks itself: "decks" (the deck and its includes in reading
order, not the files parameters name) and "groups" (every group, overrides of a later file
merged, defaults applied). Compared with the values written in a deck and its include, with
the defaults docs/input_reference.md states, and with the files the deck names."""
import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from raildyn.irregularity import write_irregularity

REPO = Path(__file__).resolve().parents[2]

BASE = """! the base deck, included by the top deck
&simulation title = 'json base', t_end = 0.5, speed = 10.0, equilibrium = 'none' /
&solver method = 'bdf', rtol = 1e-9, atol = 1e-12 /
&output interval = 0.01 /
&track irregularity_file = '../irr/rec.txt', irregularity_fade = 5.0 /
&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 20.0, izz = 30.0,
      position = 0.0, 0.0, 1.0, frozen = 'x', 'y', 'yaw' /
&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass',
      point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, 400.0 /
"""

TOP = """! the top deck: the base with two overrides
&include file = 'sub/base.nml' /
&body name = 'mass', mass = 1250.5 /
&simulation speed = 12.25 /
"""


def check_json(exe, deck):
    res = subprocess.run([str(exe), "check", str(deck), "--json"], capture_output=True, text=True, timeout=120)
    return res.returncode, json.loads(res.stdout)


def documented_defaults(group):
    """parameter -> default column of the group's table in docs/input_reference.md."""
    text = (REPO / "docs" / "input_reference.md").read_text()
    table = text.split(f"### &{group}\n", 1)[1].split("\n### ", 1)[0]
    return {m.group(1): m.group(2).strip() for m in re.finditer(r"^\| `(\w+)` \| [^|]+ \| [^|]+ \| ([^|]+) \|",
                                                                 table, re.M)}


@pytest.fixture
def decks(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "irr").mkdir()
    write_irregularity(tmp_path / "irr" / "rec.txt", np.array([0.0, 1000.0]), alignment=np.array([1e-3, 1e-3]))
    (tmp_path / "sub" / "base.nml").write_text(BASE)
    (tmp_path / "top.nml").write_text(TOP)
    return tmp_path


def test_groups_are_the_decks_values(raildyn_exe, decks):
    code, answer = check_json(raildyn_exe, decks / "top.nml")
    assert code == 0 and answer["status"] == "ok", answer["message"]
    groups = answer["groups"]
    (body,) = groups["body"]                      # the override merged into the base's body
    assert body["name"] == "mass" and body["mass"] == 1250.5
    assert (body["ixx"], body["iyy"], body["izz"]) == (10.0, 20.0, 30.0)
    assert body["position"] == [0.0, 0.0, 1.0] and body["frozen"] == ["x", "y", "yaw"]
    (sim,) = groups["simulation"]
    assert sim["speed"] == 12.25 and sim["t_end"] == 0.5 and sim["title"] == "json base"
    assert sim["equilibrium"] == "none"
    (element,) = groups["element"]
    assert element["stiffness"] == [0.0, 0.0, 4.0e5] and element["damping"] == [0.0, 0.0, 400.0]
    assert (element["body1"], element["body2"], element["type"]) == ("ground", "mass", "spring_damper")
    assert groups["solver"][0]["rtol"] == 1e-9 and groups["output"][0]["interval"] == 0.01
    # the file a parameter names, resolved against the deck naming it (sub/), is an input file,
    # not a deck
    (track,) = groups["track"]
    assert Path(track["irregularity_file"]).resolve() == (decks / "irr" / "rec.txt").resolve()
    assert [Path(p).resolve() for p in answer["decks"]] == [(decks / "top.nml").resolve(),
                                                           (decks / "sub" / "base.nml").resolve()]
    assert [Path(p).resolve() for p in answer["input_files"]] == [
        Path(p).resolve() for p in answer["decks"]] + [(decks / "irr" / "rec.txt").resolve()]
    # what the deck leaves out has the documented default; optional values not given are null
    defaults = documented_defaults("simulation")
    assert sim["gravity"] == float(defaults["gravity"]) == 9.80665
    assert sim["start_sigma"] == float(defaults["start_sigma"]) == 0.0
    assert defaults["speed_times"] == "none" and sim["speed_times"] is None
    assert set(sim) == set(defaults)             # every parameter of the group, nothing else
    assert set(groups) == {"include", "simulation", "solver", "output", "track", "body", "element"}
    assert Path(groups["include"][0]["file"]).resolve() == (decks / "sub" / "base.nml").resolve()


def test_a_deck_that_does_not_read_has_no_groups(raildyn_exe, decks):
    (decks / "bad.nml").write_text(TOP + "&body name = 'mass', mass = -1.0 /\n")
    code, answer = check_json(raildyn_exe, decks / "bad.nml")
    assert code == 1 and answer["status"] == "error" and "mass" in answer["message"]
    assert answer["decks"] == [] and answer["groups"] == {}


def test_harness_reads_decks_through_check(raildyn_exe):
    """The validation harness's deck questions answered by the runner: includes and wheelsets."""
    from raildyn import validation as V
    names = [p.name for p in V.deck_files(V.INPUTS / "tgv_bogie_straight_20.nml")]
    assert names[0] == "tgv_bogie_straight_20.nml" and "tgv001_bogie.nml" in names
    assert "tgv_designed_track.nml" in names and not any(n.endswith((".prw", ".prr", ".txt")) for n in names)
    assert V.deck_wheelsets(V.INPUTS / "tgv_bogie_straight_20.nml") == ["w1", "w2"]
    assert V.deck_wheelsets(V.INPUTS / "manchester_v1_tc1.nml") == ["w1", "w2", "w3", "w4"]
