"""Parameters that only some kinds of a group read (issue 13 item 7; category inputs_unused).

A parameter written for a kind that does not read it (attachment points on a torsion
element, FASTSIM options with the Polach law, rtol with the fixed-step rk4, a frame offset on
a body that shares another body's frame, ...) was silently ignored. Now `raildyn check` and
`raildyn run` both refuse it at its deck line, naming the group, the parameter, the value
that excludes it and the kinds that read it; the same parameter for a kind that reads it is
accepted.

READ_BY below is written from the source (which code reads which parameter: rd_scene_vehicle
build_element / build_wheelset_specs / build_bodies, rd_scene build_mechanics and the
integrator, rd_scene_track, rd_track), not from the schema; the test also requires the
reference (docs/input_reference.md) to state the same kinds. An override in a later file
that changes the kind (a scene switching its vehicle's contact model) is a warning naming
both places, not an error.
"""
import os
import re
import subprocess
from pathlib import Path

import pytest

from test_inputs_fuzz import FORBIDDEN, error_lines

REPO = Path(__file__).resolve().parents[2]

# One knife-edge wheelset body and a second body; one group per line, so a parameter's line is
# its group's line. {wheelset}, {element}, {solver}, {track}, {segments}, {body2} are filled in.
DECK = """&simulation t_end = 0.002, speed = 20.0, equilibrium = 'none' /
&output interval = 0.001 /
&solver {solver} /
&track {track} /
{segments}
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35, position = 0.0, 0.0, 0.45 /
&body name = 'frame', mass = 2000.0, ixx = 900.0, iyy = 1000.0, izz = 1200.0, position = 0.0, 0.0, 0.9{body2} /
&wheelset name = 'w1', body = 'ws1'{wheelset} /
&element name = 'k', body1 = 'ws1', body2 = 'frame'{element} /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""
STRAIGHT = "&segment type = 'straight', length = 500.0 /"
KNIFE = ", contact = 'knife_edge', nominal_radius = 0.45"
SPRING = ", type = 'spring_damper'"

# (group, selector) -> {parameter: kinds that read it}; every other kind must refuse it.
READ_BY = {
    ("element", "type"): {
        "point1": {"spring_damper", "table", "series_spring_damper"},
        "point2": {"spring_damper", "table", "series_spring_damper"},
        "axes": {"spring_damper", "torsion", "table"},
        "stiffness": {"spring_damper"},
        "damping": {"spring_damper", "table", "series_spring_damper"},
        "preload": {"spring_damper"},
        "actuator_force": {"spring_damper"},
        "torsion_stiffness": {"torsion"},
        "torsion_damping": {"torsion"},
        "table_axis": {"table"},
        "table_deflection": {"table"},
        "table_force": {"table"},
        "clearance": {"table"},
        "series_stiffness": {"series_spring_damper"},
    },
    ("wheelset", "contact"): {
        "contact_geometry": {"profile"},
        "wheel_profile": {"profile"},
        "rail_profile": {"profile"},
        "wheel_profile_right": {"profile"},
        "rail_profile_right": {"profile"},
        "back_to_back": {"profile"},
        "flange_back": {"profile"},
        "rail_precant": {"profile"},
        "rail_precant_right": {"profile"},
        "contact_distance": {"knife_edge"},
        "conicity": {"knife_edge"},
        "rail_crown_radius": {"knife_edge"},
        "flange_clearance": {"knife_edge"},
        "flange_stiffness": {"knife_edge"},
    },
    ("wheelset", "creep_law"): {
        "creep_saturation": {"linear"},
        "fastsim_grid": {"fastsim"},
        "fastsim_bound": {"fastsim"},
        "fastsim_saturation_width": {"fastsim"},
        "polach_ka": {"polach"},
        "polach_ks": {"polach"},
        "polach_friction_ratio": {"polach"},
        "polach_friction_decay": {"polach"},
    },
    ("wheelset", "contact_geometry"): {"table_shift_step": {"table"}},
    ("solver", "method"): {
        "rtol": {"bdf", "adams", "erk"},
        "atol": {"bdf", "adams", "erk"},
        "max_step": {"bdf", "adams", "erk"},
        "min_step": {"bdf", "adams", "erk"},
        "initial_step": {"bdf", "adams", "erk"},
        "max_order": {"bdf", "adams"},
        "jacobian": {"bdf"},
        "fixed_step": {"rk4"},
    },
    ("segment", "type"): {"cant_ramp": {"clothoid"}},
    ("body", "frame"): {"frame_offset": {"own"}},
}
KINDS = {
    ("element", "type"): ["spring_damper", "torsion", "table", "series_spring_damper"],
    ("wheelset", "contact"): ["knife_edge", "profile"],
    ("wheelset", "creep_law"): ["linear", "fastsim", "polach"],
    ("wheelset", "contact_geometry"): ["strips", "table"],
    ("solver", "method"): ["bdf", "adams", "erk", "rk4"],
    ("segment", "type"): ["straight", "clothoid", "curve"],
    ("body", "frame"): ["own", "ws1"],
}
# a valid value of each parameter (the default where it has one: a default written where it
# is not read is refused as well)
VALUE = {
    "point1": "0.0, 0.5, 0.0", "point2": "0.0, 0.5, -0.45", "axes": "0.0, 0.0, 0.0",
    "stiffness": "0.0, 0.0, 1e5", "damping": "0.0, 0.0, 1e3", "preload": "0.0, 0.0, 10.0",
    "actuator_force": "0.0, 0.0, 0.0", "torsion_stiffness": "1e4, 0.0, 0.0",
    "torsion_damping": "0.0, 0.0, 0.0", "table_axis": "'z'", "table_deflection": "0.0, 0.1",
    "table_force": "0.0, 1e3", "clearance": "0.0", "series_stiffness": "1e6",
    "contact_geometry": "'strips'", "wheel_profile": "'s1002'", "rail_profile": "'60e1'",
    "wheel_profile_right": "'s1002'", "rail_profile_right": "'60e1'", "back_to_back": "1.36",
    "flange_back": "-0.07", "rail_precant": "0.0", "rail_precant_right": "0.0",
    "contact_distance": "1.5", "conicity": "0.05", "rail_crown_radius": "0.3",
    "flange_clearance": "0.0", "flange_stiffness": "0.0", "creep_saturation": "'none'",
    "fastsim_grid": "10", "fastsim_bound": "'parabolic'", "fastsim_saturation_width": "0.2",
    "polach_ka": "1.0", "polach_ks": "1.0", "polach_friction_ratio": "1.0",
    "polach_friction_decay": "0.0", "table_shift_step": "1e-4", "rtol": "1e-6", "atol": "1e-8",
    "max_step": "0.0", "min_step": "0.0", "initial_step": "0.0", "max_order": "2",
    "jacobian": "'coloured'", "fixed_step": "1e-4", "cant_ramp": "'linear'", "frame_offset": "0.0",
}
# what each kind needs besides the parameter under test
NEEDS = {
    ("element", "table"): {"table_axis": "'z'", "table_deflection": "0.0, 0.1",
                           "table_force": "0.0, 1e3"},
    ("element", "series_spring_damper"): {"series_stiffness": "1e6", "damping": "1e3, 0.0, 0.0"},
    ("wheelset", "profile"): {"wheel_profile": "'s1002'", "rail_profile": "'60e1'"},
    ("wheelset", "strips"): {"wheel_profile": "'s1002'", "rail_profile": "'60e1'"},
    ("wheelset", "table"): {"wheel_profile": "'s1002'", "rail_profile": "'60e1'"},
}


def render(params):
    return "".join(f", {k} = {v}" for k, v in params.items())


def deck_for(group, selector, kind, param):
    """The deck with `param` given to an entity whose `selector` is `kind`; its line."""
    params = dict(NEEDS.get((group, kind), {}))
    params[param] = VALUE[param]
    if group == "element" and param == "damping" and kind == "series_spring_damper":
        params[param] = "1e3, 0.0, 0.0"           # along its line only
    fill = {"solver": "method = 'bdf'", "track": "gauge = 1.435", "segments": STRAIGHT,
            "body2": "", "wheelset": KNIFE, "element": SPRING}
    if group == "element":
        fill["element"] = f", {selector} = '{kind}'" + render(params)
    elif group == "wheelset":
        if selector == "contact_geometry":        # profile contact (the default model)
            base = f", contact_geometry = '{kind}'"
        elif selector == "contact":
            base = f", contact = '{kind}'" + (", nominal_radius = 0.45" if kind == "knife_edge" else "")
        else:
            base = KNIFE + f", creep_law = '{kind}'"
        fill["wheelset"] = base + render(params)
    elif group == "solver":
        fill["solver"] = f"method = '{kind}'" + render(params)
    elif group == "segment":
        fill["segments"] = {
            "straight": f"&segment type = 'straight', length = 500.0{render(params)} /",
            "clothoid": f"&segment type = 'clothoid', length = 500.0, radius = 400.0, side = 'left'"
                        f", cant = 0.05{render(params)} /",
            "curve": f"&segment type = 'curve', length = 500.0, radius = 400.0, side = 'left'"
                     f"{render(params)} /"}[kind]
    elif group == "body":
        fill["body2"] = f", frame = '{kind}'" + render(params)
    deck = DECK.format(**fill)
    line = deck[:deck.index(f", {param} = ")].count("\n") + 1
    return deck, line


def cases(read):
    out = []
    for (group, selector), params in READ_BY.items():
        for param, kinds in params.items():
            for kind in KINDS[(group, selector)]:
                if (kind in kinds) == read:
                    out.append((group, selector, param, kind))
    return out


def ident(case):
    return "{}.{}-{}={}".format(case[0], case[2], case[1], case[3])


def write(tmp_path, deck):
    p = tmp_path / "scene.nml"
    p.write_text(deck)
    return p


def env_with_cache(tmp_path):
    return {**os.environ, "RAILDYN_CACHE_DIR": str(tmp_path / "cache")}


def check_and_run(exe, deck, tmp_path):
    env = env_with_cache(tmp_path)
    chk = subprocess.run([str(exe), "check", str(deck)], capture_output=True, text=True, env=env, timeout=120)
    rn = subprocess.run([str(exe), "run", str(deck), "-o", str(tmp_path / "out.h5"), "-q"],
                        capture_output=True, text=True, env=env, timeout=120)
    return chk, rn


@pytest.mark.inputs_unused
@pytest.mark.parametrize("case", cases(read=False), ids=ident)
def test_parameter_of_another_kind_is_refused_by_check_and_run(raildyn_exe, tmp_path, case):
    group, selector, param, kind = case
    deck, line = deck_for(group, selector, kind, param)
    chk, rn = check_and_run(raildyn_exe, write(tmp_path, deck), tmp_path)
    for res in (chk, rn):
        errors = error_lines(res)
        assert res.returncode == 1 and len(errors) == 1, (deck, res.stderr)
        msg = errors[0]
        assert f"scene.nml:{line}: &{group} '{param}'" in msg, msg
        assert f"{selector} = '{kind}'" in msg and "expected it left out" in msg, msg
        readers = msg.split(f"{param} is read only with {selector} = ", 1)[1]
        for k in KINDS[(group, selector)]:
            assert (re.search(rf"\b{k}\b", readers) is not None) == (k in READ_BY[(group, selector)][param]), msg
        for bad in FORBIDDEN:
            assert bad not in res.stdout + res.stderr
    assert error_lines(chk) == error_lines(rn)
    assert not (tmp_path / "out.h5").exists()


@pytest.mark.inputs_unused
@pytest.mark.parametrize("case", cases(read=True), ids=ident)
def test_parameter_of_its_own_kind_is_accepted(raildyn_exe, tmp_path, case):
    """The same value for a kind that reads it: the refusal above is about the kind."""
    group, selector, param, kind = case
    deck, _ = deck_for(group, selector, kind, param)
    res = subprocess.run([str(raildyn_exe), "check", str(write(tmp_path, deck))], capture_output=True,
                         text=True, env=env_with_cache(tmp_path), timeout=120)
    assert res.returncode == 0, (deck, res.stderr)
    assert "not read" not in res.stderr


@pytest.mark.inputs_unused
@pytest.mark.parametrize("group_selector", sorted(READ_BY), ids=lambda gs: f"{gs[0]}.{gs[1]}")
def test_the_reference_states_which_kinds_read_each_parameter(group_selector):
    group, selector = group_selector
    text = (REPO / "docs" / "input_reference.md").read_text()
    block = text.split(f"### &{group}\n", 1)[1].split("\n### ", 1)[0]
    for param, kinds in READ_BY[group_selector].items():
        row = next(r for r in block.splitlines() if r.startswith(f"| `{param}` |"))
        m = re.search(rf"read only with {selector} = ([\w, ]+?)(?:\]|;)", row)
        assert m, row
        assert set(re.split(r", | or ", m.group(1))) == kinds, row


# ----------------------------------------------------------------- presence and values
def make_deck(**fill):
    base = {"solver": "method = 'bdf'", "track": "gauge = 1.435", "segments": STRAIGHT,
            "body2": "", "wheelset": KNIFE, "element": SPRING}
    base.update(fill)
    return DECK.format(**base)


SURVEY = "".join(f"{x:.1f} 0.0 0.0 0.0\n" for x in range(0, 605, 5))
IRREGULAR = "".join(f"{s:.1f} 0.0001 0.0 0.0 0.0\n" for s in range(0, 600, 1))

# (deck, its line and parameter, words of the message): refused by check and run
REFUSED = {
    "irregularity_scale without a file": (make_deck(track="gauge = 1.435, irregularity_scale = 2.0"),
                                          4, "&track 'irregularity_scale'", "without irregularity_file"),
    "irregularity_fade without a file": (make_deck(track="gauge = 1.435, irregularity_fade = 10.0"),
                                         4, "&track 'irregularity_fade'", "without irregularity_file"),
    "start_heading with a survey": (make_deck(track="start_heading = 0.1, survey_file = 'survey.txt'",
                                              segments=""), 4, "&track 'start_heading'",
                                    "with survey_file ("),
    "start_position with a survey": (make_deck(track="survey_file = 'survey.txt', start_position = 1.0, 2.0, 0.0",
                                               segments=""), 4, "&track 'start_position'",
                                     "with survey_file ("),
    # Kalker's linear law without saturation has no friction limit
    "friction with the unsaturated linear law": (
        make_deck(wheelset=KNIFE + ", creep_law = 'linear', friction = 0.2"), 8, "&wheelset 'friction'",
        "creep_saturation = 'none'"),
    "table damping across its axis": (
        make_deck(element=", type = 'table', table_axis = 'z', table_deflection = 0.0, 0.1, "
                          "table_force = 0.0, 1e3, damping = 1e3, 0.0, 1e3"), 9, "&element 'damping'",
        "table_axis = 'z' only"),
    "series damper across its line": (
        make_deck(element=", type = 'series_spring_damper', series_stiffness = 1e6, damping = 1e3, 5.0, 0.0"),
        9, "&element 'damping'", "damping(2) = damping(3) = 0"),
}
ACCEPTED = {
    "irregularity_scale with a file": make_deck(
        track="gauge = 1.435, irregularity_file = 'irregular.txt', irregularity_scale = 2.0, irregularity_fade = 10.0"),
    "start_heading without a survey": make_deck(track="start_heading = 0.1, start_position = 1.0, 2.0, 0.0"),
    "a survey alone": make_deck(track="survey_file = 'survey.txt'", segments=""),
    "friction with the saturated linear law": make_deck(
        wheelset=KNIFE + ", creep_law = 'linear', creep_saturation = 'shen_hedrick_elkins', friction = 0.2"),
    "friction with fastsim": make_deck(wheelset=KNIFE + ", friction = 0.2"),
    "table damping along its axis": make_deck(
        element=", type = 'table', table_axis = 'z', table_deflection = 0.0, 0.1, table_force = 0.0, 1e3, "
                "damping = 0.0, 0.0, 1e3"),
}


def with_files(tmp_path):
    (tmp_path / "survey.txt").write_text(SURVEY)
    (tmp_path / "irregular.txt").write_text(IRREGULAR)


@pytest.mark.inputs_unused
@pytest.mark.parametrize("case", sorted(REFUSED))
def test_presence_and_value_rules_refuse(raildyn_exe, tmp_path, case):
    deck, line, where, words = REFUSED[case]
    with_files(tmp_path)
    chk, rn = check_and_run(raildyn_exe, write(tmp_path, deck), tmp_path)
    for res in (chk, rn):
        errors = error_lines(res)
        assert res.returncode == 1 and len(errors) == 1, (deck, res.stderr)
        assert f"scene.nml:{line}: {where}" in errors[0] and words in errors[0], errors[0]
    assert error_lines(chk) == error_lines(rn)


@pytest.mark.inputs_unused
@pytest.mark.parametrize("case", sorted(ACCEPTED))
def test_presence_and_value_rules_accept(raildyn_exe, tmp_path, case):
    with_files(tmp_path)
    chk, rn = check_and_run(raildyn_exe, write(tmp_path, ACCEPTED[case]), tmp_path)
    assert chk.returncode == 0 and rn.returncode == 0, (chk.stderr, rn.stderr)
    assert "not read" not in chk.stderr + rn.stderr


# ----------------------------------------------------------------------- overrides
BASE = """&simulation t_end = 0.002, speed = 20.0, equilibrium = 'none' /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35, position = 0.0, 0.0, 0.45 /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45, conicity = 0.1,
      creep_law = 'fastsim', fastsim_grid = 12 /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""


