"""The TGV 001 cases: the checks of validation/tgv_checks.csv (the ``kind`` column names one
of CHECK_KINDS), the creep coefficients identified from a run, the critical-speed bisection."""
from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from ..results import Results
from ..stability import StabilityError, bisection_critical_speed
from .core import CaseError, Table
from .planar import (PLANAR_WHEELSETS, STANDARD_GRAVITY, TGV_BOGIE, TGV_CURVE, KnifeEdgeContact,
                     lateral_stability, linear_critical_speed, steady_curving, tgv_planar_model)
from .references import load_tgv_checks
from .runs import Context, deck_wheelsets
from .signals import growth_rate, oscillation_wavelength, window_mask

#: The designed track curves to the left (inputs/tracks/tgv_designed_track.nml): outward = -y.
TGV_OUTWARD_SIGN = -1.0


def _window(ctx: Context, row: dict, channel: str | None = None, results: Results | None = None):
    t = ctx.time(results)
    t0, t1 = float(row["t_from"]), float(row["t_to"])
    y = ctx.get(channel or row["channel"], results)
    m = window_mask(t, t0, t1)
    if m.sum() < 2:
        raise CaseError(f"check {row['id']}: window [{t0:g}, {t1:g}] s not covered (results end at "
                        f"{t[-1] if t.size else float('nan'):g} s)")
    return t[m], y[m]


def _bound(ctx, row, value: float, above: bool, unit: str, detail: str) -> None:
    """The check of ``row``: ``value`` above (or below) the row's threshold."""
    thr = float(row["threshold"])
    ctx.check(row["id"], value > thr if above else value < thr, value, f"{'>' if above else '<'} {thr:g}",
              unit, detail)


def _kind_growth(ctx, row, above: bool):
    rate, npk = growth_rate(*_window(ctx, row))
    _bound(ctx, row, rate, above, "1/s", f"{npk} half-cycle peaks; {row['justification']}")


def _kind_amplitude(ctx, row, above: bool):
    _bound(ctx, row, float(np.max(np.abs(_window(ctx, row)[1]))), above, row["unit"], row["justification"])


def _kind_relative_amplitude(ctx, row, above: bool):
    t_all = ctx.time()
    y_all = ctx.get(row["channel"])
    before = t_all < float(row["t_from"]) - 1e-12
    if not before.any():
        raise CaseError(f"check {row['id']}: no output before the window")
    peak = float(np.max(np.abs(y_all[before])))
    _, y = _window(ctx, row)
    amp = float(np.max(np.abs(y)))
    _bound(ctx, row, amp / peak if peak > 0 else math.inf, above, "1", f"max |y| {amp * 1e3:.4f} mm in the "
           f"window, {peak * 1e3:.4f} mm before; {row['justification']}")


def _kind_wavelength(ctx, row, above: bool):
    t, y = _window(ctx, row)
    _bound(ctx, row, oscillation_wavelength(t, y, ctx.speed()), above, "m", row["justification"])


def _kind_outward(ctx, row, above: bool):
    out = TGV_OUTWARD_SIGN * float(np.mean(_window(ctx, row)[1]))
    _bound(ctx, row, out, above, "m", f"mean outward shift in the window; {row['justification']}")


def _kind_outward_less(ctx, row):
    a_ch, b_ch = row["channel"].split("|")
    _, a = _window(ctx, row, a_ch)
    _, b = _window(ctx, row, b_ch)
    da = TGV_OUTWARD_SIGN * float(np.mean(a))
    db = TGV_OUTWARD_SIGN * float(np.mean(b))
    ctx.check(row["id"], da < db - float(row["threshold"]), da - db, "< 0", "m",
              f"outward {a_ch.split('/')[1]} {da * 1e3:.3f} mm vs {b_ch.split('/')[1]} {db * 1e3:.3f} mm; "
              f"{row['justification']}")


