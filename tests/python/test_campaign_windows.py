"""Campaign metric windows along the track and metrics naming raildyn assess quantities
(raildyn.campaign): a speed sweep compares the same stretch of track; the quantity chosen
among several, what is taken of it, and that a windowed assessment sees only the window's rows
(raildyn.results_window), each against closed forms or the file itself."""
import csv
import math

import h5py
import numpy as np
import pytest

from raildyn import campaign as cp
from raildyn.results_window import write_rows
from test_campaign import BASE            # the damped spring-mass carried along the track
from test_run_safety_maxima import WHEELSET as WHEELSET_DECK   # an oscillating knife-edge wheelset

K, C, M, V0 = 4.0e5, 400.0, 1000.0, 0.1     # BASE's spring, damper, mass, initial rate

CAMPAIGN = """name = "{name}"
deck = "{deck}"
output = "runs"
jobs = 2
raildyn = "{{exe}}"
[sweep]
"simulation.speed" = {speeds}
{{metrics}}
"""


def metrics_toml(*metrics):
    """[[metrics]] tables from dicts (strings quoted, lists as TOML arrays)."""
    def value(v):
        return f'"{v}"' if isinstance(v, str) else str(list(v))
    return "".join("\n[[metrics]]\n" + "".join(f"{k} = {value(v)}\n" for k, v in m.items()) for m in metrics)


STRETCH_WINDOW = [9.999, 15.001]
STRETCH = metrics_toml(
    dict(name="first", channel="vehicle/distance", reduce="min", window_position=STRETCH_WINDOW),
    dict(name="last", channel="vehicle/distance", reduce="final", window_position=STRETCH_WINDOW),
    dict(name="z_at_15m", channel="bodies/mass/position_track:z", reduce="final", window_position=STRETCH_WINDOW),
    dict(name="z_at_1s", channel="bodies/mass/position_track:z", reduce="final", window=[0.5, 1.0]))


def oscillator_z(t):
    """z(t) of the damped mass released from rest position with velocity V0 (closed form)."""
    wn = math.sqrt(K / M)
    zeta = C / (2 * math.sqrt(K * M))
    wd = wn * math.sqrt(1 - zeta**2)
    return 1.0 + V0 / wd * math.exp(-zeta * wn * t) * math.sin(wd * t)


def write_campaign(tmp_path, build_dir, metrics):
    (tmp_path / "base.nml").write_text(BASE)
    path = tmp_path / "c.toml"
    path.write_text(CAMPAIGN.format(name="stretch", deck="base.nml", speeds="[5.0, 10.0]")
                    .format(exe=(build_dir / "bin" / "raildyn").resolve(), metrics=metrics))
    return path


def test_position_window_compares_the_same_stretch(tmp_path, build_dir):
    camp = cp.load_campaign(write_campaign(tmp_path, build_dir, STRETCH))
    assert camp.metrics[0].window_position == (9.999, 15.001) and camp.metrics[0].window is None
    with open(cp.run_campaign(camp, progress=lambda *_: None)) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2
    for row in rows:
        v = float(row["simulation.speed"])
        assert row["exit_code"] == "0", row
        # the same stretch whatever the speed: rows from 10 m to 15 m of track
        assert float(row["first"]) == pytest.approx(10.0, abs=1e-9)
        assert float(row["last"]) == pytest.approx(15.0, abs=1e-9)
        # the end of the stretch is reached at t = 15 m / V
        assert float(row["z_at_15m"]) == pytest.approx(oscillator_z(15.0 / v), abs=1e-7)
        assert float(row["z_at_1s"]) == pytest.approx(oscillator_z(1.0), abs=1e-7)
    assert float(rows[0]["z_at_15m"]) != pytest.approx(float(rows[1]["z_at_15m"]), abs=1e-4)


def test_an_empty_window_says_what_the_run_covered(tmp_path, build_dir):
    metrics = STRETCH.replace(f"window_position = {STRETCH_WINDOW}", "window_position = [100.0, 150.0]", 1)
    camp = cp.load_campaign(write_campaign(tmp_path, build_dir, metrics))
    with pytest.raises(cp.CampaignError) as e:
        cp.run_campaign(camp, progress=lambda *_: None)
    msg = str(e.value)
    assert "metric 'first'" in msg and "[100, 150] m" in msg and "covered 0 to 20 m" in msg, msg
    assert (camp.output / "summary.csv").exists()