@pytest.mark.inputs_unused
def test_a_study_option_is_accepted_with_a_warning(raildyn_exe, tmp_path):
    """strip_normal_force 'centroid' and 'potential' are study options, not fidelity levels
    (docs/performance.md "Which fidelity level for what"): a deck that selects one runs, and
    check and run warn once per wheelset that selects it, naming its file and line; the default
    'distributed', written out, gives no warning."""
    scene = tmp_path / "scene.nml"
    scene.write_text(f"&include file = '{REPO / 'inputs' / 'manchester_v1_tc1.nml'}' /\n"
                     "&simulation t_end = 0.002 /\n"
                     "&wheelset name = 'w1', strip_normal_force = 'centroid' /\n"
                     "&wheelset name = 'w2', strip_normal_force = 'potential' /\n"
                     "&wheelset name = 'w3', strip_normal_force = 'distributed' /\n")
    chk, rn = check_and_run(raildyn_exe, scene, tmp_path)
    for res in (chk, rn):
        assert res.returncode == 0, res.stderr
        warnings = [l for l in res.stderr.splitlines() if "study option" in l]
        assert len(warnings) == 2, res.stderr
        assert all(w.startswith("raildyn: warning:") for w in warnings)
        assert "scene.nml:3: &wheelset 'strip_normal_force': 'centroid' is a study option" in warnings[0]
        assert "scene.nml:4: &wheelset 'strip_normal_force': 'potential' is a study option" in warnings[1]
        assert "not a fidelity level" in warnings[0] and "Which fidelity level for what" in warnings[0]


