#!/usr/bin/env python3
"""The C-IPC dress on the rumba dancer, with the dancer's frames read by NumPy and handed to the
body frame by frame: invfem driven from Python, as a script that computes its body (a parametric
body model, a retargeted motion) would drive it.

    PYTHONPATH=build/apps/python python3 apps/python/examples/dress_on_numpy_body.py OUT [--frames N]

writes OUT as `invfem run apps/scenes/garments/dress_dance.json --out OUT` does (check it with
`invfem check OUT`). Needs ../shared/data beside the clone (or --data).
"""

import argparse
import os
import sys
import time

import numpy as np

import invfem

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def read_obj_vertices(path):
    """The `v x y z` lines of an OBJ, in file order: (V, 3) float64."""
    with open(path) as f:
        rows = [line.split()[1:4] for line in f if line.startswith("v ")]
    return np.array(rows, dtype=np.float64)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="output folder (a run folder, as invfem run --out)")
    parser.add_argument("--frames", type=int, default=None, help="frames to simulate (default: the scene's 120)")
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"), help="the shared data folder")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
    args = parser.parse_args()

    dancer = os.path.join(args.data, "garment", "rumba", "shell{}.obj")
    if not os.path.exists(dancer.format(0)):
        sys.exit(f"{dancer.format(0)}: missing (the dancer's frames are in ../shared/data)")
    scene = os.path.join(ROOT, "apps", "scenes", "garments", "dress_dance.json")
    overrides = {} if args.frames is None else {"frames": args.frames}
    sim = invfem.Simulation(scene, set=overrides, out=args.out, overwrite=True, threads=args.threads)

    last = 120  # the dancer's last frame; past it the body holds (the scene's after_end)
    body = lambda k: read_obj_vertices(dancer.format(min(k, last)))
    sim.set_body_frame("body", 0, body(0))
    sim.set_body_frame("body", 1, body(1))
    start = time.monotonic()
    for frame in range(1, sim.frames + 1):
        if frame + 1 <= last:
            sim.set_body_frame("body", frame + 1, body(frame + 1))  # a step to frame f needs frame f + 1
        r = sim.step_frame()
        sc = r["self_collision"]
        print(f"frame {frame}/{sim.frames}  {r['seconds']['simulate']:.2f}s  substeps {r['substeps']}  "
              f"newton {r['newton_iterations']}{'' if r['newton_converged'] else ' (capped)'}  "
              f"self-collision {sc['proximity_impulses']} repulsions, {sc['ccd_hits']} CCD hits", flush=True)
    wall = time.monotonic() - start
    print(f"done: {sim.frames} frames in {wall:.1f}s ({wall / sim.frames:.2f} s/frame); output in {args.out}")


if __name__ == "__main__":
    main()
