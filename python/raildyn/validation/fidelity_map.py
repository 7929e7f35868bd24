"""The fidelity map (issue 14 item 3) as a section of the validation report.

bench/fidelity_map/run.py measures every fidelity level of the Manchester, TGV profile and TGV
knife-edge scenes (CPU s, real-time factor, steps, RHS calls, error against each scene's
reference) and publishes the same tables twice: in docs/performance.md (section
fidelity_map) and in validation/fidelity_map.json, with the Pareto plot docs/fidelity_map.png.
The report shows that published measurement with its source line (commit, host, date); it does
not rerun the bench (about ten CPU minutes on the project machine), so a report says when the
map it shows was measured.
"""
from __future__ import annotations

import json
from pathlib import Path

from .core import REPO, ReportSection, Table

PUBLISHED_JSON = REPO / "validation" / "fidelity_map.json"
PUBLISHED_PNG = REPO / "docs" / "fidelity_map.png"
TITLE = "Fidelity map: cost against accuracy"


def published_section(json_path: Path = PUBLISHED_JSON, png_path: Path = PUBLISHED_PNG) -> ReportSection:
    """The report's fidelity-map section from the published files; a section saying what is
    missing when they are not there (never an exception: the report of the cases still goes out)."""
    sec = ReportSection("fidelity_map", TITLE)
    if not json_path.exists():
        sec.paragraphs = [f"Not published: no {json_path.name} (run bench/fidelity_map/run.py)."]
        return sec
    try:
        data = json.loads(json_path.read_text())
        tables = [Table(t["title"], list(t["columns"]), [list(r) for r in t["rows"]],
                        # a row's outcome is green when its run completed (every level of the
                        # map should), red when it ended otherwise
                        [r[t["columns"].index("outcome")].startswith("completed") for r in t["rows"]],
                        " ".join(x for x in (t.get("note", ""), t.get("footnote", "")) if x),
                        value_column=t["columns"].index("outcome"))
                  for t in data["tables"]]
        paragraphs = [data["label"], data["intro"], data["source"] + " Published by bench/fidelity_map/run.py "
                      "(docs/performance.md, \"Fidelity map\"; which level for what: \"Which fidelity level for what\")."]
    except (ValueError, KeyError, TypeError) as exc:
        sec.paragraphs = [f"Not shown: {json_path.name} is not the bench's output ({type(exc).__name__}: {exc})."]
        return sec
    if data.get("quick"):
        paragraphs.insert(0, "QUICK run (shortened scenes): not a published measurement.")
    sec.paragraphs, sec.tables = paragraphs, tables
    if png_path.exists():
        sec.plots = [("CPU s against the error from each scene's reference (Pareto front labelled)",
                      png_path.read_bytes())]
    else:
        sec.paragraphs.append(f"The Pareto plot ({png_path.name}) is missing.")
    return sec