@pytest.mark.inputs_unused
def test_an_override_that_changes_the_kind_warns_at_both_places(raildyn_exe, tmp_path):
    """A deck that includes a base deck and switches its wheelset's creep law: the base's
    FASTSIM option is not read; check and run say so (a warning naming both lines), the run
    goes on. The same option written in the overriding file is an error."""
    (tmp_path / "base.nml").write_text(BASE)
    scene = tmp_path / "scene.nml"
    scene.write_text("&include file = 'base.nml' /\n&wheelset name = 'w1', creep_law = 'polach' /\n")
    chk, rn = check_and_run(raildyn_exe, scene, tmp_path)
    for res in (chk, rn):
        assert res.returncode == 0, res.stderr
        warnings = [l for l in res.stderr.splitlines() if "not read" in l]
        assert len(warnings) == 1, res.stderr
        assert "base.nml:4: &wheelset 'fastsim_grid'" in warnings[0]    # its own line
        assert "creep_law = 'polach' (" in warnings[0] and "scene.nml:2)" in warnings[0]
        assert warnings[0].startswith("raildyn: warning:")
    scene.write_text("&include file = 'base.nml' /\n&wheelset name = 'w1', creep_law = 'polach', "
                     "fastsim_bound = 'elliptic' /\n")
    chk, rn = check_and_run(raildyn_exe, scene, tmp_path)
    for res in (chk, rn):
        errors = error_lines(res)
        assert res.returncode == 1 and len(errors) == 1, res.stderr
        assert "scene.nml:2: &wheelset 'fastsim_bound'" in errors[0] and "creep_law = 'polach'" in errors[0]


