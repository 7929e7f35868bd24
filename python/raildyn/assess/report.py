"""Outputs of an assessment: the JSON summary, a text table, CSV series, PNG plots and a
self-contained HTML page in the style of the validation report (raildyn.report)."""
from __future__ import annotations

import base64
import csv
import datetime as _dt
import json
import re
from pathlib import Path

import numpy as np

from ..report import _CSS, _e, _fmt, figure_png   # the validation report's look and helpers
from .assessment import Assessment
from .quantity import Quantity

__all__ = ["to_json_text", "text_table", "write_csv", "quantity_plots", "render_html", "write_html"]


def to_json_text(a: Assessment) -> str:
    return json.dumps(a.to_json(), indent=1, allow_nan=False)


def _verdict(q: Quantity) -> str:
    if not q.available:
        return "not available"
    if q.passed is None:
        return ""
    return "inside" if q.passed else "EXCEEDED"


def text_table(a: Assessment) -> str:
    """One line per quantity: label, value, limit, margin, position, verdict or reason."""
    lines = [f"raildyn assess: {a.results_path} (run status {a.status})"]
    for q in a.quantities:
        if q.available:
            limit = "" if q.limit is None else f" limit {q.limit:.4g}"
            margin = "" if q.margin is None else f" margin {100 * q.margin:.1f} %"
            at = "" if q.position is None or not np.isfinite(q.position) else f" at {q.position:.2f} m"
            lines.append(f"  {q.label()}: {q.value:.4g} {q.unit}{limit}{margin}{at} {_verdict(q)}")
        else:
            lines.append(f"  {q.label()}: not available: {q.reason}")
    lines += [f"  note: {n}" for n in a.notes]
    return "\n".join(lines)


def _slug(q: Quantity) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", q.label()).strip("_")


_SUMMARY_COLUMNS = ["name", "wheelset", "side", "patch", "sensor", "direction", "value", "limit",
                    "margin", "unit", "position", "clause", "source", "reason"]


def write_csv(a: Assessment, directory) -> list[Path]:
    """``quantities.csv`` (one row per quantity) and one CSV per quantity series
    (``<quantity label>.csv``: abscissa [m or s], value [unit])."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    written = [out / "quantities.csv"]
    with open(written[0], "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(_SUMMARY_COLUMNS)
        for q in a.quantities:
            row = q.to_json()
            w.writerow(["" if row.get(c) is None else (repr(row[c]) if isinstance(row[c], float) else row[c])
                        for c in _SUMMARY_COLUMNS])
    for q in a.quantities:
        if not q.series:
            continue
        axis = "position" if "position" in q.series else "time"
        target = out / f"{_slug(q)}.csv"
        header = f"{axis} [{'m' if axis == 'position' else 's'}],{q.name} [{q.unit}]"
        np.savetxt(target, np.column_stack([q.series[axis], q.series["value"]]), fmt="%.17g",
                   delimiter=",", header=header, comments="")
        written.append(target)
    return written


def quantity_plots(a: Assessment) -> list[tuple[str, bytes]]:
    """One PNG per quantity series, the limit drawn as the allowed band."""
    plots = []
    for q in a.quantities:
        if not q.series:
            continue
        axis = "position" if "position" in q.series else "time"
        x, y = np.asarray(q.series[axis]), np.asarray(q.series["value"])
        # every limit bounds a magnitude; a series that never goes below 0 (Q, an rms) gets
        # the band's upper half only, so that its scale is not doubled by nothing
        lower = 0.0 if np.all(y >= 0) else -1.0
        bands = [] if q.limit is None else [(f"allowed (|value| <= {q.limit:.4g})", x,
                                             np.full_like(x, lower * q.limit), np.full_like(x, q.limit))]
        plots.append((q.label(), figure_png(f"{q.label()} [{q.unit}]", [(q.label(), x, y)],
                                            f"{q.name} [{q.unit}]",
                                            bands=bands, xlabel="track position [m]" if axis == "position"
                                            else "time [s]")))
    return plots


def render_html(a: Assessment, plots: list[tuple[str, bytes]]) -> str:
    now = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    n_limit = [q for q in a.quantities if q.passed is not None]
    exceeded = [q for q in n_limit if not q.passed]
    out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'><title>raildyn assessment</title>",
           f"<style>{_CSS}</style></head><body>", "<h1>raildyn assessment</h1>",
           f"<p>Results <code>{_e(a.results_path)}</code> ({_e(a.title)}), run status "
           f"{_e(a.status)}; generated {now}. Quantities, formulas, clauses and sources: "
           "<code>docs/assessment.md</code>; values marked secondary come from the literature "
           "quoting the standards, not from their text.</p>",
           f"<p>{len(n_limit) - len(exceeded)} of {len(n_limit)} quantities with a limit inside "
           f"it; {sum(not q.available for q in a.quantities)} not available.</p>",
           "<h2>Quantities</h2><table><tr><th>quantity</th><th>value</th><th>unit</th>"
           "<th>limit</th><th>margin</th><th>position m</th><th>result</th><th>clause</th>"
           "<th>source</th></tr>"]
    for q in a.quantities:
        cls = "" if q.passed is None else ("pass" if q.passed else "fail")
        margin = "" if q.margin is None else f"{100 * q.margin:.1f} %"
        result = _verdict(q) if q.available else f"not available: {q.reason}"
        pos = "" if q.position is None or not np.isfinite(q.position) else f"{q.position:.2f}"
        out.append(f"<tr class='{cls}'><td>{_e(q.label())}</td><td class='v'>{_e(_fmt(q.value))}</td>"
                   f"<td>{_e(q.unit)}</td><td>{_e(_fmt(q.limit))}</td><td>{margin}</td><td>{pos}</td>"
                   f"<td>{_e(result)}</td><td>{_e(q.clause)}</td><td>{_e(q.source)}</td></tr>")
    out.append("</table>")
    if a.notes:
        out.append("<h2>Notes</h2><ul>" + "".join(f"<li>{_e(n)}</li>" for n in a.notes) + "</ul>")
    if plots:
        out.append("<h2>Series</h2>")
    for title, png in plots:
        out.append(f"<h4>{_e(title)}</h4><img alt='{_e(title)}' src='data:image/png;base64,"
                   f"{base64.b64encode(png).decode('ascii')}'/>")
    out.append("</body></html>")
    return "\n".join(out)


def write_html(a: Assessment, directory) -> Path:
    """``assessment.html`` (plots embedded) and the plots as PNG files beside it."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    plots = quantity_plots(a)
    for title, png in plots:
        (out / (re.sub(r"[^A-Za-z0-9_.-]+", "_", title).strip("_") + ".png")).write_bytes(png)
    page = out / "assessment.html"
    page.write_text(render_html(a, plots), encoding="utf-8")
    return page
