#!/usr/bin/env python3
"""docs/gallery/joints_rig.png: the FK rig of tests/python/fk_rig.py, the joints the core finds
from its two keys (pins, drawn over every overlap of the rest pose), and its in-betweens.

    /usr/bin/python3 scripts/joints_picture.py   (needs the built python/bdinterp)
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.spatial import ConvexHull  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "tests", "python")]
import bdinterp  # noqa: E402
from fk_rig import NAMES, POSES, RIG  # noqa: E402
from test_rigs import bones, rig  # noqa: E402

OUT = os.path.join(ROOT, "docs", "gallery", "joints_rig.png")


def overlaps():
    """Pairs of pieces whose rectangles overlap in the rest pose."""
    box = {n: RIG[n][0] for n in NAMES}
    return [(a, b) for i, a in enumerate(NAMES) for b in NAMES[i + 1:]
            if box[a][0] < box[b][0] + box[b][2] and box[b][0] < box[a][0] + box[a][2]
            and box[a][1] < box[b][1] + box[b][3] and box[b][1] < box[a][1] + box[a][3]]


def draw(ax, ch, X, colour, alpha):
    """Each piece as its outline (the hull of its vertices: the pieces are rectangles), filled."""
    for rows in ch.ranges:
        P = X[rows][ConvexHull(X[rows]).vertices]
        ax.fill(P[:, 0], P[:, 1], fc=colour, alpha=alpha, ec=colour, lw=1)


def main():
    ch, angles = rig(), POSES["hand_crosses_body"]
    target = bones(ch, angles, 1.0)
    interp = bdinterp.Interpolator([ch.V, target], ch.F)
    centre = {n: ch.V[ch.ranges[k]].mean(axis=0) for k, n in enumerate(NAMES)}
    lowest = {int(r[0]): NAMES[k] for k, r in enumerate(ch.ranges)}
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 6.5))
    draw(a, ch, ch.V, "0.4", 0.2)
    for p, q in overlaps():
        a.plot(*np.c_[centre[p], centre[q]], ls=":", c="0.45", lw=1)
    for j in interp.joints():
        c, p = centre[lowest[j["child"]]], j["point"]
        a.annotate("", xy=c, xytext=p, arrowprops=dict(arrowstyle="->", color="C3", lw=1.4))
        a.plot(*p, "o", c="C3", ms=5)
    a.set_title("rest pose: overlaps (dotted) and the joints found (%s)"
                % ", ".join(sorted({j["kind"] for j in interp.joints()})), fontsize=10)
    for X, colour in ((ch.V, "0.6"), (target, "C2"), (interp.at(0.5), "C0")):
        draw(b, ch, X, colour, 0.15)
    lin = 0.5 * (ch.V + target)
    b.plot(*lin[ch.ranges[NAMES.index("hand_r")]].mean(axis=0), "x", c="C1", ms=9)
    b.plot(*interp.at(0.5)[ch.ranges[NAMES.index("hand_r")]].mean(axis=0), "o", c="C0", ms=7)
    b.set_title("keys (grey, green) and the in-between at t = 0.5 (blue);\n"
                "the right hand's centre: bdinterp (o) and the linear blend (x)", fontsize=10)
    save(fig, OUT, 90)


def save(fig, out, dpi):
    """Every axes of fig without its frame, at equal scale, written to `out`."""
    for ax in fig.axes:
        ax.set_aspect("equal")
        ax.axis("off")
    fig.savefig(out, dpi=dpi, bbox_inches="tight")
    print("wrote", out)


if __name__ == "__main__":
    main()
