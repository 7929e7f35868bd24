"""Track irregularities: the Python generator and writer (python/raildyn/irregularity.py) and
the runner reading ``&track irregularity_file``.

Oracles: the variance of the random-phase signal against the closed-form integral of the
ERRI B176 spectrum over the band (and over a sub-band, through the record's periodogram),
within 4 standard errors of the mean over independent seeds; the closed form itself against
a trapezoidal quadrature of the spectrum; the runner's one-line file:line messages.
"""
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from raildyn.irregularity import (band_variance, erri_psd, read_irregularity,
                                  synthetic_irregularity, write_irregularity)

REPO = Path(__file__).resolve().parents[2]

WAVELENGTHS = (3.0, 120.0)
BAND = (2 * math.pi / WAVELENGTHS[1], 2 * math.pi / WAVELENGTHS[0])


@pytest.mark.parametrize("level", ["low", "high"])
@pytest.mark.parametrize("component", ["alignment", "level"])
def test_band_variance_closed_form(level, component):
    """The partial-fraction integral against a fine trapezoidal rule (independent)."""
    w = np.linspace(*BAND, 400001)
    s = erri_psd(w, level, component)
    quad = float(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(w)))
    assert band_variance(*BAND, level, component) == pytest.approx(quad, rel=1e-8)


def _ensemble(stat, n_seeds=24, **kw):
    values = np.array([stat(seed) for seed in range(n_seeds)])
    return values.mean(), values.std(ddof=1) / math.sqrt(n_seeds)


@pytest.mark.parametrize("component", ["alignment", "level"])
def test_variance_equals_psd_integral(component):
    """E[mean square of the record] = integral of S over the band (exactly, for random phases
    and frequencies uniform in their bins); tolerance 4 standard errors over 24 seeds."""
    expected = band_variance(*BAND, "high", component)

    def mean_square(seed):
        _, c = synthetic_irregularity(3000.0, step=0.5, level="high", wavelengths=WAVELENGTHS,
                                      n_waves=600, seed=seed, components=(component,))
        return float(np.mean(c[component] ** 2))

    mean, stderr = _ensemble(mean_square)
    print(f"{component}: mean square {mean:.4e} +- {stderr:.1e} m^2, closed form {expected:.4e} m^2 "
          f"(rms {math.sqrt(expected) * 1e3:.3f} mm)")
    assert abs(mean - expected) <= 4 * stderr
    assert stderr < 0.05 * expected   # the test can resolve a 20 % error


def test_subband_power_follows_the_spectrum():
    """Power of the record's periodogram in the D1 band (3-25 m) against the closed form over
    that band: the shape of the spectrum, not only its integral."""
    d1 = (2 * math.pi / 25.0, 2 * math.pi / 3.0)
    expected = band_variance(*d1, "low", "alignment")

    def band_power(seed):
        sigma, c = synthetic_irregularity(3000.0, step=0.5, level="low", wavelengths=WAVELENGTHS,
                                          n_waves=600, seed=seed, components=("alignment",))
        x = c["alignment"]
        n = x.size
        spec = np.abs(np.fft.rfft(x)) ** 2 / n**2
        omega = 2 * math.pi * np.fft.rfftfreq(n, d=0.5)
        inside = (omega >= d1[0]) & (omega <= d1[1])
        return float(2 * spec[inside].sum())   # one-sided: both signs of the frequency

    mean, stderr = _ensemble(band_power)
    print(f"D1 power {mean:.4e} +- {stderr:.1e} m^2, closed form {expected:.4e} m^2")
    assert abs(mean - expected) <= 4 * stderr
    assert stderr < 0.05 * expected


