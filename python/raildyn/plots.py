"""Quick-look plots of results files (matplotlib, Agg backend: no display needed).

    python -m raildyn.plots track    track.h5  track.png      # alignment from `raildyn track`
    python -m raildyn.plots channels run.h5    run.png  [CHANNEL ...]
    python -m raildyn.plots root-locus locus.csv locus.png   # from `raildyn eigen --csv`

``track``: plan view (Y over X, equal axes, from the series ``track/position``) and every
other ``track/...`` series over the file's axis (sigma). ``channels``: the given series or
'path:component' columns (default all) over the axis, one panel each. ``root-locus``: the
damping ratio and the frequency of every mode against the speed (neutral modes left out).
"""

from __future__ import annotations

import os
import sys
from typing import Iterable

from .results import Results

__all__ = ["plot_channels", "plot_track", "plot_root_locus", "main"]

_MAX_PANELS = 24


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


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
    plt = _pyplot()
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
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        plt.close(fig)
    return os.fspath(out)


def plot_track(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """Plan view of ``track/position`` plus every other ``track/...`` series."""
    plt = _pyplot()
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
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        plt.close(fig)
    return os.fspath(out)


def plot_profile_scan(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """The contact table of ``raildyn profile-scan --h5``: contact positions on the rail and
    the wheel, rolling-radius difference and contact angles against the lateral shift."""
    plt = _pyplot()
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
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        plt.close(fig)
    return os.fspath(out)


def plot_root_locus(path: str | os.PathLike, out: str | os.PathLike) -> str:
    """The root locus of ``raildyn eigen --speeds ... --csv``: damping ratio and frequency of
    every mode against the running speed, one point per mode and speed; the least-damped
    mode of each speed is marked, and zero damping (the stability limit) drawn."""
    from .stability import read_root_locus
    plt = _pyplot()
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
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)
    return os.fspath(out)


def main(argv: list[str] | None = None) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="python -m raildyn.plots",
                                     description="Quick-look plots of raildyn results files.")
    sub = parser.add_subparsers(dest="command", required=True)
    p_track = sub.add_parser("track", help="track alignment (from `raildyn track`)")
    p_track.add_argument("file")
    p_track.add_argument("out")
    p_scan = sub.add_parser("profile-scan", help="contact table (from `raildyn profile-scan --h5`)")
    p_scan.add_argument("file")
    p_scan.add_argument("out")
    p_locus = sub.add_parser("root-locus", help="modes against speed (from `raildyn eigen --csv`)")
    p_locus.add_argument("file")
    p_locus.add_argument("out")
    p_chan = sub.add_parser("channels", help="series over the file's axis")
    p_chan.add_argument("file")
    p_chan.add_argument("out")
    p_chan.add_argument("channels", nargs="*")
    args = parser.parse_args(argv)
    try:
        if args.command == "track":
            written = plot_track(args.file, args.out)
        elif args.command == "profile-scan":
            written = plot_profile_scan(args.file, args.out)
        elif args.command == "root-locus":
            written = plot_root_locus(args.file, args.out)
        else:
            written = plot_channels(args.file, args.out, args.channels or None)
    except (OSError, ValueError, KeyError) as exc:
        print(f"raildyn.plots: {exc}", file=sys.stderr)
        return 1
    print(written)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
