"""Curve comparison the OpenFAST regression way.

Each column of each series (a "channel", 'path:component') of a test run ``a`` is
compared with a reference run ``b`` on a common time base: the union of both time
grids inside the overlap of their time spans, with both curves interpolated linearly.
A channel passes when at every time

    |a - b| <= rtol * (max(b) - min(b)) + atol

i.e. the tolerance is scaled to the reference channel's range over the overlap, so one
rtol suits forces in kN and rotations in mrad alike; ``atol`` covers channels whose range
is zero (a constant, e.g. a lateral displacement that stays 0 on straight track).
The normalised error ``|a - b| / (rtol * range + atol)`` is <= 1 for a pass; the report
gives its maximum per channel and the time where it occurs.

    report = compare_results("new.h5", "baseline.h5", rtol=1e-3, atol=1e-9)
    print(report.summary())
    if not report.passed:
        plot_failures(report, "new.h5", "baseline.h5", "compare_plots/")

``rtol``/``atol`` may be dicts mapping fnmatch patterns of channel names to values
(first match wins, e.g. ``{"wheelsets/*/creep*": 1e-2, "*": 1e-3}``).
"""

from __future__ import annotations

import contextlib
import fnmatch
import math
import os
from dataclasses import dataclass, field
from typing import Iterable, Iterator, Mapping, Union

import numpy as np

from .results import Results

__all__ = ["ChannelComparison", "ComparisonReport", "compare_curves", "compare_results",
           "plot_failures"]

Tolerance = Union[float, Mapping[str, float]]
DEFAULT_RTOL = 1e-3
DEFAULT_ATOL = 1e-12


@dataclass
class ChannelComparison:
    """Outcome for one channel."""
    channel: str
    passed: bool
    max_normalized_error: float      #: max |a-b| / (rtol*range + atol); <= 1 passes
    time_of_max: float               #: time [s] of that maximum (nan if no overlap)
    max_abs_error: float             #: max |a-b| in the channel's unit
    reference_range: float           #: max(b) - min(b) over the overlap
    tolerance: float                 #: rtol * range + atol
    unit: str = ""
    note: str = ""                   #: why a channel failed without numbers (missing...)


@dataclass
class ComparisonReport:
    channels: list[ChannelComparison] = field(default_factory=list)
    rtol: Tolerance = DEFAULT_RTOL
    atol: Tolerance = DEFAULT_ATOL

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.channels)

    def failed(self) -> list[ChannelComparison]:
        return [c for c in self.channels if not c.passed]

    def __getitem__(self, channel: str) -> ChannelComparison:
        for c in self.channels:
            if c.channel == channel:
                return c
        raise KeyError(channel)

    def summary(self, only_failed: bool = False) -> str:
        rows = [f"{'channel':48s} {'result':6s} {'max err/tol':>12s} {'at t [s]':>10s} "
                f"{'max |a-b|':>12s} {'range(b)':>12s} unit"]
        for c in self.channels:
            if only_failed and c.passed:
                continue
            rows.append(f"{c.channel:48s} {'pass' if c.passed else 'FAIL':6s} "
                        f"{c.max_normalized_error:12.4g} {c.time_of_max:10.4g} "
                        f"{c.max_abs_error:12.4g} {c.reference_range:12.4g} {c.unit}"
                        + (f"  ({c.note})" if c.note else ""))
        nfail = len(self.failed())
        rows.append(f"{len(self.channels) - nfail} of {len(self.channels)} channels pass")
        return "\n".join(rows)


def _tolerance(tol: Tolerance, channel: str, what: str) -> float:
    if isinstance(tol, Mapping):
        for pattern, value in tol.items():
            if fnmatch.fnmatchcase(channel, pattern):
                return float(value)
        raise KeyError(f"no {what} pattern matches channel {channel!r} (add a '*' entry)")
    return float(tol)


def _common_time(t_a: np.ndarray, t_b: np.ndarray) -> np.ndarray:
    lo = max(t_a[0], t_b[0])
    hi = min(t_a[-1], t_b[-1])
    if hi < lo:
        return np.empty(0)
    t = np.union1d(t_a[(t_a >= lo) & (t_a <= hi)], t_b[(t_b >= lo) & (t_b <= hi)])
    return t


def compare_curves(t_a, a, t_b, b, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
                   channel: str = "", unit: str = "") -> ChannelComparison:
    """Compare one curve a(t_a) with the reference b(t_b) (1-D arrays, times increasing)."""
    t_a = np.asarray(t_a, dtype=float)
    t_b = np.asarray(t_b, dtype=float)
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if rtol < 0 or atol < 0:
        raise ValueError("rtol and atol must be >= 0")
    if t_a.shape != a.shape or t_b.shape != b.shape or a.ndim != 1 or b.ndim != 1:
        raise ValueError(f"{channel}: times and values must be 1-D arrays of equal length")
    nan = float("nan")
    if a.size == 0 or b.size == 0:
        return ChannelComparison(channel, False, math.inf, nan, nan, nan, nan, unit,
                                 "empty curve")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return ChannelComparison(channel, False, math.inf, nan, nan, nan, nan, unit,
                                 "non-finite values")
    t = _common_time(t_a, t_b)
    if t.size == 0:
        return ChannelComparison(channel, False, math.inf, nan, nan, nan, nan, unit,
                                 "time spans do not overlap")
    a_t = np.interp(t, t_a, a)
    b_t = np.interp(t, t_b, b)
    reference_range = float(b_t.max() - b_t.min())
    tolerance = rtol * reference_range + atol
    err = np.abs(a_t - b_t)
    k = int(np.argmax(err))
    if tolerance > 0:
        normalized = float(err[k] / tolerance)
    else:
        normalized = 0.0 if err[k] == 0 else math.inf
    return ChannelComparison(channel, bool(err[k] <= tolerance), normalized, float(t[k]),
                             float(err[k]), reference_range, tolerance, unit)


