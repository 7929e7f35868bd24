"""docs/output.md and the scene's channels cannot drift: every series a scene with bodies,
elements and wheelsets writes is documented (name, components, unit) and every documented
series of those groups is written."""
import re
from pathlib import Path

import raildyn

REPO = Path(__file__).resolve().parents[2]


def documented(section_title):
    text = (REPO / "docs" / "output.md").read_text()
    start = text.index(section_title)
    end = text.index("\n#", start + 5)      # the next heading of any level
    rows = {}
    for line in text[start:end].splitlines():
        m = re.match(r"\| `([^`]+)` \| `([^`]+)` \| `?([^`|]+)`? \|", line)
        if m:
            rows[m.group(1)] = (m.group(2).split(), m.group(3).strip())
    return rows


def test_scene_channels_match_the_documentation():
    m = raildyn.Model.from_file(REPO / "inputs" / "tgv_wheelset.nml")
    m.initialize(write_output=False)
    names = m.output_names()
    m.close()
    body = [n for n in names if n.startswith("bodies/")][0].split("/")[1]
    element = [n for n in names if n.startswith("elements/")][0].split("/")[1]
    wheelset = [n for n in names if n.startswith("wheelsets/")][0].split("/")[1]
    for title, prefix in (("### `/bodies/<name>/`", f"bodies/{body}/"),
                          ("### `/elements/<name>/`", f"elements/{element}/"),
                          ("### `/wheelsets/<name>/` and", f"wheelsets/{wheelset}/")):
        doc = documented(title)
        written = {n[len(prefix):] for n in names if n.startswith(prefix)}
        pattern = {re.sub(r"^(left|right)/", "<side>/", re.sub(r"patch\d+$", "patch<j>", n))
                   for n in written}
        assert pattern == set(doc), (title, sorted(pattern ^ set(doc)))
    # components as documented (checked through the HDF5 file, which carries them)
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        deck = Path(d) / "w.nml"
        deck.write_text(f"&include file = '{REPO / 'inputs' / 'tgv_wheelset.nml'}' /\n"
                        "&simulation t_end = 0.01 /\n&output file = 'w.h5' /\n")
        m = raildyn.Model.from_file(deck)
        m.initialize(write_output=True)
        m.advance(0.01)
        m.finalize()
        m.close()
        r = raildyn.Results(Path(d) / "w.h5")
        for title, prefix in (("### `/bodies/<name>/`", f"bodies/{body}/"),
                              ("### `/elements/<name>/`", f"elements/{element}/"),
                              ("### `/wheelsets/<name>/` and", f"wheelsets/{wheelset}/")):
            doc = documented(title)
            for name in (n for n in r.channels() if n.startswith(prefix)):
                key = re.sub(r"^(left|right)/", "<side>/", re.sub(r"patch\d+$", "patch<j>", name[len(prefix):]))
                comps, unit = doc[key]
                assert list(r.components(name)) == comps, name
