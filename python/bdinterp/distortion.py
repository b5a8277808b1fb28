"""Per-face distortion measures of a result relative to a source shape."""
import numpy as np

from . import _core
from . import _validate
from .plane import Plane


def _pair(source, result, faces):
    """Both shapes in one 2D frame, so that a face keeps its orientation unless the map flips it.

    3D input: the frame is the source's plane. A result in that plane (every result of
    bdinterp for 3D input) is projected into it; a result in another plane (e.g. the source moved
    rigidly in space) gets its own plane, turned so that its normal points to the source normal's
    side.
    """
    s = _validate.coordinates(source, "source")
    r = _validate.coordinates(result, "result")
    if s.shape != r.shape:
        raise ValueError(f"source has shape {s.shape}, result has {r.shape}")
    f = _validate.faces(faces, s.shape[0])
    if s.shape[1] == 2:
        return np.ascontiguousarray(s), np.ascontiguousarray(r), f
    plane = Plane.fit(s)
    own = plane
    if not plane.contains(r):
        own = Plane.fit(r)
        if np.dot(own.normal, plane.normal) < 0:
            own = own.flipped()
    return plane.to_plane(s, "source"), own.to_plane(r, "result"), f


def conformal_distortion(source, result, faces):
    """(m,) K = sigma_max / sigma_min of each face's affine map source -> result (1 = conformal,
    inf for a collapsed result face)."""
    return _core.conformal_distortion(*_pair(source, result, faces))


def flipped_faces(source, result, faces):
    """Number of faces of `result` flipped (or collapsed) relative to `source`."""
    return _core.flipped_faces(*_pair(source, result, faces))


def area_ratio(source, result, faces):
    """(m,) signed area(result) / area(source) per face; negative where the result is flipped."""
    return _core.area_ratio(*_pair(source, result, faces))
