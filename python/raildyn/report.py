"""Self-contained HTML report of validation cases (raildyn.validation): one file, plots
embedded as base64 PNG (matplotlib, Agg backend), no external resources."""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import os
import platform
from pathlib import Path
from typing import Sequence

__all__ = ["figure_png", "write_report", "render_report"]


def figure_png(title: str, series: list, ylabel: str, scale: float = 1.0,
               window: tuple[float, float] | None = None, bands: list = (),
               xlabel: str = "time [s]") -> bytes:
    """PNG of histories: series = [(label, t, y)], y multiplied by ``scale``; an optional
    shaded evaluation window and tolerance bands [(label, t, lower, upper)]; the abscissa is
    time unless ``xlabel`` says otherwise (e.g. track position)."""
    from .plots import agg_pyplot
    plt = agg_pyplot()
    fig, ax = plt.subplots(figsize=(8.0, 3.6), dpi=90)
    try:
        for label, t, lo, hi in bands:
            ax.fill_between(t, lo * scale, hi * scale, alpha=0.25, color="tab:green", label=label)
        for label, t, y in series:
            ax.plot(t, y * scale, lw=1.0, label=label)
        if window is not None:
            ax.axvspan(window[0], window[1], color="0.85", zorder=0, label="evaluation window")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, lw=0.3)
        if series or bands:
            ax.legend(fontsize=7, ncol=4, loc="best")
        fig.tight_layout()
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        return buf.getvalue()
    finally:
        plt.close(fig)


_CSS = """
body { font-family: sans-serif; margin: 1.5em; max-width: 80em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1em 0; font-size: 0.85em; }
th, td { border: 1px solid #bbb; padding: 2px 6px; text-align: left; vertical-align: top; }
th { background: #eee; }
tr.pass td.v { background: #d8f0d8; } tr.fail td.v { background: #f6d0d0; }
.pass-badge { color: #fff; background: #2a7d2a; padding: 1px 6px; border-radius: 3px; }
.fail-badge { color: #fff; background: #b02020; padding: 1px 6px; border-radius: 3px; }
.error { color: #b02020; font-weight: bold; }
section { border-top: 2px solid #888; margin-top: 2em; }
img { max-width: 100%; }
code { font-size: 0.9em; }
"""


def _e(x) -> str:
    return html.escape(str(x))


def _badge(ok: bool) -> str:
    return '<span class="pass-badge">PASS</span>' if ok else '<span class="fail-badge">FAIL</span>'


