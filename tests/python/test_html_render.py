"""The HTML pages raildyn writes, rendered by a real browser (headless Chromium, Debian package
`chromium`, installed by `scripts/setup.sh --tests`): the assessment page of
`raildyn assess --html` and the validation report (raildyn.report, whose look and helpers
the assessment page shares).

For each page the test checks, independently of the code that wrote it:

- every reference of the page (src, href, url(...)) resolves: an anchor names an element of
  the page, a data: URI holds a decodable PNG, a relative path names an existing file; none
  points off the machine (the pages are self-contained);
- in the browser, every image of the page decoded (complete, natural width > 0; a probe page
  loads the page in a frame and reads its DOM), and the page has text;
- the screenshot of the whole page (PNG) was written, has the page's size and is not blank:
  dark pixels (text) and coloured pixels (plots, pass/fail cells).

The checks themselves are tested on broken pages (a missing image, a damaged data URI, a
missing style sheet, an anchor to nothing, a blank page): each must be caught.
"""
import base64
import io
import re
import shutil
import subprocess
import urllib.parse
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from raildyn.assess import assess
from raildyn.assess.report import write_html
from raildyn.report import figure_png, write_report
from raildyn.validation import CaseResult, Check, Table
from raildyn.validation.fidelity_map import published_section
from test_assess_results_file import write_scene

WIDTH = 1280


def chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.fail("chromium not installed (scripts/setup.sh --tests installs Debian's chromium)")
    return exe


