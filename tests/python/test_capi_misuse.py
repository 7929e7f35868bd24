"""A host program must survive any call of the C API (issue 13, items 9-11): calls after
failures, destroyed and foreign handles, NULL arguments, and failed runs recorded in their
results file exactly as the runner records them. Category: pytest -m capi_misuse.

Sequences that crashed the host before (a Fortran runtime error, a segfault) run in a child
process, so that a regression fails its test instead of killing the test session."""
import ctypes
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pytest

import raildyn
from raildyn.model import load_library

pytestmark = pytest.mark.capi_misuse

REPO = Path(__file__).resolve().parents[2]

RD_OK, RD_ERR_INPUT, RD_ERR_RUNTIME, RD_ERR_PHYSICS, RD_ERR_IO, RD_ERR_HANDLE = 0, 1, 2, 3, 4, 6

#: a damped mass on a spring, gravity on: the static preload solve sets the spring's preload
MASS = """&simulation title = 'mass', t_end = 2.0, speed = 10.0, gravity = 9.81,
            equilibrium = '{equilibrium}' /
&solver method = 'bdf', rtol = 1e-9, atol = 1e-12{solver} /
&output interval = 0.01{output} /
&body name = 'mass', mass = 1000.0, ixx = 10.0, iyy = 10.0, izz = 10.0,
      position = 0.0, 0.0, 1.0, velocity = 0.0, 0.0, 0.1, frozen = 'x', 'y', 'yaw', 'roll', 'pitch' /
{element}"""
SPRING = """&element name = 'spring', type = 'spring_damper', body1 = 'ground', body2 = 'mass',
      point1 = 0.0, 0.0, 1.0, stiffness = 0.0, 0.0, 4.0e5, damping = 0.0, 0.0, 400.0 /
"""


def mass_deck(equilibrium="preload", solver="", output="", element=SPRING):
    return MASS.format(equilibrium=equilibrium, solver=solver, output=output, element=element)


#: for code run by run_isolated: [status, message] of each call (0, '' when it succeeded)
OUTCOMES = """
import json, raildyn
def outcomes(*calls):
    seen = []
    for call in calls:
        try:
            call()
            seen.append([0, ''])
        except raildyn.RaildynError as e:
            seen.append([e.status, e.message])
    return seen
"""


def run_isolated(code: str, cwd) -> dict:
    """Run `code` (after OUTCOMES) in a fresh Python with the package importable, in the
    test's own directory `cwd` (string decks write their results there); it prints one JSON
    object."""
    env = dict(os.environ, PYTHONPATH=str(REPO / "python"))
    proc = subprocess.run([sys.executable, "-c", OUTCOMES + textwrap.dedent(code)], env=env,
                          capture_output=True, text=True, timeout=120, cwd=cwd)
    assert proc.returncode == 0, f"host process died (status {proc.returncode}):\n{proc.stderr}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


# ------------------------------------------------------------------ item 9
def test_initialize_again_after_unwritable_results_path(tmp_path):
    """A failed initialize leaves the model as loaded: calling it again fails the same way
    (no 'already allocated' crash), and once the folder exists it runs exactly like a fresh
    model of the same deck."""
    deck = tmp_path / "m.nml"
    deck.write_text(mass_deck(output=", file = 'missing/r.h5'"))
    result = run_isolated(f"""
        m = raildyn.Model.from_file({str(deck)!r})
        print(json.dumps(outcomes(*[lambda: m.initialize(write_output=True)] * 3)))
    """, tmp_path)
    assert [s for s, _ in result] == [RD_ERR_IO] * 3, result
    assert len({m for _, m in result}) == 1 and "missing/r.h5" in result[0][1], result

    with raildyn.Model.from_file(deck) as retried, raildyn.Model.from_file(deck) as fresh:
        with pytest.raises(raildyn.RaildynError) as e:
            retried.initialize(write_output=True)
        assert e.value.status == RD_ERR_IO
        (tmp_path / "missing").mkdir()
        retried.initialize(write_output=True)
        retried.advance(0.5)
        fresh.initialize(write_output=False)
        fresh.advance(0.5)
        assert retried.time == fresh.time == pytest.approx(0.5)
        assert np.array_equal(retried.state(), fresh.state())
        retried.finalize()
    r = raildyn.Results(tmp_path / "missing" / "r.h5")
    assert r.metadata["status"] == "completed" and len(r.time) == 51


