"""Track irregularity files for ``&track irregularity_file`` (docs/theory_track.md).

    >>> from raildyn.irregularity import synthetic_irregularity, write_irregularity
    >>> sigma, comps = synthetic_irregularity(1000.0, step=0.25, level="low", seed=1)
    >>> write_irregularity("erri_low.txt", sigma, **comps)

File format (read by ``rd_track_irregularity``): text, ``#`` starts a comment, five columns
``sigma_m alignment_m level_m cross_level_m gauge_m``, sigma strictly increasing, every offset
in metres with ``|offset| <= 0.1`` m. Signs (docs/conventions.md, "Track irregularities"):
alignment + moves the track centre line to +Y (left), level + up, cross-level + = left rail
higher, gauge + = widened.

Synthetic irregularities follow the ERRI B176 / ORE spectra of alignment and vertical level
(ORE B176, "Bogies with steered or steering wheelsets", Report No. 1: Specifications and
proposals, Utrecht 1989; the parameter values below are those reproduced throughout the
railway-dynamics literature, not re-checked against the report itself)::

    S(Omega) = A Omega_c^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2))   [m^2 / (rad/m)]

one-sided in the spatial angular frequency Omega [rad/m], with Omega_c = 0.8246 rad/m,
Omega_r = 0.0206 rad/m and A [m rad] per level of quality:

=============  ===========  ===========
quality        A alignment  A level
=============  ===========  ===========
``low``        2.119e-7     4.032e-7
``high``       6.125e-7     10.80e-7
=============  ===========  ===========

("low" and "high" are the levels of *disturbance*: "high" is the worse track.) The signal is a
sum of cosines with random phases (Shinozuka & Jan, J. Sound Vib. 25, 1972): the band
[Omega_min, Omega_max] is cut into ``n`` equal bins of width dOmega, each contributes
``sqrt(2 S(Omega_k) dOmega) cos(Omega_k s + phi_k)`` with phi_k uniform on [0, 2 pi) and
Omega_k uniform inside its bin (so the record does not repeat with period 2 pi / dOmega).
The expected variance is then exactly the integral of S over the band, which
:func:`band_variance` gives in closed form.
"""
import math

import numpy as np

__all__ = ["ERRI_B176", "erri_psd", "band_variance", "synthetic_irregularity",
           "write_irregularity", "read_irregularity", "COMPONENTS", "MAX_OFFSET"]

#: Column order of the file after sigma.
COMPONENTS = ("alignment", "level", "cross_level", "gauge")
#: Largest |offset| the reader accepts [m] (a larger one means millimetres were written).
MAX_OFFSET = 0.1

#: ERRI B176 / ORE spectrum parameters: Omega_c, Omega_r [rad/m] and A [m rad] per quality
#: and component.
ERRI_B176 = {
    "omega_c": 0.8246,
    "omega_r": 0.0206,
    "A": {
        "low": {"alignment": 2.119e-7, "level": 4.032e-7},
        "high": {"alignment": 6.125e-7, "level": 10.80e-7},
    },
}


def _params(level, component):
    try:
        a = ERRI_B176["A"][level][component]
    except KeyError:
        raise ValueError(f"ERRI B176 spectrum: level must be 'low' or 'high' and component "
                         f"'alignment' or 'level', got {level!r}, {component!r}") from None
    return a, ERRI_B176["omega_c"], ERRI_B176["omega_r"]


def erri_psd(omega, level="low", component="alignment"):
    """One-sided PSD S(Omega) [m^2/(rad/m)] of the ERRI B176 spectrum at Omega [rad/m]."""
    a, wc, wr = _params(level, component)
    w2 = np.asarray(omega, dtype=float) ** 2
    return a * wc**2 / ((w2 + wr**2) * (w2 + wc**2))


def band_variance(omega_min, omega_max, level="low", component="alignment"):
    """Closed-form integral of :func:`erri_psd` over [omega_min, omega_max] [m^2].

    Partial fractions: 1/((x + r^2)(x + c^2)) = (1/(x + r^2) - 1/(x + c^2)) / (c^2 - r^2), and
    the integral of 1/(w^2 + r^2) is atan(w/r)/r.
    """
    a, wc, wr = _params(level, component)

    def primitive(w):
        return (math.atan(w / wr) / wr - math.atan(w / wc) / wc) * a * wc**2 / (wc**2 - wr**2)

    return primitive(omega_max) - primitive(omega_min)


