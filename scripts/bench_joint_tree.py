#!/usr/bin/env python3
"""Choosing the joint tree against a warm frame, for a character of 30 pieces: the biped of
tests/python/biped.py in its run and 13 of its pieces again beside it, meshed at CELL (0.05: 17.7k
vertices, 0.042: about 25k). The tree is chosen when the Interpolator is made: its cost is the
least CPU time of this thread to make one with joints=True minus the least with joints=False
(alternated REPEATS times each; CPU time and the least, as the machine is shared); a warm frame
is the median CPU time of `at(t)` just after a frame 0.002 away, one thread, with joints and
without. Prints one JSON line.

    /usr/bin/python3 scripts/bench_joint_tree.py PYTHON_DIR CELL REPEATS   (e.g. python 0.05 11)
"""
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [sys.argv[1], os.path.join(ROOT, "tests", "python")]
import numpy as np  # noqa: E402

import bdinterp  # noqa: E402
from biped import POSES, posed  # noqa: E402


def character(cell, extra=13):
    """(V, T, F): the biped meshed at `cell` and its first `extra` pieces again, 4 to the right."""
    import biped
    import cutout_meshes
    ch = cutout_meshes.Character([cutout_meshes.rectangle(*biped.BONES[n][2], cell, seed=k)
                                  for k, n in enumerate(biped.PIECES)], biped.pins())
    T1 = posed(ch, POSES["run"], 1.0)
    rows = np.concatenate(ch.ranges[:extra])
    faces = ch.F[np.concatenate(ch.face_ranges[:extra])]
    V = np.vstack([ch.V, ch.V[rows] + [4.0, 0.0]])
    T = np.vstack([T1, T1[rows] + [4.0, 0.0]])
    return V, T, np.vstack([ch.F, faces + len(ch.V)])


def warm_frame(interp, frames=60):
    """The median CPU time of interp.at(t) just after a frame 0.002 away."""
    interp.at(0.3)
    times = []
    for k in range(frames):
        start = time.thread_time()
        interp.at(0.3 + 0.002 * (k % 50))
        times.append(time.thread_time() - start)
    return float(np.median(times))


def main():
    V, T, F = character(float(sys.argv[2]))
    made = {True: [], False: []}
    for _ in range(int(sys.argv[3])):
        for joints in (True, False):
            start = time.thread_time()
            bdinterp.Interpolator([V, T], F, threads=1, joints=joints)
            made[joints].append(time.thread_time() - start)
    warm = {joints: warm_frame(bdinterp.Interpolator([V, T], F, threads=1, joints=joints))
            for joints in (True, False)}
    tree = min(made[True]) - min(made[False])
    print(json.dumps({"pieces": 30, "vertices": len(V), "tree_ms": round(1e3 * tree, 2),
                      "warm_frame_ms": round(1e3 * warm[True], 2), "tree_per_frame": round(tree / warm[True], 3),
                      "warm_frame_without_joints_ms": round(1e3 * warm[False], 2)}))


if __name__ == "__main__":
    main()