@pytest.mark.parametrize("entry, words", [
    ('window = [1.0, 2.0]\nwindow_position = [1.0, 2.0]', "not both"),
    ('window_position = [2.0, 1.0]', "s_from < s_to"),
    ('window_position = [1.0]', "window_position must be"),
    ('quantity = "Y/Q"\nreduce = "max"', "not both"),
    ('quantity = "Y/Q"\ntake = "median"', "take must be one of"),
    ('wheelset = "w1"', "belong to quantity metrics"),
    ('windows = [1.0, 2.0]', "unknown entry 'windows'"),
])
def test_bad_metric_entries(tmp_path, build_dir, entry, words):
    channel = "" if "quantity" in entry else 'channel = "vehicle/distance"\nreduce = "max"\n'
    if "reduce" in entry:
        channel = ""
    text = f'\n[[metrics]]\nname = "m"\n{channel}{entry}\n'
    path = write_campaign(tmp_path, build_dir, text)
    with pytest.raises(cp.CampaignError) as e:
        cp.load_campaign(path)
    assert words in str(e.value) and "c.toml: metrics[0]" in str(e.value), str(e.value)


QUANTITIES = [
    {"name": "Y/Q", "wheelset": "w1", "side": "left", "value": 0.31, "limit": 0.8, "unit": "1",
     "position": 120.5, "margin": (0.8 - 0.31) / 0.8},
    {"name": "Y/Q", "wheelset": "w1", "side": "right", "value": 0.52, "limit": 0.8, "unit": "1",
     "position": 133.0, "margin": (0.8 - 0.52) / 0.8},
    {"name": "Y/Q", "wheelset": "w2", "side": "left", "value": 0.44, "limit": 0.8, "unit": "1",
     "position": 101.0, "margin": (0.8 - 0.44) / 0.8},
    {"name": "T_gamma", "wheelset": "w1", "side": "left", "patch": 1, "value": -75.0, "limit": None,
     "unit": "N", "position": 80.0, "margin": None},
    {"name": "T_gamma", "wheelset": "w1", "side": "left", "patch": 2, "value": 40.0, "limit": None,
     "unit": "N", "position": 90.0, "margin": None},
    {"name": "RCF_index", "wheelset": "w1", "side": "left", "value": -0.3, "limit": None, "unit": "1",
     "position": 70.0, "margin": None},
    {"name": "RCF_index", "wheelset": "w1", "side": "right", "value": 0.1, "limit": None, "unit": "1",
     "position": 75.0, "margin": None},
    {"name": "N_MV", "wheelset": None, "side": None, "value": None, "limit": None, "unit": "1",
     "position": None, "margin": None, "reason": "the file has no sensors"},
]


def quantity_metric(**entry):
    return cp._load_metric({"name": "m", **entry}, "test")


def test_quantity_metric_takes_the_worst_match(tmp_path):
    camp = cp.Campaign(path=tmp_path / "c.toml", name="c", deck=tmp_path / "d.nml", output=tmp_path)
    pick = lambda **e: cp.quantity_metric(camp, quantity_metric(**e), QUANTITIES, tmp_path / "r.h5")
    # several wheelsets and sides: the smallest margin
    assert pick(quantity="Y/Q") == 0.52
    assert pick(quantity="Y/Q", take="position") == 133.0
    assert pick(quantity="Y/Q", take="margin") == pytest.approx((0.8 - 0.52) / 0.8)
    assert pick(quantity="Y/Q", take="limit") == 0.8
    assert pick(quantity="Y/Q", wheelset="w2") == 0.44
    assert pick(quantity="Y/Q", wheelset="w1", side="left") == 0.31
    # no limit: the largest magnitude, signed as reported
    assert pick(quantity="T_gamma") == -75.0
    assert pick(quantity="T_gamma", patch=2, take="position") == 90.0
    # the RCF index FI_surf: the largest value, not magnitude (-0.3 is further below shakedown)
    assert pick(quantity="RCF_index") == 0.1
    for entry, words in ((dict(quantity="Q_max"), "has no quantity 'Q_max' for"), (dict(quantity="Q_max"), "; it has N_MV, RCF_index, T_gamma, Y/Q"),
                         (dict(quantity="Y/Q", wheelset="w3"), "there are Y/Q w1 left, Y/Q w1 right"),
                         (dict(quantity="N_MV"), "not available for") ,
                         (dict(quantity="N_MV"), "the file has no sensors"),
                         (dict(quantity="T_gamma", take="margin"), "has no margin")):
        with pytest.raises(cp.CampaignError) as e:
            pick(**entry)
        assert words in str(e.value) and "metric 'm'" in str(e.value), str(e.value)


