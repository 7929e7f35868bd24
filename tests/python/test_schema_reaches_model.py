"""Every deck parameter reaches the model (issue 13 item 8; category inputs_schema).

For every parameter of the deck schema (the tables of docs/input_reference.md, which
test_deck_reference_doc keeps equal to src/fortran/io/deck/rd_deck_schema.f90), MUTATIONS
changes its value in a small deck and the test asserts that something observable changes:
the text of `raildyn check`, the results file of a short `raildyn run` (every dataset and
attribute, except the deck's own text stored with it and what varies between two runs of
the same deck), the run's messages and exit status, the files it writes, or the alignment
that `raildyn track --csv` writes.

A parameter added to the schema without an entry here fails ("no mutation"); one that no
code reads fails because nothing changes. UNOBSERVABLE lists, each with its reason, the
parameters that legitimately change nothing a finished check or run shows.
"""
import hashlib
import itertools
import math
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from test_inputs_fuzz import set_param

REPO = Path(__file__).resolve().parents[2]


def schema_parameters():
    """(group, parameter) of every row of the reference's tables."""
    text = (REPO / "docs" / "input_reference.md").read_text()
    body = text.split("<!-- BEGIN schema -->", 1)[1].split("<!-- END schema -->", 1)[0]
    out, group = [], None
    for line in body.splitlines():
        if line.startswith("### &"):
            group = line[5:].strip()
        elif line.startswith("| `"):
            out.append((group, line.split("`")[1]))
    return out

# One wheelset with S1002/60E1 profiles and a body on it, in a clothoid into a canted left
# curve, every element kind, an external force, a sensor and an include; everything moving
# (initial velocities and rates), so that stiffnesses, dampings and creep forces all act
# within the 4 ms simulated. The wheelset starts 0.03 mm into its rails (rigid contact at
# 0.459818 m: raildyn profile-scan's row y = 0). The first words of each group are unique:
# set_param finds a group by them.
BASE = """&simulation title = 'schema probe', t_end = 0.004, speed = 20.0, start_sigma = 60.0,
      equilibrium = 'none' /
&solver method = 'bdf' /
&output interval = 0.001 /
&track gauge = 1.435 /
&segment type = 'straight', length = 50.0 /
&segment type = 'clothoid', length = 30.0, radius = 400.0, side = 'left', cant = 0.1 /
&segment type = 'curve', length = 200.0, radius = 400.0, side = 'left', gradient = 0.01 /
&body name = 'ws1', mass = 1500.0, ixx = 800.0, iyy = 100.0, izz = 800.0,
      position = 0.0, 0.001, 0.45979, velocity = 0.0, 0.05, 0.0, angular_rate = 0.02, 0.01, 0.0 /
&body name = 'frame', frame = 'ws1', mass = 2000.0, ixx = 900.0, iyy = 1000.0, izz = 1200.0,
      position = 0.0, 0.0, 0.9, velocity = 0.0, 0.02, 0.01, angular_rate = 0.01, 0.02, 0.03 /
&wheelset name = 'w1', body = 'ws1', wheel_profile = 's1002', rail_profile = '60e1' /
&element name = 'spring', type = 'spring_damper', body1 = 'ws1', body2 = 'frame',
      point1 = 0.0, 0.8, 0.0, point2 = 0.0, 0.8, -0.4, stiffness = 1e6, 1e6, 1e6,
      damping = 1e4, 1e4, 1e4 /
&element name = 'torsion', type = 'torsion', body1 = 'ground', body2 = 'frame',
      torsion_stiffness = 1e5, 1e5, 1e5, torsion_damping = 1e3, 1e3, 1e3 /
&element name = 'table', type = 'table', body1 = 'ws1', body2 = 'frame',
      point1 = 0.0, -0.8, 0.0, point2 = 0.0, -0.8, -0.4, table_axis = 'z',
      table_deflection = 0.0, 0.05, 0.1, table_force = 0.0, 1e4, 5e4 /
&element name = 'series', type = 'series_spring_damper', body1 = 'ground', body2 = 'frame',
      point1 = 0.0, 1.5, 0.9, point2 = 0.0, 0.0, 0.0, damping = 2e4, 0.0, 0.0,
      series_stiffness = 1e6 /
&external_force body = 'frame', frame = 'track', force = 0.0, 0.0, -20000.0 /
&sensor name = 's1', body = 'frame', position = 1.0, 0.5, 0.2 /
&include file = '../part_a.nml' /
"""

