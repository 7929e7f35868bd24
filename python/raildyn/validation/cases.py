"""The validation cases (CASES) and running them: a case's run (or given results), the
contact-output and band checks every case gets, its evaluation."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

from ..results import Results
from ..stability import StabilityError
from . import references
from .core import CaseError, CaseResult
from .manchester import evaluate_manchester, evaluate_manchester_quiet
from .runs import Case, Context, RunInfo, deck_assumptions, deck_sha256, deck_wheelsets, run_deck, run_notes
from .signals import compare_band_curve
from .tgv import evaluate_tgv

_TGV_BASE = ("bodies/ws1/position_track:y", "bodies/ws1/position_track:yaw", "bodies/ws2/position_track:y")
_MANCHESTER_BASE = ("bodies/ws1/position_track:y", "bodies/ws1/position_track:yaw",
                    "wheelsets/w1/left/wheel:force_lateral_Y", "wheelsets/w1/left/wheel:force_vertical_Q")

CASES: dict[str, Case] = {c.name: c for c in [
    Case("manchester_v1_tc1", "manchester_v1_tc1.nml", "Manchester Benchmark Vehicle 1, Track Case 1",
         "Quasi-static curving in R 150 m with 100 mm cant at 4.4 m/s: wheelset lateral shift and yaw, "
         "wheel forces against the five packages of thesis tables 5.9-5.11, and quiet (no contact "
         "loss, wheel loads steady within 1 kN in the window; issue 12).", evaluate_manchester_quiet,
         baseline_channels=_MANCHESTER_BASE),
    Case("manchester_v1_tc1_tables", "manchester_v1_tc1_tables.nml",
         "Manchester Benchmark Vehicle 1, Track Case 1, contact tables",
         "The acceptance scene with its profile contact evaluated from pre-computed tables of the strip "
         "model (docs/theory_contact_geometry.md section 10): the same rule.", evaluate_manchester,
         baseline_channels=_MANCHESTER_BASE),
    Case("tgv_wheelset", "tgv_wheelset.nml", "TGV 001 single wheelset, straight, 20 m/s",
         "Knife-edge wheelset on primary springs to the track frame: the 1 mm disturbance decays.",
         evaluate_tgv, baseline_channels=_TGV_BASE[:2]),
    Case("tgv_bogie_straight_20", "tgv_bogie_straight_20.nml", "TGV 001 bogie, straight, 20 m/s",
         "Thesis 5.3.4.1, figs. 5.16-5.17: stable, the 1 mm offset decays.", evaluate_tgv,
         baseline_channels=_TGV_BASE),
    Case("tgv_bogie_straight_40", "tgv_bogie_straight_40.nml", "TGV 001 bogie, straight, 40 m/s",
         "Thesis fig. 5.18: hunting grows; wavelength between the wheelset and rigid-bogie Klingel values.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_bogie_critical_speed", "tgv_bogie_straight_40.nml", "TGV 001 bogie, critical speed",
         "Bisection between 20 and 40 m/s on decay vs growth after a lateral pulse (8 s runs of the 40 m/s deck).",
         evaluate_tgv, run=False),
    Case("tgv_bogie_curve", "tgv_bogie_curve.nml", "TGV 001 bogie, transition into R 1000 m, 20 m/s",
         "Thesis 5.3.4.2, figs. 5.20-5.22: wheelsets move outward, the trailing one less; settle in the curve.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_vehicle_straight", "tgv_vehicle_straight.nml", "TGV 001 vehicle (42 DOF), straight, 20 m/s",
         "Thesis 5.3.4.3: the complete vehicle is stable.", evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_vehicle_curve", "tgv_vehicle_curve.nml", "TGV 001 vehicle (42 DOF), transition into R 1000 m",
         "Thesis 5.3.4.4, figs. 5.24-5.27: wheelsets 1/3 and 2/4 alike, trailing wheelsets shifted less.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_profile_fastsim", "tgv_profile_fastsim.nml", "TGV 001 vehicle, S1002/UIC60, FASTSIM, 25.6 m/s",
         "Thesis 5.5, figs. 5.52-5.64: flange-limited lateral shift of the leading wheelsets.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_profile_polach", "tgv_profile_polach.nml", "TGV 001 vehicle, S1002/UIC60, Polach, 25.6 m/s",
         "Thesis 5.6, figs. 5.65-5.70: Polach close to FASTSIM, both without spin creepage as in the "
         "thesis; the FASTSIM reference is this deck rerun with creep_law = 'fastsim'.", evaluate_tgv,
         baseline_channels=_TGV_BASE),
]}


# ------------------------------------------------------------------------------------------
# case execution


def _check_contact_outputs(ctx: Context) -> None:
    """Every wheelset of the deck must have written its wheel forces: a scene that runs the
    bodies without wheel-rail contact must not pass a validation case by accident."""
    missing = [w for w in deck_wheelsets(ctx.case.deck_path)
               if not ctx.has(f"wheelsets/{w}/left/wheel:force_lateral_Y")]
    ctx.check("wheel-rail contact outputs present", not missing, None, "all wheelsets", "",
              "" if not missing else "no wheelsets/<name>/left/wheel for " + ", ".join(missing) +
              ": the scene ran without wheel-rail contact for these wheelsets (contact not wired)")


def _attach_band_checks(ctx: Context) -> None:
    """Reference curves (validation/curves/<case>/*.csv) and the frozen baseline."""
    files = sorted((references.BANDS / "curves" / ctx.case.name).glob("*.csv"))
    base = references.BANDS / "baselines" / f"{ctx.case.name}.csv"
    sources = [("reference curve", f) for f in files] + ([("baseline", base)] if base.exists() else [])
    t = ctx.time()
    for kind, f in sources:
        for ch, (tr, v, lo, hi) in references.read_band_csv(f).items():
            try:
                y = ctx.get(ch)
            except CaseError as exc:
                ctx.check(f"{kind} {f.name}: {ch}", False, None, "", "", str(exc))
                continue
            ok, worst, tw, n = compare_band_curve(t, y, tr, lo, hi)
            ctx.check(f"{kind} {f.name}: {ch}", ok, worst, "0 (inside the band)", "",
                      f"largest excursion outside the band at t = {tw:.3f} s over {n} points")
            ctx.plot(f"{ch} against {kind} {f.name}", [("raildyn", t, y)], ch, 1.0,
                     bands=[(kind, tr, lo, hi)])


def run_case(name: str, out_dir: str | os.PathLike, exe: str | os.PathLike | None = None,
             reuse: bool = False, given: str | os.PathLike | None = None) -> CaseResult:
    """Run (or reuse) one case and evaluate it. Never raises for physics or run problems:
    they are reported in the CaseResult (``error`` and failed checks).
    ``given``: evaluate this results file instead of running the case's deck (e.g. one run of
    a campaign that varies the deck); the report says so."""
    case = CASES[name]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = CaseResult(name, case.title, case.description, f"inputs/{case.deck}")
    try:
        res.assumptions = deck_assumptions(case.deck_path)
        res.deck_sha256 = deck_sha256(case.deck_path)
    except (OSError, CaseError) as exc:
        res.error = f"deck {case.deck_path}: {exc}"
        return res
    results_path = out_dir / f"{name}.h5"
    try:
        r = None
        if case.run and given is not None:
            given = Path(given)
            if not given.is_file():
                raise CaseError(f"results file {given} given for case {name} (--results) does not exist")
            info = RunInfo(given, 0, 0.0, "", reused=True)
            res.results_path = os.fspath(given)
            res.notes.append(f"results taken from {given} (--results), not run from the case deck "
                             f"inputs/{case.deck}: the assumptions listed are that deck's")
            r = Results(given)
        elif case.run:
            info = run_deck(case.deck_path, results_path, exe, reuse=reuse)
            res.results_path = os.fspath(info.results)
            res.run_wall_time = None if info.reused else info.wall_time
            r = Results(info.results)
        try:
            if r is not None:
                meta = r.metadata
                res.status = str(meta.get("status"))
                res.raildyn_version = str(meta.get("raildyn_version") or "")
                if info.reused:
                    wt = meta.get("wall_time")
                    res.run_wall_time = float(wt) if wt is not None else None
                    if given is None:
                        res.notes.append("results reused from an earlier run (--reuse)")
                if res.status != "completed":
                    res.notes.append(f"run status: {res.status}")
                res.notes.extend(f"run: {n}" for n in run_notes(meta))
                if meta.get("solver"):
                    res.notes.append("solver statistics: " + ", ".join(
                        f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}"
                        for k, v in sorted(meta["solver"].items())))
            else:
                res.status = "variants only"
            ctx = Context(case, res, r, out_dir, exe, reuse)
            try:
                if r is not None:
                    _check_contact_outputs(ctx)
                case.evaluate(ctx)
                if r is not None:
                    _attach_band_checks(ctx)
            finally:
                ctx.close()
        finally:
            if r is not None:
                r.close()
    except (CaseError, StabilityError) as exc:
        res.error = str(exc)
    except (KeyError, ValueError, OSError) as exc:
        res.error = f"{type(exc).__name__}: {exc}"
    return res


def run_cases(names: Sequence[str], out_dir: str | os.PathLike, exe: str | os.PathLike | None = None,
              reuse: bool = False, given: dict[str, Path] | None = None) -> list[CaseResult]:
    """Run and evaluate the cases (each once, in the order given). ``given``: case name ->
    results file to evaluate instead of running that case's deck."""
    given = dict(given or {})
    return [run_case(n, out_dir, exe, reuse, given.get(n)) for n in dict.fromkeys(names)]
