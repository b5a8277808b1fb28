#!/usr/bin/env python3
"""Choosing the joint tree against a warm frame, for a character of 30 pieces: the biped of
tests/python/biped.py in its run and 13 of its pieces again beside it, meshed at CELL (0.047:
20246 vertices; 0.05: 17734). The tree is chosen when the Interpolator is made: its cost is
`Interpolator.joints_seconds` (the wall-clock time the joints took inside the constructor, just
after the solvers' setup, so with the caches as a user gets them) over REPEATS Interpolators; a
warm frame is `stats.seconds` of `at(t)` just after a frame 0.002 away, one thread. Prints one
JSON line: each as its least and its median, and the ratio of the medians.

    /usr/bin/python3 scripts/bench_joint_tree.py PYTHON_DIR CELL REPEATS   (e.g. python 0.047 21)
"""
import json
import os
import sys

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


def warm_frames(interp, frames=60):
    """Seconds of interp.at(t), each just after a frame 0.002 away."""
    interp.at(0.3)
    times = []
    for k in range(frames):
        interp.at(0.3 + 0.002 * (k % 50))
        times.append(interp.stats.seconds)
    return np.array(times)


def main():
    V, T, F = character(float(sys.argv[2]))
    interps = [bdinterp.Interpolator([V, T], F, threads=1, joints=True) for _ in range(int(sys.argv[3]))]
    tree = np.array([i.joints_seconds for i in interps])
    warm = warm_frames(interps[-1])
    ms = lambda x: round(1e3 * float(x), 3)  # noqa: E731
    print(json.dumps({"pieces": 30, "vertices": len(V), "tree_ms": [ms(tree.min()), ms(np.median(tree))],
                      "warm_frame_ms": [ms(warm.min()), ms(np.median(warm))],
                      "tree_per_frame": round(float(np.median(tree) / np.median(warm)), 3)}))


if __name__ == "__main__":
    main()
