#!/usr/bin/env python3
"""Ringing of the wheelsets' contact modes (docs/theory_flange_chatter.md, section 8): steps a
deck through the C API from T0 to T1 in increments DT, then prints per wheelset the standard
deviation and the dominant frequency (Hann-windowed spectrum) of its lateral, vertical and roll
rates relative to the track frame.

    PYTHONPATH=python python3 bench/contact_chatter/ringing.py DECK T0 T1 DT
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
import raildyn  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("deck")
    ap.add_argument("t0", type=float)
    ap.add_argument("t1", type=float)
    ap.add_argument("dt", type=float)
    args = ap.parse_args()
    with raildyn.Model.from_file(args.deck) as m:
        m.initialize(write_output=False)
        m.advance(args.t0)
        wheelsets = sorted({n.split("/")[1] for n in m.output_names()
                            if n.startswith("bodies/ws") and n.endswith("velocity_track")})
        rows, t = [], args.t0
        while t < args.t1 - 1e-12:
            t += args.dt
            m.advance(t)
            rows.append(np.concatenate([m.output(f"bodies/{w}/velocity_track") for w in wheelsets]))
    rates = np.array(rows)
    freq = np.fft.rfftfreq(len(rates), args.dt)
    window = np.hanning(len(rates))
    print(f"{args.deck}: t = {args.t0:g}-{args.t1:g} s every {args.dt:g} s")
    for k, w in enumerate(wheelsets):
        for j, label in ((1, "lateral rate [m/s]"), (2, "vertical rate [m/s]"), (4, "roll rate [rad/s]")):
            x = rates[:, 6 * k + j] - rates[:, 6 * k + j].mean()
            peak = freq[1 + np.argmax(np.abs(np.fft.rfft(x * window))[1:])]
            print(f"  {w} {label}: std {x.std():.3e}, dominant {peak:.0f} Hz")


if __name__ == "__main__":
    main()
