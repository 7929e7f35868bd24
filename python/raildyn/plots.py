"""Quick-look plots of results files (matplotlib, Agg backend: no display needed).

    python -m raildyn.plots track    track.h5  track.png      # alignment from `raildyn track`
    python -m raildyn.plots channels run.h5    run.png  [CHANNEL ...]
    python -m raildyn.plots root-locus locus.csv locus.png   # from `raildyn eigen --csv`
    python -m raildyn.plots conicity c.csv c.png            # from `raildyn profile-scan --conicity-csv`
    python -m raildyn.plots contact-points s.h5 s_profiles.csv s.png   # `profile-scan --contact-plot`

``track``: plan view (Y over X, equal axes, from the series ``track/position``) and every
other ``track/...`` series over the file's axis (sigma). ``channels``: the given series or
'path:component' columns (default all) over the axis, one panel each. ``root-locus``: the
damping ratio and the frequency of every mode against the speed (neutral modes left out).
``conicity``: equivalent conicity against amplitude by the three methods. ``contact-points``:
wheel and rail profiles with lines joining their contact points for the scanned shifts.
"""

from __future__ import annotations

import os
import sys
from typing import Iterable

from .results import Results

__all__ = ["plot_channels", "plot_track", "plot_root_locus", "plot_conicity", "plot_contact_points", "main"]

_MAX_PANELS = 24


def agg_pyplot():
    """matplotlib.pyplot on the Agg backend (files only, no display): the plots here, the
    validation report's (raildyn.report) and raildyn.compare's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, out: str | os.PathLike) -> str:
    """Write the figure to ``out`` (90 dpi) and free it; returns the image path."""
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    agg_pyplot().close(fig)
    return os.fspath(out)


def _axis_label(r: Results) -> str:
    return f"{r.axis} [{r.unit(r.axis)}]"


def _plot_series(ax, r: Results, channel: str) -> None:
    data = r.get(channel)
    names = r.components(channel) if data.ndim == 2 else [channel.rsplit(":", 1)[-1]]
    units = r.units(channel) if data.ndim == 2 else [r.unit(channel)]
    data = data.reshape(len(r.time), -1)
    for k in range(data.shape[1]):
        ax.plot(r.time, data[:, k], label=f"{names[k]} [{units[k]}]")
    ax.set_ylabel(channel.split(":")[0].rsplit("/", 1)[-1])
    ax.set_title(channel, fontsize=8)
    ax.grid(True, alpha=0.3)
    if data.shape[1] > 1 or units[0]:
        ax.legend(fontsize=7, loc="best")


def plot_channels(path: str | os.PathLike, out: str | os.PathLike,
                  channels: Iterable[str] | None = None) -> str:
    """One panel per channel over the file's axis; returns the image path."""
    plt = agg_pyplot()
    with Results(path) as r:
        chans = list(channels) if channels else r.channels()
        if not chans:
            raise ValueError(f"{path}: no series to plot")
        chans = chans[:_MAX_PANELS]
        fig, axes = plt.subplots(len(chans), 1, sharex=True, figsize=(9, 2.2 * len(chans) + 0.8),
                                 squeeze=False)
        for ax, ch in zip(axes[:, 0], chans):
            _plot_series(ax, r, ch)
        axes[-1, 0].set_xlabel(_axis_label(r))
        fig.suptitle(f"{os.path.basename(os.fspath(path))} ({r.status})", fontsize=9)
        return _save(fig, out)