# Files beside the run folders (decks name them '../...').
SHARED_FILES = {
    # the include's mutation names the other part
    "part_a.nml": "&external_force body = 'ws1', frame = 'body', force = 0.0, 100.0, 0.0 /\n",
    "part_b.nml": "&external_force body = 'ws1', frame = 'body', force = 0.0, 300.0, 0.0 /\n",
    # x y z h: a track curving gently to the left (about R 800 m), a point every 5 m
    "survey.txt": "".join(f"{x:.1f} {x * x / 1600:.6f} 0.0 0.0\n" for x in range(0, 305, 5)),
    # sigma alignment level cross_level gauge [m]: waves of a few 0.1 mm
    "irregular.txt": "".join(f"{s:.1f} {0.0002 * math.sin(s / 1.6):.7f} {0.0001 * math.cos(s / 1.6):.7f} "
                             f"{0.00005 * math.sin(s / 3.0):.7f} 0.0\n" for s in np.arange(0.0, 300.0, 0.5)),
    # the Manchester benchmark's S1002 (CONTACT's table, not raildyn's analytic one)
    "mbench_wheel.prw": (REPO / "validation" / "reference" / "profiles" / "MBench_S1002_v3.prw").read_text(),
}

# knife-edge wheelset (r0 0.46 m): its profiles left out (profile contact reads them)
KNIFE = [lambda d: d.replace(", wheel_profile = 's1002', rail_profile = '60e1'", ""),
         ("&wheelset", "contact", "'knife_edge'")]
RAILS = [lambda d: d + RAIL_BODIES]                    # rail bodies, not yet under the wheels
RAIL_BODIES = "".join(
    f"&body name = 'rail_{s}', mass = 245.0, ixx = 1.0, iyy = 1.0, izz = 1.0, frame = 'ws1',\n"
    f"      frozen = 'x', 'yaw', 'roll', 'pitch' /\n"
    f"&element name = 'pad_{s}', type = 'spring_damper', body1 = 'ground', body2 = 'rail_{s}',\n"
    f"      stiffness = 0.0, 4e7, 1.5e8, damping = 0.0, 1.2e5, 1.2e5 /\n" for s in ("l", "r"))


def rename(old, new):
    """A name and every reference to it."""
    return lambda d: d.replace(f"'{old}'", f"'{new}'")


def survey_track(d):
    d = re.sub(r"&segment [^/]*/\n", "", d)
    return set_param(d, "&track", "survey_file", "'../survey.txt'")


