"""Inputs that never surprise (issue 13, items 5-8): fuzz-style categories over the real
`raildyn` executable, one pytest mark per category (pytest.ini):

- inputs_agree: `check` and `run` give the same verdict and the same message, and values
  inside the ranges documented in docs/input_reference.md are accepted by both;
- inputs_location: every rejection names the deck file:line, group and parameter, and for
  a profile file also the profile file and its line and the wheelset naming it;
- inputs_bytes: control bytes, byte order marks, CR line ends, special files;
- inputs_names: names that would become broken HDF5 paths;
- inputs_scaling: deck parsing linear in the deck's size;
- inputs_warnings: legal input that deserves a warning (stiffness, wheelset inertia);
- inputs_schema: every schema parameter changes what a user sees (test_schema_reaches_model.py);
- inputs_unused: a parameter given to a kind of its group that does not read it is refused
  (test_inputs_unused.py).

The expected messages are written here from the documented rules, not copied from the
program's output.
"""
import math
import os
import re
import subprocess
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# A single knife-edge wheelset on springs: fast to build and to step. Line numbers matter
# (messages are checked against them): &simulation 1, &output 2, &segment 3, &body 4,
# &wheelset 6, &element 9, &external_force 11.
KNIFE = """&simulation t_end = 0.002, speed = 20.0, equilibrium = 'none' /
&output interval = 0.001 /
&segment type = 'straight', length = 500.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, 0.45 /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = 0.1, creep_law = 'polach',
      friction = 0.3, contact_damping = 5.0e5 /
&element name = 'spring1', type = 'spring_damper', body1 = 'ground', body2 = 'ws1',
      point1 = 0.0, 1.0, 0.45, point2 = 0.0, 1.0, 0.0, stiffness = 3.9e7, 7.85e6, 0.0 /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""

# Profile contact with the wheel profile in a file (line 7 names it).
PROFILE = """&simulation t_end = 0.002, speed = 20.0, equilibrium = 'none' /
&output interval = 0.001 /
&segment type = 'straight', length = 500.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, 0.46 /
&wheelset name = 'w1', body = 'ws1',
      wheel_profile = 'wheel.prw', rail_profile = '60e1' /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""

FORBIDDEN = ("Fortran runtime error", "Backtrace", "ERROR STOP", "Error termination", "NaN")


def run(exe, *args, cwd=None, timeout=60):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def error_lines(res):
    return [l for l in res.stderr.splitlines() if l.startswith("raildyn: error:")]


def check_and_run(exe, deck, tmp_path):
    """(check result, run result); the run writes into tmp_path."""
    return run(exe, "check", deck), run(exe, "run", deck, "-o", tmp_path / "out.h5", "-q")


def assert_one_clean_error(res, *fragments):
    errors = error_lines(res)
    assert res.returncode != 0 and len(errors) == 1, (res.returncode, res.stdout, res.stderr)
    for f in fragments:
        assert f in errors[0], (f, errors[0])
    for bad in FORBIDDEN:
        assert bad not in res.stderr + res.stdout, res.stderr
    return errors[0]


# ----------------------------------------------------------------------------- agree
def documented_ranges(group):
    """{parameter: range text} of the real parameters of one group, from the reference."""
    text = (REPO / "docs" / "input_reference.md").read_text()
    block = text.split(f"### &{group}\n", 1)[1].split("\n### ", 1)[0]
    ranges = {}
    for row in block.splitlines():
        cells = [c.strip() for c in row.split("|")]
        if len(cells) > 6 and cells[2] == "real" and cells[5]:
            ranges[cells[1].strip("`")] = cells[5]
    return ranges


def values_inside(rng):
    """Values a user may write by the documented range: each end (closed) or just inside
    it (open), and a large value for a half-open range."""
    m = re.fullmatch(r"([\[(])(-?[\d.e+-]+), (-?[\d.e+-]+)([\])])", rng)
    if m:
        lo, hi = float(m.group(2)), float(m.group(3))
        eps = 1e-6 * (hi - lo)
        return [lo if m.group(1) == "[" else lo + eps, hi if m.group(4) == "]" else hi - eps]
    m = re.fullmatch(r"(>=?) (-?[\d.e+-]+)", rng)
    if m:
        lo = float(m.group(2))
        return [lo if m.group(1) == ">=" else lo + 1e-6 * max(1.0, abs(lo)), lo + 1e6]
    raise ValueError(rng)