@pytest.mark.inputs_unused
def test_an_override_to_the_unsaturated_linear_law_warns_on_the_base_friction(raildyn_exe, tmp_path):
    """The base deck gives friction (read by its FASTSIM law); a scene switches the law to
    Kalker's unsaturated linear one, which has no friction limit: the base's friction is
    reported on its own line as unread (warning of check and run, the run goes on), like any
    kind-changing override. Written in the overriding file itself, it stays an error."""
    (tmp_path / "base.nml").write_text(BASE.replace("fastsim_grid = 12", "friction = 0.2"))
    scene = tmp_path / "scene.nml"
    scene.write_text("&include file = 'base.nml' /\n&wheelset name = 'w1', creep_law = 'linear' /\n")
    chk, rn = check_and_run(raildyn_exe, scene, tmp_path)
    for res in (chk, rn):
        assert res.returncode == 0, res.stderr
        warnings = [l for l in res.stderr.splitlines() if "not read" in l]
        assert len(warnings) == 1, res.stderr
        assert "base.nml:4: &wheelset 'friction'" in warnings[0] and "no friction limit" in warnings[0]
        assert warnings[0].startswith("raildyn: warning:")
    scene.write_text("&include file = 'base.nml' /\n&wheelset name = 'w1', creep_law = 'linear', "
                     "friction = 0.3 /\n")
    chk, rn = check_and_run(raildyn_exe, scene, tmp_path)
    for res in (chk, rn):
        errors = error_lines(res)
        assert res.returncode == 1 and len(errors) == 1, res.stderr
        assert "scene.nml:2: &wheelset 'friction'" in errors[0] and "no friction limit" in errors[0]