def _kind_steadiness(ctx, row):
    _, y = _window(ctx, row)
    mean, std = float(np.mean(y)), float(np.std(y))
    thr = float(row["threshold"])
    ok = std < thr * abs(mean) or std < 5e-5
    ctx.check(row["id"], ok, std / abs(mean) if mean else math.inf, f"< {thr:g} (or std < 0.05 mm)", "1",
              f"std {std * 1e3:.4f} mm, mean {mean * 1e3:.4f} mm; {row['justification']}")


def _kind_same_mean(ctx, row):
    a_ch, b_ch = row["channel"].split("|")
    _, a = _window(ctx, row, a_ch)
    _, b = _window(ctx, row, b_ch)
    ma, mb = float(np.mean(a)), float(np.mean(b))
    thr = float(row["threshold"])
    rel = abs(ma - mb) / max(abs(mb), 1e-12)
    ctx.check(row["id"], abs(ma - mb) <= max(thr * abs(mb), 1e-4), rel, f"<= {thr:g} (or 0.1 mm)", "1",
              f"{a_ch.split('/')[1]} {ma * 1e3:.3f} mm vs {b_ch.split('/')[1]} {mb * 1e3:.3f} mm; "
              f"{row['justification']}")


def _kind_flange_contact(ctx, row):
    base = row["channel"]              # wheelsets/<w>/<side>
    side = base.rsplit("/", 1)[1]
    sgn = 1.0 if side == "right" else -1.0   # conventions: gamma > 0 at a right flange contact
    gam = []
    j = 1
    while ctx.has(f"{base}/patch{j}:contact_angle"):
        _, g = _window(ctx, row, f"{base}/patch{j}:contact_angle")
        _, nf = _window(ctx, row, f"{base}/patch{j}:normal_force")
        gam.append(np.where(nf > 0.0, sgn * g, -np.inf))      # active: carries normal force
        j += 1
    if not gam:
        raise CaseError(f"check {row['id']}: no contact point series under {base} "
                        f"(expected {base}/patch1, docs/output.md)")
    mean_max = float(np.mean(np.max(np.vstack(gam), axis=0)))
    thr = float(row["threshold"])
    ctx.check(row["id"], mean_max > thr, mean_max, f"> {thr:g}", "rad",
              f"window mean of the largest active contact angle; {row['justification']}")


def fastsim_reference(ctx: "Context") -> Results:
    """The case's own deck run again with FASTSIM on every wheelset (everything else, spin
    treatment included, as the deck says): the thesis' 5.6 compares Polach with FASTSIM on the
    same vehicle and track, both "as the spin creepage is not taken into account"."""
    key = ("fastsim_reference",)
    if key not in ctx.cache:
        overrides = "\n".join(f"&wheelset name = '{w}', creep_law = 'fastsim' /"
                              for w in deck_wheelsets(ctx.case.deck_path))
        ctx.cache[key] = ctx.run_variant("fastsim", overrides)
    return ctx.cache[key]


def _kind_case_difference(ctx, row, forces: bool):
    other = fastsim_reference(ctx)
    thr = float(row["threshold"])
    items = [(k, s) for k in range(1, 5) for s in (("left", "right") if forces else ("",))]
    worst, ok_all, parts = 0.0, True, []
    for k, side in items:
        ch = row["channel"].format(k=k, side=side)
        _, a = _window(ctx, row, ch)
        _, b = _window(ctx, row, ch, other)
        ma, mb = float(np.mean(a)), float(np.mean(b))
        d = abs(ma - mb)
        if forces:
            allowed = max(thr * max(abs(ma), abs(mb)), 2000.0)
        else:
            allowed = max(thr, 0.10 * abs(mb))
        ok_all &= d <= allowed
        worst = max(worst, d / allowed)
        parts.append(f"ws{k}{' ' + side if side else ''}: {ma:.4g} vs {mb:.4g}")
    ctx.check(row["id"], ok_all, worst, "<= 1 (difference / allowed)", "1",
              "Polach vs FASTSIM window means: " + "; ".join(parts) + f". {row['justification']}")