# (group, parameter) -> (edits making the variant both decks start from, the change, whether
# the changed run fails). An edit is (group start, parameter, value) for set_param, or a
# function of the deck text.
MUTATIONS = {
    ("simulation", "title"): ([], [("&simulation", "title", "'another title'")], False),
    ("simulation", "t_end"): ([], [("&simulation", "t_end", "0.003")], False),
    ("simulation", "gravity"): ([], [("&simulation", "gravity", "9.5")], False),
    ("simulation", "speed"): ([], [("&simulation", "speed", "25.0")], False),
    ("simulation", "speed_times"): (
        [lambda d: d.replace("speed = 20.0,", "speed_times = 0.0, 1.0, speed_values = 20.0, 30.0,")],
        [("&simulation", "speed_times", "0.0, 0.5")], False),
    ("simulation", "speed_values"): (
        [lambda d: d.replace("speed = 20.0,", "speed_times = 0.0, 1.0, speed_values = 20.0, 30.0,")],
        [("&simulation", "speed_values", "20.0, 40.0")], False),
    ("simulation", "start_sigma"): ([], [("&simulation", "start_sigma", "62.0")], False),
    ("simulation", "equilibrium"): ([], [("&simulation", "equilibrium", "'solve'")], False),
    # the wheels leave their rails by more than 1 um in the first milliseconds: stopped
    ("simulation", "max_wheel_lift"): ([], [("&simulation", "max_wheel_lift", "1e-6")], True),
    ("solver", "method"): ([], [("&solver", "method", "'rk4'")], False),
    ("solver", "rtol"): ([], [("&solver", "rtol", "1e-4")], False),
    ("solver", "atol"): ([], [("&solver", "atol", "1e-6")], False),
    ("solver", "atol_velocity"): ([], [("&solver", "atol_velocity", "1e-4")], False),
    ("solver", "max_step"): ([], [("&solver", "max_step", "1e-4")], False),
    # a smallest step larger than the contact's stiffness allows: the integrator fails
    ("solver", "min_step"): ([], [("&solver", "min_step", "1e-4")], True),
    ("solver", "initial_step"): ([], [("&solver", "initial_step", "1e-7")], False),
    ("solver", "max_num_steps"): ([], [("&solver", "max_num_steps", "3")], True),
    ("solver", "fixed_step"): ([("&solver", "method", "'rk4'")], [("&solver", "fixed_step", "5e-5")], False),
    ("solver", "max_order"): ([], [("&solver", "max_order", "1")], False),
    ("solver", "jacobian_max_age"): ([], [("&solver", "jacobian_max_age", "1")], False),
    ("solver", "jacobian"): ([], [("&solver", "jacobian", "'dense'")], False),
    ("output", "file"): ([], [("&output", "file", "'elsewhere.h5'")], False),
    ("output", "interval"): ([], [("&output", "interval", "0.002")], False),
    ("output", "mean_samples"): ([], [("&output", "mean_samples", "4")], False),
    ("output", "groups"): ([], [("&output", "groups", "'bodies', 'state'")], False),
    ("output", "progress"): ([], [("&output", "progress", "'on'")], False),
    ("track", "gauge"): ([], [("&track", "gauge", "1.44")], False),
    ("track", "cant_base"): ([], [("&track", "cant_base", "1.6")], False),
    ("track", "rail_inclination"): ([], [("&track", "rail_inclination", "0.03")], False),
    ("track", "survey_file"): ([], [survey_track], False),
    ("track", "irregularity_file"): ([], [("&track", "irregularity_file", "'../irregular.txt'")], False),
    ("track", "irregularity_scale"): ([("&track", "irregularity_file", "'../irregular.txt'")],
                                      [("&track", "irregularity_scale", "2.0")], False),
    ("track", "irregularity_fade"): ([("&track", "irregularity_file", "'../irregular.txt'")],
                                     [("&track", "irregularity_fade", "100.0")], False),
    ("track", "start_heading"): ([], [("&track", "start_heading", "0.1")], False),
    ("track", "start_position"): ([], [("&track", "start_position", "1.0, 2.0, 3.0")], False),
    # a clothoid from 1/400 to 1/400 m: the same curvature, but its cant defaults to 0
    # where a curve's is the previous segment's end cant (0.1 m)
    ("segment", "type"): ([], [("&segment type = 'curve'", "type", "'clothoid'")], False),
    ("segment", "length"): ([], [("&segment type = 'straight'", "length", "45.0")], False),
    # (the clothoid's end and the curve change together: curvature may not jump)
    ("segment", "radius"): ([], [("&segment type = 'clothoid'", "radius", "300.0"),
                                 ("&segment type = 'curve'", "radius", "300.0")], False),
    ("segment", "side"): ([], [("&segment type = 'clothoid'", "side", "'right'"),
                               ("&segment type = 'curve'", "side", "'right'")], False),
    ("segment", "cant"): ([], [("&segment type = 'clothoid'", "cant", "0.12")], False),
    ("segment", "cant_ramp"): ([], [("&segment type = 'clothoid'", "cant_ramp", "'cosine'")], False),
    ("segment", "gradient"): ([], [("&segment type = 'curve'", "gradient", "0.02")], False),
    ("body", "name"): ([], [rename("frame", "bogie")], False),
    ("body", "mass"): ([], [("&body name = 'frame'", "mass", "2100.0")], False),
    ("body", "ixx"): ([], [("&body name = 'frame'", "ixx", "950.0")], False),
    ("body", "iyy"): ([], [("&body name = 'frame'", "iyy", "1050.0")], False),
    ("body", "izz"): ([], [("&body name = 'frame'", "izz", "1250.0")], False),
    ("body", "ixy"): ([], [("&body name = 'frame'", "ixy", "50.0")], False),
    ("body", "ixz"): ([], [("&body name = 'frame'", "ixz", "50.0")], False),
    ("body", "iyz"): ([], [("&body name = 'frame'", "iyz", "50.0")], False),
    ("body", "position"): ([], [("&body name = 'frame'", "position", "0.0, 0.0, 0.95")], False),
    ("body", "orientation"): ([], [("&body name = 'frame'", "orientation", "0.01, 0.0, 0.0")], False),
    ("body", "velocity"): ([], [("&body name = 'frame'", "velocity", "0.0, 0.03, 0.01")], False),
    ("body", "angular_rate"): ([], [("&body name = 'frame'", "angular_rate", "0.01, 0.02, 0.04")], False),
    ("body", "frame"): ([], [("&body name = 'frame'", "frame", "'own'")], False),
    ("body", "frame_offset"): ([("&body name = 'frame'", "frame", "'own'")],
                               [("&body name = 'frame'", "frame_offset", "1.0")], False),
    ("body", "frozen"): ([], [("&body name = 'frame'", "frozen", "'yaw'")], False),
    ("wheelset", "name"): ([], [rename("w1", "front")], False),
    # the body on the wheelset becomes the wheelset, and the former wheelset a plain body
    # the contact moved to a second wheelset-like body at rail height (moved to 'frame', 0.39 m
    # above the rails, the initial state is a lift-off stop, which raildyn check reports)
    ("wheelset", "body"): ([lambda d: d.replace("&body name = 'frame',", "&body name = 'ws2', frame = 'ws1', "
                                                "mass = 1500.0, ixx = 800.0, iyy = 100.0, izz = 800.0,\n"
                                                "      position = 0.0, 0.0, 0.45979 /\n&body name = 'frame',")],
                           [("&wheelset", "body", "'ws2'")], False),
    ("wheelset", "left_rail_body"): (RAILS, [("&wheelset", "left_rail_body", "'rail_l'")], False),
    ("wheelset", "right_rail_body"): (RAILS, [("&wheelset", "right_rail_body", "'rail_r'")], False),
    ("wheelset", "contact"): ([], KNIFE, False),
    ("wheelset", "wheel_profile"): ([], [("&wheelset", "wheel_profile", "'../mbench_wheel.prw'")], False),
    ("wheelset", "rail_profile"): ([], [("&wheelset", "rail_profile", "'54e1'")], False),
    ("wheelset", "wheel_profile_right"): ([], [("&wheelset", "wheel_profile_right", "'../mbench_wheel.prw'")],
                                          False),
    ("wheelset", "rail_profile_right"): ([], [("&wheelset", "rail_profile_right", "'54e1'")], False),
    # a larger wheel, its centre raised as much
    ("wheelset", "nominal_radius"): ([], [("&wheelset", "nominal_radius", "0.47"),
                                          lambda d: d.replace("0.001, 0.45979", "0.001, 0.46979")], False),
    ("wheelset", "reference_radius"): ([], [("&wheelset", "reference_radius", "0.45")], False),
    ("wheelset", "contact_distance"): (KNIFE, [("&wheelset", "contact_distance", "1.49")], False),
    ("wheelset", "conicity"): (KNIFE, [("&wheelset", "conicity", "0.1")], False),
    ("wheelset", "back_to_back"): ([], [("&wheelset", "back_to_back", "1.362")], False),
    ("wheelset", "flange_back"): ([], [("&wheelset", "flange_back", "-0.071")], False),
    ("wheelset", "creep_law"): ([], [("&wheelset", "creep_law", "'linear'")], False),
    ("wheelset", "spin_creep"): ([], [("&wheelset", "spin_creep", ".false.")], False),
    ("wheelset", "creep_saturation"): ([("&wheelset", "creep_law", "'linear'")],
                                       [("&wheelset", "creep_saturation", "'shen_hedrick_elkins'")], False),
    ("wheelset", "friction"): ([], [("&wheelset", "friction", "0.2")], False),
    ("wheelset", "shear_modulus"): ([], [("&wheelset", "shear_modulus", "7e10")], False),
    ("wheelset", "poisson"): ([], [("&wheelset", "poisson", "0.3")], False),
    ("wheelset", "fastsim_grid"): ([], [("&wheelset", "fastsim_grid", "12")], False),
    ("wheelset", "fastsim_bound"): ([], [("&wheelset", "fastsim_bound", "'elliptic'")], False),
    ("wheelset", "fastsim_saturation_width"): ([], [("&wheelset", "fastsim_saturation_width", "0.5")], False),
    ("wheelset", "normal_contact"): ([], [("&wheelset", "normal_contact", "'quasi_static'")], False),
    ("wheelset", "contact_geometry"): ([], [("&wheelset", "contact_geometry", "'table'")], False),
    ("wheelset", "strip_normal_force"): ([], [("&wheelset", "strip_normal_force", "'potential'")], False),
    ("wheelset", "table_shift_step"): ([("&wheelset", "contact_geometry", "'table'")],
                                       [("&wheelset", "table_shift_step", "2.0e-4")], False),
    ("wheelset", "strip_spacing"): ([], [("&wheelset", "strip_spacing", "1.0e-4")], False),
    ("wheelset", "polach_ka"): ([("&wheelset", "creep_law", "'polach'")], [("&wheelset", "polach_ka", "0.5")], False),
    ("wheelset", "polach_ks"): ([("&wheelset", "creep_law", "'polach'")], [("&wheelset", "polach_ks", "0.5")], False),
    ("wheelset", "creep_velocity_min"): ([], [("&wheelset", "creep_velocity_min", "5.0")], False),
    ("wheelset", "contact_damping"): ([], [("&wheelset", "contact_damping", "1e5")], False),
    ("wheelset", "hertz_method"): ([], [("&wheelset", "hertz_method", "'table'")], False),
    ("wheelset", "rail_precant"): ([], [("&wheelset", "rail_precant", "0.01")], False),
    ("wheelset", "rail_precant_right"): ([], [("&wheelset", "rail_precant_right", "0.01")], False),
    ("wheelset", "rail_crown_radius"): (KNIFE, [("&wheelset", "rail_crown_radius", "0.2")], False),
    # the wheelset starts 1 mm to the left: a 0.5 mm clearance engages the stop
    ("wheelset", "flange_clearance"): (KNIFE + [("&wheelset", "flange_stiffness", "1e7")],
                                       [("&wheelset", "flange_clearance", "0.0005")], False),
    ("wheelset", "flange_stiffness"): (KNIFE + [("&wheelset", "flange_clearance", "0.0005"),
                                                ("&wheelset", "flange_stiffness", "1e7")],
                                       [("&wheelset", "flange_stiffness", "2e7")], False),
    # (mu = mu0 ((1 - A) exp(-B w) + A): A matters only with a decay B > 0)
    ("wheelset", "polach_friction_ratio"): ([("&wheelset", "creep_law", "'polach'"),
                                             ("&wheelset", "polach_friction_decay", "5.0")],
                                            [("&wheelset", "polach_friction_ratio", "0.5")], False),
    ("wheelset", "polach_friction_decay"): ([("&wheelset", "creep_law", "'polach'"),
                                             ("&wheelset", "polach_friction_ratio", "0.5")],
                                            [("&wheelset", "polach_friction_decay", "0.5")], False),
    ("element", "name"): ([], [rename("spring", "primary")], False),
    # the torsion element becomes a spring-damper with the same stiffness and damping (each
    # kind's own parameters: a torsion element reads no 'stiffness')
    ("element", "type"): ([], [lambda d: d.replace(
        "type = 'torsion', body1 = 'ground', body2 = 'frame',\n"
        "      torsion_stiffness = 1e5, 1e5, 1e5, torsion_damping = 1e3, 1e3, 1e3 /",
        "type = 'spring_damper', body1 = 'ground', body2 = 'frame',\n"
        "      stiffness = 1e5, 1e5, 1e5, damping = 1e3, 1e3, 1e3 /")], False),
    ("element", "body1"): ([], [("&element name = 'spring'", "body1", "'ground'")], False),
    ("element", "body2"): ([], [("&element name = 'series'", "body2", "'ws1'")], False),
    ("element", "point1"): ([], [("&element name = 'spring'", "point1", "0.0, 0.9, 0.0")], False),
    ("element", "point2"): ([], [("&element name = 'spring'", "point2", "0.0, 0.9, -0.4")], False),
    ("element", "axes"): ([], [("&element name = 'spring'", "axes", "0.1, 0.0, 0.0")], False),
    ("element", "stiffness"): ([], [("&element name = 'spring'", "stiffness", "2e6, 1e6, 1e6")], False),
    ("element", "damping"): ([], [("&element name = 'spring'", "damping", "2e4, 1e4, 1e4")], False),
    ("element", "preload"): ([], [("&element name = 'spring'", "preload", "0.0, 0.0, 1000.0")], False),
    ("element", "actuator_force"): ([], [("&element name = 'spring'", "actuator_force", "0.0, 500.0, 0.0")],
                                    False),
    ("element", "torsion_stiffness"): ([], [("&element name = 'torsion'", "torsion_stiffness", "2e5, 1e5, 1e5")],
                                       False),
    ("element", "torsion_damping"): ([], [("&element name = 'torsion'", "torsion_damping", "2e3, 1e3, 1e3")],
                                     False),
    ("element", "table_axis"): ([], [("&element name = 'table'", "table_axis", "'y'")], False),
    ("element", "table_deflection"): ([], [("&element name = 'table'", "table_deflection", "0.0, 0.02, 0.1")],
                                      False),
    ("element", "table_force"): ([], [("&element name = 'table'", "table_force", "0.0, 2e4, 5e4")], False),
    ("element", "clearance"): ([], [("&element name = 'table'", "clearance", "0.001")], False),
    ("element", "series_stiffness"): ([], [("&element name = 'series'", "series_stiffness", "2e6")], False),
    ("external_force", "body"): ([], [("&external_force body = 'frame'", "body", "'ws1'")], False),
    ("external_force", "frame"): ([], [("&external_force body = 'frame'", "frame", "'fixed'")], False),
    ("external_force", "force"): ([], [("&external_force body = 'frame'", "force", "0.0, 0.0, -25000.0")], False),
    ("external_force", "moment"): ([], [("&external_force body = 'frame'", "moment", "100.0, 0.0, 0.0")], False),
    ("external_force", "t_start"): ([], [("&external_force body = 'frame'", "t_start", "0.002")], False),
    ("external_force", "t_end"): ([], [("&external_force body = 'frame'", "t_end", "0.002")], False),
    ("sensor", "name"): ([], [rename("s1", "accelerometer")], False),
    ("sensor", "body"): ([], [("&sensor", "body", "'ws1'")], False),
    ("sensor", "position"): ([], [("&sensor", "position", "1.0, 0.5, 0.3")], False),
    ("include", "file"): ([], [lambda d: d.replace("part_a.nml", "part_b.nml")], False),
}

