"""The runner's completion summary names wheels that lost contact: a wheelset dropped onto the
rails is in flight for t_f = sqrt(2 h / g) (closed form), so exactly the output samples before
t_f are without contact; a wheelset that never leaves the rails gets no note. The results
file keeps the notes (/meta attribute 'notes') and the validation harness carries them into its
case notes (the HTML report), for reused results too."""
import re
import subprocess

import pytest

from raildyn import Results, validation as V

G = 9.80665            # standard gravity of the model (docs/conventions.md)
R0 = 0.45              # nominal radius: knife-edge contact when the centre is R0 above the rail

DECK = """&simulation title = 'drop', t_end = {t_end}, speed = 0.0, equilibrium = 'none' /
&solver method = 'bdf', rtol = 1e-8, atol = 1e-12, max_step = 1e-5 /
&output interval = {interval} /
&segment type = 'straight', length = 100.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, {z0!r}, frozen = 'x', 'y', 'yaw', 'roll' /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = {r0},
      contact_distance = 1.5, conicity = 0.05, creep_law = 'linear',
      shear_modulus = 8.4e10, poisson = 0.25 {extra} /
"""


def run(exe, tmp_path, **kw):
    deck = tmp_path / "drop.nml"
    deck.write_text(DECK.format(r0=R0, extra="", **kw))
    res = subprocess.run([exe, "run", deck, "-o", tmp_path / "drop.h5"], capture_output=True,
                         text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    return res.stdout


def test_dropped_wheelset_is_reported_without_contact_until_it_lands(raildyn_exe, tmp_path):
    t_flight, interval, t_end = 9.95e-3, 1e-4, 10.5e-3    # lands between two samples
    out = run(raildyn_exe, tmp_path, t_end=t_end, interval=interval,
              z0=R0 + 0.5 * G * t_flight ** 2)
    n = round(t_end / interval) + 1
    expected = 100.0 * sum(1 for k in range(n) if k * interval < t_flight) / n
    for side in ("left", "right"):
        m = re.search(rf"note: wheelset w1 {side} wheel without contact in ([0-9.]+) % of (\d+) "
                      r"output samples \(largest sampled Q ([0-9.]+) kN\)", out)
        assert m, out
        assert int(m.group(2)) == n
        assert float(m.group(1)) == pytest.approx(expected, abs=0.05)
        assert float(m.group(3)) > 0        # it has landed by the last sample


def test_no_note_while_the_wheels_stay_on_the_rails(raildyn_exe, tmp_path):
    out = run(raildyn_exe, tmp_path, t_end=2e-3, interval=1e-4, z0=R0 + 1e-3)
    assert "without contact in 100.0 % of 21 output samples" in out   # in flight all along
    # on the rails: started 10 um into them, less than its static approach under its weight
    # (about 17 um), it oscillates between 10 and 25 um without leaving them: no note at all
    deck = tmp_path / "rest.nml"
    deck.write_text(DECK.format(r0=R0, t_end=0.05, interval=1e-3, z0=R0 - 1.0e-5, extra=""))
    res = subprocess.run([raildyn_exe, "run", deck, "-o", tmp_path / "rest.h5"], capture_output=True,
                         text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert "completed" in res.stdout and "note:" not in res.stdout, res.stdout


def test_the_results_file_and_the_harness_keep_the_notes(raildyn_exe, tmp_path):
    """The notes the runner prints are kept in the results file (/meta attribute 'notes'), so
    the validation harness reports them for reused results too; a run without notes has no
    attribute."""
    import h5py
    deck = tmp_path / "drop.nml"
    deck.write_text(DECK.format(r0=R0, t_end=2e-3, interval=1e-4, z0=R0 + 1e-3, extra=""))
    info = V.run_deck(deck, tmp_path / "drop.h5", raildyn_exe)
    printed = [line[len("note: "):] for line in info.stdout.splitlines() if line.startswith("note: ")]
    with h5py.File(info.results, "r") as f:
        kept = f["meta"].attrs["notes"]
        kept = (kept.decode() if isinstance(kept, bytes) else str(kept)).split("\n")
    assert kept == printed and len(kept) == 2
    notes = V.run_notes(Results(info.results).metadata)
    assert notes == printed
    assert [n.split(" wheel ")[0] for n in notes] == ["wheelset w1 left", "wheelset w1 right"]
    assert all("without contact in 100.0 % of 21 output samples" in n for n in notes)
    deck.write_text(DECK.format(r0=R0, t_end=0.05, interval=1e-3, z0=R0 - 1.0e-5, extra=""))
    info = V.run_deck(deck, tmp_path / "rest.h5", raildyn_exe)
    with h5py.File(info.results, "r") as f:
        assert "notes" not in f["meta"].attrs
    assert V.run_notes(Results(info.results).metadata) == []


def test_the_c_api_gives_the_same_notes(raildyn_exe, tmp_path):
    """rd_run_notes (Model.run_notes) while stepping: none before the first sample without
    contact, then the lines the runner prints for the same deck at the end."""
    import raildyn
    text = DECK.format(r0=R0, t_end=2e-3, interval=1e-4, z0=R0 + 1e-3, extra="")
    deck = tmp_path / "drop.nml"
    deck.write_text(text)
    printed = [line[len("note: "):] for line in run(raildyn_exe, tmp_path, t_end=2e-3, interval=1e-4,
                                                        z0=R0 + 1e-3).splitlines()
               if line.startswith("note: ")]
    with raildyn.Model.from_string(text, tmp_path) as m:
        m.initialize(write_output=False)
        assert len(m.run_notes()) == 2          # step 0 is already a sample in flight
        m.advance(1e-3)
        assert all("100.0 % of 11 output samples" in n for n in m.run_notes())
        m.advance(2e-3)
        assert m.run_notes() == printed and len(printed) == 2


def test_a_share_that_rounds_to_zero_reads_below_a_tenth(raildyn_exe, tmp_path):
    """Dropped from 0.1 nm it lands within the first output interval: one of 2001 samples
    (0.05 %) is without contact. The note says '< 0.1 %', not '.0 %' or '0.0 %'."""
    t_flight, interval, t_end = 5e-6, 1e-5, 0.02
    out = run(raildyn_exe, tmp_path, t_end=t_end, interval=interval, z0=R0 + 0.5 * G * t_flight ** 2)
    for side in ("left", "right"):
        assert f"wheelset w1 {side} wheel without contact in < 0.1 % of 2001 output samples" in out, out
    assert " .0 %" not in out and " 0.0 %" not in out
