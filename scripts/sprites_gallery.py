#!/usr/bin/env python3
"""docs/gallery/sprites.png: each example sprite (examples/sprites) with its mesh from
bdinterp.mesh_from_image (default parameters) drawn over it, and below, a bend of that mesh baked
by bdinterp: the source and the bent target (faint) and the in-between at t = 0.5, coloured by
each face's conformal distortion K. Prints a Markdown table of the figures and checks that no
in-between's max K exceeds its target's.

    /usr/bin/python3 scripts/sprites_gallery.py   (needs the built python/bdinterp)
"""
import os
import sys

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "python"), os.path.join(ROOT, "tools")]
import bdinterp  # noqa: E402
from bdinterp import figures  # noqa: E402
from bdinterp_tools.sprites import SPRITES  # noqa: E402

SPRITE_DIR = os.path.join(ROOT, "examples", "sprites")
OUT = os.path.join(ROOT, "docs", "gallery", "sprites.png")
T = 0.5
ANGLE = np.pi / 2  # the right part's turn
BAND = 0.8  # the width over which the turn ramps up, a share of the sprite's width


def bend(V):
    """The points V (n, 2) turned about a pivot at the top of their bounding box, half-way across,
    by an angle that ramps smoothly (smoothstep) from 0 to ANGLE across a band around the pivot:
    left of it nothing moves, right of it a rigid turn. The Jacobian's determinant is
    1 + theta'(x) (pivot_y - y) >= 1, so the bend is locally injective for any mesh."""
    lo, hi = V.min(axis=0), V.max(axis=0)
    pivot = np.array([(lo[0] + hi[0]) / 2, hi[1]])
    width = BAND * (hi[0] - lo[0])
    s = np.clip((V[:, 0] - pivot[0]) / width + 0.5, 0.0, 1.0)
    theta = ANGLE * s * s * (3 - 2 * s)
    c, n = np.cos(theta), np.sin(theta)
    d = V - pivot
    return pivot + np.c_[c * d[:, 0] - n * d[:, 1], n * d[:, 0] + c * d[:, 1]]


def bake(name):
    """The sprite's image, its mesh, the bent target, the in-between at T and both K per face."""
    image = np.asarray(Image.open(os.path.join(SPRITE_DIR, f"{name}.png")).convert("RGBA"))
    mesh = bdinterp.mesh_from_image(image)
    V, F = mesh.vertices, mesh.faces
    target = bend(V)
    between = bdinterp.Interpolator([V, target], F).frames([T])[0]
    k_target = bdinterp.conformal_distortion(V, target, F)
    k_between = bdinterp.conformal_distortion(V, between, F)
    assert bdinterp.flipped_faces(V, between, F) == 0, name
    assert k_between.max() <= k_target.max() * (1 + 1e-9), (name, k_between.max(), k_target.max())
    return dict(name=name, image=image, V=V, F=F, target=target, between=between,
                k_target=k_target, k_between=k_between)


def checkerboard(ax, h, w, square=8):
    """A light grey checkerboard under the sprite, so that its alpha shows."""
    y, x = np.mgrid[0:h, 0:w] // square
    ax.imshow(np.where((x + y) % 2, 0.93, 0.82), cmap="gray", vmin=0, vmax=1,
              extent=(0, w, 0, h), interpolation="nearest")


def draw_sprite(ax, r):
    """Row 1: the sprite (y up, pixels) with its mesh over it."""
    h, w = r["image"].shape[:2]
    checkerboard(ax, h, w)
    ax.imshow(r["image"], extent=(0, w, 0, h), interpolation="nearest")
    ax.triplot(r["V"][:, 0], r["V"][:, 1], r["F"], color="k", linewidth=0.5)
    ax.set_xlim(0, w)
    ax.set_ylim(0, h)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(f"{r['name']}\n{len(r['V'])} vertices, {len(r['F'])} faces", fontsize=11)


def draw_bend(ax, r, norm):
    """Row 2: source (grey) and target (green), faint, and the in-between coloured by K."""
    V, F = r["V"], r["F"]
    ax.triplot(V[:, 0], V[:, 1], F, color="0.75", linewidth=0.4)
    ax.triplot(r["target"][:, 0], r["target"][:, 1], F, color="tab:green", alpha=0.35,
               linewidth=0.4)
    coll = figures.draw_mesh(ax, r["between"], F, r["k_between"], norm, cmap="viridis")
    coll.set_edgecolor("k")
    coll.set_linewidth(0.3)
    ax.set_title(f"max K: target {r['k_target'].max():.3g}\n"
                 f"in-between (t = {T:g}) {r['k_between'].max():.3g}", fontsize=11)
    return coll


def figure(results):
    """One column per sprite; one K colour scale (to the largest target K) for the bottom row."""
    from matplotlib.colors import LogNorm
    plt = figures.pyplot()
    n = len(results)
    fig, axes = plt.subplots(2, n, figsize=(3.6 * n, 7.6),
                             gridspec_kw=dict(hspace=0.15, height_ratios=[1, 1.1]))
    norm = LogNorm(vmin=1.0, vmax=max(r["k_target"].max() for r in results))
    for col, r in enumerate(results):
        draw_sprite(axes[0, col], r)
        coll = draw_bend(axes[1, col], r, norm)
    bar = fig.colorbar(coll, ax=axes[1, :], shrink=0.8, pad=0.01,
                       label=f"K at t = {T:g}")
    bar.ax.yaxis.set_major_formatter("{x:g}")
    bar.ax.yaxis.set_minor_formatter("{x:g}")
    fig.suptitle(f"mesh_from_image (default parameters); below: the right part turned "
                 f"{np.degrees(ANGLE):.0f}° (target, green), the source (grey) and bdinterp's "
                 f"in-between at t = {T:g}", fontsize=12)
    return fig


def main():
    results = [bake(name) for name in SPRITES]
    print(f"| sprite | vertices | faces | target max K | in-between max K (t = {T:g}) |")
    print("|---|---:|---:|---:|---:|")
    for r in results:
        print(f"| {r['name']} | {len(r['V'])} | {len(r['F'])} | {r['k_target'].max():.3f} "
              f"| {r['k_between'].max():.3f} |")
    figures.save(figure(results), OUT, dpi=100)


if __name__ == "__main__":
    main()