# Parameters whose value legitimately changes nothing that a finished check or run shows.
UNOBSERVABLE = {
    # how often the results file is flushed while the run goes on: what a reader sees
    # during the run or after a kill (test_hdf5_kill), not what the finished file holds
    ("output", "flush_every"),
}


SCHEMA = schema_parameters()


PROGRESS = re.compile(r"\rt = [^\r\n]*")


def apply(deck, edits):
    for edit in edits:
        deck = edit(deck) if callable(edit) else set_param(deck, *edit)
    return deck


def digest(data):
    return hashlib.sha256(data).hexdigest()


# attributes that differ between two runs of the same deck (a clock's readings, in seconds
# or finer: two runs within one second may agree, so they are named, not only calibrated)
CLOCK_ATTRIBUTES = {"created", "wall_time"}


def results_items(path):
    """{name: digest} of every dataset and attribute of a results file (names with '@' are
    attributes); the stored deck text is left out: it echoes the input."""
    items = {}

    def attrs(name, obj):
        for key, value in obj.attrs.items():
            if key not in CLOCK_ATTRIBUTES:
                items[f"{name}@{key}"] = digest(np.asarray(value).tobytes())

    with h5py.File(path, "r") as f:
        attrs("", f)

        def visit(name, obj):
            attrs(name, obj)
            if isinstance(obj, h5py.Dataset) and name != "meta/deck_text":
                items[name] = digest(np.asarray(obj[()]).tobytes())

        f.visititems(visit)
    return items