def test_initialize_again_after_failed_equilibrium(tmp_path):
    """A static preload solve that cannot succeed (no element to carry the mass): every
    initialize returns the same input error, and the other calls answer with a status."""
    result = run_isolated(f"""
        m = raildyn.Model.from_string({mass_deck(element='')!r})
        out = outcomes(*[lambda: m.initialize(write_output=False)] * 3, lambda: m.advance(1.0))
        out.append([0, str(m.time)])
        m.close()
        print(json.dumps(out))
    """, tmp_path)
    statuses = [s for s, _ in result]
    assert statuses[:3] == [RD_ERR_INPUT] * 3, result
    assert "preload" in result[0][1] and result[0][1] == result[1][1] == result[2][1]
    assert statuses[3] == RD_ERR_HANDLE and "before initialize" in result[3][1]
    assert result[4] == [0, "0.0"]


# ------------------------------------------------------------------ item 10
def test_destroyed_handle_stays_invalid():
    """Create and destroy many models: every handle is new, and a destroyed handle is
    refused (with a message saying so) even when the next model reuses the memory; destroying
    it again does not destroy the live model."""
    lib = load_library()
    deck = b"&simulation t_end = 1.0, speed = 10.0 /\n&segment type = 'straight', length = 100.0 /\n"
    seen = []
    for _ in range(50):
        h = ctypes.c_int64()
        assert lib.rd_create_from_string(deck, None, ctypes.byref(h)) == RD_OK
        seen.append(h.value)
        assert lib.rd_destroy(h) == RD_OK
    assert len(set(seen)) == len(seen) and 0 not in seen
    live = ctypes.c_int64()
    assert lib.rd_create_from_string(deck, None, ctypes.byref(live)) == RD_OK
    assert live.value not in seen
    t = ctypes.c_double()
    buffer = ctypes.create_string_buffer(512)
    for old in seen:
        assert lib.rd_get_time(old, ctypes.byref(t)) == RD_ERR_HANDLE
        assert lib.rd_initialize(old, 0) == RD_ERR_HANDLE
        assert lib.rd_destroy(old) == RD_ERR_HANDLE
        assert lib.rd_error_message(old, buffer, 512) == RD_ERR_HANDLE
        assert b"destroyed" in buffer.value
    for never in (0, -1, 2**62):
        assert lib.rd_get_time(never, ctypes.byref(t)) == RD_ERR_HANDLE
        assert lib.rd_error_message(never, buffer, 512) == RD_ERR_HANDLE
        assert b"no model was created" in buffer.value
    # the live model is untouched by all of that
    assert lib.rd_initialize(live, 0) == RD_OK
    assert lib.rd_advance(live, 1.0) == RD_OK
    assert lib.rd_get_time(live, ctypes.byref(t)) == RD_OK and t.value == pytest.approx(1.0)
    assert lib.rd_destroy(live) == RD_OK
    assert lib.rd_destroy(live) == RD_ERR_HANDLE


