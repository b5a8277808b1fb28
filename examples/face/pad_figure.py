"""The gallery picture of examples/face: the head's pad (angle_x x angle_y) at 5 x 5 points,
bdinterp's blend against the linear blend a runtime does (Live2D, Inochi2D, glTF morph targets),
with the head's area against the same weights' blend of the poses' areas (what it should be when
nothing is lost); and a mouth opened on a turned head, both groups
combined (bdinterp: in the blended metric; linear: the mouth's vertex offsets added).

    PYTHONPATH=python:tools /usr/bin/python3 examples/face/pad_figure.py [out.png]

Prints the area lost at the worst point of the pad by each blend.
"""

import os
import sys

import numpy as np

from bdinterp import figures
from bdinterp.pose_grid import Parameter, PoseBlender, PoseGrid

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import face_rig  # noqa: E402

COLORS = {"body": "#9bb7d4", "head": "#f2d0b5", "eye_l": "#333333", "eye_r": "#333333",
          "nose": "#d9a07e", "mouth": "#b03a48"}
PAD = np.linspace(-30, 30, 5)


def blender_of(shapes, faces, groups):
    grids = []
    for name, (params, keys) in groups.items():
        ps = [Parameter(n, v["values"], wrap=v.get("wrap", False)) if isinstance(v, dict)
              else Parameter(n, v) for n, v in params.items()]
        grids.append(PoseGrid(ps, keys, name=name))
    return PoseBlender(shapes, faces, grids, "Basis")


def linear(blender, shapes, points):
    """The runtime's blend: the weights' sum of the poses' vertex positions."""
    w = blender.weights(points)
    return sum(wk * shapes[k] for k, wk in w.items())


def area(X, F, idx):
    """Total area of the faces of the vertices idx (their projection on the picture plane)."""
    mask = np.isin(F[:, 0], idx)
    a, b, c = (X[F[mask, i], :2] for i in range(3))
    return 0.5 * np.abs(np.cross(b - a, c - a)).sum()


def draw(ax, X, F, labels, offset, scale=0.3):
    for name in face_rig.DEPTHS:
        idx = labels[name]
        mask = np.isin(F[:, 0], idx)
        P = X[:, :2] * scale + offset
        ax.tripcolor(P[:, 0], P[:, 1], F[mask], facecolors=np.zeros(mask.sum()),
                     cmap=_flat(COLORS[name]), edgecolors="none")


def _flat(color):
    from matplotlib.colors import ListedColormap
    return ListedColormap([color])


def main(out):
    plt = figures.pyplot()
    shapes, F, groups = face_rig.poses()
    _, _, labels = face_rig.mesh()
    blender = blender_of(shapes, F, groups)
    head = np.concatenate([labels[n] for n in ("head", "eye_l", "eye_r", "nose", "mouth")])
    areas = {k: area(X, F, head) for k, X in shapes.items()}
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.4), gridspec_kw={"width_ratios": [5, 5, 2.4]})
    worst = {}
    for ax, method in zip(axes[:2], ("bdinterp", "linear")):
        ratios = []
        for i, x in enumerate(PAD):
            for j, y in enumerate(PAD):
                pt = {"head": (x, y)}
                X = blender.blend(pt).shape if method == "bdinterp" else linear(blender, shapes, pt)
                expected = sum(w * areas[k] for k, w in blender.weights(pt).items())
                ratios.append((area(X, F, head) / expected, x, y))
                draw(ax, X, F, labels, np.array([i * 1.0, j * 1.25]))
        r, x, y = min(ratios)
        worst[method] = (1 - r, x, y)
        ax.set_title("%s: head area lost at worst %.1f %% (angle_x %g, angle_y %g)"
                     % (method, 100 * (1 - r), x, y), fontsize=10)
    for ax in axes[:2]:
        ax.set_aspect("equal")
        ax.set_xticks(np.arange(5) * 1.0 + 0.0)
        ax.set_xticklabels(["%g" % v for v in PAD])
        ax.set_yticks(np.arange(5) * 1.25 + 0.36)
        ax.set_yticklabels(["%g" % v for v in PAD])
        ax.set_xlabel("angle_x (yaw)")
        ax.set_ylabel("angle_y (nod)")
    pt = {"head": (30, 30), "mouth": 1.0}
    draw(axes[2], blender.blend(pt).shape, F, labels, np.array([0.0, 0.0]))
    draw(axes[2], linear(blender, shapes, pt), F, labels, np.array([0.9, 0.0]))
    axes[2].set_aspect("equal")
    axes[2].set_axis_off()
    axes[2].set_title("mouth open on the head at (30, 30):\nbdinterp (left), linear (right)",
                      fontsize=10)
    figures.save(fig, out)
    return worst


if __name__ == "__main__":
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    target = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "docs", "gallery", "face_pad.png")
    for method, (lost, x, y) in main(target).items():
        print("%s: head area lost at worst %.2f %% at angle_x %g, angle_y %g" % (method, 100 * lost, x, y))
