"""The docs table of docs/KEYFRAMES.md: keys that Interpolator.keyframes needs on each gallery
example for 0.5 % and 0.1 % of the size, against the fewest evenly spaced keys for the same bound
(both checked on 1201 evenly spaced factors).

    PYTHONPATH=python /usr/bin/python3 scripts/keyframes_table.py
"""

import glob
import os

import numpy as np

import bdinterp
from bdinterp import io
from bdinterp.keyframes import dense_error, even_count

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOLERANCES = (0.005, 0.001)
DENSE = np.linspace(0.0, 1.0, 1201)


def main():
    print("| example | vertices | " + " | ".join(
        "%g %%: adaptive | even | error" % (100 * t) for t in TOLERANCES) + " |")
    print("|---|---:|" + "---:|---:|---:|" * len(TOLERANCES))
    for path in sorted(glob.glob(os.path.join(ROOT, "examples", "*", "target.obj"))):
        name = os.path.basename(os.path.dirname(path))
        V, F = io.read_obj(os.path.join(os.path.dirname(path), "source.obj"))[:2]
        Y = io.read_obj(path)[0]
        interp = bdinterp.Interpolator([V, Y], F, threads=1)
        frames, cells = interp.frames(DENSE), []
        for tol in TOLERANCES:
            keys = interp.keyframes(tol)
            err = dense_error(interp, keys, DENSE, frames)
            cells += [str(len(keys)), str(even_count(interp, tol, DENSE)), "%.2f %%" % (100 * err)]
        print("| %s | %d | %s |" % (name, len(V), " | ".join(cells)))


if __name__ == "__main__":
    main()