def test_null_arguments_return_a_status(tmp_path):
    """Every pointer argument of raildyn.h given as NULL: an input error with a message
    naming the argument, never a segfault; NULL arrays are accepted for size 0 only."""
    result = run_isolated("""
        import ctypes
        from raildyn.model import load_library
        lib = load_library()
        deck = b"&simulation t_end = 1.0, speed = 10.0 /\\n&segment type = 'straight', length = 100.0 /\\n"
        out = {}
        def message(h):
            buf = ctypes.create_string_buffer(512)
            lib.rd_error_message(h, buf, 512)
            return buf.value.decode()
        out['create_file_handle'] = [lib.rd_create_from_file(b'x.nml', None), '']
        out['create_string_handle'] = [lib.rd_create_from_string(deck, None, None), '']
        h = ctypes.c_int64()
        s = lib.rd_create_from_file(None, ctypes.byref(h))
        out['create_file_path'] = [s, message(h)]
        lib.rd_destroy(h)
        s = lib.rd_create_from_string(None, None, ctypes.byref(h))
        out['create_string_text'] = [s, message(h)]
        lib.rd_destroy(h)
        assert lib.rd_create_from_string(deck, None, ctypes.byref(h)) == 0
        assert lib.rd_initialize(h, 0) == 0
        calls = {
            'get_time': lambda: lib.rd_get_time(h, None),
            'get_state_size': lambda: lib.rd_get_state_size(h, None),
            'output_count': lambda: lib.rd_output_count(h, None),
            'output_name': lambda: lib.rd_output_name(h, 1, None, 64),
            'output_name_len': lambda: lib.rd_output_name(h, 1, ctypes.create_string_buffer(8), 0),
            'output_size_name': lambda: lib.rd_output_size(h, None, ctypes.byref(ctypes.c_int())),
            'output_size_size': lambda: lib.rd_output_size(h, b'vehicle/speed', None),
            'get_output_name': lambda: lib.rd_get_output(h, None, None, 0),
            'get_output_values': lambda: lib.rd_get_output(h, b'vehicle/speed', None, 1),
            'set_input_name': lambda: lib.rd_set_input(h, None, None, 0),
            'set_input_values': lambda: lib.rd_set_input(h, b'speed', None, 1),
            'get_state_negative': lambda: lib.rd_get_state(h, None, -1),
            'linearize_matrix': lambda: lib.rd_linearize(h, None, 4),
            'run_notes': lambda: lib.rd_run_notes(h, None, 64),
        }
        for name, call in calls.items():
            out[name] = [call(), message(h)]
        # reading the message with a NULL buffer fails without replacing the message
        out['error_message'] = [lib.rd_error_message(h, None, 64), message(h)]
        # a NULL array of size 0 is an empty array: the track-only scene has no state
        out['get_state_empty'] = [lib.rd_get_state(h, None, 0), '']
        t = ctypes.c_double()
        out['still_works'] = [lib.rd_advance(h, 0.5) or lib.rd_get_time(h, ctypes.byref(t)), str(t.value)]
        lib.rd_destroy(h)
        print(json.dumps(out))
    """, tmp_path)
    words = {"create_file_path": "deck_path", "create_string_text": "deck_text", "get_time": "time",
             "get_state_size": "size", "output_count": "count", "output_name": "name",
             "output_name_len": "name_len", "output_size_name": "name", "output_size_size": "size",
             "get_output_name": "name", "get_output_values": "values", "set_input_name": "name",
             "set_input_values": "values", "get_state_negative": "size", "run_notes": "notes",
             "linearize_matrix": "matrix"}
    for name, word in words.items():
        status, message = result[name]
        assert status == RD_ERR_INPUT, (name, result[name])
        assert word in message and ("NULL" in message or ">=" in message), (name, message)
    assert result["create_file_handle"][0] == RD_ERR_INPUT
    assert result["create_string_handle"][0] == RD_ERR_INPUT
    assert result["error_message"] == [RD_ERR_INPUT, result["run_notes"][1]]
    assert result["get_state_empty"][0] == RD_OK
    assert result["still_works"] == [RD_OK, "0.5"]


def test_header_documents_null_and_handles():
    header = (REPO / "src" / "c_api" / "raildyn.h").read_text()
    assert "NULL" in header and "RD_ERR_INPUT" in header
    assert "destroyed" in header


