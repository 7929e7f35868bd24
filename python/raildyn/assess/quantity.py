"""One assessed quantity: its value, limit and margin, where on the track, and the clause
and source it comes from; or why it is not available."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Quantity", "not_available"]


@dataclass
class Quantity:
    """A quantity of the assessment (docs/assessment.md lists them all).

    ``value`` is None when the quantity is not available; ``reason`` then says why (no
    sensors in the file, track shorter than a window, ...). ``limit`` is None where the
    standard sets none. ``margin`` = (limit - |value|) / limit: >= 0 inside the limit (for the
    limits that are lower bounds there is none in raildyn). Every limit of the assessment
    bounds a magnitude, so the margin is that of ``|value|``."""
    name: str
    unit: str
    value: float | None = None
    limit: float | None = None
    position: float | None = None      #: track position of the value [m]
    wheelset: str | None = None
    side: str | None = None
    patch: int | None = None
    sensor: str | None = None
    direction: str | None = None
    clause: str = ""                   #: the standard's clause (or the paper) it follows
    source: str = ""                   #: 'standard' or the secondary source it was taken from
    reason: str = ""                   #: why it is not available
    series: dict[str, Any] = field(default_factory=dict, repr=False)   #: for CSV and plots

    @property
    def available(self) -> bool:
        return self.value is not None

    @property
    def margin(self) -> float | None:
        if self.value is None or self.limit is None or self.limit == 0:
            return None
        return (self.limit - abs(self.value)) / self.limit

    @property
    def passed(self) -> bool | None:
        m = self.margin
        return None if m is None else m >= 0

    def label(self) -> str:
        """'Y/Q w1 left', 'N_MV car_floor', ...: the quantity and what it belongs to."""
        parts = [self.name]
        for p in (self.wheelset, self.side, None if self.patch is None else f"patch{self.patch}",
                  self.sensor, self.direction):
            if p:
                parts.append(str(p))
        return " ".join(parts)

    def to_json(self) -> dict[str, Any]:
        def number(v):
            return None if v is None or not math.isfinite(v) else float(v)
        out = {"name": self.name, "wheelset": self.wheelset, "side": self.side,
               "value": number(self.value), "limit": number(self.limit), "unit": self.unit,
               "position": number(self.position), "margin": number(self.margin)}
        for key in ("patch", "sensor", "direction"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        out["clause"] = self.clause
        out["source"] = self.source
        if not self.available:
            out["reason"] = self.reason
        return out


def not_available(name: str, unit: str, reason: str, **kwargs) -> Quantity:
    """A quantity that cannot be evaluated from this file, with the reason."""
    return Quantity(name, unit, value=None, reason=reason, **kwargs)