def synthetic_irregularity(length, step=0.25, level="low", wavelengths=(3.0, 120.0), n_waves=2000,
                           seed=None, components=("alignment", "level"), start=0.0):
    """Random irregularities from the ERRI B176 spectra.

    length, step: record length and point spacing [m] (sigma = start, start + step, ...);
    level: 'low' or 'high'; wavelengths: (shortest, longest) [m], the band
    Omega = 2 pi / wavelength; n_waves: cosines per component; seed: numpy seed (the same seed
    gives the same record); components: any of 'alignment', 'level' (the others stay zero).
    Returns (sigma, {component: offsets [m]}) for all four components.
    """
    lmin, lmax = wavelengths
    if not (0 < lmin < lmax):
        raise ValueError(f"wavelengths must be 0 < shortest < longest, got {wavelengths}")
    if not (length > 0 and step > 0 and n_waves >= 1):
        raise ValueError("length and step must be > 0 and n_waves >= 1")
    if step > lmin / 4:
        raise ValueError(f"step {step} m too coarse for the shortest wavelength {lmin} m "
                         "(linear interpolation needs >= 4 points per wavelength)")
    rng = np.random.default_rng(seed)
    sigma = start + step * np.arange(int(round(length / step)) + 1)
    w_min, w_max = 2 * math.pi / lmax, 2 * math.pi / lmin
    dw = (w_max - w_min) / n_waves
    out = {c: np.zeros_like(sigma) for c in COMPONENTS}
    for comp in components:
        if comp not in ("alignment", "level"):
            raise ValueError(f"no ERRI B176 spectrum for {comp!r}; expected 'alignment' or 'level'")
        omega = w_min + dw * (np.arange(n_waves) + rng.random(n_waves))
        phase = 2 * math.pi * rng.random(n_waves)
        amp = np.sqrt(2 * erri_psd(omega, level, comp) * dw)
        # sum in blocks: a (points x waves) matrix of a long record would not fit in memory
        for i in range(0, sigma.size, 4096):
            s = sigma[i:i + 4096, None]
            out[comp][i:i + 4096] = np.cos(omega[None, :] * s + phase[None, :]) @ amp
    return sigma, out


def write_irregularity(path, sigma, alignment=None, level=None, cross_level=None, gauge=None,
                       comment=None):
    """Write an irregularity file; components not given are zero. Checks what the reader
    checks (increasing sigma, finite numbers, |offset| <= 0.1 m) so a bad record fails here."""
    sigma = np.asarray(sigma, dtype=float)
    if sigma.ndim != 1 or sigma.size < 2:
        raise ValueError("sigma must be a 1-D array of at least 2 points")
    cols = []
    for name, v in zip(COMPONENTS, (alignment, level, cross_level, gauge)):
        v = np.zeros_like(sigma) if v is None else np.asarray(v, dtype=float)
        if v.shape != sigma.shape:
            raise ValueError(f"{name}: {v.shape} values for {sigma.shape} sigma points")
        cols.append(v)
    table = np.column_stack([sigma] + cols)
    if not np.all(np.isfinite(table)):
        raise ValueError("sigma and the offsets must be finite")
    if not np.all(np.diff(sigma) > 0):
        raise ValueError("sigma must be strictly increasing")
    if np.abs(table[:, 1:]).max() > MAX_OFFSET:
        raise ValueError(f"an offset exceeds {MAX_OFFSET} m: irregularities are in metres")
    header = "sigma_m alignment_m level_m cross_level_m gauge_m"
    if comment:
        header = "\n".join(str(comment).splitlines() + [header])
    np.savetxt(path, table, fmt=["%.6f"] + ["%.9e"] * 4, header=header)


def read_irregularity(path):
    """(sigma, {component: offsets}) of an irregularity file (comments '#', commas allowed)."""
    rows = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].replace(",", " ").strip()
            if line:
                rows.append([float(x) for x in line.split()])
    table = np.array(rows, dtype=float)
    return table[:, 0], {c: table[:, i + 1] for i, c in enumerate(COMPONENTS)}