@contextlib.contextmanager
def _opened(res) -> Iterator[Results]:
    """A Results object as given (left open), or the results file at a path, closed after."""
    if isinstance(res, Results):
        yield res
    else:
        with Results(res) as opened:
            yield opened


def compare_results(res_a, res_b, channels: Iterable[str] | None = None,
                    rtol: Tolerance = DEFAULT_RTOL, atol: Tolerance = DEFAULT_ATOL
                    ) -> ComparisonReport:
    """Compare run ``res_a`` with reference ``res_b`` (Results objects or paths).

    channels: series paths ('bodies/car/position_track', every column) or single columns
    ('bodies/car/position_track:y'); default all columns of the reference. A channel of
    the reference missing from ``res_a`` fails.
    """
    with _opened(res_a) as a, _opened(res_b) as b:
        if channels is None:
            columns = b.columns()
        else:
            columns = []
            for ch in channels:
                path = ch.strip("/")
                if path in b.channels():
                    columns += [f"{path}:{k}" for k in b.components(path)]
                else:
                    columns.append(path)
        report = ComparisonReport(rtol=rtol, atol=atol)
        t_a, t_b = a.time, b.time
        nan = float("nan")
        for col in columns:
            r = _tolerance(rtol, col, "rtol")
            t = _tolerance(atol, col, "atol")
            missing = [name for name, res in (("test", a), ("reference", b)) if col not in res]
            if missing:
                report.channels.append(ChannelComparison(
                    col, False, math.inf, nan, nan, nan, nan, "",
                    f"missing in {' and '.join(missing)} run"))
                continue
            report.channels.append(compare_curves(t_a, a.get(col), t_b, b.get(col), r, t,
                                                  channel=col, unit=b.unit(col)))
        return report


def plot_failures(report: ComparisonReport, res_a, res_b, out_dir: str | os.PathLike,
                  max_plots: int = 50, label_a: str = "test", label_b: str = "reference"
                  ) -> list[str]:
    """Plot every failing channel (both curves and the error against the tolerance band)
    as a PNG in ``out_dir``; returns the file names. Uses the Agg backend (no display)."""
    from .plots import agg_pyplot
    plt = agg_pyplot()

    written: list[str] = []
    with _opened(res_a) as a, _opened(res_b) as b:
        os.makedirs(out_dir, exist_ok=True)
        for c in report.failed()[:max_plots]:
            fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
            have_a, have_b = c.channel in a, c.channel in b
            if have_b:
                ax1.plot(b.time, b.get(c.channel), "k-", label=label_b)
            if have_a:
                ax1.plot(a.time, a.get(c.channel), "r--", label=label_a)
            ax1.set_ylabel(f"{c.channel} [{c.unit}]")
            ax1.legend()
            ax1.set_title(f"{c.channel}: max err/tol = {c.max_normalized_error:.3g}"
                          + (f" at t = {c.time_of_max:.4g} s" if np.isfinite(c.time_of_max) else "")
                          + (f" ({c.note})" if c.note else ""))
            if have_a and have_b and np.isfinite(c.tolerance):
                t = _common_time(a.time, b.time)
                if t.size:
                    err = np.interp(t, a.time, a.get(c.channel)) - np.interp(t, b.time, b.get(c.channel))
                    ax2.plot(t, err, "b-", label=f"{label_a} - {label_b}")
                    ax2.axhline(c.tolerance, color="g", ls=":", label="tolerance")
                    ax2.axhline(-c.tolerance, color="g", ls=":")
                    ax2.legend()
            ax2.set_xlabel("time [s]")
            ax2.set_ylabel(f"error [{c.unit}]")
            name = os.path.join(os.fspath(out_dir),
                                c.channel.replace("/", "_").replace(":", "__") + ".png")
            fig.tight_layout()
            fig.savefig(name, dpi=80)
            plt.close(fig)
            written.append(name)
    return written


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m raildyn.compare test.h5 reference.h5 [--rtol R]
    [--atol A] [--channel C ...] [--plot DIR] [--all]``; exit status 0 when every channel
    passes, 1 otherwise."""
    import argparse
    parser = argparse.ArgumentParser(
        prog="python -m raildyn.compare",
        description="Compare the channels of a raildyn results file with a reference "
                    "(|a-b| <= rtol*range(b) + atol on a common time base).")
    parser.add_argument("test", help="results file under test")
    parser.add_argument("reference", help="reference (baseline) results file")
    parser.add_argument("--rtol", type=float, default=DEFAULT_RTOL,
                        help=f"tolerance relative to each channel's range (default {DEFAULT_RTOL})")
    parser.add_argument("--atol", type=float, default=DEFAULT_ATOL,
                        help=f"absolute tolerance in the channel's unit (default {DEFAULT_ATOL})")
    parser.add_argument("--channel", action="append", dest="channels",
                        help="series path or 'path:component' (repeatable; default all)")
    parser.add_argument("--plot", metavar="DIR", help="write PNG plots of failing channels")
    parser.add_argument("--all", action="store_true", help="list passing channels too")
    args = parser.parse_args(argv)
    report = compare_results(args.test, args.reference, channels=args.channels,
                             rtol=args.rtol, atol=args.atol)
    print(report.summary(only_failed=not args.all))
    if args.plot and not report.passed:
        for name in plot_failures(report, args.test, args.reference, args.plot):
            print(f"plot: {name}")
    return 0 if report.passed else 1


if __name__ == "__main__":
    raise SystemExit(main())
