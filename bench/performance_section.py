#!/usr/bin/env python3
"""Replace one benchmark's section of docs/performance.md (between <!-- BEGIN name --> and
<!-- END name -->), or append it. Used by every script in bench/.

    python3 bench/performance_section.py NAME TABLE_FILE [TITLE]
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "performance.md"


def bench_arguments(doc: str) -> argparse.ArgumentParser:
    """The options every measuring script takes: --build, --json, --from-json, --no-write."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--build", default=os.environ.get("RAILDYN_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--json", default=None, help="write the measurements as JSON")
    ap.add_argument("--from-json", default=None, help="render an earlier run's JSON instead of measuring")
    ap.add_argument("--no-write", action="store_true", help="print, leave docs/performance.md alone")
    return ap


def earlier_json(args) -> dict | None:
    """The measurements of an earlier run (--from-json), or None: measure now."""
    return json.loads(Path(args.from_json).read_text()) if args.from_json else None


def measurement_start(args) -> tuple[Path, str, datetime.datetime]:
    """The runner to measure (--build), the repository's revision and the start time (UTC)."""
    return (Path(args.build).resolve() / "bin" / "raildyn", git_revision(),
            datetime.datetime.now(datetime.timezone.utc))


def git_revision() -> str:
    """The repository's HEAD, short (the 'on commit' of a published measurement)."""
    return subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()


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