def observe(exe, folder, deck):
    """What a user sees of a deck: {item: digest}."""
    folder.mkdir()
    (folder / "scene.nml").write_text(deck)
    seen = {}
    for command, extra in (("check", []), ("track", ["--csv", "track.csv"]), ("run", [])):
        res = subprocess.run([str(exe), command, "scene.nml", *extra], capture_output=True,
                             text=True, cwd=folder, timeout=120)
        text = res.stdout + res.stderr
        # the progress line (raildyn run) carries wall-clock figures: seen as shown or not
        seen[f"{command} progress line"] = str(bool(PROGRESS.search(text)))
        seen[f"{command} status"] = str(res.returncode)
        seen[f"{command} output"] = digest(PROGRESS.sub("", text).encode())
    seen["track.csv"] = digest((folder / "track.csv").read_bytes()) if (folder / "track.csv").exists() else ""
    written = sorted(p.name for p in folder.glob("*.h5"))
    seen["results files"] = " ".join(written)
    for name in written:
        seen.update({f"{name}:{k}": v for k, v in results_items(folder / name).items()})
    return seen


def differences(base, seen, varying):
    """The items that differ between two observations, leaving out `varying`."""
    return sorted(k for k in (set(base) | set(seen)) - varying if base.get(k) != seen.get(k))


