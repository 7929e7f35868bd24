"""The reference rolling radius r0 of a wheelset (&wheelset reference_radius, issue 13 item 8):
the radius of the nominal spin V / r0. By default, with profiles, the centred rolling radius
(mean of the left and right rolling radii of rigid contact at y = 0, zero yaw); knife edge:
nominal_radius (the tape-circle radius). Checked against

- a conical wheel (conicity lam) on a circular rail head (radius R, no inclination), whose
  centred contact point follows in closed form from the tangency of cone and circle;
- raildyn profile-scan's contact table at y = 0 for S1002 on 60E1 1:40;
- the physics it sets: a wheelset started centred at the nominal spin V / r0 rolls without
  longitudinal creepage at t = 0 when r0 is its centred rolling radius, and with
  xi = 1 - r / r0 (thesis 3.6.1: xi = (V - omega r) / V at zero lateral motion) when r0 is
  another radius.
"""
import math
import re
import subprocess

import h5py
import pytest

TAPE = 0.46            # &wheelset nominal_radius of the decks below [m]
GAUGE, BACK_TO_BACK, FLANGE_BACK = 1.435, 1.360, -0.070   # the schema defaults
SPEED = 20.0


def deck(wheelset_extra="", track="", z=TAPE, t_end=0.002):
    """One wheelset at height z, in the deck's configuration (no static solve)."""
    return f"""&simulation t_end = {t_end}, speed = {SPEED}, equilibrium = 'none' /
&output interval = 0.001 /
&track {track} /
&segment type = 'straight', length = 500.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35,
      position = 0.0, 0.0, {z} /
&wheelset name = 'w1', body = 'ws1', nominal_radius = {TAPE}, creep_law = 'linear',
      {wheelset_extra} /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""


def run(exe, *args, cwd=None):
    res = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, cwd=cwd,
                         timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr
    return res.stdout


def printed_reference(check_output):
    """(r0 [m], its origin, tape circle [m]) of wheelset w1 from raildyn check."""
    m = re.search(r"reference rolling radius r0 \(nominal spin V / r0\): w1 ([\d.]+) m \(([^;]+); "
                  r"tape circle ([\d.]+) m\)", check_output)
    assert m, check_output
    return float(m.group(1)), m.group(2), float(m.group(3))


def write_cone_and_circle(folder, lam, radius):
    """Conical wheel F(s) = -lam s, s in [-70, 60] mm, and a circular rail head of radius R
    with its top at the origin, |u| <= 100 mm: plain y-z tables in metres, 0.1 mm apart."""
    wheel = [f"{-0.070 + 1e-4 * k:.6f} {-lam * (-0.070 + 1e-4 * k):.9f}" for k in range(1301)]
    rail = [f"{-0.1 + 1e-4 * k:.6f} {math.sqrt(radius**2 - (-0.1 + 1e-4 * k)**2) - radius:.9f}"
            for k in range(2001)]
    (folder / "cone.txt").write_text("# cone wheel\n" + "\n".join(wheel) + "\n")
    (folder / "circle.txt").write_text("# circular rail head\n" + "\n".join(rail) + "\n")


def cone_on_circle_height(lam, radius):
    """Height of the wheelset centre at rigid centred contact of the cone on the circle: the
    cone line Z = z - r_tape + lam (Y - Y_tape) tangent to the circle centred (Y_c, -R)."""
    y_centre = GAUGE / 2 + math.sqrt(radius**2 - (radius - 0.014)**2)
    y_tape = BACK_TO_BACK / 2 - FLANGE_BACK
    return TAPE + lam * y_tape - lam * y_centre - radius + radius * math.sqrt(1 + lam**2)


def cone_on_circle_rolling_radius(lam, radius):
    """Centred rigid contact of the cone on the uninclined circle, in the track frame: the
    rail head's centre lies at Y_c = gauge/2 + sqrt(R^2 - (R - 14 mm)^2) (its gauge point 14 mm
    below the top at gauge/2); the cone's slope lam touches the circle where its normal is
    tilted by atan(lam), at Y = Y_c - R sin(atan(lam)); the tape circle of the wheel lies at
    Y_tape = back_to_back/2 - flange_back, so the wheel coordinate there is s = Y - Y_tape and
    the rolling radius r = r_tape - lam s."""
    y_centre = GAUGE / 2 + math.sqrt(radius**2 - (radius - 0.014)**2)
    y_contact = y_centre - radius * math.sin(math.atan(lam))
    s = y_contact - (BACK_TO_BACK / 2 - FLANGE_BACK)
    return TAPE - lam * s


def test_cone_on_circle_reference_radius_is_the_closed_form(raildyn_exe, tmp_path):
    lam, radius = 0.05, 0.3
    write_cone_and_circle(tmp_path, lam, radius)
    (tmp_path / "scene.nml").write_text(deck("wheel_profile = 'cone.txt', rail_profile = 'circle.txt'",
                                             track="rail_inclination = 0.0"))
    r0, origin, tape = printed_reference(run(raildyn_exe, "check", tmp_path / "scene.nml"))
    expected = cone_on_circle_rolling_radius(lam, radius)
    assert origin == "centred rolling radius of the profiles"
    assert tape == TAPE
    # 2 mm below the tape circle: a default at the tape circle would fail by 1000 times the
    # tolerance (the profiles are polygons of 0.1 mm chords, resampled at 0.2 mm)
    assert abs(expected - TAPE) > 2e-3
    assert r0 == pytest.approx(expected, abs=2e-6)


def test_s1002_60e1_reference_radius_is_profile_scan_at_y0(raildyn_exe, tmp_path):
    (tmp_path / "scene.nml").write_text(deck("wheel_profile = 's1002', rail_profile = '60e1'"))
    r0, origin, _ = printed_reference(run(raildyn_exe, "check", tmp_path / "scene.nml"))
    assert origin == "centred rolling radius of the profiles"
    run(raildyn_exe, "profile-scan", "--wheel", "s1002", "--rail", "60e1", "--radius", TAPE,
        "--csv", tmp_path / "scan.csv")
    lines = (tmp_path / "scan.csv").read_text().splitlines()
    head = lines[0].split(",")
    row = next(dict(zip(head, l.split(","))) for l in lines[1:] if float(l.split(",")[0]) == 0.0)
    scan = 0.5 * (float(row["left_p1_rolling_radius_m"]) + float(row["right_p1_rolling_radius_m"]))
    assert r0 == pytest.approx(scan, abs=1e-6)      # check prints micrometres
    assert r0 != TAPE          # S1002 on 60E1 1:40 touches 0.09 mm below its tape circle


def test_knife_edge_and_explicit_reference_radius(raildyn_exe, tmp_path):
    knife = "contact = 'knife_edge', conicity = 0.1"
    (tmp_path / "knife.nml").write_text(deck(knife))
    assert printed_reference(run(raildyn_exe, "check", tmp_path / "knife.nml")) == \
        (TAPE, "knife edge: nominal_radius", TAPE)
    (tmp_path / "given.nml").write_text(deck(knife + ", reference_radius = 0.455"))
    assert printed_reference(run(raildyn_exe, "check", tmp_path / "given.nml")) == \
        (0.455, "reference_radius", TAPE)
    (tmp_path / "profiles.nml").write_text(deck("wheel_profile = 's1002', rail_profile = '60e1', "
                                                "reference_radius = 0.47"))
    assert printed_reference(run(raildyn_exe, "check", tmp_path / "profiles.nml")) == \
        (0.47, "reference_radius", TAPE)


def start_creepage(exe, folder, name, extra):
    """(longitudinal creepage, rolling radius, reference speed) of patch 1 (left, right) at
    t = 0 of a short
    run of the cone (lam 0.05) on the circle (R 0.3 m)."""
    # both wheels 0.1 um into their rails: they touch at t = 0, with contact points
    # (midway through the penetration) 0.05 um inside the wheels' rolling radii
    z = cone_on_circle_height(0.05, 0.3) - 1e-7
    (folder / f"{name}.nml").write_text(deck(extra, track="rail_inclination = 0.0", z=z))
    run(exe, "run", folder / f"{name}.nml", "-o", folder / f"{name}.h5", "-q")
    with h5py.File(folder / f"{name}.h5", "r") as f:
        out = []
        for side in ("left", "right"):
            ds = f[f"wheelsets/w1/{side}/patch1"]
            comps = ds.attrs["components"]
            comps = (comps.decode() if isinstance(comps, bytes) else comps).split()
            out.append(tuple(ds[0, comps.index(c)] for c in ("xi", "rolling_radius", "reference_speed")))
        return out


def test_nominal_spin_at_the_reference_radius_rolls_without_creepage(raildyn_exe, tmp_path):
    lam, radius = 0.05, 0.3
    write_cone_and_circle(tmp_path, lam, radius)
    profiles = "wheel_profile = 'cone.txt', rail_profile = 'circle.txt'"
    centred = start_creepage(raildyn_exe, tmp_path, "centred", profiles)
    tape = start_creepage(raildyn_exe, tmp_path, "tape", profiles + f", reference_radius = {TAPE}")
    for xi, r, v_ref in centred:
        assert abs(xi) < 1e-6, centred
    for xi, r, v_ref in tape:
        # spinning at V / r_tape on the radius r: the wheel's material point at the contact
        # moves forward at V - V r / r_tape relative to the rail
        assert xi == pytest.approx((SPEED - SPEED * r / TAPE) / v_ref, rel=1e-3), tape
        assert abs(xi) > 4e-3