# wheelset parameters of the knife-edge model with the Polach law (KNIFE), and of profile
# contact (PROFILE_S1002): each read where it is given (test_inputs_unused)
KNIFE_PARAMS = ["nominal_radius", "contact_distance", "conicity", "friction", "shear_modulus",
                "poisson", "creep_velocity_min", "contact_damping", "rail_crown_radius",
                "flange_clearance", "flange_stiffness", "polach_ka", "polach_ks",
                "polach_friction_ratio", "polach_friction_decay"]
PROFILE_PARAMS = ["rail_precant", "rail_precant_right"]
PROFILE_S1002 = """&simulation t_end = 0.002, speed = 20.0, equilibrium = 'none' /
&output interval = 0.001 /
&segment type = 'straight', length = 500.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, 0.45979 /
&wheelset name = 'w1', body = 'ws1', wheel_profile = 's1002', rail_profile = '60e1' /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""


def set_param(deck, group_line_start, param, value):
    """Add or replace `param = value` in the group that starts with group_line_start (all
    of a list value: up to the next `name =` or the group's end)."""
    i = deck.index(group_line_start)
    j = deck.index("/\n", i)
    group = deck[i:j]
    if re.search(rf"\b{param} = ", group):
        group = re.sub(rf"\b{param} = .*?(?=,\s*\w+ =|\s*$)", f"{param} = {value}", group, count=1,
                       flags=re.S)
    else:
        group = group + f", {param} = {value} "
    return deck[:i] + group + deck[j:]


def inside_cases():
    cases = []
    for group, start, names in [("wheelset", "&wheelset", KNIFE_PARAMS),
                                ("wheelset", "&wheelset name = 'w1', body = 'ws1', wheel", PROFILE_PARAMS),
                                ("simulation", "&simulation", ["max_wheel_lift", "gravity"]),
                                ("track", None, ["gauge", "rail_inclination"])]:
        ranges = documented_ranges(group)
        for name in names:
            for v in values_inside(ranges[name]):
                cases.append((group, start, name, v))
    return cases


@pytest.mark.inputs_agree
@pytest.mark.parametrize("group,start,param,value", inside_cases(),
                         ids=lambda x: str(x) if not isinstance(x, str) or "&" not in x else None)
def test_documented_values_are_accepted(raildyn_exe, tmp_path, group, start, param, value):
    deck = PROFILE_S1002 if param in PROFILE_PARAMS else KNIFE
    if param == "flange_clearance":       # a flange stop needs its stiffness (documented)
        deck = set_param(deck, "&wheelset", "flange_stiffness", "1e7")
    if param == "nominal_radius":         # the wheelset's centre at its wheels' radius
        deck = deck.replace("position = 0.0, 0.0, 0.45", f"position = 0.0, 0.0, {value!r}")
    if start is None:
        deck = deck + f"&{group} {param} = {value!r} /\n"
    else:
        deck = set_param(deck, start, param, repr(value))
    p = tmp_path / "scene.nml"
    p.write_text(deck)
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    assert chk.returncode == 0, chk.stderr
    assert rn.returncode == 0, rn.stderr


# (parameter, value outside the documented range, group start)
OUTSIDE = [
    ("contact_damping", "1e12", "&wheelset"), ("shear_modulus", "1e15", "&wheelset"),
    ("max_wheel_lift", "1.0", "&simulation"), ("back_to_back", "0.3", "&wheelset"),
    ("back_to_back", "2.5", "&wheelset"), ("contact_distance", "0.3", "&wheelset"),
    ("contact_distance", "3.5", "&wheelset"), ("conicity", "1.0", "&wheelset"),
    ("creep_velocity_min", "100.0", "&wheelset"), ("flange_stiffness", "1e15", "&wheelset"),
    ("ixx", "0.0", "&body"), ("ixx", "-5.0", "&body"),
]


@pytest.mark.inputs_agree
@pytest.mark.parametrize("param,value,start", OUTSIDE)
def test_outside_the_documented_range_both_refuse_at_the_line(raildyn_exe, tmp_path, param,
                                                              value, start):
    p = tmp_path / "scene.nml"
    deck = set_param(PROFILE_S1002 if param == "back_to_back" else KNIFE, start, param, value)
    p.write_text(deck)
    line = deck[:deck.index(f"{param} = {value}")].count("\n") + 1
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    group = start[1:]
    for res in (chk, rn):
        assert res.returncode == 1
        assert_one_clean_error(res, f"scene.nml:{line}:", f"&{group} '{param}'", "expected")
    assert error_lines(chk) == error_lines(rn)
    assert not (tmp_path / "out.h5").exists()


@pytest.mark.inputs_agree
@pytest.mark.parametrize("radius,ok", [("1e-300", False), ("9.99", False), ("10.0", True)])
def test_curve_radius_bound(raildyn_exe, tmp_path, radius, ok):
    """A curve of radius 1e-300 m passed check and gave NaN accelerations in run; the
    documented bound (>= 10 m) is refused by both at the line, and accepted at the bound."""
    deck = KNIFE.replace("&segment type = 'straight', length = 500.0 /",
                         "&segment type = 'straight', length = 10.0 /\n"
                         f"&segment type = 'clothoid', length = 30.0, radius = {radius}, side = 'left' /\n"
                         f"&segment type = 'curve', length = 500.0, radius = {radius}, side = 'left' /")
    deck = deck.replace("speed = 20.0,", "speed = 20.0, start_sigma = 60.0,")
    p = tmp_path / "scene.nml"
    p.write_text(deck)
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    if ok:
        assert chk.returncode == 0 and rn.returncode == 0, (chk.stderr, rn.stderr)
    else:
        for res in (chk, rn):
            assert res.returncode == 1
            assert_one_clean_error(res, "scene.nml:4: &segment 'radius'", ">= 10")


# Decks the schema's per-value ranges cannot judge: checked by the scene build, at the
# deck line, by check as well as run (before: check said ok and run blamed 'equilibrium').
BUILD_REFUSALS = {
    "inertia 1e-300": (("&body", "ixx", "1e-300"), 4, "&body 'ixx'", "radius of gyration"),
    "products of inertia": (("&body", "ixy", "900.0"), 5, "&body 'ixy'", "positive definite"),
    "flange stop without stiffness": (("&wheelset", "flange_clearance", "0.01"), 6,
                                      "&wheelset 'flange_stiffness'", "flange_stiffness > 0"),
}


@pytest.mark.inputs_agree
@pytest.mark.parametrize("case", sorted(BUILD_REFUSALS))
def test_build_refusals_agree(raildyn_exe, tmp_path, case):
    (start, param, value), line, where, words = BUILD_REFUSALS[case]
    p = tmp_path / "scene.nml"
    p.write_text(set_param(KNIFE, start, param, value))
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    for res in (chk, rn):
        assert res.returncode == 1, res.stderr
        assert_one_clean_error(res, f"scene.nml:{line}: {where}", words)
    assert error_lines(chk) == error_lines(rn)


@pytest.mark.inputs_agree
def test_check_runs_the_static_equilibrium(raildyn_exe, tmp_path):
    """A wheelset alone with equilibrium = 'preload' has no preload to adjust: run refused
    it after check had said ok; now check refuses it too, with the same message."""
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("equilibrium = 'none'", "equilibrium = 'preload'")
                 .replace(KNIFE[KNIFE.index("&element"):KNIFE.index("&external_force")], ""))
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    assert chk.returncode == rn.returncode != 0
    assert error_lines(chk) == error_lines(rn)
    assert "scene.nml:1: &simulation 'equilibrium'" in error_lines(chk)[0]


