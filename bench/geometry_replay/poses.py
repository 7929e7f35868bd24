#!/usr/bin/env python3
"""Wheelset poses for bench_geometry_replay from a results file: for every output row and
wheelset body, the contact geometry's pose (lateral y, vertical z, roll, yaw relative to the
track frame, docs/conventions.md) from bodies/<body>/position_track (x y z yaw roll pitch).

    python3 bench/geometry_replay/poses.py RESULTS.h5 POSES.txt [--bodies ws1 ws2 ws3 ws4]
"""
import argparse

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results")
    ap.add_argument("poses")
    ap.add_argument("--bodies", nargs="+", default=["ws1", "ws2", "ws3", "ws4"])
    args = ap.parse_args()
    rows = []
    with h5py.File(args.results, "r") as f:
        for body in args.bodies:
            q = f[f"bodies/{body}/position_track"][()]
            rows.append(q[:, [1, 2, 4, 3]])          # y, z, roll, yaw
    poses = np.concatenate(rows)
    poses = poses[np.all(np.isfinite(poses), axis=1)]
    np.savetxt(args.poses, poses, fmt="%.17e")
    print(f"{len(poses)} poses written to {args.poses}")


if __name__ == "__main__":
    main()
