"""A results file cut to some of its rows: every series and ``/time`` keep only the rows
selected, the root and ``/meta`` attributes, ``/meta/deck_text`` and ``/meta/solver`` are
copied (``/meta n_steps`` becomes the number of rows kept). Campaign metrics use it to assess
one stretch of track or one time window (``raildyn.campaign``, window_position / window):
the assessment then sees exactly those rows, as if the run had written no others."""
from __future__ import annotations

import os
from pathlib import Path

import h5py
import numpy as np

from .results import open_results_file

__all__ = ["write_rows"]


def write_rows(source: str | os.PathLike, rows: np.ndarray, target: str | os.PathLike) -> Path:
    """Write the rows ``rows`` (a boolean mask over ``/time``) of ``source`` to ``target``."""
    rows = np.asarray(rows, bool)
    target = Path(target)
    with open_results_file(source) as src, h5py.File(target, "w", libver="latest") as dst:
        n = src["time"].shape[0]
        if rows.shape != (n,):
            raise ValueError(f"{source}: a row mask of {rows.shape[0]} entries for {n} rows")
        dst.attrs.update(src.attrs)

        def copy(name: str, obj) -> None:
            if isinstance(obj, h5py.Group):
                dst.require_group(name).attrs.update(obj.attrs)
                return
            data = obj[()]
            if obj.ndim >= 1 and obj.shape[0] == n:
                data = data[rows]
                maxshape = (None, *obj.shape[1:])
                made = dst.create_dataset(name, data=data, maxshape=maxshape, chunks=True)
            else:
                made = dst.create_dataset(name, data=data)
            made.attrs.update(obj.attrs)

        src.visititems(copy)
        if "meta" in dst:
            dst["meta"].attrs["n_steps"] = np.int64(rows.sum())
    return target