# ------------------------------------------------------------------ item 11
def test_failed_run_recorded_like_the_runner(tmp_path, raildyn_exe):
    """A run that fails through the C API: the results file says 'failed: <message>' with
    the message the call returned, the same status and rows as `raildyn run` writes for the
    deck; later stepping calls are refused with a message that names no call the C API does
    not have, queries still answer."""
    deck = tmp_path / "f.nml"
    deck.write_text(mass_deck(equilibrium="none", solver=", max_num_steps = 20",
                              output=", interval = 0.5, file = 'api.h5'"))
    with raildyn.Model.from_file(deck) as m:
        m.initialize()
        with pytest.raises(raildyn.RaildynError) as e:
            m.advance(2.0)
        failure = e.value
        assert failure.status == RD_ERR_RUNTIME
        t_failed = m.time
        assert 0 < t_failed < 0.5
        for call in (lambda: m.advance(2.0), lambda: m.set_input("speed", 5.0),
                     lambda: m.initialize()):
            with pytest.raises(raildyn.RaildynError) as again:
                call()
            assert again.value.status == RD_ERR_HANDLE
            assert failure.message in again.value.message
            assert "reinit" not in again.value.message and "new model" in again.value.message
        assert m.output("vehicle/distance")[0] == pytest.approx(10.0 * t_failed)
        m.finalize()            # nothing left to close: the failure is already recorded
    proc = subprocess.run([str(raildyn_exe), "run", str(deck), "-o", str(tmp_path / "runner.h5")],
                          capture_output=True, text=True)
    assert proc.returncode == RD_ERR_RUNTIME
    assert proc.stderr.strip() == f"raildyn: error: {failure.message}"
    with h5py.File(tmp_path / "api.h5") as api, h5py.File(tmp_path / "runner.h5") as runner:
        status = api["meta"].attrs["status"].decode()
        assert status == f"failed: {failure.message}"
        assert status == runner["meta"].attrs["status"].decode()
        assert api["meta"].attrs["end_time"] == runner["meta"].attrs["end_time"] == t_failed
        assert np.array_equal(api["bodies/mass/position_track"][:],
                              runner["bodies/mass/position_track"][:])



def test_failed_start_recorded_like_the_runner(tmp_path, raildyn_exe):
    """A run whose first outputs fail (a wheel 10 mm above its rail at t = 0, beyond the
    lift-off limit of 5 mm: the output evaluation's error is not dropped) fails its start
    through the C API and the runner alike: physics limit (status / exit 3), the same
    message, a results file saying 'failed: <message>' at end time 0 and holding no row."""
    deck = tmp_path / "lifted.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'tgv_wheelset.nml'}' /\n"
                    "&simulation t_end = 0.01 /\n&output file = 'api.h5' /\n"
                    "&body name = 'ws1', position(3) = 0.46 /\n")
    with raildyn.Model.from_file(deck) as m:
        with pytest.raises(raildyn.RaildynError) as e:
            m.initialize()
    failure = e.value
    assert failure.status == RD_ERR_PHYSICS and "lift-off" in failure.message
    proc = subprocess.run([str(raildyn_exe), "run", str(deck), "-o", str(tmp_path / "runner.h5")],
                          capture_output=True, text=True)
    assert proc.returncode == RD_ERR_PHYSICS
    assert proc.stderr.strip().splitlines()[-1] == f"raildyn: error: {failure.message}"
    with h5py.File(tmp_path / "api.h5") as api, h5py.File(tmp_path / "runner.h5") as runner:
        for f in (api, runner):
            assert f["meta"].attrs["status"].decode() == f"failed: {failure.message}"
            assert f["meta"].attrs["end_time"] == 0.0
            assert len(f["time"]) == 0