def _kind_critical_speed(ctx, row, above: bool):
    if "critical_speed" not in ctx.cache:
        ctx.cache["critical_speed"] = critical_speed_bisection(ctx, row)
    _bound(ctx, row, ctx.cache["critical_speed"], above, "m/s", row["justification"])


def _identify_creep_coefficients(ctx: Context, row: dict, wheelsets: Sequence[str]) -> tuple[float, float]:
    """f11, f22 [N] of the run's own contacts in the window, least squares over the wheelsets:
    f11 from the difference right - left of Fx against that of xi, f22 from the sum left + right
    of Fy against that of eta (the spin contributions of a cone's two wheels cancel in the sum)."""
    dfx, dxi, sfy, seta = [], [], [], []
    for w in wheelsets:
        c = {}
        for side in ("left", "right"):
            base = f"wheelsets/{w}/{side}/patch1"
            _, cr = _window(ctx, row, f"{base}:xi")
            _, et = _window(ctx, row, f"{base}:eta")
            _, fx = _window(ctx, row, f"{base}:creep_force_x")
            _, fy = _window(ctx, row, f"{base}:creep_force_y")
            c[side] = [float(np.mean(v)) for v in (cr, et, fx, fy)]
        dxi.append(c["right"][0] - c["left"][0])
        dfx.append(c["right"][2] - c["left"][2])
        seta.append(c["right"][1] + c["left"][1])
        sfy.append(c["right"][3] + c["left"][3])
    dxi, dfx, seta, sfy = map(np.array, (dxi, dfx, seta, sfy))
    if not (np.dot(dxi, dxi) > 0 and np.dot(seta, seta) > 0):
        raise CaseError("zero creepages in the window: cannot identify the creep coefficients")
    return float(-np.dot(dfx, dxi) / np.dot(dxi, dxi)), float(-np.dot(sfy, seta) / np.dot(seta, seta))


def identify_knife_edge_contact(ctx: Context, wheelsets: Sequence[str], t_from: float,
                                results: Results | None = None) -> KnifeEdgeContact:
    """The run's own contact state for ``lateral_stability``, from the samples after t_from of
    every wheel of the wheelsets: Kalker's linear law (thesis eqs. 3.39-3.43) scales with the
    contact ellipse as Fx = -k11 (ab) xi, Fy = -k22 (ab) eta - k23 (ab)^1.5 phi, so k11 is fitted
    to Fx and k22, k23 together to Fy by least squares over all samples of all wheels (the ellipse
    of each sample from the outputs), and f11 = k11 ab0, f22 = k22 ab0, f23 = k23 ab0^1.5 at the
    mean ab0; N0 is the mean normal force. Fitting per wheel with the ellipse keeps the load
    transfer out of the coefficients: a fit of the wheel sums Fy_L + Fy_R against eta and phi
    alone takes the spin force that moves with the load (f23 ~ N) for part of f22 (-7% on the
    TGV bogie, docs/validation.md)."""
    t = ctx.time(results)
    m = t >= t_from
    cols = {k: [] for k in ("xi", "eta", "phi", "fx", "fy", "ab", "n")}
    for w in wheelsets:
        for side in ("left", "right"):
            base = f"wheelsets/{w}/{side}/patch1"
            for k, ch in (("xi", "xi"), ("eta", "eta"), ("phi", "spin"), ("fx", "creep_force_x"),
                          ("fy", "creep_force_y"), ("n", "normal_force")):
                cols[k].append(ctx.get(f"{base}:{ch}", results)[m])
            cols["ab"].append(ctx.get(f"{base}:semi_axis_a", results)[m] * ctx.get(f"{base}:semi_axis_b", results)[m])
    xi, eta, phi, fx, fy, ab, n = (np.concatenate(cols[k]) for k in ("xi", "eta", "phi", "fx", "fy", "ab", "n"))
    if not (ab.size and np.all(ab > 0)):
        raise CaseError("no loaded contact ellipse in the samples: cannot identify the creep coefficients")
    ab0 = float(np.mean(ab))
    u = ab / ab0 * xi
    v = ab / ab0 * eta
    w = (ab / ab0) ** 1.5 * phi
    if not (np.dot(u, u) > 0 and np.dot(v, v) > 0):
        raise CaseError("zero creepages: cannot identify the creep coefficients")
    f11 = float(-np.dot(fx, u) / np.dot(u, u))
    # scale the columns so that lstsq's rank decision is unit-free
    nv, nw = np.linalg.norm(v), max(np.linalg.norm(w), 1e-300)
    coef = np.linalg.lstsq(np.column_stack([v / nv, w / nw]), -fy, rcond=1e-9)[0]
    return KnifeEdgeContact(f11, float(coef[0] / nv), float(coef[1] / nw), float(np.mean(n)))


