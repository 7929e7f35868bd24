#!/usr/bin/env python3
"""Replace one benchmark's section of docs/performance.md (between <!-- BEGIN name --> and
<!-- END name -->), or append it. Used by every script in bench/.

    python3 bench/performance_section.py NAME TABLE_FILE [TITLE]
"""
import sys
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance.md"


def write_section(name: str, body: str, title: str = "") -> None:
    begin, end = f"<!-- BEGIN {name} -->", f"<!-- END {name} -->"
    text = DOC.read_text() if DOC.exists() else "# Performance\n"
    heading = f"{title}\n\n" if title else ""
    block = f"{begin}\n{heading}{body.rstrip()}\n{end}"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        text = head + block + rest.split(end, 1)[1]
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    DOC.write_text(text)


if __name__ == "__main__":
    write_section(sys.argv[1], Path(sys.argv[2]).read_text(), sys.argv[3] if len(sys.argv) > 3 else "")
