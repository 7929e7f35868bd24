"""The assessment of one results file: every quantity of EN 14363 (running safety, track
loading), EN 12299 (ride comfort) and the wear indices that the file allows, each with its
limit and margin, or with the reason it is not available."""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..results import Results
from .comfort import comfort_quantities
from .filters import butterworth_lowpass_gain, magnitude_filter
from .layout import SIDES, LayoutError, read_sensors, read_wheelsets, wheelset_names
from .quantity import Quantity, not_available
from .running_safety import running_safety
from .track_loading import track_loading
from .comfort import _SOURCE as _COMFORT_SOURCE
from .running_safety import _SOURCE as _SAFETY_SOURCE
from .track_loading import _SOURCE as _LOADING_SOURCE
from .wear import _SOURCE_RCF, _SOURCE_TG, SHEAR_YIELD_DEFAULT, wear_quantities

__all__ = ["Assessment", "assess", "FORCE_CUTOFF"]

FORCE_CUTOFF = 20.0    #: Hz, low pass of the wheel forces (EN 14363, secondary source)


@dataclass
class Assessment:
    results_path: str
    status: str
    title: str
    quantities: list[Quantity] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        return {"results": self.results_path, "status": self.status, "title": self.title,
                "quantities": [q.to_json() for q in self.quantities], "notes": list(self.notes)}

    def find(self, name: str, **where) -> list[Quantity]:
        """The quantities called ``name`` whose attributes equal ``where`` (wheelset=..., ...)."""
        return [q for q in self.quantities if q.name == name
                and all(getattr(q, k) == v for k, v in where.items())]


def _lowpass_for(t: np.ndarray, notes: list[str]):
    if t.size < 2:
        return lambda y: np.asarray(y, float)
    fs = 1.0 / float(np.median(np.diff(t)))
    if fs <= 2 * FORCE_CUTOFF * (1 + 1e-9):      # 40 Hz output: Nyquist at the cut-off
        notes.append(f"output rate {fs:.3g} Hz: nothing above the {FORCE_CUTOFF:g} Hz force filter "
                     "is resolved, forces used as written")
        return lambda y: np.asarray(y, float)
    notes.append(f"wheel forces low-pass filtered at {FORCE_CUTOFF:g} Hz (4th-order Butterworth "
                 "magnitude, zero phase)")
    return lambda y: magnitude_filter(y, fs, lambda f: butterworth_lowpass_gain(f, FORCE_CUTOFF))


#: where each quantity comes from (docs/assessment.md): given to a quantity that is not
#: available too, so that every row of the JSON, CSV and HTML says it
SOURCES = {"Y/Q": _SAFETY_SOURCE, "sum_Y": _SAFETY_SOURCE, "sum_Y_rms": _SAFETY_SOURCE,
           "Q_max": _LOADING_SOURCE, "Y_qst": _LOADING_SOURCE, "Q_qst": _LOADING_SOURCE,
           "DeltaQ/Q": _LOADING_SOURCE, "T_gamma": _SOURCE_TG, "RCF_index": _SOURCE_RCF,
           "N_MV": _COMFORT_SOURCE, "Cc": _COMFORT_SOURCE}


#: the wheelset quantities: (name, unit, per wheel)
_WHEELSET_QUANTITIES = (("Y/Q", "1", True), ("sum_Y", "N", False), ("sum_Y_rms", "N", False),
                        ("Q_max", "N", True), ("Y_qst", "N", True), ("Q_qst", "N", True),
                        ("DeltaQ/Q", "1", True), ("T_gamma", "N", True), ("RCF_index", "1", True))


def _wheelset_not_available(wheelset: str | None, reason: str) -> list[Quantity]:
    """Every wheelset quantity of one wheelset (or of none) as not available."""
    out = []
    for name, unit, per_wheel in _WHEELSET_QUANTITIES:
        for side in (SIDES if per_wheel and wheelset else (None,)):
            out.append(not_available(name, unit, reason, wheelset=wheelset, side=side))
    return out


def assess(path: str | os.PathLike, prudhomme_alpha: float = 1.0,
           instability_frequency: float | None = None,
           shear_yield: float = SHEAR_YIELD_DEFAULT) -> Assessment:
    """Assess the results file ``path`` (docs/assessment.md); ``shear_yield`` [Pa] is the
    yield limit in pure shear k of the RCF index FI_surf."""
    with Results(path) as r:
        if r.axis != "time":
            raise ValueError(f"its rows are along '{r.axis}', not in time (a raildyn track export?): "
                             "only the results of a run can be assessed")
        meta = r.metadata
        a = Assessment(os.fspath(path), str(meta.get("status", "unknown")), str(meta.get("title", "")))
        if a.status != "completed":
            a.notes.append(f"run status '{a.status}': the quantities cover the rows written")
        if meta.get("output_mean_samples"):
            a.notes.append("rows are interval means (output_mean_samples > 0): peaks shorter "
                           "than the output interval are averaged")
        t = np.asarray(r.time, float)
        lowpass = _lowpass_for(t, a.notes)
        speed = np.asarray(r.get("vehicle/speed:V"), float) if "vehicle/speed" in r else np.zeros(0)
        try:
            wheelsets = read_wheelsets(r)
        except LayoutError as e:
            wheelsets = []
            for name in wheelset_names(r):
                a.quantities += _wheelset_not_available(name, str(e))
        if not wheelset_names(r):
            a.quantities += _wheelset_not_available(
                None, "the file has no wheelsets/ series: no wheel-rail contact written")
        for ws in wheelsets:
            a.notes.append(f"wheelset {ws.name}: track position = {ws.position_note}")
            a.quantities += running_safety(ws, t, lowpass, prudhomme_alpha, instability_frequency)
            a.quantities += track_loading(ws, speed, lowpass)
            a.quantities += wear_quantities(ws, shear_yield)
        sensors = read_sensors(r)
        if not sensors:
            reason = "the file has no sensors/<name>/ series (no &sensor in the deck, or &output groups without 'sensors')"
            a.quantities.append(not_available("N_MV", "1", reason))
            a.quantities.append(not_available("Cc", "m/s^2", reason))
        distance = np.asarray(r.get("vehicle/distance:sigma"), float) if "vehicle/distance" in r else None
        for sensor in sensors:
            # docs/output.md /sensors: the track position of a sensor's row is vehicle/distance
            # plus the frame offset of its body plus the sensor's x in position_track
            offset = sensor.frame_offset or 0.0
            a.notes.append(f"sensor {sensor.name}: accelerations from {sensor.series}; track position "
                           f"= vehicle/distance + {offset:g} m" + ("" if sensor.frame_offset is not None
                                                                  else " (its body's frame not found in the deck)")
                           + (" + x of position_track" if sensor.x is not None
                              else " (position_track not written: the sensor's x left out)"))
            along = None if distance is None else distance + offset + (0.0 if sensor.x is None else sensor.x)

            def position_at(time, along=along):
                return float("nan") if along is None else float(np.interp(time, t, along))
            a.quantities += comfort_quantities(sensor.name, t, sensor.acceleration, position_at)
    for q in a.quantities:
        q.source = q.source or SOURCES[q.name]
    return a
