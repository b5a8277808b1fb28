"""Bake Grid's error on examples/face: for each group and n = 1, 2, 4 fine nodes per cell side,
the largest distance of a vertex between the runtime's linear blend of the baked poses and
bdinterp's blend (relative to the face's size), checked at 4 points per fine cell side.

    PYTHONPATH=python:tools /usr/bin/python3 examples/face/bake_errors.py
"""

import os
import sys

from bdinterp.pose_bake import GridBake

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import face_rig  # noqa: E402
from pad_figure import blender_of  # noqa: E402


def main():
    shapes, faces, groups = face_rig.poses()
    blender = blender_of(shapes, faces, groups)
    print("| group | n = 1 | n = 2 | n = 4 | keys at n = 4 |")
    print("|---|---:|---:|---:|---:|")
    for group in groups:
        row = []
        for n in (1, 2, 4):
            bake = GridBake(blender, group, n)
            row.append("%.2e" % bake.error(samples=4)[0])
        print("| %s | %s | %d |" % (group, " | ".join(row), len(bake.shapes)))


if __name__ == "__main__":
    main()