def test_seed_reproducible_and_components():
    a = synthetic_irregularity(100.0, seed=7)
    b = synthetic_irregularity(100.0, seed=7)
    assert np.array_equal(a[1]["alignment"], b[1]["alignment"])
    assert not np.array_equal(a[1]["alignment"], a[1]["level"])
    assert not np.any(a[1]["cross_level"]) and not np.any(a[1]["gauge"])
    with pytest.raises(ValueError, match="no ERRI B176 spectrum"):
        synthetic_irregularity(100.0, components=("gauge",))
    with pytest.raises(ValueError, match="too coarse"):
        synthetic_irregularity(100.0, step=1.0, wavelengths=(3.0, 50.0))


def test_write_read_roundtrip(tmp_path):
    sigma, c = synthetic_irregularity(200.0, step=0.25, level="high", seed=3)
    p = tmp_path / "rec.txt"
    write_irregularity(p, sigma, comment="ERRI B176 high, seed 3", **c)
    text = p.read_text()
    assert text.startswith("# ERRI B176 high, seed 3\n# sigma_m alignment_m level_m cross_level_m gauge_m")
    s2, c2 = read_irregularity(p)
    assert np.allclose(s2, sigma, atol=1e-6, rtol=0)
    for k in c:
        assert np.allclose(c2[k], c[k], rtol=1e-9, atol=1e-15)