def _contact_text(c: KnifeEdgeContact) -> str:
    return (f"f11 = {c.f11:.4g} N, f22 = {c.f22:.4g} N, f23 = {c.f23:.4g} N m, "
            f"N0 = {c.normal_force:.4g} N")


def _kind_linear_stability(ctx, row, what: str):
    """what = 'rate' (growth rate vs the model's least-damped eigenvalue) or 'wavelength'."""
    kind = row["channel"]
    nws = PLANAR_WHEELSETS[kind]
    t0 = float(row["t_from"])
    contact = identify_knife_edge_contact(ctx, [f"w{k}" for k in range(1, nws + 1)], t0)
    V = ctx.speed()
    ev = lateral_stability(kind, contact, speed=V)
    t, y = _window(ctx, row, "bodies/ws1/position_track:y")
    thr = float(row["threshold"])
    info = f"linear model with the run's own {_contact_text(contact)} at {V:g} m/s"
    if what == "rate":
        rate, npk = growth_rate(t, y)
        allowed = thr * abs(ev.real) + 0.1
        ctx.check(row["id"], abs(rate - ev.real) <= allowed, rate, f"{ev.real:.4g} +- {allowed:.2g}", "1/s",
                  f"{info}; {npk} peaks; {row['justification']}")
    else:
        lam_model = V * 2 * math.pi / abs(ev.imag)
        lam = oscillation_wavelength(t, y, V)
        allowed = thr * lam_model
        ctx.check(row["id"], abs(lam - lam_model) <= allowed, lam, f"{lam_model:.4g} +- {allowed:.2g}", "m",
                  f"{info}; {row['justification']}")


def _kind_linear_curving(ctx, row):
    kind = row["channel"]
    nws = PLANAR_WHEELSETS[kind]
    f11, f22 = _identify_creep_coefficients(ctx, row, [f"w{k}" for k in range(1, nws + 1)])
    V = ctx.speed()
    phi = math.asin(TGV_CURVE["cant"] / TGV_CURVE["cant_base"])
    a_q = V ** 2 / TGV_CURVE["radius"] * math.cos(phi) - STANDARD_GRAVITY * math.sin(phi)
    bodies, springs = tgv_planar_model(kind)
    model = steady_curving(bodies, springs, f11, f22, TGV_CURVE["radius"], a_q, TGV_BOGIE["r0"],
                           TGV_BOGIE["e0"], TGV_BOGIE["lam"])
    thr = float(row["threshold"])
    ws = [f"ws{k}" for k in range(1, nws + 1)]
    scale_y = max(abs(model[w][0]) for w in ws)
    scale_p = max(abs(model[w][1]) for w in ws)
    for w in ws:
        for comp, col, scale, floor, unit in (("y", 0, scale_y, 5e-5, "m"), ("yaw", 1, scale_p, 2e-5, "rad")):
            _, v = _window(ctx, row, f"bodies/{w}/position_track:{comp}")
            got, ref = float(np.mean(v)), model[w][col]
            allowed = thr * scale + floor
            ctx.check(f"{row['id']}:{w} {comp}", abs(got - ref) <= allowed, got, f"{ref:.4g} +- {allowed:.2g}",
                      unit, f"linear steady-curving model with the run's own f11 = {f11:.4g} N, "
                      f"f22 = {f22:.4g} N, a_q = {a_q:.4g} m/s^2; {row['justification']}")