# -------------------------------------------------------------------------- location
def s1002_lines():
    return (REPO / "inputs" / "profiles" / "s1002.prw").read_text().splitlines()


def first_point_index(lines):
    return next(i for i, l in enumerate(lines) if "point.begin" in l) + 1


def profile_mutations():
    """(name, mutate(lines) -> lines, file line expected in the message, words)."""
    def malformed(l):
        i = first_point_index(l) + 3
        l[i] = " 1x 2"
        return l, i + 1, "malformed profile point"

    def repeated(l):
        i = first_point_index(l) + 5
        l[i] = l[i - 2]
        return l, i + 1, "does not increase from the point at line"

    def long_line(l):
        i = first_point_index(l) + 3
        l[i] = l[i] + " " * 1100 + "! end"
        return l, i + 1, "line longer than 1024 characters"

    def two_blocks(l):
        i, j = first_point_index(l), next(k for k, x in enumerate(l) if "point.end" in x)
        out = l[:j + 1] + l[i - 1:j + 1] + l[j + 1:]
        return out, j + 2, "a second point.begin"

    def nan_point(l):
        i = first_point_index(l) + 3
        l[i] = " 0.5 nan"
        return l, i + 1, "malformed profile point"

    return {"malformed point": malformed, "repeated point": repeated, "long line": long_line,
            "two point blocks": two_blocks, "nan": nan_point}


