"""`raildyn conicity` on the reference cases of EN 15302:2008+A1:2010 Annex E with the
tolerance of its Annex F, the standard's own benchmark of a calculation method (step 1:
the calculation on given Delta r functions). The data are the transcription of the nine
cases in validation/reference/en15302_annex_e/ (provenance, column meanings and caveats in
its README): Delta r every 0.1 mm and the reference equivalent conicity every 0.1 mm of
amplitude, 1 to 7.5 mm.

Annex F: |tan(gamma_e) - reference| <= min(0.05, 0.5 reference). Every amplitude whose
kinematic motion stays inside the Delta r rows is checked (the rows stop at 6.8-7.1 mm; the
largest amplitude is computed here from the rows' potential, independently of raildyn). The
integration (Klingel) method also reproduces the printed references to their rounding
(0.0005) plus 0.0005 for the interpolation of the 0.1 mm rows, except E5, whose rows are of
another kind (README) and which is held to Annex F only. Measured: within 0.0007 (E1-E4,
E6-E9), 0.0062 (E5)."""
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[2] / "validation" / "reference" / "en15302_annex_e"
#: first and last y [mm] of each case's Delta r rows (README table)
ROWS = {1: (-6.8, 6.8), 2: (-6.8, 6.8), 3: (-6.8, 6.8), 4: (-7.1, 7.1), 5: (-6.8, 6.8), 6: (-6.9, 6.8),
        7: (-6.8, 6.7), 8: (-7.1, 7.0), 9: (-6.8, 6.8)}


def case_rows(n):
    dr = np.array((DATA / f"dr_ce_E{n}.dat").read_text().split(), float)
    a, b = ROWS[n]
    y = a + 0.1 * np.arange(round((b - a) / 0.1) + 1)
    assert y.size == dr.size, f"E{n}: {dr.size} Delta r values for {y.size} rows"
    return y * 1e-3, dr * 1e-3


def largest_amplitude(y, dr):
    """Half the widest motion about the centre (where Delta r rises through 0, or the middle of
    its zero zone) whose energy stays below the potential at both table ends: the turning
    points solve V(y) = min(V(first row), V(last row)), V = integral of Delta r (trapezoids:
    exact for the linear rows)."""
    v = np.concatenate([[0.0], np.cumsum(0.5 * (dr[1:] + dr[:-1]) * np.diff(y))])
    lo = np.flatnonzero(dr < 0)[-1]             # last row left of the centre with Delta r < 0
    hi = np.flatnonzero(dr > 0)[0]              # first row right of it with Delta r > 0
    assert lo < hi
    e = min(v[0], v[-1])
    fine = np.linspace(y[0], y[-1], 200001)
    vf = np.interp(fine, y, v)                  # V between rows is quadratic; linear is enough here
    left = fine[(fine <= y[lo]) & (vf <= e)].min()
    right = fine[(fine >= y[hi]) & (vf <= e)].max()
    return 0.5 * (right - left)


@pytest.mark.parametrize("n", sorted(ROWS))
def test_annex_e_case_within_annex_f(raildyn_exe, tmp_path, n):
    y, dr = case_rows(n)
    table = tmp_path / f"E{n}.csv"
    table.write_text("".join(f"{a!r},{b!r}\n" for a, b in zip(y, dr)))
    ref = np.loadtxt(DATA / f"ben_E{n}.dat")
    a_max = largest_amplitude(y, dr)
    ref = ref[ref[:, 0] * 1e-3 <= a_max - 2e-6]       # 2 um inside the last supported motion
    assert ref.shape[0] >= 40
    res = subprocess.run([str(raildyn_exe), "conicity", "--delta-r", str(table), "--r0", "0.46", "--e0", "0.75",
                          "--amplitudes", ",".join(f"{a * 1e-3!r}" for a in ref[:, 0]), "--json"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["amplitude"] == pytest.approx(ref[:, 0] * 1e-3, rel=1e-12)
    conicity = np.array(out["conicity"], float)
    reference = ref[:, 1]
    annex_f = np.minimum(0.05, 0.5 * reference)
    assert np.all(np.abs(conicity - reference) <= annex_f + 1e-12), \
        [(a, c, r) for a, c, r, t in zip(ref[:, 0], conicity, reference, annex_f) if abs(c - r) > t]
    if n != 5:
        assert np.abs(conicity - reference).max() <= 0.001
