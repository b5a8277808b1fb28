"""Writes examples/sprites/character.ora: a cut-out character of ten layers drawn by the project
(head, torso, and each side's upper arm, forearm, thigh and shin as antialiased capsules that
overlap at the neck, shoulders, elbows, hips and knees), each layer a PNG cropped to its part at
its offset in the canvas, the left limbs behind the torso and the right ones in front; then prints
the quality of each layer's mesh (default parameters) as a Markdown table.

    PYTHONPATH=python /usr/bin/python3 examples/sprites/make_character.py

Import it in Blender with File > Import > Layered painting (bdinterp), or
bdinterp_blender.import_layered("examples/sprites/character.ora").
"""
import io
import pathlib
import sys
import time
import zipfile

import numpy as np
from PIL import Image

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parents[1] / "tools"), str(HERE)]

from bdinterp_tools.sprites import coverage, rgba  # noqa: E402

W, H = 256, 384  # the canvas, pixels
# Parts bottom first (the draw order): (name, colour, shape), a shape being ("capsule", (x0, y0),
# (x1, y1), radius) or ("ellipse", (cx, cy), (rx, ry)) in canvas pixels (y downwards).
PARTS = [
    ("forearm_l", (150, 95, 70), ("capsule", (74, 172), (62, 236), 10)),
    ("upper_arm_l", (165, 105, 80), ("capsule", (102, 112), (74, 172), 12)),
    ("shin_l", (60, 70, 120), ("capsule", (110, 280), (106, 356), 12)),
    ("thigh_l", (70, 80, 135), ("capsule", (114, 196), (110, 280), 15)),
    ("shin_r", (70, 85, 140), ("capsule", (146, 280), (150, 356), 12)),
    ("thigh_r", (80, 95, 155), ("capsule", (142, 196), (146, 280), 15)),
    ("torso", (190, 60, 60), ("ellipse", (128, 150), (38, 62))),
    ("head", (235, 190, 150), ("ellipse", (128, 66), (32, 36))),
    ("upper_arm_r", (215, 150, 120), ("capsule", (154, 112), (182, 172), 12)),
    ("forearm_r", (225, 165, 135), ("capsule", (182, 172), (194, 236), 10)),
]
MARGIN = 2  # clear pixels around each part in its layer


def inside_test(shape, left, top):
    """inside(x, y) of the shape, x and y in the layer's pixels (its top-left corner at left, top)."""
    if shape[0] == "ellipse":
        (cx, cy), (rx, ry) = shape[1:]
        return lambda x, y: ((x + left - cx) / rx) ** 2 + ((y + top - cy) / ry) ** 2 <= 1
    a, b, r = np.array(shape[1], float), np.array(shape[2], float), shape[3]
    ab = b - a

    def inside(x, y):
        px, py = x + left - a[0], y + top - a[1]
        t = np.clip((px * ab[0] + py * ab[1]) / ab.dot(ab), 0, 1)
        return (px - t * ab[0]) ** 2 + (py - t * ab[1]) ** 2 <= r * r
    return inside


def layer(shape, colour):
    """(RGBA uint8 image, left, top) of one part, cropped to it with MARGIN clear pixels."""
    if shape[0] == "ellipse":
        (cx, cy), (rx, ry) = shape[1:]
        lo, hi = np.array([cx - rx, cy - ry]), np.array([cx + rx, cy + ry])
    else:
        ends, r = np.array(shape[1:3], float), shape[3]
        lo, hi = ends.min(0) - r, ends.max(0) + r
    left, top = (np.floor(lo) - MARGIN).astype(int)
    right, bottom = (np.ceil(hi) + MARGIN).astype(int)
    alpha = coverage(bottom - top, right - left, inside_test(shape, left, top))
    return rgba(alpha, colour), int(left), int(top)


def stack_xml(placed):
    rows = "\n".join(f'  <layer name="{name}" src="data/{name}.png" x="{left}" y="{top}"/>'
                     for name, _, left, top in reversed(placed))  # the top layer first
    return f'<?xml version="1.0" encoding="UTF-8"?>\n<image version="0.0.5" w="{W}" h="{H}">\n' \
           f'<stack>\n{rows}\n</stack>\n</image>\n'


def png_bytes(image):
    out = io.BytesIO()
    image.save(out, "PNG")
    return out.getvalue()


def write_ora(path, placed):
    """OpenRaster: mimetype first and stored, stack.xml, the layers, the merged image, a thumbnail."""
    merged = Image.new("RGBA", (W, H))
    for _, pixels, left, top in placed:
        merged.alpha_composite(Image.fromarray(pixels), (left, top))
    thumbnail = merged.copy()
    thumbnail.thumbnail((256, 256))
    entries = [("stack.xml", stack_xml(placed))]
    entries += [(f"data/{name}.png", png_bytes(Image.fromarray(pixels))) for name, pixels, _, _ in placed]
    entries += [("mergedimage.png", png_bytes(merged)), ("Thumbnails/thumbnail.png", png_bytes(thumbnail))]
    with zipfile.ZipFile(path, "w") as z:  # fixed dates: the same drawing gives the same file
        z.writestr(zipfile.ZipInfo("mimetype"), "image/openraster", zipfile.ZIP_STORED)
        for name, data in entries:
            z.writestr(zipfile.ZipInfo(name), data, zipfile.ZIP_DEFLATED)


def main():
    placed = [(name, *layer(shape, colour)) for name, colour, shape in PARTS]
    write_ora(HERE / "character.ora", placed)
    import bdinterp
    from make_sprites import smallest_angles
    print("| layer | size | offset | vertices | faces | smallest angle | ms |")
    print("|---|---|---|---:|---:|---:|---:|")
    for name, pixels, left, top in placed:
        start = time.perf_counter()
        mesh = bdinterp.mesh_from_image(pixels)
        ms = 1000 * (time.perf_counter() - start)
        angle = smallest_angles(mesh.vertices, mesh.faces).min()
        print(f"| {name} | {pixels.shape[1]}×{pixels.shape[0]} | {left}, {top} | {len(mesh.vertices)} | "
              f"{len(mesh.faces)} | {angle:.1f}° | {ms:.1f} |")


if __name__ == "__main__":
    main()