@pytest.mark.inputs_location
@pytest.mark.parametrize("case", sorted(profile_mutations()))
@pytest.mark.parametrize("command", ["check", "run"])
def test_profile_file_errors_name_both_files(raildyn_exe, tmp_path, case, command):
    lines, line, words = profile_mutations()[case](s1002_lines())
    (tmp_path / "wheel.prw").write_text("\n".join(lines) + "\n")
    p = tmp_path / "scene.nml"
    p.write_text(PROFILE)
    args = [command, p] + (["-o", tmp_path / "out.h5"] if command == "run" else [])
    res = run(raildyn_exe, *args)
    assert res.returncode == 1
    assert_one_clean_error(res, "scene.nml:7: &wheelset 'wheel_profile'", "wheelset 'w1'",
                           f"wheel.prw:{line}:", words)


@pytest.mark.inputs_location
def test_good_profile_file_still_reads(raildyn_exe, tmp_path):
    (tmp_path / "wheel.prw").write_text("\n".join(s1002_lines()) + "\n")
    p = tmp_path / "scene.nml"
    p.write_text(PROFILE)
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 0, res.stderr


@pytest.mark.inputs_location
def test_long_number_in_a_profile_is_read_whole(raildyn_exe, tmp_path):
    """A point written with 80 significant zeros is the same profile, not an error and
    not a value cut at 64 characters (it was read 1000 times too large)."""
    lines = s1002_lines()
    i = first_point_index(lines) + 3
    y, z = lines[i].split()
    mant, exp = z.lower().split("e")
    lines[i] = f" {y} {mant}{'0' * 80}e{exp}"
    (tmp_path / "wheel.prw").write_text("\n".join(lines) + "\n")
    p = tmp_path / "scene.nml"
    p.write_text(PROFILE)
    assert run(raildyn_exe, "check", p).returncode == 0


@pytest.mark.inputs_location
@pytest.mark.parametrize("table", ["irregularity", "survey"])
def test_overlong_table_line_is_an_error_at_both_lines(raildyn_exe, tmp_path, table):
    """Irregularity and survey tables: a line over 4096 characters is an error naming the
    deck line and the table's line (it was cut and its first columns read as data)."""
    if table == "irregularity":
        rows = [f"{s:.1f} 0 0 0 0" for s in range(0, 600, 10)]
        param, deck = "irregularity_file", KNIFE + "&track irregularity_file = 'table.txt' /\n"
    else:
        rows = [f"{x:.1f} 0 0 0" for x in range(0, 600, 10)]
        param = "survey_file"
        deck = KNIFE.replace("&segment type = 'straight', length = 500.0 /",
                             "&track survey_file = 'table.txt' /")
    rows[3] = rows[3] + " " * 4100 + "# long comment"
    (tmp_path / "table.txt").write_text("\n".join(rows) + "\n")
    p = tmp_path / "scene.nml"
    p.write_text(deck)
    line = deck[:deck.index(param)].count("\n") + 1
    res = run(raildyn_exe, "check", p)
    assert_one_clean_error(res, f"scene.nml:{line}: &track '{param}'", "table.txt:4:",
                           "line longer than 4096 characters")


@pytest.mark.inputs_location
@pytest.mark.parametrize("kind", ["directory", "fifo", "device"])
def test_profile_that_is_not_a_regular_file(raildyn_exe, tmp_path, kind):
    target = {"directory": tmp_path / "wheel.prw", "fifo": tmp_path / "wheel.prw",
              "device": Path("/dev/zero")}[kind]
    if kind == "directory":
        target.mkdir()
    elif kind == "fifo":
        os.mkfifo(target)
    p = tmp_path / "scene.nml"
    p.write_text(PROFILE.replace("'wheel.prw'", f"'{target}'"))
    res = run(raildyn_exe, "check", p, timeout=20)
    msg = assert_one_clean_error(res, "scene.nml:7: &wheelset 'wheel_profile'", "expected a regular file")
    assert ("directory" in msg) == (kind == "directory")