def test_destroyed_before_t_end_reads_stopped(tmp_path):
    """A host that leaves a run (an exception in its own code) before the deck's t_end
    without finalize: the file says 'stopped', not 'completed'; at t_end it says
    'completed' with or without finalize."""
    deck = tmp_path / "s.nml"
    deck.write_text(mass_deck(equilibrium="none", output=", file = 'half.h5'"))
    with pytest.raises(ZeroDivisionError):
        with raildyn.Model.from_file(deck) as m:
            m.initialize()
            m.advance(1.0)                 # t_end = 2 s
            1 / 0
    (tmp_path / "full.nml").write_text(deck.read_text().replace("half.h5", "full.h5"))
    with raildyn.Model.from_file(tmp_path / "full.nml") as m:
        m.initialize()
        m.advance(2.0)
    for name, status, rows in (("half.h5", "stopped", 101), ("full.h5", "completed", 201)):
        r = raildyn.Results(tmp_path / name)
        assert r.metadata["status"] == status and len(r.time) == rows, name


def test_calculators_null_arguments(tmp_path):
    """raildyn_calculators.h: each pointer argument NULL in turn gives status 1, the same
    call with every pointer given succeeds."""
    result = run_isolated("""
        import ctypes
        from raildyn.model import find_library
        lib = ctypes.CDLL(find_library())
        d, i, p = ctypes.c_double, ctypes.c_int, ctypes.c_void_p
        lib.rd_hertz_patch.argtypes = [p, d, d, i, d, p, p, p, p, p, p, p]
        lib.rd_creep_forces.argtypes = [p, d, d, d, d, d, d, d, d, d, i, p, p, p]
        curv = (d * 4)(2.0, 0.0, 0.0, 1.0 / 0.3)
        warning = ctypes.c_int()
        hertz = [curv, *[ctypes.byref(d()) for _ in range(6)], ctypes.byref(warning)]
        law = ctypes.create_string_buffer(b"fastsim")
        creep = [law, *[ctypes.byref(d()) for _ in range(3)]]
        def call_hertz(ptrs):
            return lib.rd_hertz_patch(ctypes.cast(ptrs[0], p), 2.1e11, 0.28, 0, 1e5,
                                      *[ctypes.cast(x, p) for x in ptrs[1:]])
        def call_creep(ptrs):
            return lib.rd_creep_forces(ctypes.cast(ptrs[0], p), 6e-3, 4e-3, 1e5, 8.2e10, 0.28, 0.3,
                                       1e-3, 0.0, 0.0, 10, *[ctypes.cast(x, p) for x in ptrs[1:]])
        out = {"hertz_ok": call_hertz(hertz), "creep_ok": call_creep(creep),
               "hertz_null": [call_hertz(hertz[:k] + [None] + hertz[k + 1:]) for k in range(len(hertz))],
               "creep_null": [call_creep(creep[:k] + [None] + creep[k + 1:]) for k in range(len(creep))]}
        print(json.dumps(out))
    """, tmp_path)
    assert result["hertz_ok"] == 0 and result["creep_ok"] == 0
    assert result["hertz_null"] == [RD_ERR_INPUT] * 8
    assert result["creep_null"] == [RD_ERR_INPUT] * 4


