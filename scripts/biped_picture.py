#!/usr/bin/env python3
"""docs/gallery/joints_biped.png: the FK biped of tests/python/biped.py, the joint tree the core
finds from the keys of its run (pins as dots, each child linked to its joint, the root starred;
the knee and the elbow drawn with a gap), and the fall at t = 1/2: the bones' in-between, the
core's with pins, and the vertices' linear blend.

    /usr/bin/python3 scripts/biped_picture.py   (needs the built python/bdinterp)
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "tests", "python"),
                os.path.join(ROOT, "scripts")]
import bdinterp  # noqa: E402
from biped import PIECES, POSES, posed  # noqa: E402
from joints_picture import draw, save  # noqa: E402
from test_biped import biped_character  # noqa: E402

OUT = os.path.join(ROOT, "docs", "gallery", "joints_biped.png")


def tree(ax, ch, interp):
    """The rest pose with the joints of `interp`: pins as dots, links to the children's centres."""
    draw(ax, ch, ch.V, "0.4", 0.2)
    centre = {int(r[0]): ch.V[r].mean(axis=0) for r in ch.ranges}
    for j in interp.joints():
        p, c = j["point"], centre[j["child"]]
        ax.plot([p[0], c[0]], [p[1], c[1]], c="C3", lw=1)
        ax.plot(*p, "o", c="C3" if j["kind"] == "pin" else "C1", ms=4)
    for r in interp.joint_roots():
        ax.plot(*centre[r["piece"]], "*", c="C0", ms=14)
    ax.set_title("the run's joint tree: pins (dots), links to the children,\nthe root (star: %s)"
                 % ", ".join("%s, %s" % (PIECES[[int(x[0]) for x in ch.ranges].index(r["piece"])],
                                         r["reason"]) for r in interp.joint_roots()), fontsize=10)


def main():
    ch = biped_character()
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 7))
    tree(a, ch, bdinterp.Interpolator([ch.V, posed(ch, POSES["run"], 1.0)], ch.F))
    pose = POSES["fall"]
    target = posed(ch, pose, 1.0)
    interp = bdinterp.Interpolator([ch.V, target], ch.F)
    for X, colour in ((ch.V, "0.75"), (target, "0.75"), (posed(ch, pose, 0.5), "C2"),
                      (interp.at(0.5), "C0"), (0.5 * (ch.V + target), "C1")):
        draw(b, ch, X, colour, 0.15)
    b.set_title("the fall at t = 1/2: the bones' (green), pins (blue),\nthe linear blend (orange); "
                "the keys in grey", fontsize=10)
    save(fig, OUT, 80)


if __name__ == "__main__":
    main()
