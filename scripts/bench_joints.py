#!/usr/bin/env python3
"""Warm frames of the FK rig (tests/python/fk_rig.py, pieces meshed at CELL): the median time of
`at(t)` just after a frame 0.002 away, one thread; prints one JSON line.

    /usr/bin/python3 scripts/bench_joints.py PYTHON_DIR CELL FRAMES   (e.g. python 0.05 100)

PYTHON_DIR holds the bdinterp package to time, so that two builds can be run alternately.
"""
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [sys.argv[1], os.path.join(ROOT, "tests", "python")]
import numpy as np  # noqa: E402

import bdinterp  # noqa: E402
import test_rigs  # noqa: E402
from cutout_meshes import Character, rectangle  # noqa: E402
from fk_rig import NAMES, POSES, RIG  # noqa: E402

cell = float(sys.argv[2])
pieces = [rectangle(*RIG[n][0], cell, seed=i) for i, n in enumerate(NAMES)]
pins = [(NAMES.index(RIG[n][1]), NAMES.index(n), np.array(RIG[n][2])) for n in NAMES if RIG[n][1]]
ch = Character(pieces, pins)
T = test_rigs.bones(ch, POSES["limbs_out"], 1.0)
I = bdinterp.Interpolator([ch.V, T], ch.F, threads=1)
I.at(0.3)
ts = []
for k in range(int(sys.argv[3])):
    t = 0.3 + 0.002 * (k % 50)
    s = time.perf_counter(); I.at(t); ts.append(time.perf_counter() - s)
print(json.dumps({"n": len(ch.V), "median_ms": 1e3 * float(np.median(ts))}))