CHECK_KINDS: dict[str, Callable] = {
    "linear_steady_curving": _kind_linear_curving,
    "linear_growth_rate": lambda c, r: _kind_linear_stability(c, r, "rate"),
    "linear_wavelength": lambda c, r: _kind_linear_stability(c, r, "wavelength"),
    "linear_critical_speed": lambda c, r: _kind_linear_critical_speed(c, r),
    "growth_rate_below": lambda c, r: _kind_growth(c, r, False),
    "growth_rate_above": lambda c, r: _kind_growth(c, r, True),
    "amplitude_below": lambda c, r: _kind_amplitude(c, r, False),
    "amplitude_above": lambda c, r: _kind_amplitude(c, r, True),
    "relative_amplitude_below": lambda c, r: _kind_relative_amplitude(c, r, False),
    "relative_amplitude_above": lambda c, r: _kind_relative_amplitude(c, r, True),
    "wavelength_above": lambda c, r: _kind_wavelength(c, r, True),
    "wavelength_below": lambda c, r: _kind_wavelength(c, r, False),
    "outward_above": lambda c, r: _kind_outward(c, r, True),
    "outward_below": lambda c, r: _kind_outward(c, r, False),
    "outward_less_than": _kind_outward_less,
    "steadiness_below": _kind_steadiness,
    "same_mean": _kind_same_mean,
    "flange_contact_above": _kind_flange_contact,
    "case_difference_below": lambda c, r: _kind_case_difference(c, r, False),
    "case_force_difference_below": lambda c, r: _kind_case_difference(c, r, True),
    "critical_speed_above": lambda c, r: _kind_critical_speed(c, r, True),
    "critical_speed_below": lambda c, r: _kind_critical_speed(c, r, False),
}


#: Critical-speed search (case tgv_bogie_critical_speed: the 40 m/s bogie deck, whose small
#: disturbance keeps unstable runs short of large amplitudes, at other speeds).
CRITICAL_SPEED_BRACKET = (20.0, 40.0)
CRITICAL_SPEED_RESOLUTION = 1.0
CRITICAL_SPEED_T_END = 8.0


def _kind_linear_critical_speed(ctx, row):
    if "critical_speed" not in ctx.cache:
        ctx.cache["critical_speed"] = critical_speed_bisection(ctx, row)
    vc = ctx.cache["critical_speed"]
    if "creep_coefficients" not in ctx.cache:
        raise CaseError("no probe run to identify the creep coefficients from")
    contact = ctx.cache["creep_coefficients"]
    vc_model = linear_critical_speed("bogie", contact)
    thr = float(row["threshold"])
    allowed = thr * vc_model
    ctx.check(row["id"], abs(vc - vc_model) <= allowed + CRITICAL_SPEED_RESOLUTION / 2, vc,
              f"{vc_model:.4g} +- {allowed + CRITICAL_SPEED_RESOLUTION / 2:.2g}", "m/s",
              f"linear model with {_contact_text(contact)} identified from the "
              f"{ctx.cache['creep_coefficients_speed']:g} m/s probe; {row['justification']}")