def plot_track(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """Plan view of ``track/position`` plus every other ``track/...`` series."""
    plt = agg_pyplot()
    with Results(path) as r:
        track = [c for c in r.channels() if c.startswith("track/")] or r.channels()
        others = [c for c in track if c != "track/position"][:_MAX_PANELS]
        has_plan = "track/position" in track
        n = len(others) + (1 if has_plan else 0)
        if n == 0:
            raise ValueError(f"{path}: no track series to plot")
        fig, axes = plt.subplots(n, 1, figsize=(9, 2.2 * n + (2.5 if has_plan else 0.8)),
                                 squeeze=False)
        axes = list(axes[:, 0])
        if has_plan:
            ax = axes.pop(0)
            xyz = r.get("track/position")
            ax.plot(xyz[:, 0], xyz[:, 1], "k-")
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xlabel("X [m]")
            ax.set_ylabel("Y [m] (left)")
            ax.set_title("plan view (fixed frame)", fontsize=8)
            ax.grid(True, alpha=0.3)
        for ax, ch in zip(axes, others):
            _plot_series(ax, r, ch)
        if axes:
            axes[-1].set_xlabel(_axis_label(r))
        return _save(fig, out)


def plot_profile_scan(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """The contact table of ``raildyn profile-scan --h5``: contact positions on the rail and
    the wheel, rolling-radius difference and contact angles against the lateral shift."""
    plt = agg_pyplot()
    with Results(path) as r:
        y = r.time * 1000.0
        fig, axes = plt.subplots(2, 2, figsize=(10, 7))
        (a_rail, a_wheel), (a_dr, a_gam) = axes
        for side, style in (("left", "b."), ("right", "r.")):
            n = r.get(f"scan/{side}/n_patches")[:, 0]
            p = 1
            while f"scan/{side}/patch{p}" in r.channels():
                d = r.get(f"scan/{side}/patch{p}")
                on = n >= p
                label = side if p == 1 else None
                a_rail.plot(y[on], d[on, 1] * 1000, style, ms=3, label=label)
                a_wheel.plot(y[on], d[on, 0] * 1000, style, ms=3, label=label)
                a_gam.plot(y[on], d[on, 4], style, ms=3, label=label)
                p += 1
        a_dr.plot(y, r.get("scan/delta_r")[:, 0] * 1000, "k-")
        a_rail.set_ylabel("contact on rail profile [mm]")
        a_wheel.set_ylabel("contact on wheel profile [mm]")
        a_dr.set_ylabel("r_left - r_right [mm]")
        a_gam.set_ylabel("contact angle [rad]")
        for ax in axes.flat:
            ax.set_xlabel("lateral shift y [mm] (+ left)")
            ax.grid(True, alpha=0.3)
        a_rail.legend(fontsize=8)
        attrs = {k: v for k, v in r.metadata.items() if str(k).startswith("equivalent_conicity")}
        title = ", ".join(f"{k.replace('equivalent_conicity_', 'lambda_e ')} = {float(v):.3f}"
                          for k, v in attrs.items())
        fig.suptitle(title or "profile scan", fontsize=9)
        return _save(fig, out)


def plot_root_locus(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """The root locus of ``raildyn eigen --speeds ... --csv``: damping ratio and frequency of
    every mode against the running speed, one point per mode and speed; the least-damped
    mode of each speed is marked, and zero damping (the stability limit) drawn."""
    from .stability import read_root_locus
    plt = agg_pyplot()
    locus = read_root_locus(path)
    fig, (a_zeta, a_freq) = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
    for speed, modes in locus.items():
        modes = [m for m in modes if not m.neutral]
        if not modes:
            continue
        a_zeta.plot([speed] * len(modes), [m.damping_ratio for m in modes], "k.", ms=4)
        a_freq.plot([speed] * len(modes), [m.frequency_hz for m in modes], "k.", ms=4)
        least = min(modes, key=lambda m: m.damping_ratio)
        a_zeta.plot([speed], [least.damping_ratio], "ro", ms=5, mfc="none")
        a_freq.plot([speed], [least.frequency_hz], "ro", ms=5, mfc="none")
    a_zeta.axhline(0.0, color="r", lw=0.8)
    a_zeta.set_ylabel("damping ratio [-]")
    a_freq.set_ylabel("frequency [Hz]")
    a_freq.set_xlabel("speed [m/s]")
    for ax in (a_zeta, a_freq):
        ax.grid(True, alpha=0.3)
    fig.suptitle("root locus (red: least-damped mode at each speed)", fontsize=9)
    return _save(fig, out)


def plot_conicity(path: str | os.PathLike, out: str | os.PathLike, title: str | None = None) -> str:
    """Equivalent conicity against amplitude from ``raildyn profile-scan --conicity-csv``:
    harmonic linearisation and EN 15302's integration (Klingel) and regression methods.
    ``title``: what the curves are of (profile-scan passes its wheel and rail); default the
    file's name."""
    import numpy as np
    plt = agg_pyplot()
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0:
        raise ValueError(f"{path}: no rows")
    data = np.atleast_1d(data)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for column, style, label in (("integration", "k-", "EN 15302 integration (Klingel)"),
                                 ("regression", "b--", "EN 15302 regression"),
                                 ("harmonic", "r:", "harmonic linearisation")):
        ax.plot(data["amplitude_m"] * 1000, data[column], style, label=label)
    ax.set_xlabel("amplitude [mm] (half the peak-to-peak kinematic motion)")
    ax.set_ylabel("equivalent conicity [-]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title or f"equivalent conicity, {os.path.basename(os.fspath(path))}", fontsize=9)
    return _save(fig, out)


def plot_contact_points(scan_path: str | os.PathLike, curves_path: str | os.PathLike,
                        out: str | os.PathLike, lines: int = 21, gap: float = 0.012) -> str:
    """Wheel and rail profiles (``raildyn profile-scan --contact-plot``: the scan's HDF5 file and
    its ``_profiles.csv``) with lines joining the contact points of the wheel and of the rail
    for about ``lines`` of the scanned lateral shifts, one panel per side. The wheel is drawn
    centred and lifted by ``gap`` [m] above the rail so that the lines show where each shift
    touches: the upper end on the wheel profile, the lower end on the rail."""
    import numpy as np
    plt = agg_pyplot()
    curves = np.genfromtxt(curves_path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    with Results(scan_path) as r:
        shifts = r.time
        sides = {side: (r.get(f"scan/{side}/n_patches")[:, 0], r.get(f"scan/{side}/patch1"))
                 for side in ("left", "right")}
    picked = np.unique(np.linspace(0, len(shifts) - 1, min(lines, len(shifts))).round().astype(int))
    cmap = plt.get_cmap("coolwarm")
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, side in zip(axes, ("right", "left")):
        n, patch = sides[side]
        wheel = curves[(curves["side"] == side) & (curves["surface"] == "wheel")]
        rail = curves[(curves["side"] == side) & (curves["surface"] == "rail")]
        rail = rail[np.argsort(rail["y_m"])]          # the right rail's rows run towards -Y
        order = np.argsort(wheel["profile_coordinate_m"])
        s_sorted = wheel["profile_coordinate_m"][order]
        ax.plot(rail["y_m"] * 1000, rail["z_m"] * 1000, "k-", lw=1.2, label="rail")
        ax.plot(wheel["y_m"] * 1000, (wheel["z_m"] + gap) * 1000, "k-", lw=0.8,
                label=f"wheel (centred, lifted {gap * 1000:g} mm)")
        touched = []
        for k in picked:
            if n[k] < 1:
                continue
            s_wheel, y_rail = patch[k, 0], patch[k, 2]
            yw = np.interp(s_wheel, s_sorted, wheel["y_m"][order])
            zw = np.interp(s_wheel, s_sorted, wheel["z_m"][order]) + gap
            zr = np.interp(y_rail, rail["y_m"], rail["z_m"])
            colour = cmap((shifts[k] - shifts[0]) / max(shifts[-1] - shifts[0], 1e-12))
            ax.plot([yw * 1000, y_rail * 1000], [zw * 1000, zr * 1000], "-", color=colour, lw=0.8)
            ax.plot([yw * 1000, y_rail * 1000], [zw * 1000, zr * 1000], ".", color=colour, ms=3)
            touched += [yw, y_rail]
        if touched:
            ax.set_xlim(min(touched) * 1000 - 25, max(touched) * 1000 + 25)
            lo = np.interp(min(touched) - 0.025, rail["y_m"], rail["z_m"])
            ax.set_ylim(min(rail["z_m"].min(), lo) * 1000 - 5, (gap + 0.04) * 1000)
        ax.set_xlabel("Y, track frame [mm] (+ left)")
        ax.set_ylabel("Z [mm]")
        ax.set_title(f"{side} wheel and rail: contact points, shifts "
                     f"{shifts[0] * 1000:g} .. {shifts[-1] * 1000:g} mm (blue .. red)", fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    return _save(fig, out)


def main(argv: list[str] | None = None) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="python -m raildyn.plots",
                                     description="Quick-look plots of raildyn results files.")
    sub = parser.add_subparsers(dest="command", required=True)

    def command(name: str, help_text: str, plot, *positionals: str) -> argparse.ArgumentParser:
        """A subcommand: its positional arguments after the input file, and the plot it makes
        of the parsed arguments."""
        p = sub.add_parser(name, help=help_text)
        for arg in ("file", *positionals):
            p.add_argument(arg)
        p.set_defaults(plot=plot)
        return p

    command("track", "track alignment (from `raildyn track`)", lambda a: plot_track(a.file, a.out), "out")
    command("profile-scan", "contact table (from `raildyn profile-scan --h5`)",
            lambda a: plot_profile_scan(a.file, a.out), "out")
    command("root-locus", "modes against speed (from `raildyn eigen --csv`)",
            lambda a: plot_root_locus(a.file, a.out), "out")
    command("conicity", "conicity against amplitude (profile-scan --conicity-csv)",
            lambda a: plot_conicity(a.file, a.out, a.title), "out").add_argument(
        "--title", help="plot title (default: the file's name)")
    command("contact-points", "profiles with contact-point lines (profile-scan --contact-plot: H5 and profiles CSV)",
            lambda a: plot_contact_points(a.file, a.curves, a.out), "curves", "out")
    command("channels", "series over the file's axis", lambda a: plot_channels(a.file, a.out, a.channels or None),
            "out").add_argument("channels", nargs="*")
    args = parser.parse_args(argv)
    try:
        written = args.plot(args)
    except (OSError, ValueError, KeyError) as exc:
        print(f"raildyn.plots: {exc}", file=sys.stderr)
        return 1
    print(written)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
