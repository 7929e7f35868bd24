"""Reader for raildyn results files (HDF5, layout in docs/output.md).

    from raildyn import Results
    with Results("run.h5") as r:
        t = r.time                                   # (n,) [s]
        q = r.get("bodies/car/position_track")       # (n, 6)
        y = r.get("bodies/car/position_track:y")     # (n,) one column by name
        r.unit("bodies/car/position_track")          # 'm m m rad rad rad'
        r.metadata["status"]                         # 'completed', 'failed: ...', 'running'

A run that was killed leaves a file still flagged "open for SWMR write"; plain
``h5py.File(path, 'r')`` refuses it, so the reader falls back to ``swmr=True``, which
is the mode designed for that state. Rows are trimmed to the common extent of
``/time`` and every series, and to the last finite time (unwritten cells hold the
fill value NaN), so a killed run reads as the steps up to its last flush.
"""

from __future__ import annotations

import os
from typing import Any

import h5py
import numpy as np

__all__ = ["Results", "open_results_file"]

#: Groups that hold metadata, never time series.
_META_GROUPS = ("meta",)


def _text(value: Any) -> Any:
    """Decode HDF5 fixed-length strings (h5py gives bytes) and numpy scalars."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray) and value.dtype.kind == "S":
        return [v.decode("utf-8", errors="replace") for v in value.ravel()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def open_results_file(path: str | os.PathLike) -> h5py.File:
    """Open a results file read-only; a file left open for SWMR write (killed run) is
    opened in SWMR read mode instead of failing."""
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        if "already open for write" not in str(exc):
            raise
        return h5py.File(path, "r", swmr=True)


class Results:
    """Read-only view of one results file."""

    def __init__(self, path: str | os.PathLike):
        self.path = os.fspath(path)
        self._file = open_results_file(self.path)
        #: Name of the common axis: 'time' for runs; another one (e.g. 'sigma' for a
        #: track export) is named in the root attribute 'axis'.
        self.axis = str(_text(self._file.attrs.get("axis", b"time")))
        if self.axis not in self._file or not isinstance(self._file[self.axis], h5py.Dataset):
            self._file.close()
            raise ValueError(f"{self.path}: not a raildyn results file (no /{self.axis} dataset)")
        self._channels = self._find_channels()
        self._n = self._count_rows()

    # -- life cycle ---------------------------------------------------------------
    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def __enter__(self) -> "Results":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Results({self.path!r}, steps={self._n}, channels={len(self._channels)})"

    # -- discovery ----------------------------------------------------------------
    def _find_channels(self) -> list[str]:
        names: list[str] = []

        def visit(name: str, obj: Any) -> None:
            if not isinstance(obj, h5py.Dataset) or name == self.axis:
                return
            if name.split("/", 1)[0] in _META_GROUPS:
                return
            if obj.ndim == 2 and obj.maxshape[0] is None:
                names.append(name)

        self._file.visititems(visit)
        return sorted(names)

    def _count_rows(self) -> int:
        n = self._file[self.axis].shape[0]
        for name in self._channels:
            n = min(n, self._file[name].shape[0])
        if n > 0:
            n = self._first_nonfinite_row(self._file[self.axis][:n], n)
        # A file still marked 'running' (live or killed) may hold cells HDF5 extended but
        # never wrote (fill value NaN). The writer refuses non-finite values, so the first
        # such row ends the complete data. Closed files need no scan.
        meta = self._file.get("meta")
        running = meta is not None and _text(meta.attrs.get("status", b"")) == "running"
        if n > 0 and running:
            for name in self._channels:
                n = self._first_nonfinite_row(self._file[name][:n], n)
        return int(n)

    @staticmethod
    def _first_nonfinite_row(data: np.ndarray, n: int) -> int:
        finite = np.isfinite(data)
        if finite.ndim > 1:
            finite = finite.all(axis=1)
        bad = np.flatnonzero(~finite)
        return int(bad[0]) if bad.size else n

    # -- data -----------------------------------------------------------------------
    @property
    def n_steps(self) -> int:
        """Number of complete output steps (rows)."""
        return self._n

    @property
    def time(self) -> np.ndarray:
        """Simulated time of each output step [s], shape (n,) (the values of the common
        axis when the file has another one, see ``axis``)."""
        return self._file[self.axis][: self._n]

    def channels(self) -> list[str]:
        """Paths of all time series, e.g. 'bodies/car/position_track' (no leading '/')."""
        return list(self._channels)

    def columns(self) -> list[str]:
        """Every column as 'path:component', the unit of curve comparison."""
        return [f"{c}:{k}" for c in self._channels for k in self.components(c)]

    def _split(self, channel: str) -> tuple[str, str | None]:
        path = channel.strip("/")
        if path in self._channels or path == self.axis:
            return path, None
        if ":" in path:
            series, component = path.rsplit(":", 1)
            if series in self._channels:
                names = self.components(series)
                if component not in names:
                    raise KeyError(f"{self.path}: series {series!r} has no component "
                                   f"{component!r}; components: {' '.join(names)}")
                return series, component
        raise KeyError(f"{self.path}: no series {channel!r}; available: {', '.join(self._channels)}")

    def get(self, channel: str) -> np.ndarray:
        """Series as an array (n, ncomp) (the axis ``time``: (n,)); 'path:component'
        gives one column (n,)."""
        path, component = self._split(channel)
        data = self._file[path][: self._n]
        if component is None:
            return data
        return data[:, self.components(path).index(component)]

    def __getitem__(self, channel: str) -> np.ndarray:
        return self.get(channel)

    def __contains__(self, channel: str) -> bool:
        try:
            self._split(channel)
        except KeyError:
            return False
        return True

    def _attr(self, path: str, name: str, default: Any = None) -> Any:
        return _text(self._file[path].attrs.get(name, default))

    def unit(self, channel: str) -> str:
        """The ``unit`` attribute as stored: one unit for all columns or one per column.
        For 'path:component' the unit of that column."""
        path, component = self._split(channel)
        if component is None:
            return self._attr(path, "unit", "")
        return self.units(path)[self.components(path).index(component)]

    def units(self, channel: str) -> list[str]:
        """One unit per column."""
        path, _ = self._split(channel)
        units = str(self._attr(path, "unit", "")).split()
        ncomp = 1 if path == self.axis else self._file[path].shape[1]
        if len(units) == 1:
            units = units * ncomp
        return units

    def components(self, channel: str) -> list[str]:
        """Column names, e.g. ['x', 'y', 'z', 'yaw', 'roll', 'pitch']."""
        path, _ = self._split(channel)
        names = str(self._attr(path, "components", "")).split()
        if path != self.axis and len(names) != self._file[path].shape[1]:
            names = [f"c{k + 1}" for k in range(self._file[path].shape[1])]
        return names

    def description(self, channel: str) -> str:
        path, _ = self._split(channel)
        return self._attr(path, "description", "")

    # -- metadata -------------------------------------------------------------------
    @property
    def metadata(self) -> dict[str, Any]:
        """Root attributes and ``/meta`` attributes merged, plus ``solver`` (dict of
        ``/meta/solver`` attributes) and ``version`` (= ``raildyn_version``)."""
        meta: dict[str, Any] = {k: _text(v) for k, v in self._file.attrs.items()}
        if "meta" in self._file:
            meta.update({k: _text(v) for k, v in self._file["meta"].attrs.items()})
            solver = self._file["meta"].get("solver")
            meta["solver"] = {k: _text(v) for k, v in solver.attrs.items()} if solver is not None else {}
        else:
            meta["solver"] = {}
        meta["version"] = meta.get("raildyn_version")
        meta.setdefault("status", "unknown")
        meta["steps_read"] = self._n
        return meta

    @property
    def status(self) -> str:
        """'completed', 'failed: <message>', 'stopped', or 'running' (killed run)."""
        return self.metadata["status"]

    @property
    def deck_text(self) -> str | None:
        """The full deck the run was made from (``/meta/deck_text``), if stored."""
        for name in ("meta/deck_text", "meta/deck"):   # 'deck' was used by early writers
            if name in self._file:
                return _text(self._file[name][()])
        return None
