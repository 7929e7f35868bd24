"""What the assessment reads from a results file (docs/output.md): the wheelsets, where each
one is on the track, the curvature under it, its wheel forces and contact patches, and the
sensors.

Where a wheelset is: a results file does not name the body of a wheelset nor the track frame
of a body, but it stores the deck it was run from (``/meta/deck_text``, includes spliced).
The &wheelset group names its ``body``; that body's ``frame_offset`` (or the one of the body
whose ``frame`` it shares) places its track frame at ``sigma_vehicle + frame_offset``
(docs/input_reference.md &body), so the wheelset's track position is
``vehicle/distance + frame_offset + x`` with ``x`` its position in that frame
(``bodies/<body>/position_track:x``, 0 when the bodies are not in the file). The frame's own
series (``track/frames/<k>``, k the frame whose ``sigma - vehicle/distance`` is that offset)
give the curvature under the wheelset.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from ..results import Results

__all__ = ["LayoutError", "WheelsetData", "SensorData", "deck_groups", "read_wheelsets",
           "read_sensors", "wheelset_names", "SIDES"]

SIDES = ("left", "right")


class LayoutError(ValueError):
    """The file lacks what a group of quantities needs; the message is the reason."""


def _first_outside_quotes(text: str, chars: str, start: int = 0) -> int:
    """Index of the first character of ``chars`` at or after ``start`` that is not inside a
    quoted string; len(text) when there is none."""
    quote = None
    for i in range(start, len(text)):
        ch = text[i]
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch in chars:
            return i
    return len(text)


def deck_groups(text: str) -> list[tuple[str, dict[str, str]]]:
    """The namelist groups of a deck text as (group name, {parameter: raw value text}), in
    order; quotes are kept off string values. Enough for names and numbers; the Fortran deck
    reader remains the authority on what a deck means."""
    body = "\n".join(line[:_first_outside_quotes(line, "!")] for line in text.splitlines())
    groups: list[tuple[str, dict[str, str]]] = []
    i, n = 0, len(body)
    while i < n:
        start = body.find("&", i)
        if start < 0:
            break
        m = re.match(r"&(\w+)", body[start:])
        if not m:
            i = start + 1
            continue
        j = _first_outside_quotes(body, "/", start + m.end())     # the group ends at '/'
        content = body[start + m.end():j]
        params: dict[str, str] = {}
        equals, k = set(), _first_outside_quotes(content, "=")      # '=' not inside a string
        while k < len(content):
            equals.add(k)
            k = _first_outside_quotes(content, "=", k + 1)
        names = [a for a in re.finditer(r"(?:^|,|\s)(\w+)\s*=", content) if a.end() - 1 in equals]
        for k, a in enumerate(names):
            end = names[k + 1].start() if k + 1 < len(names) else len(content)
            value = content[a.end():end].strip().rstrip(",").strip()
            if len(value) >= 2 and value[0] == value[-1] and value[0] in "'\"":
                value = value[1:-1]
            params[a.group(1).lower()] = value
        groups.append((m.group(1).lower(), params))
        i = j + 1
    return groups


def _merged(groups, kind: str) -> dict[str, dict[str, str]]:
    """Groups of one kind by name; a later group of the same name overrides parameters."""
    out: dict[str, dict[str, str]] = {}
    for g, params in groups:
        if g == kind and "name" in params:
            out.setdefault(params["name"], {}).update(params)
    return out


@dataclass
class WheelsetData:
    name: str
    position: np.ndarray                  #: track position of the wheelset [m] per row
    position_note: str                    #: how the position was found
    curvature: np.ndarray | None          #: horizontal curvature under it [1/m], or None
    wheel: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)      #: side -> column -> (n,)
    patches: dict[str, list[dict[str, np.ndarray]]] = field(default_factory=dict)  #: side -> [patch columns]


@dataclass
class SensorData:
    name: str
    series: str                           #: the results series the accelerations come from
    acceleration: np.ndarray              #: (n, 3) x y z [m/s^2]
    frame_offset: float | None = None     #: of its body's track frame, None if not in the deck
    x: np.ndarray | None = None           #: (n,) its x in its track frame (position_track), m


def _columns(r: Results, series: str) -> dict[str, np.ndarray]:
    data = np.asarray(r.get(series), float)
    return {c: data[:, k] for k, c in enumerate(r.components(series))}


def _frame_offset(bodies: dict[str, dict[str, str]], body: str) -> float:
    seen = set()
    while body in bodies and body not in seen:
        seen.add(body)
        frame = bodies[body].get("frame", "own")
        if frame in ("", "own") or frame not in bodies:
            return float(bodies[body].get("frame_offset", "0").replace("d", "e").replace("D", "e"))
        body = frame
    raise LayoutError(f"body {body!r} is not in the deck stored in the file")


def wheelset_names(r: Results) -> list[str]:
    """Names of the wheelsets that have series in the file, sorted."""
    return sorted({c.split("/")[1] for c in r.channels() if c.startswith("wheelsets/")})


def read_wheelsets(r: Results) -> list[WheelsetData]:
    """Every wheelset with wheel-rail contact series in the file, in file order."""
    names = wheelset_names(r)
    if not names:
        return []
    groups = deck_groups(r.deck_text or "")
    bodies = _merged(groups, "body")
    wheelsets = _merged(groups, "wheelset")
    if "vehicle/distance" not in r:
        raise LayoutError("the file has no vehicle/distance series: wheelset positions unknown")
    distance = np.asarray(r.get("vehicle/distance:sigma"), float)
    frames = {}
    for c in r.channels():
        m = re.fullmatch(r"track/frames/(\d+)/sigma", c)
        if m:
            frames[m.group(1)] = np.asarray(r.get(c), float)[:, 0]
    out = []
    for name in names:
        spec = wheelsets.get(name)
        if spec is None or "body" not in spec:
            raise LayoutError(f"wheelset {name!r}: no &wheelset group naming its body in the "
                              "deck stored in the file (/meta/deck_text)")
        body = spec["body"]
        offset = _frame_offset(bodies, body)
        x_channel = f"bodies/{body}/position_track:x"
        if x_channel in r:
            x = np.asarray(r.get(x_channel), float)
            note = f"vehicle/distance + frame_offset {offset:g} m + x of body {body}"
        else:
            x = np.zeros_like(distance)
            note = f"vehicle/distance + frame_offset {offset:g} m (bodies not in the file: x = 0)"
        curvature = None
        for k, sigma in frames.items():
            if sigma.size and np.allclose(sigma - distance, offset, rtol=0, atol=1e-6 * (1 + abs(offset))):
                if f"track/frames/{k}/curvature" in r:
                    curvature = np.asarray(r.get(f"track/frames/{k}/curvature"), float)[:, 0]
                break
        ws = WheelsetData(name, distance + offset + x, note, curvature)
        for side in SIDES:
            base = f"wheelsets/{name}/{side}"
            if f"{base}/wheel" in r:
                ws.wheel[side] = _columns(r, f"{base}/wheel")
            ws.patches[side] = [_columns(r, f"{base}/patch{j}") for j in range(1, 9)
                                if f"{base}/patch{j}" in r]
        out.append(ws)
    return out


#: sensor series in order of preference: what an accelerometer on the floor reads (docs/output.md
#: /sensors: acceleration minus gravity, car body axes), then the absolute acceleration
_SENSOR_SERIES = ("specific_force_body", "acceleration_body", "acceleration_track")


def read_sensors(r: Results) -> list[SensorData]:
    """Sensor accelerations (``/sensors/<name>/...``, three columns x y z in m/s^2), from the
    first of ``specific_force_body``, ``acceleration_body``, ``acceleration_track`` the file
    holds: EN 12299 measures with accelerometers along the car body's axes."""
    names = sorted({c.split("/")[1] for c in r.channels() if c.startswith("sensors/")})
    groups = deck_groups(r.deck_text or "")
    bodies, specs = _merged(groups, "body"), _merged(groups, "sensor")
    out = []
    for name in names:
        offset = None
        if "body" in specs.get(name, {}):
            try:
                offset = _frame_offset(bodies, specs[name]["body"])
            except (LayoutError, ValueError):
                offset = None
        x = None
        if f"sensors/{name}/position_track" in r:
            x = np.asarray(r.get(f"sensors/{name}/position_track"), float)[:, 0]
        for kind in _SENSOR_SERIES:
            series = f"sensors/{name}/{kind}"
            if series in r and r.get(series).shape[1] == 3:
                out.append(SensorData(name, series, np.asarray(r.get(series), float), offset, x))
                break
    return out
