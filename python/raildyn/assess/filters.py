"""Filters of the standards as s-domain transfer functions, applied in the frequency domain.

Comfort weightings (EN 12299:2009 annex A, which takes them from ISO 2631-1:1997 annex A and,
for Wb, from ISO 2631-4:2001 / BS 6841:1987): each weighting is the product of

- band limiting: a second-order Butterworth high pass at f1 and low pass at f2
  ``Hh = 1 / (1 + sqrt(2) w1/p + (w1/p)^2)``, ``Hl = 1 / (1 + sqrt(2) p/w2 + (p/w2)^2)``;
- acceleration-velocity transition ``Ht = (1 + p/w3) / (1 + p/(Q4 w4) + (p/w4)^2)``;
- upward step ``Hs = (1 + p/(Q5 w5) + (p/w5)^2) / (1 + p/(Q6 w6) + (p/w6)^2) (w5/w6)^2``
  (Wb only);

times a gain K, with ``p = j 2 pi f`` and ``w_i = 2 pi f_i``. SECONDARY SOURCE: the parameter
values below are those of ISO 2631-1:1997 table A.2 (Wc, Wd) and of BS 6841:1987 / ISO
2631-4:2001 (Wb) as the ride-comfort literature quotes them; the text of EN 12299 was not at
hand (docs/assessment.md "Sources"). Checked (tests/python/test_assess_filters.py) against
three published tables, none read in the standard itself: ISO 2631-1:1997 table 3 (Wc, Wd at
the one-third-octave frequencies, as reproduced in the literature); ISO 8041's parameter
table (all three, as reproduced in Larson Davis, HVM200 Reference Manual, table 3.1); the
value at the reference frequency 100 rad/s (Wb 0.8126, Wc 0.5145, Wd 0.1261, as listed by
ZETLAB, "Frequency weighting functions").

The filters are applied by multiplying the signal's discrete Fourier transform with the
transfer function at the exact bin frequencies (no bilinear warping): gain and phase are
the s-domain ones at every bin. The signal is padded with zeros (``causal``: the filter
then acts like the analogue filter switched on at the first sample, the long tail of the
0.4 Hz high pass included) or, for the zero-phase magnitude filters (``magnitude_filter``),
extended by its mirror image so that the ends do not ring. The transfer function stops at
the Nyquist frequency, where the weightings still pass (Wb 0.115 at 100 Hz): the cut makes a
small precursor ahead of a sudden onset (1e-5 of the output 0.1 s ahead at 200 Hz sampling,
3e-8 at 1 kHz; tests/python/test_assess_filters.py), negligible for rms values.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Weighting", "WEIGHTINGS", "weighting_response", "apply_weighting",
           "butterworth_lowpass_gain", "butterworth_bandpass_gain", "magnitude_filter"]


@dataclass(frozen=True)
class Weighting:
    """Parameters of one frequency weighting (frequencies in Hz)."""
    name: str
    f1: float
    f2: float
    f3: float
    f4: float
    q4: float
    f5: float | None = None
    q5: float | None = None
    f6: float | None = None
    q6: float | None = None
    k: float = 1.0
    source: str = ""


#: The comfort weightings of EN 12299 (SECONDARY SOURCE, see the module text).
WEIGHTINGS: dict[str, Weighting] = {
    "Wb": Weighting("Wb", 0.4, 100.0, 16.0, 16.0, 0.55, 2.5, 0.9, 4.0, 0.95, 1.024,
                    "vertical, floor (EN 12299 / ISO 2631-4:2001 / BS 6841:1987; ISO 8041 table; secondary)"),
    "Wc": Weighting("Wc", 0.4, 100.0, 8.0, 8.0, 0.63, k=1.0,
                    source="longitudinal, seat back (ISO 2631-1:1997 table A.2, ISO 8041 table; secondary)"),
    "Wd": Weighting("Wd", 0.4, 100.0, 2.0, 2.0, 0.63, k=1.0,
                    source="horizontal, floor and seat (ISO 2631-1:1997 table A.2, ISO 8041 table; secondary)"),
}


def weighting_response(name: str, f) -> np.ndarray:
    """Complex transfer function H(j 2 pi f) of weighting ``name`` ('Wb', 'Wc', 'Wd')."""
    w = WEIGHTINGS[name]
    f = np.asarray(f, float)
    p = 2j * np.pi * f
    with np.errstate(divide="ignore", invalid="ignore"):
        w1, w2, w3, w4 = (2 * np.pi * x for x in (w.f1, w.f2, w.f3, w.f4))
        # high pass written with p in the numerator so that f = 0 gives 0, not 0/0
        hh = p**2 / (p**2 + np.sqrt(2.0) * w1 * p + w1**2)
        hl = 1.0 / (1.0 + np.sqrt(2.0) * p / w2 + (p / w2) ** 2)
        ht = (1.0 + p / w3) / (1.0 + p / (w.q4 * w4) + (p / w4) ** 2)
        h = hh * hl * ht * w.k
        if w.f5 is not None:
            w5, w6 = 2 * np.pi * w.f5, 2 * np.pi * w.f6
            h = h * (1.0 + p / (w.q5 * w5) + (p / w5) ** 2) / (1.0 + p / (w.q6 * w6) + (p / w6) ** 2) \
                * (w5 / w6) ** 2
    return h


def _padded_length(n: int, extra: int) -> int:
    """A length >= n + extra with small prime factors (fast FFT)."""
    m = n + extra
    size = 1
    while size < m:
        size *= 2
    for candidate in (size * 3 // 4, size * 5 // 8):   # 3*2^k and 5*2^k are also fast
        if candidate >= m:
            size = min(size, candidate)
    return size


def apply_weighting(name: str, a, fs: float, settle: float = 20.0) -> np.ndarray:
    """The weighted acceleration of ``a`` sampled at ``fs`` [Hz]: the causal analogue filter
    applied to the signal zero-padded by ``settle`` seconds (the impulse response of the
    0.4 Hz high pass has decayed to 1e-15 of its start after 20 s, so nothing wraps)."""
    a = np.asarray(a, float)
    n = a.size
    if n == 0:
        return a.copy()
    size = _padded_length(n, max(n, int(np.ceil(settle * fs))))
    spectrum = np.fft.rfft(a, size)
    f = np.fft.rfftfreq(size, 1.0 / fs)
    return np.fft.irfft(spectrum * weighting_response(name, f), size)[:n]


def butterworth_lowpass_gain(f, fc: float, order: int = 4) -> np.ndarray:
    """|H| of a Butterworth low pass of the given order and cut-off fc [Hz]."""
    return 1.0 / np.sqrt(1.0 + (np.asarray(f, float) / fc) ** (2 * order))


def butterworth_bandpass_gain(f, f_low: float, f_high: float, order: int = 4) -> np.ndarray:
    """|H| of a Butterworth high pass at f_low times a low pass at f_high."""
    f = np.asarray(f, float)
    with np.errstate(divide="ignore"):
        high = 1.0 / np.sqrt(1.0 + (f_low / np.where(f > 0, f, np.nan)) ** (2 * order))
    return np.nan_to_num(high, nan=0.0) * butterworth_lowpass_gain(f, f_high, order)


def magnitude_filter(y, fs: float, gain) -> np.ndarray:
    """Zero-phase filtering of ``y`` (sampled at fs [Hz]) with the real gain ``gain(f)``: the
    signal is extended by its mirror image at both ends (no jump where the ends meet), and
    the spectrum multiplied by the gain (what a forward-backward filter with |H| does)."""
    y = np.asarray(y, float)
    n = y.size
    if n < 2:
        return y.copy()
    ext = np.concatenate([y[::-1], y, y[::-1]])
    spectrum = np.fft.rfft(ext)
    f = np.fft.rfftfreq(ext.size, 1.0 / fs)
    return np.fft.irfft(spectrum * gain(f), ext.size)[n:2 * n]
