#!/usr/bin/env python3
"""Speed of bdinterp.strokes: N strokes of P points (random arcs, each turned and bent between
the keys), K in-betweens, from the strokes to the in-between strokes (pairing, bands, meetings,
the Interpolator and its frames).  Prints the median of R runs and each stage once.

    PYTHONPATH=python /usr/bin/python3 scripts/bench_strokes.py [N P K R]   (default 200 100 10 5)
"""
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples", "strokes"))
import drawn  # noqa: E402
from bdinterp.strokes import StrokeInterpolator  # noqa: E402


def drawing(n, points, seed=1):
    """Two keys of n strokes spread over a 20 x 20 sheet: arcs 1-3 long bent by up to 90
    degrees; in the second key each is turned by up to 150 degrees about its start (which stays,
    as a hair's root does) and bent by up to 60 degrees more."""
    rng = np.random.default_rng(seed)
    a, b = [], []
    for _ in range(n):
        start, heading = rng.uniform(0, 20, 2), rng.uniform(-180, 180)
        length, bend = rng.uniform(1, 3), rng.uniform(-90, 90)
        a.append(drawn.arc(start, heading, length, bend, points))
        b.append(drawn.arc(start, heading + rng.uniform(-150, 150), length, bend + rng.uniform(-60, 60), points))
    return a, b


def main(n=200, points=100, count=10, runs=5):
    a, b = drawing(n, points)
    ts = np.linspace(0, 1, count + 2)[1:-1]
    times = []
    for _ in range(runs):
        start, cpu = time.perf_counter(), time.process_time()
        si = StrokeInterpolator(a, b)
        built = time.perf_counter()
        si.frames(ts)
        times.append((time.perf_counter() - start, built - start, time.process_time() - cpu))
    total, build, cpu = (np.median([t[k] for t in times]) for k in range(3))
    print(f"{n} strokes x {points} points, {count} in-betweens: {total:.3f} s median of {runs} "
          f"(setup {build:.3f} s, frames {total - build:.3f} s; CPU {cpu:.3f} s); {len(si.joints)} joints, "
          f"{len(si.still)} still ends, {si.stats.pieces} pieces")


if __name__ == "__main__":
    main(*[int(x) for x in sys.argv[1:]])