def test_random_call_sequences_never_kill_the_host(tmp_path):
    """Fuzz: 1500 calls drawn at random (seeded) from the whole API, on live, failed,
    finalized, destroyed and made-up handles, with bad times, names, sizes and NULLs. The
    host survives, every status is one of raildyn.h's, a failing call leaves a message, and
    a successful advance reaches its target."""
    decks = [mass_deck(equilibrium="none"), mass_deck(element=""),          # runs / cannot start
             mass_deck(equilibrium="none", solver=", max_num_steps = 20"),  # fails in advance
             mass_deck(output=f", file = '{tmp_path}/fuzz.h5'"), "&simulation t_ned = 1 /\n"]
    result = run_isolated(f"""
        import ctypes, math, random
        from raildyn.model import load_library
        lib = load_library()
        rng = random.Random(20261125)
        decks = {[d.encode() for d in decks]!r}
        handles, issued = [], []
        statuses, problems = {{}}, []
        def message(h):
            buf = ctypes.create_string_buffer(1024)
            lib.rd_error_message(h, buf, 1024)
            return buf.value
        def pick():
            roll = rng.random()
            if handles and roll < 0.7:
                return rng.choice(handles)
            if issued and roll < 0.9:
                return rng.choice(issued)
            return rng.choice([0, -5, 2**40, rng.randrange(1, 1000)])
        def doubles(n):
            return (ctypes.c_double * max(n, 1))(*[rng.uniform(-1e3, 1e3)] * max(n, 1))
        for step in range(1500):
            what = rng.choices(["create", "initialize", "advance", "time", "state", "outputs",
                                "input", "finalize", "destroy", "notes"],
                               weights=[2, 4, 8, 1, 1, 2, 2, 1, 1, 1])[0]
            h = pick()
            if what == "create":
                out = ctypes.c_int64()
                s = lib.rd_create_from_string(rng.choice(decks + [None]), None,
                                              ctypes.byref(out) if rng.random() < 0.95 else None)
                if out.value:
                    handles.append(out.value); issued.append(out.value)
                h = out.value      # 0: no handle made (NULL handle argument), no message
            elif what == "initialize":
                s = lib.rd_initialize(h, rng.choice([0, 1]))
            elif what == "advance":
                t = ctypes.c_double()
                before = lib.rd_get_time(h, ctypes.byref(t))
                target = rng.choice([t.value + rng.uniform(0, 0.3), t.value - 1.0, math.nan, math.inf])
                s = lib.rd_advance(h, target)
                if s == 0 and (lib.rd_get_time(h, ctypes.byref(t)) != 0 or abs(t.value - target) > 1e-9):
                    problems.append(f"advance to {{target}} reached {{t.value}}")
            elif what == "time":
                t = ctypes.c_double()
                s = lib.rd_get_time(h, ctypes.byref(t) if rng.random() < 0.8 else None)
            elif what == "state":
                n = ctypes.c_int()
                lib.rd_get_state_size(h, ctypes.byref(n))
                size = n.value + rng.choice([0, 0, 1, -1, -n.value - 3])
                s = lib.rd_get_state(h, doubles(size) if rng.random() < 0.9 else None, size)
            elif what == "outputs":
                n = ctypes.c_int()
                lib.rd_output_count(h, ctypes.byref(n))
                index = rng.randrange(-1, n.value + 2)
                name = ctypes.create_string_buffer(256)
                s = lib.rd_output_name(h, index, name, rng.choice([256, 1, 0]))
                key = name.value if s == 0 and name.value else rng.choice([b"vehicle/speed", b"x", None])
                size = ctypes.c_int()
                lib.rd_output_size(h, key, ctypes.byref(size))
                s = lib.rd_get_output(h, key, doubles(size.value), size.value + rng.choice([0, 0, 1]))
            elif what == "input":
                key = rng.choice([b"speed", b"body/mass/external_force", b"body/none/external_force",
                                  b"nonsense", None])
                size = rng.choice([1, 6, 0, -2])
                s = lib.rd_set_input(h, key, doubles(size), size)
            elif what == "finalize":
                s = lib.rd_finalize(h)
            elif what == "destroy":
                s = lib.rd_destroy(h)
                if s == 0:
                    handles.remove(h)
            else:
                s = lib.rd_run_notes(h, ctypes.create_string_buffer(64), 64)
            statuses[what + ":" + str(s)] = statuses.get(what + ":" + str(s), 0) + 1
            if s not in range(7):
                problems.append(f"{{what}} returned {{s}}")
            if s != 0 and h != 0 and not message(h):
                problems.append(f"{{what}} failed with status {{s}} and no message")
        for h in handles:
            lib.rd_destroy(h)
        print(json.dumps({{"statuses": statuses, "problems": problems}}))
    """, tmp_path)
    assert result["problems"] == []
    seen = result["statuses"]
    # the sequence exercised successes and every kind of refusal
    for key in ("initialize:0", "advance:0", "advance:1", "advance:2", "advance:6", "create:1",
                "destroy:0", "destroy:6", "input:1", "time:1"):
        assert seen.get(key, 0) > 0, (key, seen)