def test_write_refuses_what_the_reader_refuses(tmp_path):
    s = np.array([0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="metres"):
        write_irregularity(tmp_path / "a.txt", s, alignment=np.array([0.0, 2.0, 0.0]))
    with pytest.raises(ValueError, match="increasing"):
        write_irregularity(tmp_path / "a.txt", np.array([0.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="finite"):
        write_irregularity(tmp_path / "a.txt", s, gauge=np.array([0.0, np.nan, 0.0]))
    with pytest.raises(ValueError, match="values for"):
        write_irregularity(tmp_path / "a.txt", s, level=np.zeros(4))


# ---------------------------------------------------------------- runner
DECK = """&simulation title = 'irregularity', t_end = 2.0, speed = 10.0, equilibrium = 'none' /
&output interval = 0.01 /
&track irregularity_file = '{file}', irregularity_fade = 5.0 /
&body name = 'ws1', mass = 1500.0, ixx = 799.35, iyy = 93.75, izz = 799.35, position = 0.0, 0.0, 0.45 /
&wheelset name = 'w1', body = 'ws1', contact = 'knife_edge', nominal_radius = 0.45,
      contact_distance = 1.5, conicity = 0.10033, creep_law = 'linear', creep_saturation = 'none',
      shear_modulus = 8.4e10, poisson = 0.25, contact_damping = 5.0e5 /
&element name = 'spring1', type = 'spring_damper', body1 = 'ground', body2 = 'ws1',
      point1 = 0.0, 1.0, 0.45, point2 = 0.0, 1.0, 0.0, stiffness = 5.0e5, 0.0, 0.0 /
&element name = 'spring2', type = 'spring_damper', body1 = 'ground', body2 = 'ws1',
      point1 = 0.0, -1.0, 0.45, point2 = 0.0, -1.0, 0.0, stiffness = 5.0e5, 0.0, 0.0 /
&external_force body = 'ws1', frame = 'track', force = 0.0, 0.0, -120723.0 /
"""


def run(exe, *args, cwd=None):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=120)


def test_runner_deck_with_irregularity_file(raildyn_exe, tmp_path):
    """The path is relative to the deck (run from another directory); a constant 1 mm
    alignment after a 5 m fade-in pulls the wheelset towards +Y."""
    h5py = pytest.importorskip("h5py")
    (tmp_path / "irr").mkdir()
    s = np.array([0.0, 1000.0])
    write_irregularity(tmp_path / "irr" / "rec.txt", s, alignment=np.array([1e-3, 1e-3]))
    deck = tmp_path / "scene.nml"
    deck.write_text(DECK.format(file="irr/rec.txt"))
    (tmp_path / "work").mkdir()
    res = run(raildyn_exe, "run", deck, cwd=tmp_path / "work")
    assert res.returncode == 0, res.stderr
    with h5py.File(tmp_path / "work" / "scene.h5", "r") as f:
        y = f["bodies/ws1/position_track"][:, 1]
        assert "irr/rec.txt" in f["meta/deck_text"][()].decode()
    # kinematic wavelength 11 m: within 20 m the wheelset has moved well towards the rails
    print(f"lateral position after 20 m: {y[-1] * 1e3:.3f} mm (alignment 1 mm), max {y.max() * 1e3:.3f} mm")
    assert y.max() > 0.5e-3 and y.max() < 2.5e-3


@pytest.mark.parametrize("lines, line_no, words", [
    (["0 0 0 0 0", "1 0 abc 0 0"], 2, ["column 3", "not a number", "expected 5 numbers"]),
    (["0 0 0 0 0", "1 0 0 0"], 2, ["4 columns, expected 5"]),
    (["# header", "0 0 0 0 0", "0 0 0 0 0"], 3, ["does not increase", "strictly increasing"]),
    (["0 0 0 0 0", "1 0 nan 0 0"], 2, ["not finite"]),
    (["0 0 0 0 0", "1 0 0 1.5 0"], 2, ["metres"]),
])
@pytest.mark.parametrize("command", ["check", "run"])
def test_bad_irregularity_file_fails_well(raildyn_exe, tmp_path, lines, line_no, words, command):
    rec = tmp_path / "rec.txt"
    rec.write_text("\n".join(lines) + "\n")
    deck = tmp_path / "scene.nml"
    deck.write_text(DECK.format(file="rec.txt"))
    res = run(raildyn_exe, command, deck, cwd=tmp_path)
    assert res.returncode == 1, (res.returncode, res.stdout, res.stderr)
    err = [l for l in res.stderr.splitlines() if l.strip()]
    assert len(err) == 1, res.stderr
    msg = err[0]
    assert f"{deck}:3:" in msg and "irregularity_file" in msg, msg       # the deck line
    assert f"{rec}:{line_no}:" in msg, msg                               # the file line
    for w in words:
        assert w in msg, msg
    for bad in ("Fortran runtime error", "Backtrace", "NaN"):
        assert bad not in res.stderr + res.stdout
    assert not (tmp_path / "scene.h5").exists()


def test_example_deck_and_scale(raildyn_exe, tmp_path):
    """inputs/tgv_wheelset_irregular.nml runs; irregularity_scale = 0 turns the irregularities
    off (lateral motion at the numerical noise level), scale 1 excites the wheelset."""
    h5py = pytest.importorskip("h5py")
    example = REPO / "inputs" / "tgv_wheelset_irregular.nml"
    text = example.read_text()
    record = REPO / "inputs" / "irregularities" / "erri_low_400m_seed1.txt"
    assert "irregularity_scale = 1.0" in text
    lateral = {}
    for scale in ("1.0", "0.0"):
        deck = tmp_path / f"scale{scale}.nml"
        deck.write_text(text.replace("irregularity_scale = 1.0", f"irregularity_scale = {scale}")
                        .replace("'irregularities/erri_low_400m_seed1.txt'", f"'{record}'"))
        res = run(raildyn_exe, "run", deck, cwd=tmp_path)
        assert res.returncode == 0, res.stderr
        with h5py.File(deck.with_suffix(".h5"), "r") as f:
            t = f["time"][:]
            y = f["bodies/ws1/position_track"][:, 1]
            q_left = f["wheelsets/w1/left/wheel"][:, 3]
        lateral[scale] = np.abs(y).max()
        print(f"scale {scale}: max |y| {lateral[scale] * 1e3:.4f} mm, left Q {q_left[t > 0.5].min() / 1e3:.1f}"
              f"..{q_left[t > 0.5].max() / 1e3:.1f} kN")
    assert lateral["0.0"] < 1e-6 and lateral["1.0"] > 1e-4
