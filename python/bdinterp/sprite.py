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
import os

import numpy as np

from . import _core
from .errors import invalid


# The mesh and the options with their defaults are the compiled core's (one definition, in
# cpp/include/bdinterp/sprite_mesh.h); a core built without the mesher has neither.
SpriteMesh = getattr(_core, "SpriteMesh", None)
SpriteMeshOptions = getattr(_core, "SpriteMeshOptions", None)
OPTIONS = tuple(n for n in dir(SpriteMeshOptions) if not n.startswith("_")) if SpriteMeshOptions else ()


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


def mesh_from_image(image, **options):
    """A SpriteMesh of the pixels with alpha >= threshold of `image` (a path to a PNG or another
    image Pillow reads, an (h, w, 4) RGBA array of uint8 or floats in [0, 1], or an (h, w) alpha).

    options (defaults: SpriteMeshOptions()): threshold; spacing: the longest edge in pixels, None
    or 0: the larger side of the sprite's bounding box / spacing_divisions (12), at least 2;
    detail: how far the simplified outline may stray from the traced one; padding: how far the
    outline grows outwards (both pixels); min_angle: degrees, in (0, 30]; min_area: islands and
    holes smaller than this (pixels^2) are dropped.
    Raises InvalidInputError naming the problem: not an image, smaller than 2 x 2, NaN alpha,
    an unknown option, threshold outside (0, 1], spacing < 0, nothing at or above the threshold.
    """
    if SpriteMesh is None:
        raise RuntimeError("this build of bdinterp has no sprite mesher (built without CGAL)")
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise invalid(f"unknown option {', '.join(unknown)}; the options are {', '.join(OPTIONS)}")
    settings = SpriteMeshOptions()
    for name, value in options.items():
        if name == "spacing" and value is None:
            value = 0.0
        try:
            setattr(settings, name, float(value))
        except (TypeError, ValueError):
            raise invalid(f"{name} must be a number, not {value!r}") from None
    return _core.mesh_from_alpha(alpha_of(image), settings)