def test_windowed_quantities_see_only_the_window(tmp_path, build_dir, monkeypatch):
    """The assessment of a windowed quantity metric gets a copy of the results holding
    exactly the window's rows (checked inside the stand-in assessment)."""
    metrics = metrics_toml(dict(name="whole", quantity="rows"),
                           dict(name="stretch", quantity="rows", window_position=STRETCH_WINDOW),
                           dict(name="stretch_start", quantity="rows", take="position",
                                window_position=STRETCH_WINDOW))
    seen = []

    def stand_in(path):
        with h5py.File(path, "r") as f:
            s = f["vehicle/distance"][:, 0]
            seen.append((len(f["time"]), f["meta"].attrs["n_steps"], s.min(), s.max()))
            for name in ("bodies/mass/position_track", "time"):
                assert f[name].shape[0] == len(s)
            assert f["meta"].attrs["status"] == b"completed"
        return [{"name": "rows", "wheelset": None, "side": None, "value": float(len(s)), "limit": None,
                 "unit": "1", "position": float(s.min()), "margin": None}]

    monkeypatch.setattr(cp, "_assessment_quantities", stand_in)
    camp = cp.load_campaign(write_campaign(tmp_path, build_dir, metrics))
    with open(cp.run_campaign(camp, progress=lambda *_: None)) as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        v = float(row["simulation.speed"])
        step = v * 0.002                          # m between rows
        assert float(row["whole"]) == 2001
        assert float(row["stretch"]) == round(5.0 / step) + 1
        assert float(row["stretch_start"]) == pytest.approx(10.0, abs=1e-9)
    # one assessment per window and run, never the whole file for a windowed metric
    assert len(seen) == 4
    assert sorted(n for n, *_ in seen) == [251, 501, 2001, 2001]
    assert all(n == n_steps for n, n_steps, *_ in seen)


def test_write_rows_keeps_the_layout(tmp_path, make_results_file):
    t = np.linspace(0.0, 1.0, 11)
    src = make_results_file("r.h5", t, {"vehicle/distance": (np.c_[10 * t], "m", "sigma", "d"),
                                        "bodies/b/position_track": (np.c_[t, 2 * t], "m m", "x y", "p")},
                            root_attrs={"title": "x"}, meta_attrs={"status": "completed", "n_steps": 11},
                            deck_text="&simulation t_end = 1.0 /")
    cut = write_rows(src, (t > 0.25) & (t < 0.75), tmp_path / "cut.h5")
    with h5py.File(cut, "r") as f:
        np.testing.assert_array_equal(f["time"][:], t[3:8])
        np.testing.assert_array_equal(f["bodies/b/position_track"][:], np.c_[t, 2 * t][3:8])
        assert f["bodies/b/position_track"].attrs["components"] == b"x y"
        assert f.attrs["title"] == b"x" and f["meta"].attrs["n_steps"] == 5
        assert f["meta/deck_text"][()] == b"&simulation t_end = 1.0 /"
    with pytest.raises(ValueError):
        write_rows(src, np.ones(4, bool), tmp_path / "bad.h5")


WHEELSET = WHEELSET_DECK.format(t_end=1.0, speed=20.0, y0=0.003, frozen="'x'", interval=0.005)
ASSESSED = metrics_toml(dict(name="yq", quantity="Y/Q"),
                        dict(name="yq_right_at", quantity="Y/Q", side="right", take="position"),
                        dict(name="sum_y_margin", quantity="sum_Y", wheelset="w1", take="margin"),
                        dict(name="yq_stretch", quantity="Y/Q", window_position=[2.0, 12.0]))


def test_quantity_metrics_from_raildyn_assess(tmp_path, build_dir):
    from raildyn.assess import assess
    (tmp_path / "ws.nml").write_text(WHEELSET)
    path = tmp_path / "a.toml"
    path.write_text(CAMPAIGN.format(name="assessed", deck="ws.nml", speeds="[15.0, 20.0]")
                    .format(exe=(build_dir / "bin" / "raildyn").resolve(), metrics=ASSESSED))
    camp = cp.load_campaign(path)
    with open(cp.run_campaign(camp, progress=lambda *_: None)) as f:
        rows = list(csv.DictReader(f))
    for i, row in enumerate(rows):
        results = camp.output / f"run{i:04d}" / "results.h5"
        a = assess(results)
        yq = [q for q in a.find("Y/Q") if q.value is not None]
        assert len(yq) == 2
        worst = min(yq, key=lambda q: q.margin)
        assert float(row["yq"]) == pytest.approx(worst.value, rel=1e-12)
        (right,) = a.find("Y/Q", side="right")
        assert float(row["yq_right_at"]) == pytest.approx(right.position, rel=1e-12)
        (sum_y,) = a.find("sum_Y", wheelset="w1")
        assert float(row["sum_y_margin"]) == pytest.approx(sum_y.margin, rel=1e-12)
        # the stretch: the assessment of the rows from 2 m to 12 m of track only
        with h5py.File(results, "r") as f:
            s = f["vehicle/distance"][:, 0]
        cut = write_rows(results, (s >= 2.0) & (s <= 12.0), tmp_path / f"cut{i}.h5")
        stretch = [q for q in assess(cut).find("Y/Q") if q.value is not None]
        assert float(row["yq_stretch"]) == pytest.approx(min(stretch, key=lambda q: q.margin).value, rel=1e-12)
        # its 2 m windows lie within the stretch: centres from 3 m to 11 m
        assert all(3.0 - 1e-9 <= q.position <= 11.0 + 1e-9 for q in stretch), [q.position for q in stretch]
