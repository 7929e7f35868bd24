"""The C API through the Python package: handles, stepping, outputs, inputs, errors
(issue: foundation, items 7 and 8)."""
from pathlib import Path

import numpy as np
import pytest

import raildyn

DECK_A = """&simulation title = 'A', t_end = 10.0, speed = 4.4 /
&output interval = 0.05 /
&segment type = 'straight', length = 50.0 /
&segment type = 'clothoid', length = 30.0, radius = 150.0, side = 'left', cant = 0.100 /
&segment type = 'curve', length = 60.0, radius = 150.0, side = 'left', cant = 0.100 /
"""
DECK_B = """&simulation title = 'B', t_end = 10.0, speed = 20.0 /
&output interval = 0.1 /
&segment type = 'straight', length = 100.0 /
&segment type = 'clothoid', length = 200.0, radius = 1000.0, side = 'right', cant = 0.050 /
&segment type = 'curve', length = 500.0, radius = 1000.0, side = 'right', cant = 0.050 /
"""


def test_two_models_do_not_interfere():
    a = raildyn.Model.from_string(DECK_A)
    b = raildyn.Model.from_string(DECK_B)
    a.initialize(write_output=False)
    b.initialize(write_output=False)
    for k in range(1, 21):
        a.advance(0.5 * k)
        b.advance(0.25 * k)
    assert a.time == pytest.approx(10.0) and b.time == pytest.approx(5.0)
    assert a.output("vehicle/distance")[0] == pytest.approx(44.0)
    assert b.output("vehicle/distance")[0] == pytest.approx(100.0)
    # a third model with A's deck alone gives the same as A interleaved with B
    c = raildyn.Model.from_string(DECK_A)
    c.initialize(write_output=False)
    c.advance(10.0)
    for name in c.outputs():
        assert np.array_equal(c.output(name), a.output(name)), name
    # B curves right: heading decreases, cant angle > 0 (left rail raised)
    b.advance(10.0)
    ang = b.output("track/frames/1/angles")
    assert ang[0] < 0 and ang[2] > 0
    for m in (a, b, c):
        m.close()


def test_chunks_equal_one_run(tmp_path):
    one = raildyn.Model.from_string(DECK_A)
    one.initialize(write_output=False)
    one.advance(7.3)
    many = raildyn.Model.from_string(DECK_A)
    many.initialize(write_output=False)
    for t in np.linspace(0.0, 7.3, 147)[1:]:
        many.advance(t)
    for name in one.outputs():
        assert np.allclose(one.output(name), many.output(name), rtol=0, atol=1e-12), name
    one.close()
    many.close()


def test_set_speed_input():
    m = raildyn.Model.from_string(DECK_A)
    m.initialize(write_output=False)
    m.advance(1.0)
    m.set_input("speed", [10.0])
    m.advance(2.0)
    assert m.output("vehicle/speed")[0] == pytest.approx(10.0)
    # the distance is continuous: 4.4 m in the first second, then the new speed (with the
    # ramp the speed law uses for an override, at most the new speed)
    d = m.output("vehicle/distance")[0]
    assert 4.4 + 4.4 < d <= 4.4 + 10.0 + 1e-9
    m.close()


def test_errors_are_reported_per_handle(tmp_path):
    with pytest.raises(raildyn.RaildynError) as e:
        raildyn.Model.from_string(DECK_A.replace("t_end", "t_ned"))
    assert "t_ned" in str(e.value) and e.value.status == 1
    m = raildyn.Model.from_string(DECK_A)
    with pytest.raises(raildyn.RaildynError) as e:
        m.advance(1.0)        # before initialize
    assert e.value.status == 6
    m.initialize(write_output=False)
    with pytest.raises(raildyn.RaildynError) as e:
        m.output("no/such/channel")
    assert "no/such/channel" in str(e.value)
    with pytest.raises(raildyn.RaildynError) as e:
        m.set_input("speed", [-1.0])
    assert "speed" in str(e.value) and e.value.status == 1
    m.advance(0.5)             # the handle still works after errors
    m.close()


def test_output_file_through_api(tmp_path, monkeypatch):
    """Without &output file the results go to the host's working directory."""
    monkeypatch.chdir(tmp_path)
    deck = tmp_path / "a.nml"
    deck.write_text(DECK_A)
    m = raildyn.Model.from_file(deck)
    m.initialize(write_output=True)
    m.advance(1.0)
    m.finalize()
    m.close()
    r = raildyn.Results(tmp_path / "a.h5")
    assert len(r.time) == 21
    assert r.metadata["status"] == "completed"


def test_version():
    m = raildyn.Model.from_string(DECK_A)
    assert m.version.count(".") == 2
    m.close()
