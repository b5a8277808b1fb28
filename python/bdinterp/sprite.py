"""mesh_from_image: a triangle mesh of a sprite's alpha, ready to bend (the compiled core's mesher).

The outline of alpha >= threshold is traced at sub-pixel accuracy (marching squares), with holes and
several islands; islands and holes smaller than `min_area` are dropped (and counted); it is
simplified within `detail` pixels, grown by `padding` pixels and filled by CGAL's 2D conforming
Delaunay mesher (a well-kept, GPL-compatible mesher; Shewchuk's Triangle's licence does not fit):
no angle below `min_angle` (sharper corners of the outline itself are blunted within `detail`) and
no edge longer than `spacing`.

PNG files are read with Pillow (Debian's python3-pil); inside Blender the add-on reads images with
bpy and passes arrays, so no image library is needed there.
"""
from dataclasses import dataclass
import os

import numpy as np

from . import _core
from .errors import invalid


@dataclass(frozen=True)
class SpriteMesh:
    """vertices (n, 2) in pixels (x right, y up, origin at the image's bottom-left corner), faces
    (m, 3) counter-clockwise, uvs (n, 2) = vertices / (width, height); spacing: the edge bound used;
    islands, holes: kept; dropped_islands, dropped_holes: smaller than min_area (or closed by the
    padding); outline_vertices; area (pixels^2); size: the image's (width, height)."""
    vertices: np.ndarray
    faces: np.ndarray
    uvs: np.ndarray
    spacing: float
    outline_vertices: int
    islands: int
    holes: int
    dropped_islands: int
    dropped_holes: int
    area: float
    size: tuple


def read_alpha(path):
    """The alpha channel of an image file as float32 (h, w) in [0, 1] (Pillow; no alpha: opaque)."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise invalid(f"no image file {path!r}")
    try:
        from PIL import Image, UnidentifiedImageError
    except ImportError as e:
        raise ImportError("reading an image file needs Pillow (Debian: python3-pil); "
                          "or pass the image as an array") from e
    try:
        with Image.open(path) as image:
            rgba = np.asarray(image.convert("RGBA"))
    except (UnidentifiedImageError, OSError, SyntaxError) as e:
        raise invalid(f"{path!r} is not an image Pillow can read ({e})") from None
    return rgba[:, :, 3].astype(np.float32) / np.float32(255)


def alpha_of(image):
    """float32 (h, w) alpha of a path, an (h, w, 4) RGBA / (h, w, 2) grey-alpha array or an (h, w)
    alpha array; integer arrays are scaled by their type's maximum, floats taken as in [0, 1]."""
    if isinstance(image, (str, bytes, os.PathLike)):
        return read_alpha(image)
    a = np.asarray(image)
    if a.ndim == 3 and a.shape[2] in (2, 4):
        a = a[:, :, -1]
    elif a.ndim != 2:
        raise invalid(f"an image must be (h, w) alpha or (h, w, 4) RGBA, not an array of shape {a.shape}")
    if a.dtype == bool:
        a = a.astype(np.float32)
    elif np.issubdtype(a.dtype, np.integer):
        a = a.astype(np.float32) / np.float32(np.iinfo(a.dtype).max)
    elif not np.issubdtype(a.dtype, np.floating):
        raise invalid(f"an image's values must be numbers, not {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float32)


def mesh_from_image(image, *, threshold=0.5, spacing=None, detail=1.0, padding=1.0, min_angle=20.0,
                    min_area=4.0):
    """A SpriteMesh of the pixels with alpha >= threshold of `image` (a path to a PNG or another
    image Pillow reads, an (h, w, 4) RGBA array of uint8 or floats in [0, 1], or an (h, w) alpha).

    spacing: the longest edge in pixels; None: a twelfth of the larger side of the sprite's bounding
    box (at least 2). detail: how far the simplified outline may stray from the traced one; padding:
    how far the outline grows outwards (both pixels); min_angle: degrees, in (0, 30]; min_area:
    islands and holes smaller than this (pixels^2) are dropped.
    Raises InvalidInputError naming the problem: not an image, smaller than 2 x 2, NaN alpha,
    threshold outside (0, 1], spacing <= 0, nothing at or above the threshold.
    """
    if not getattr(_core, "has_sprite_mesher", False):
        raise RuntimeError("this build of bdinterp has no sprite mesher (built without CGAL)")
    if spacing is not None and not float(spacing) > 0:
        raise invalid(f"spacing must be a positive number of pixels (or None), not {spacing}")
    alpha = alpha_of(image)
    out = _core.mesh_from_alpha(alpha, float(threshold), 0.0 if spacing is None else float(spacing),
                                float(detail), float(padding), float(min_angle), float(min_area))
    return SpriteMesh(size=(alpha.shape[1], alpha.shape[0]), **out)