@pytest.fixture(scope="module")
def observed(raildyn_exe, tmp_path_factory):
    """observed(edits, twice) -> (what the deck BASE with those edits shows, the items that
    differed between two runs of it when `twice`, e.g. its creation date and wall time);
    cached per deck."""
    root = tmp_path_factory.mktemp("schema")
    for name, text in SHARED_FILES.items():
        (root / name).write_text(text)
    cache = {}
    folders = itertools.count()

    def see(edits, twice=False):
        deck = apply(BASE, edits)
        if deck not in cache:
            cache[deck] = (observe(raildyn_exe, root / f"deck{next(folders)}", deck), None)
        seen, varying = cache[deck]
        if twice and varying is None:
            again = observe(raildyn_exe, root / f"deck{next(folders)}", deck)
            varying = {k for k in set(seen) | set(again) if seen.get(k) != again.get(k)}
            cache[deck] = (seen, varying)
        return seen, varying

    return see


@pytest.mark.inputs_schema
def test_the_variants_check_and_run(observed):
    """Every variant the changes start from is a deck that checks and runs."""
    for variant, _, _ in MUTATIONS.values():
        seen, _ = observed(variant, twice=True)
        assert (seen["check status"], seen["run status"]) == ("0", "0"), apply(BASE, variant)