def _fmt(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def _tables_html(tables) -> list[str]:
    out = []
    for tab in tables:
        out.append(f"<h3>{_e(tab.title)}</h3><table><tr>" +
                   "".join(f"<th>{_e(c)}</th>" for c in tab.columns) + "</tr>")
        for i, row in enumerate(tab.rows):
            st = tab.status[i] if i < len(tab.status) else None
            cls = "" if st is None else ("pass" if st else "fail")
            cells = "".join(f"<td class='v'>{_e(_fmt(x))}</td>" if j == tab.value_column else f"<td>{_e(_fmt(x))}</td>"
                            for j, x in enumerate(row))
            out.append(f"<tr class='{cls}'>{cells}</tr>")
        out.append("</table>")
        if tab.note:
            out.append(f"<p><small>{_e(tab.note)}</small></p>")
    return out


def _plots_html(plots) -> list[str]:
    return [f"<h4>{_e(title)}</h4><img alt='{_e(title)}' src='data:image/png;base64,"
            f"{base64.b64encode(png).decode('ascii')}'/>" for title, png in plots]


def render_report(results: Sequence, git_commit: str = "", total_time: float | None = None,
                  sections: Sequence = ()) -> str:
    """The HTML text for a list of raildyn.validation.CaseResult, followed by `sections`
    (raildyn.validation.core.ReportSection: published measurements such as the fidelity map)."""
    now = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    versions = sorted({r.raildyn_version for r in results if r.raildyn_version})
    out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'><title>raildyn validation report</title>",
           f"<style>{_CSS}</style></head><body>", "<h1>raildyn validation report</h1>",
           "<p>", f"Generated {now}; raildyn {_e(', '.join(versions) or 'unknown')}; "
           f"repository commit {_e(git_commit or 'unknown')}; Python {_e(platform.python_version())}"
           + (f"; total {total_time:.1f} s" if total_time is not None else "") + ".</p>",
           "<p>Cases, reference data and acceptance rules: <code>docs/validation.md</code>, "
           "<code>validation/</code>. Units SI unless a column says otherwise; frames and signs "
           "as <code>docs/conventions.md</code>.</p>",
           "<h2>Summary</h2><table><tr><th>case</th><th>result</th><th>run status</th>"
           "<th>run time s</th><th>checks passed</th><th>deck</th></tr>"]
    for r in results:
        npass = sum(c.passed for c in r.checks)
        rt = "" if r.run_wall_time is None else f"{r.run_wall_time:.1f}"
        out.append(f"<tr class='{'pass' if r.passed else 'fail'}'><td><a href='#{_e(r.name)}'>{_e(r.name)}</a></td>"
                   f"<td class='v'>{_badge(r.passed)}</td><td>{_e(r.status)}</td><td>{rt}</td>"
                   f"<td>{npass}/{len(r.checks)}</td><td><code>{_e(r.deck)}</code></td></tr>")
    out.append("</table>")
    if sections:
        out.append("<p>Also in this report: " + ", ".join(f"<a href='#{_e(sec.name)}'>{_e(sec.title)}</a>"
                                                         for sec in sections) + ".</p>")
    for r in results:
        out.append(f"<section id='{_e(r.name)}'><h2>{_e(r.name)}: {_e(r.title)} {_badge(r.passed)}</h2>")
        out.append(f"<p>{_e(r.description)}</p>")
        out.append("<table>"
                   f"<tr><th>deck</th><td><code>{_e(r.deck)}</code> (sha256 of the deck and its "
                   f"includes: <code>{_e(r.deck_sha256[:16])}</code>)</td></tr>"
                   f"<tr><th>results</th><td><code>{_e(r.results_path)}</code></td></tr>"
                   f"<tr><th>run status</th><td>{_e(r.status)}</td></tr>"
                   f"<tr><th>run wall time</th><td>{'' if r.run_wall_time is None else f'{r.run_wall_time:.2f} s'}</td></tr>"
                   f"<tr><th>raildyn version</th><td>{_e(r.raildyn_version)}</td></tr></table>")
        if r.error:
            out.append(f"<p class='error'>Not evaluated: {_e(r.error)}</p>")
        if r.checks:
            out.append("<h3>Checks</h3><table><tr><th>check</th><th>result</th><th>value</th>"
                       "<th>unit</th><th>limit</th><th>detail</th></tr>")
            for c in r.checks:
                out.append(f"<tr class='{'pass' if c.passed else 'fail'}'><td>{_e(c.name)}</td>"
                           f"<td class='v'>{'pass' if c.passed else 'FAIL'}</td><td>{_e(_fmt(c.value))}</td>"
                           f"<td>{_e(c.unit)}</td><td>{_e(c.limit)}</td><td>{_e(c.detail)}</td></tr>")
            out.append("</table>")
        out += _tables_html(r.tables)
        if r.notes:
            out.append("<h3>Notes</h3><ul>" + "".join(f"<li>{_e(n)}</li>" for n in r.notes) + "</ul>")
        if r.assumptions:
            out.append("<h3>Assumptions (ASSUMPTION lines of the deck and its includes)</h3><ul>" +
                       "".join(f"<li>{_e(a)}</li>" for a in r.assumptions) + "</ul>")
        out += _plots_html(r.plots)
        out.append("</section>")
    for sec in sections:
        out.append(f"<section id='{_e(sec.name)}'><h2>{_e(sec.title)}</h2>")
        out += [f"<p>{_e(par)}</p>" for par in sec.paragraphs]
        out += _tables_html(sec.tables) + _plots_html(sec.plots)
        out.append("</section>")
    out.append("</body></html>")
    return "\n".join(out)


def write_report(results: Sequence, path: str | os.PathLike, git_commit: str = "",
                 total_time: float | None = None, sections: Sequence = ()) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(render_report(results, git_commit, total_time, sections), encoding="utf-8")
    return path