def run_chromium(profile: Path, *args, timeout=180) -> subprocess.CompletedProcess:
    # --no-sandbox: the tests run as root, where Chromium's sandbox refuses to start; a
    # private profile directory keeps parallel runs apart and writes nothing in $HOME
    return subprocess.run([chromium(), "--headless", "--no-sandbox", "--disable-gpu",
                           "--hide-scrollbars", "--no-first-run", "--allow-file-access-from-files",
                           f"--user-data-dir={profile}", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout)


class _References(HTMLParser):
    """Every reference of a page: (what, value) for src/href/srcset/data/poster attributes and
    url(...) in style elements and style attributes; the ids of its elements."""

    def __init__(self):
        super().__init__()
        self.refs, self.ids, self._in_style = [], set(), False

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name == "id":
                self.ids.add(value)
            elif name in ("src", "href", "data", "poster"):
                self.refs.append((f"<{tag} {name}>", value))
            elif name == "srcset":
                self.refs += [(f"<{tag} srcset>", v.split()[0]) for v in value.split(",") if v.strip()]
            elif name == "style":
                self.refs += [(f"<{tag} style>", u) for u in _css_urls(value)]
        self._in_style = tag == "style"

    def handle_endtag(self, tag):
        self._in_style = False

    def handle_data(self, data):
        if self._in_style:
            self.refs += [("<style>", u) for u in _css_urls(data)]


def _css_urls(css: str) -> list[str]:
    return [m.strip("'\" ") for m in re.findall(r"url\(([^)]*)\)", css)]


def _png_decodes(data: bytes) -> bool:
    import matplotlib.image
    try:
        return matplotlib.image.imread(io.BytesIO(data), format="png").size > 0
    except Exception:
        return False


def missing_references(page: Path) -> list[str]:
    """What the page refers to and cannot be had: the list is empty for a sound page."""
    parser = _References()
    parser.feed(page.read_text(encoding="utf-8"))
    problems = []
    for what, ref in parser.refs:
        if ref.startswith("#"):
            if ref[1:] not in parser.ids:
                problems.append(f"{what} {ref}: no element with that id")
        elif ref.startswith("data:"):
            head, _, payload = ref.partition(",")
            if not head.startswith("data:image/png;base64"):
                problems.append(f"{what} {head}: not a base64 PNG")
            else:
                try:
                    ok = _png_decodes(base64.b64decode(payload, validate=True))
                except ValueError:
                    ok = False
                if not ok:
                    problems.append(f"{what} {head}: the PNG does not decode")
        elif re.match(r"[a-z][a-z0-9+.-]*:", ref, re.I) or ref.startswith("//"):
            problems.append(f"{what} {ref}: refers off the page's directory (not self-contained)")
        else:
            target = page.parent / urllib.parse.unquote(ref.split("#")[0].split("?")[0])
            if not target.is_file():
                problems.append(f"{what} {ref}: no such file")
    return problems


PROBE = """<!DOCTYPE html><html><head><meta charset='utf-8'></head><body><pre id='result'>no load</pre>
<iframe id='page' src='{page}' width='{width}' height='600'></iframe>
<script>
document.getElementById('page').addEventListener('load', function () {{
  var out = [];
  try {{
    var doc = this.contentDocument;
    for (var i = 0; i < doc.images.length; i++) {{
      var img = doc.images[i];
      out.push('img ' + (img.complete && img.naturalWidth > 0 ? 'ok' : 'broken') + ' ' +
               (img.getAttribute('src') || '').slice(0, 40));
    }}
    out.push('text ' + doc.body.innerText.length);
    out.push('height ' + doc.documentElement.scrollHeight);
  }} catch (e) {{ out.push('error ' + e); }}
  document.getElementById('result').textContent = out.join('\\n');
}});
</script></body></html>
"""


def browser_probe(page: Path, profile: Path) -> dict:
    """Load ``page`` in Chromium (in a frame of a probe page beside it) and read its DOM:
    {'images': [(ok, src)], 'text': characters of text, 'height': page height in px}."""
    probe = page.parent / f"probe_{page.stem}.html"
    probe.write_text(PROBE.format(page=urllib.parse.quote(page.name), width=WIDTH), encoding="utf-8")
    try:
        res = run_chromium(profile, "--virtual-time-budget=10000", "--dump-dom", probe.as_uri())
    finally:
        probe.unlink()
    assert res.returncode == 0, res.stderr[-2000:]
    m = re.search(r"<pre id=\"result\">(.*?)</pre>", res.stdout, re.S)
    assert m, res.stdout[:2000]
    lines = m.group(1).splitlines()
    assert not any(line.startswith(("error", "no load")) for line in lines), lines
    images = [(line.split()[1] == "ok", line.split(" ", 2)[2] if line.count(" ") > 1 else "")
              for line in lines if line.startswith("img ")]
    text = int(next(line.split()[1] for line in lines if line.startswith("text ")))
    height = int(next(line.split()[1] for line in lines if line.startswith("height ")))
    return {"images": images, "text": text, "height": height}


def screenshot(page: Path, png: Path, height: int, profile: Path) -> np.ndarray:
    """The whole page as a PNG (window as high as the page), read back as an RGB array."""
    import matplotlib.image
    res = run_chromium(profile, f"--screenshot={png}", f"--window-size={WIDTH},{height}", page.as_uri())
    assert res.returncode == 0 and png.is_file(), res.stderr[-2000:]
    return matplotlib.image.imread(png)[..., :3]


def ink(image: np.ndarray) -> tuple[float, float]:
    """(share of dark pixels, share of coloured pixels) of an RGB image in [0, 1]."""
    dark = np.mean(image.mean(axis=2) < 0.5)
    coloured = np.mean(image.max(axis=2) - image.min(axis=2) > 0.08)   # the green bands and cells: 0.09-0.11
    return float(dark), float(coloured)


def check_page(page: Path, tmp_path: Path, n_images: int) -> Path:
    """Every check of the module text on one page; returns the screenshot."""
    assert missing_references(page) == []
    profile = tmp_path / "chromium-profile"
    seen = browser_probe(page, profile)
    assert len(seen["images"]) == n_images
    assert all(ok for ok, _ in seen["images"]), [src for ok, src in seen["images"] if not ok]
    assert seen["text"] > 200
    height = min(seen["height"], 16000)
    png = tmp_path / f"{page.stem}.png"
    image = screenshot(page, png, height, profile)
    assert image.shape[:2] == (height, WIDTH)
    dark, coloured = ink(image)
    assert dark > 5e-4, dark             # text (a blank page has none)
    assert coloured > 0.01, coloured     # plots and the coloured result cells
    return png


def test_assessment_page_renders(make_results_file, tmp_path):
    a = assess(write_scene(make_results_file))
    page = write_html(a, tmp_path / "html")
    n_plots = sum(1 for q in a.quantities if q.series)
    assert n_plots > 5
    check_page(page, tmp_path, n_plots)


def test_validation_report_renders(tmp_path):
    t = np.linspace(0.0, 2.0, 201)
    case = CaseResult(
        name="synthetic_case", title="a synthetic case", description="rendering only",
        deck="inputs/none.nml", results_path="none.h5", status="completed", run_wall_time=1.5,
        raildyn_version="0", deck_sha256="0" * 64,
        checks=[Check("inside", True, 1.0, "< 2", "m", "by construction"),
                Check("outside", False, 3.0, "< 2", "m", "by construction")],
        tables=[Table("values", ["quantity", "unit", "raildyn", "reference"],
                      [["a", "m", 1.0, 1.1], ["b", "N", 2.0, 2.5]], [True, False], note="a note")],
        plots=[("sine", figure_png("sine", [("y", t, np.sin(2 * np.pi * t))], "m",
                                   bands=[("band", t, np.sin(2 * np.pi * t) - 0.1,
                                           np.sin(2 * np.pi * t) + 0.1)]))],
        notes=["a note"])
    # with the published fidelity map's section (raildyn.validation.fidelity_map): its tables
    # and its Pareto plot, the second image of the page
    page = write_report([case], tmp_path / "report.html", git_commit="0000000",
                        sections=[published_section()])
    check_page(page, tmp_path, 2)


def test_the_checks_catch_broken_pages(tmp_path):
    """A page with a missing image file, a damaged data URI, a missing style sheet and an
    anchor to nothing: each is reported; the browser sees the two images broken; a blank page
    has no ink."""
    good = base64.b64encode(figure_png("x", [("y", np.arange(3.0), np.arange(3.0))], "m")).decode()
    damaged = base64.b64encode(b"\x89PNG\r\n\x1a\n" + b"not an image" * 20).decode()    # PNG signature, no image
    page = tmp_path / "broken.html"
    page.write_text("<!DOCTYPE html><html><head><link rel='stylesheet' href='gone.css'></head><body>"
                    "<p><a href='#nowhere'>x</a> text</p><img src='gone.png'>"
                    f"<img src='data:image/png;base64,{damaged}'><img src='data:image/png;base64,{good}'>"
                    "</body></html>", encoding="utf-8")
    problems = missing_references(page)
    assert len(problems) == 4, problems
    assert any("gone.css" in p for p in problems) and any("gone.png" in p for p in problems)
    assert any("#nowhere" in p for p in problems) and any("does not decode" in p for p in problems)
    seen = browser_probe(page, tmp_path / "chromium-profile")
    assert [ok for ok, _ in seen["images"]] == [False, False, True]
    blank = tmp_path / "blank.html"
    blank.write_text("<!DOCTYPE html><html><body></body></html>", encoding="utf-8")
    image = screenshot(blank, tmp_path / "blank.png", 400, tmp_path / "chromium-profile")
    assert ink(image) == (0.0, 0.0)
