#!/usr/bin/env python3
"""The FK biped of tests/python/biped.py in every pose: the largest distance of any vertex from the
bones' own in-between over t = 1/4, 1/2, 3/4, relative to the size, raw and after the best rigid
fit of the whole character, for the joints found from the keys (pins), the bones' links given
(bones), each piece on its own path (joints off) and the vertices' linear blend.

    PYTHONPATH=python /usr/bin/python3 scripts/biped_report.py
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests", "python"))
import numpy as np  # noqa: E402

import bdinterp  # noqa: E402
from biped import POSES, posed, rigid_fit_error  # noqa: E402
from test_biped import TS, biped_character, root_links  # noqa: E402


def worst(ch, pose, frames):
    raw = fit = 0.0
    for t, X in zip(TS, frames):
        Y = posed(ch, pose, t)
        raw = max(raw, np.linalg.norm(X - Y, axis=1).max() / ch.size)
        fit = max(fit, rigid_fit_error(X, Y) / ch.size)
    return "%.3g %% / %.3g %%" % (100 * raw, 100 * fit)


def main():
    ch = biped_character()
    print("| pose | pins | bones | joints off | linear blend |")
    print("|---|---|---|---|---|")
    for name, pose in POSES.items():
        keys = [ch.V, posed(ch, pose, 1.0)]
        row = [worst(ch, pose, bdinterp.Interpolator(keys, ch.F, joints=j).frames(TS))
               for j in (True, root_links(ch), False)]
        row.append(worst(ch, pose, [(1 - t) * keys[0] + t * keys[1] for t in TS]))
        print("| %s | %s |" % (name, " | ".join(row)))


if __name__ == "__main__":
    main()
