"""The repository stands on its own: no tracked file names a directory of a development
machine (the reference folder beside a development checkout, the machines' work tree, a user's
home, a named file or folder in a temporary directory). A clone on another machine has none of
them, so a test, deck or doc pointing there is broken or misleading."""
import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# The character classes keep this file's own patterns from matching themselves.
MACHINE_PATH = re.compile(
    r"\.\./share[d]\b"                           # the reference folder beside a development checkout
    r"|(?<![\w.~-])/wor[k]/"                     # the development machines' work tree
    r"|(?<![\w.~-])/(?:tm[p]|var/tm[p])/[\w.-]"  # a fixed name under a temporary folder
    r"|(?<![\w.~-])/(?:hom[e]|User[s])/[\w.-]"   # a user's home folder
    r"|(?<![\w.~-])/roo[t]/")                    # root's home folder


def machine_paths(text: str) -> list[tuple[int, str]]:
    """(line number, matched text) of every machine path in text."""
    return [(text.count("\n", 0, m.start()) + 1, m.group(0)) for m in MACHINE_PATH.finditer(text)]


# The examples are split into adjacent literals so that this file itself stays clean.
@pytest.mark.parametrize("text, found", [
    ("see ../sha" "red/reference/oracles.md", ["../sha" "red"]),
    ("! Sources: /wo" "rk/shared/reference/x.md", ["/wo" "rk/"]),
    ("csv = '/tm" "p/raildyn_test.csv'", ["/tm" "p/r"]),
    ("frozen from /var/tm" "p/val/a.h5", ["/var/tm" "p/v"]),
    ("lib = '/ho" "me/alice/build/libraildyn.so'", ["/ho" "me/a"]),
    ("open /Use" "rs/bob/x and /ro" "ot/y", ["/Use" "rs/b", "/ro" "ot/"]),
    ("a/wo" "rk/b, src/tm" "p/x, ~/tm" "p/x, $TMPDIR (else /tm" "p), validation/reference/", []),
])
def test_the_pattern(text, found):
    """The pattern finds what it is meant to find and nothing in ordinary relative paths."""
    assert [m for _, m in machine_paths(text)] == found


def test_no_machine_paths_in_tracked_files():
    """git ls-files: every tracked file, text or binary, is free of machine paths."""
    if not (REPO / ".git").exists():
        pytest.skip("not a git work tree: the tracked files are unknown")
    files = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True, check=True
                           ).stdout.decode().split("\0")
    offenders = []
    for name in filter(None, files):
        path = REPO / name
        if not path.is_file():          # deleted in the work tree, not yet committed
            continue
        text = path.read_bytes().decode("utf-8", errors="replace")
        offenders += [f"{name}:{line}: {match}" for line, match in machine_paths(text)]
    assert not offenders, "machine paths in tracked files (cite by repository path or title):\n" + \
        "\n".join(offenders)
