"""Writes the project's test sprites as PNGs (examples/sprites/*.png) and prints the quality of
their meshes (default parameters) as a Markdown table: smallest angle, the share of triangles
below min_angle, coverage, vertices, faces, islands/holes and the time of one mesh_from_image.

    PYTHONPATH=python /usr/bin/python3 examples/sprites/make_sprites.py
"""
import pathlib
import sys
import time

import numpy as np
from matplotlib.tri import Triangulation
from PIL import Image

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parents[1] / "tools")]

import bdinterp  # noqa: E402
from bdinterp_tools.sprites import SPRITES, triangle_angles  # noqa: E402


def smallest_angles(V, F):
    """(m,) the smallest angle (degrees) of every triangle."""
    return triangle_angles(V, F).min(axis=1)


def main():
    print("| sprite | size | vertices | faces | islands / holes | smallest angle | below 20° | "
          "pixel centres covered | ms |")
    print("|---|---|---:|---:|---|---:|---:|---:|---:|")
    for name, draw in SPRITES.items():
        image = draw()
        Image.fromarray(image).save(HERE / f"{name}.png")
        start = time.perf_counter()
        mesh = bdinterp.mesh_from_image(HERE / f"{name}.png")
        ms = 1000 * (time.perf_counter() - start)
        h = image.shape[0]
        rows, cols = np.nonzero(image[..., 3] >= 128)
        centres = np.c_[cols + 0.5, h - rows - 0.5]
        tri = Triangulation(mesh.vertices[:, 0], mesh.vertices[:, 1], mesh.faces)
        covered = (tri.get_trifinder()(centres[:, 0], centres[:, 1]) >= 0).mean()
        angles = smallest_angles(mesh.vertices, mesh.faces)
        print(f"| {name} | {image.shape[1]}×{h} | {len(mesh.vertices)} | {len(mesh.faces)} | "
              f"{mesh.islands} / {mesh.holes} | {angles.min():.1f}° | {(angles < 20).mean():.1%} | "
              f"{covered:.2%} | {ms:.1f} |")


if __name__ == "__main__":
    main()