@pytest.mark.inputs_schema
@pytest.mark.parametrize("group,param", SCHEMA, ids=[f"{g}.{p}" for g, p in SCHEMA])
def test_every_schema_parameter_changes_what_a_user_sees(observed, group, param):
    if (group, param) in UNOBSERVABLE:
        assert (group, param) not in MUTATIONS
        return
    assert (group, param) in MUTATIONS, (f"no mutation for &{group} {param}: add one to MUTATIONS "
                                         "(or, with the reason, to UNOBSERVABLE)")
    variant, change, fails = MUTATIONS[(group, param)]
    base, varying = observed(variant, twice=True)
    seen, _ = observed(variant + change)
    assert seen["check status"] == "0", f"the changed deck must be valid input:\n{apply(BASE, variant + change)}"
    assert (seen["run status"] != "0") == fails, f"run status {seen['run status']}"
    assert differences(base, seen, varying), f"&{group} {param}: nothing observable changed"


@pytest.mark.inputs_schema
def test_a_deck_change_no_code_reads_is_seen_as_no_change(observed):
    """The comparison can fail: a comment and a value written differently (the deck's text
    changes, the model does not) change nothing the test looks at."""
    base, varying = observed([], twice=True)
    seen, _ = observed([lambda d: "! a comment\n" + d.replace("t_end = 0.004", "t_end = 4.0e-3")])
    assert differences(base, seen, varying) == []