@pytest.mark.inputs_location
@pytest.mark.parametrize("command", ["check", "run"])
def test_results_path_errors_name_the_deck_line(raildyn_exe, tmp_path, command):
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("&output interval = 0.001",
                               "&output interval = 0.001, file = 'no_such_dir/r.h5'"))
    res = run(raildyn_exe, command, p)
    assert res.returncode == 4          # file error (README: exit status)
    assert_one_clean_error(res, "scene.nml:2: &output 'file'", "no_such_dir", "expected")
    (tmp_path / "adir").mkdir()
    res = run(raildyn_exe, command, p, "-o", tmp_path / "adir")
    assert_one_clean_error(res, "-o", "is a directory")


# ----------------------------------------------------------------------------- bytes
@pytest.mark.inputs_bytes
@pytest.mark.parametrize("byte", [0, 1, 8, 11, 12, 27, 127])
def test_control_bytes_are_refused_at_their_line(raildyn_exe, tmp_path, byte):
    data = KNIFE.encode()
    at = data.index(b"length")
    line = data[:at].count(b"\n") + 1
    column = at - data.rindex(b"\n", 0, at)
    p = tmp_path / "scene.nml"
    p.write_bytes(data[:at] + bytes([byte]) + data[at:])
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 1
    assert_one_clean_error(res, f"scene.nml:{line}:", f"control byte 0x{byte:02X}", f"column {column}")


@pytest.mark.inputs_bytes
@pytest.mark.parametrize("variant", ["bom", "crlf", "cr", "bom+crlf"])
def test_bom_and_line_ends_read_as_the_plain_deck(raildyn_exe, tmp_path, variant):
    """The same deck with a byte order mark, CR LF or CR-only line ends is the same deck:
    accepted, and a mistake in it reported at the same line."""
    def encode(text):
        data = text.encode()
        if "crlf" in variant:
            data = data.replace(b"\n", b"\r\n")
        elif variant == "cr":
            data = data.replace(b"\n", b"\r")
        if "bom" in variant:
            data = b"\xef\xbb\xbf" + data
        return data

    p = tmp_path / "scene.nml"
    p.write_bytes(encode(KNIFE))
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 0, res.stderr
    p.write_bytes(encode(KNIFE.replace("length = 500.0", "lenght = 500.0")))
    res = run(raildyn_exe, "check", p)
    assert_one_clean_error(res, "scene.nml:3: &segment 'lenght'")


@pytest.mark.inputs_bytes
@pytest.mark.parametrize("kind", ["directory", "fifo", "/dev/null", "/dev/zero"])
def test_special_files_as_includes_are_refused(raildyn_exe, tmp_path, kind):
    target = tmp_path / "inc.nml"
    if kind == "directory":
        target.mkdir()
    elif kind == "fifo":
        os.mkfifo(target)
    else:
        target = Path(kind)
    p = tmp_path / "scene.nml"
    p.write_text(f"&include file = '{target}' /\n" + KNIFE)
    res = run(raildyn_exe, "check", p, timeout=20)    # a FIFO used to block forever
    msg = assert_one_clean_error(res, "scene.nml:1: &include 'file'", "expected a regular file")
    assert ("directory" in msg) == (kind == "directory")


# ----------------------------------------------------------------------------- names
@pytest.mark.inputs_names
@pytest.mark.parametrize("group", ["body", "wheelset", "element"])
@pytest.mark.parametrize("name", ["", "   ", ".", "..", "a/b", "/w", " lead", "trail "])
def test_names_that_break_results_paths_are_refused(raildyn_exe, tmp_path, group, name):
    old = {"body": "name = 'ws1'", "wheelset": "name = 'w1'", "element": "name = 'spring1'"}[group]
    line = {"body": 4, "wheelset": 6, "element": 9}[group]
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace(old, f"name = '{name}'", 1))
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 1
    assert_one_clean_error(res, f"scene.nml:{line}: &{group} 'name'", "expected")


@pytest.mark.inputs_names
def test_ordinary_names_stay_accepted(raildyn_exe, tmp_path):
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("'spring1'", "'primary spring-1 (left) é'"))
    assert run(raildyn_exe, "check", p).returncode == 0


# --------------------------------------------------------------------------- scaling
def speed_law_deck(n):
    times = ", ".join(f"{i * 1e-3:.3f}" for i in range(n))
    values = ", ".join(["20.0"] * n)
    return KNIFE.replace("speed = 20.0,", f"speed_times = {times},\n  speed_values = {values},")