def critical_speed_bisection(ctx: Context, row: dict) -> float:
    """The product's bisection (raildyn.stability, ``raildyn critical-speed --method
    bisection``) on the sign of the growth rate of wheelset 1's lateral motion between the
    bracket speeds; returns the midpoint of the final bracket (a bracket end when the sign
    does not change). Each probe is a variant run of the case (reused with --reuse), checked
    for wheel forces, and the fastest one identifies the creep coefficients."""
    lo, hi = CRITICAL_SPEED_BRACKET
    rows = []

    def probe(v: float) -> dict:
        res = ctx.run_variant(f"v{v:.3f}", f"&simulation speed = {v:.6g}, t_end = {CRITICAL_SPEED_T_END:g} /")
        with res:
            missing = [w for w in deck_wheelsets(ctx.case.deck_path)
                       if not ctx.has(f"wheelsets/{w}/left/wheel:force_lateral_Y", res)]
            if missing:
                raise CaseError(f"speed {v:g} m/s: no wheel forces of {', '.join(missing)}: the scene "
                                "ran without wheel-rail contact (contact not wired)")
            t = ctx.time(res)
            y = ctx.get(row["channel"], res)
            m = window_mask(t, float(row["t_from"]), float(row["t_to"]))
            rate, npk = growth_rate(t[m], y[m])
            best = ctx.cache.get("creep_coefficients_speed", -1.0)
            if v > best:      # identified at the fastest probe (largest creepages of the runs)
                ctx.cache["creep_coefficients"] = identify_knife_edge_contact(ctx, ["w1", "w2"], float(row["t_from"]),
                                                                              res)
                ctx.cache["creep_coefficients_speed"] = v
        rows.append([f"{v:.3f}", f"{rate:.4g}", npk, "growth" if rate > 0 else "decay"])
        return {"speed": v, "growth_rate": rate, "peaks": npk}

    # resolution: the half-width, so that the final bracket is CRITICAL_SPEED_RESOLUTION wide
    answer = bisection_critical_speed(ctx.case.deck_path, lo, hi, CRITICAL_SPEED_RESOLUTION / 2, row["channel"],
                                      float(row["t_from"]), float(row["t_to"]), ctx.out_dir, ctx.exe, jobs=1,
                                      probe=probe)
    a, b = answer.bracket
    if answer.critical_speed is None:
        ctx.result.tables.append(Table("Critical speed search", ["speed m/s", "growth rate 1/s", "peaks", ""], rows))
        return a
    vc = answer.critical_speed
    ctx.result.tables.append(Table(f"Critical speed search: {vc:.2f} m/s (bracket {a:.2f}-{b:.2f} m/s)",
                                   ["speed m/s", "growth rate 1/s", "peaks", ""], rows))
    return vc


def evaluate_tgv(ctx: Context) -> None:
    rows = [r for r in load_tgv_checks() if r["case"] == ctx.case.name]
    if not rows:
        raise CaseError(f"validation/tgv_checks.csv has no check for case {ctx.case.name}")
    for row in rows:
        kind = CHECK_KINDS.get(row["kind"])
        if kind is None:
            raise CaseError(f"tgv_checks.csv: unknown kind {row['kind']!r} (check {row['id']})")
        try:
            kind(ctx, row)
        except (CaseError, StabilityError) as exc:
            ctx.check(row["id"], False, None, "", "", f"not evaluated: {exc}")
    if not ctx.case.run:
        return
    t = ctx.time()
    nws = sum(1 for k in range(1, 5) if ctx.has(f"bodies/ws{k}/position_track:y"))
    if nws:
        ctx.plot("Lateral displacement of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:y"))
                                                          for k in range(1, nws + 1)], "y [mm]", 1e3)
        ctx.plot("Yaw angle of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:yaw"))
                                                for k in range(1, nws + 1)], "yaw [mrad]", 1e3)
    if ctx.has("wheelsets/w1/left/wheel:force_lateral_Y"):
        ctx.plot("Lateral wheel forces of wheelset 1", [(f"w1 {s}", t, ctx.get(f"wheelsets/w1/{s}/wheel:force_lateral_Y"))
                                                        for s in ("left", "right")], "force [kN]", 1e-3)
