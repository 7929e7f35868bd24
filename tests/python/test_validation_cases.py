"""One test per validation case (python/raildyn/validation/, docs/validation.md): run the
scene with the runner and apply the case's comparison and acceptance rule, so that CI fails
when the physics regresses. Markers: `validation` plus the case name (pytest.ini).

Results go to $RAILDYN_VALIDATION_OUT if set (kept, e.g. for the HTML report or `--reuse`),
else to a temporary directory of the session. A case that cannot run (executable missing,
scene not able to build bodies or wheelsets, run failure) FAILS with the harness' message;
nothing is skipped."""
import os
from pathlib import Path

import pytest

from raildyn import validation as V


@pytest.fixture(scope="session")
def validation_out(tmp_path_factory, build_dir):
    os.environ.setdefault("RAILDYN_BUILD_DIR", str(build_dir))
    out = os.environ.get("RAILDYN_VALIDATION_OUT")
    out = Path(out) if out else tmp_path_factory.mktemp("validation")
    # contact tables of the cases (manchester_v1_tc1_tables) next to their results, not in the
    # user's cache
    os.environ.setdefault("RAILDYN_CACHE_DIR", str(out / "table_cache"))
    return out


# Known failures, visible in every test report (xfail), with the reason; the issue that asks
# for these cases stays open until they pass. strict=True: a case that starts passing turns
# the test red, so the mark cannot outlive the problem.
KNOWN_FAILURES: dict = {}


@pytest.mark.parametrize("name", [pytest.param(n, marks=[pytest.mark.validation, getattr(pytest.mark, n)]
                                                  + ([KNOWN_FAILURES[n]] if n in KNOWN_FAILURES else []))
                                  for n in V.CASES])
def test_validation_case(name, validation_out):
    res = V.run_case(name, validation_out)
    passed = res.passed        # (the CaseResult's repr would carry the plots)
    assert passed, res.summary()