@pytest.mark.inputs_scaling
def test_deck_parsing_is_linear_in_the_deck_size(raildyn_exe, tmp_path):
    """check on an 8 times larger deck takes less than 20 times as long (linear: about 8,
    plus the fixed start-up; the quadratic parser took 64 times as long, 80 s for 40 000
    points). Ratios of two runs measured here, no absolute time."""
    def seconds(text, name):
        p = tmp_path / name
        p.write_text(text)
        best = math.inf
        for _ in range(2):
            t0 = time.perf_counter()
            res = run(raildyn_exe, "check", p, timeout=120)
            best = min(best, time.perf_counter() - t0)
            assert res.returncode == 0, res.stderr
        return best

    small, large = seconds(speed_law_deck(5000), "small.nml"), seconds(speed_law_deck(40000), "large.nml")
    assert large < 20 * small, (small, large)
    title = "&simulation title = '{}', "
    small = seconds(KNIFE.replace("&simulation ", title.format("x" * 125000)), "small_title.nml")
    large = seconds(KNIFE.replace("&simulation ", title.format("x" * 1000000)), "large_title.nml")
    assert large < 20 * small, (small, large)


@pytest.mark.inputs_scaling
def test_huge_number_message_is_short(raildyn_exe, tmp_path):
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("speed = 20.0", "speed = " + "1" * 100000))
    res = run(raildyn_exe, "check", p)
    msg = assert_one_clean_error(res, "scene.nml:1: &simulation 'speed'")
    assert len(msg) < 400


# -------------------------------------------------------------------------- warnings
def warnings_of(res):
    return [l for l in res.stderr.splitlines() if l.startswith("raildyn: warning:")]


CRAWL_HZ = 5000.0     # documented in docs/input_reference.md (Warnings)


@pytest.mark.inputs_warnings
@pytest.mark.parametrize("factor,warned", [(0.9, False), (1.1, True), (1e3, True)])
def test_stiffness_that_makes_a_run_crawl_is_warned(raildyn_exe, tmp_path, factor, warned):
    """Natural frequency sqrt(k/m)/(2 pi) of the 1500 kg wheelset on a grounded spring
    against the documented 5 kHz limit."""
    k = factor * 1500.0 * (2 * math.pi * CRAWL_HZ) ** 2
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("stiffness = 3.9e7,", f"stiffness = {k:.6e},"))
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 0, res.stderr
    w = warnings_of(res)
    assert bool(w) == warned, res.stderr
    if warned:
        assert len(w) == 1 and "scene.nml:10: &element 'stiffness'" in w[0] and "Hz" in w[0]
        run_res = run(raildyn_exe, "run", p, "-o", tmp_path / "o.h5", "-q")
        assert warnings_of(run_res) == w


@pytest.mark.inputs_warnings
def test_wheelset_with_unequal_roll_and_yaw_inertia_is_warned(raildyn_exe, tmp_path):
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("izz = 799.35", "izz = 750.0"))
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 0
    w = warnings_of(res)
    assert len(w) == 1 and "scene.nml:4: &body 'izz'" in w[0] and "ixx = izz" in w[0], w
    p.write_text(KNIFE)
    assert warnings_of(run(raildyn_exe, "check", p)) == []


@pytest.mark.inputs_warnings
def test_impossible_moments_of_inertia_are_warned(raildyn_exe, tmp_path):
    """Ixx + Iyy >= Izz (and permutations) holds for every rigid body."""
    p = tmp_path / "scene.nml"
    p.write_text(KNIFE.replace("iyy = 93.75", "iyy = 2000.0"))
    res = run(raildyn_exe, "check", p)
    assert res.returncode == 0
    assert any("scene.nml:4: &body 'iyy'" in w for w in warnings_of(res)), res.stderr


@pytest.mark.inputs_location
def test_wheel_and_rail_apart_name_where_back_to_back_was_given(raildyn_exe, tmp_path):
    """back_to_back inside its documented range but with wheels beside the rails: the
    rejection named only the &wheelset's own line (in the included file); it must also name
    the line of the file that set the value."""
    (tmp_path / "base.nml").write_text(PROFILE_S1002)
    p = tmp_path / "scene.nml"
    p.write_text("&include file = 'base.nml' /\n&wheelset name = 'w1', back_to_back = 1.10 /\n")
    chk, rn = check_and_run(raildyn_exe, p, tmp_path)
    for res in (chk, rn):
        assert res.returncode == 1
        assert_one_clean_error(res, "base.nml:", "overlap laterally", "scene.nml:2: &wheelset 'back_to_back'")
    assert not (tmp_path / "out.h5").exists()
