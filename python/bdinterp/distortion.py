"""Per-face distortion measures of a result relative to a source shape."""
import numpy as np

from . import _core
from . import _validate


def _pair(source, result, faces):
    s = _validate.coordinates(source, "source")
    r = _validate.coordinates(result, "result")
    if s.shape != r.shape:
        raise ValueError(f"source has shape {s.shape}, result has {r.shape}")
    f = _validate.faces(faces, s.shape[0])
    if s.shape[1] == 2:
        return np.ascontiguousarray(s), np.ascontiguousarray(r), f
    plane = _validate.Plane.fit(s)
    own = _validate.Plane.fit(r)
    if np.dot(own.normal, plane.normal) < 0:  # keep the sign of flipped faces meaningful
        own = _validate.Plane(own.origin, own.axes[::-1].copy(), -own.normal)
    return plane.to_plane(s, "source"), own.to_plane(r, "result"), f


def conformal_distortion(source, result, faces):
    """(m,) K = sigma_max / sigma_min of each face's affine map source -> result (1 = conformal)."""
    return _core.conformal_distortion(*_pair(source, result, faces))


def flipped_faces(source, result, faces):
    """Number of faces of `result` flipped (or collapsed) relative to `source`."""
    return _core.flipped_faces(*_pair(source, result, faces))


def area_ratio(source, result, faces):
    """(m,) signed area(result) / area(source) per face; negative where the result is flipped."""
    return _core.area_ratio(*_pair(source, result, faces))
