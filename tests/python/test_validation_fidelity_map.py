"""The fidelity map (issue 14 item 3) as a section of the validation report.

bench/fidelity_map/run.py publishes one measurement twice: docs/performance.md's section
fidelity_map and validation/fidelity_map.json (with the Pareto plot docs/fidelity_map.png),
which raildyn.validation.fidelity_map turns into the report's section. Checked here, on the
published files: the two publications are one measurement (the JSON's rows are the docs' table
rows, line for line, and they name the same source); every fidelity level of the bench's
scenes (bench/fidelity_map/run.py scene_list, the integrators on each scene's fastest level
included) has its row; the report shows the section, linked from the summary, with its tables
and the plot. A missing or foreign file gives a section that says so, not an exception.
No simulation runs.
"""
import html
import json
from pathlib import Path

from conftest import load_script
from raildyn.report import render_report
from raildyn.validation import fidelity_map as FM

REPO = Path(__file__).resolve().parents[2]


def docs_section() -> str:
    text = (REPO / "docs" / "performance.md").read_text()
    return text[text.index("<!-- BEGIN fidelity_map -->"):text.index("<!-- END fidelity_map -->")]


def test_published_map_is_the_docs_map_and_has_every_level():
    data = json.loads(FM.PUBLISHED_JSON.read_text())
    md = docs_section()
    md_rows = [ln for ln in md.splitlines() if ln.startswith("| ") and not ln.startswith("| level |")]
    json_rows = ["| " + " | ".join(r) + " |" for t in data["tables"] for r in t["rows"]]
    assert json_rows == md_rows
    assert data["source"] in md and data["intro"] in md
    assert not data["quick"], "a quick (shortened) run is not a published map"
    fm = load_script("bench/fidelity_map/run.py", "bench_fidelity_map_run_pub")
    tables = {t["title"]: {r[0] for r in t["rows"]} for t in data["tables"]}
    for sc in fm.scene_list():
        levels = {lv.name for lv in sc.levels + fm.integrator_levels(sc)}
        assert levels <= tables[sc.title], (sc.title, levels - tables[sc.title])
    assert FM.PUBLISHED_PNG.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_report_shows_the_section():
    sec = FM.published_section()
    page = render_report([], "0000000", sections=[sec])
    assert "<section id='fidelity_map'>" in page and "<a href='#fidelity_map'>" in page
    assert len(sec.tables) >= 3 and len(sec.plots) == 1
    body = page[page.index("<section id='fidelity_map'>"):]
    for tab in sec.tables:
        assert f"<h3>{html.escape(tab.title, quote=True)}</h3>" in body
        for row in tab.rows:
            assert f"<td>{html.escape(row[0], quote=True)}</td>" in body, row[0]
    assert body.count("data:image/png;base64,") == 1
    # rows coloured by their run's outcome: every published row completed
    assert all(all(tab.status) and len(tab.status) == len(tab.rows) for tab in sec.tables)
    assert body.count("<tr class='pass'>") == sum(len(tab.rows) for tab in sec.tables)
    assert body.count("<td class='v'>completed</td>") == sum(len(tab.rows) for tab in sec.tables)


def test_a_row_that_did_not_complete_is_red(tmp_path):
    data = json.loads(FM.PUBLISHED_JSON.read_text())
    t = data["tables"][0]
    k = t["columns"].index("outcome")
    t["rows"][1][k] = "FAILURE (solver failure)"
    path = tmp_path / "map.json"
    path.write_text(json.dumps(data))
    sec = FM.published_section(path, FM.PUBLISHED_PNG)
    assert sec.tables[0].status[1] is False and sec.tables[0].status[0] is True
    page = render_report([], "0000000", sections=[sec])
    assert page.count("<tr class='fail'>") == 1


def test_missing_or_foreign_file_is_said(tmp_path):
    sec = FM.published_section(tmp_path / "none.json", tmp_path / "none.png")
    assert not sec.tables and sec.paragraphs[0].startswith("Not published")
    foreign = tmp_path / "foreign.json"
    foreign.write_text('{"rows": []}')
    sec = FM.published_section(foreign, tmp_path / "none.png")
    assert not sec.tables and sec.paragraphs[0].startswith("Not shown")
    page = render_report([], "0000000", sections=[sec])
    assert "Not shown" in page
