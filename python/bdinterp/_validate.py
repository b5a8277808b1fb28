"""Input checks shared by the public functions; every message names the argument in the caller's terms.

Everything the compiled core needs is turned into C-contiguous float64 (n, 2) and int32 (m, 3)
arrays here; arrays that already have that layout are passed through without a copy.
"""
import numbers

import numpy as np

from .constants import INT_MAX, PLANAR_TOLERANCE
from .errors import invalid
from .layers import Layers
from .plane import Plane


def _error(detail, name, shape=None, vertex=None):
    """InvalidInputError at (shape, vertex) when the array is one of the shapes, else a ValueError
    naming it ("anchor path positions ...")."""
    if shape is not None:
        return invalid(detail, shape=shape, vertex=vertex)
    return ValueError(f"{name}: vertex {vertex} has {detail}" if vertex is not None else f"{name} {detail}")


def real_array(x, name, shape=None):
    """`x` as a float64 array; for ragged, complex or non-numeric input an error naming `name`
    (InvalidInputError at `shape` when given)."""
    try:
        a = np.asarray(x)
    except ValueError:  # numpy >= 1.24 refuses ragged nested sequences
        raise _error("is ragged: its rows have different lengths", name, shape) from None
    if a.dtype.kind == "c":
        raise _error(f"is complex (dtype {a.dtype}); give real coordinates, e.g. np.c_[z.real, z.imag]",
                     name, shape)
    if a.dtype.kind == "O":
        try:
            return np.asarray(a, dtype=np.float64)
        except (TypeError, ValueError):
            raise _error("must hold real numbers; it holds other objects", name, shape) from None
    if a.dtype.kind not in "biuf":
        raise _error(f"must hold real numbers, got dtype {a.dtype}", name, shape)
    return np.asarray(a, dtype=np.float64)


def coordinates(x, name, shape=None):
    """Returns `x` as a float64 (n, 2) or (n, 3) array of finite numbers; else an error naming `name`
    (InvalidInputError at `shape` when given, and at the vertex of a non-finite coordinate)."""
    a = real_array(x, name, shape)
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise _error(f"must be an (n, 2) or (n, 3) array of coordinates, got shape {a.shape}", name, shape)
    if a.shape[0] == 0:
        raise _error("has no vertices", name, shape)
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if bad.size:
        raise _error("a non-finite coordinate", name, shape, int(bad[0]))
    return a


def _ragged_face(f):
    """Index of the first face of a nested sequence that does not have 3 entries, or None."""
    try:
        for i, row in enumerate(f):
            if len(row) != 3:
                return i, len(row)
    except TypeError:
        return None
    return None


def faces(f, num_vertices):
    """Returns faces as a C-contiguous int32 (m, 3) array after checking type, shape and index range."""
    try:
        a = np.asarray(f)
    except ValueError:
        a = None
    if a is None or a.dtype.kind == "O" or (a.ndim == 2 and a.shape[1] != 3):
        bad = _ragged_face(f)
        if bad is not None:
            raise invalid(f"has {bad[1]} vertices: faces must be triangles", face=bad[0])
    if a is None or a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array of vertex indices, got "
                         f"{'a ragged list' if a is None else f'shape {a.shape}'}")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"faces must be an integer array, got dtype {a.dtype}")
    if a.size:  # checked here as well as in the core: Layers.fit indexes with the faces first
        low, high = a.min(), a.max()
        if low < 0 or high >= num_vertices:
            bad = np.flatnonzero(((a < 0) | (a >= num_vertices)).any(axis=1))[0]
            raise invalid(f"a vertex index out of range [0, {num_vertices}): {a[bad].tolist()}", face=bad)
    return np.ascontiguousarray(a, dtype=np.int32)


def real(x, name):
    """A finite real scalar as float; ValueError naming `name` otherwise (complex, str, NaN, inf)."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        if isinstance(x, np.ndarray) and x.ndim == 0 and x.dtype.kind in "iuf":
            x = x.item()
        else:
            raise ValueError(f"{name} must be a real number, got {x!r}")
    value = float(x)
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value}")
    return value


def positive(x, name):
    """A finite real scalar > 0 (a tolerance); ValueError naming `name` otherwise."""
    value = real(x, name)
    if not value > 0:
        raise ValueError(f"{name} must be > 0, got {value:g}")
    return value


def integer(x, name, low=0, high=INT_MAX):
    """An int in [low, high] (the core's options are C ints); ValueError naming `name` otherwise."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (numbers.Integral, np.integer)):
        raise ValueError(f"{name} must be an integer, got {x!r}")
    if not low <= int(x) <= high:
        raise ValueError(f"{name} must be an integer in [{low}, {high}], got {int(x)}")
    return int(x)


def times(ts, name="ts"):
    """A 1-D float64 array of finite times; ValueError naming `name` and the first bad entry."""
    a = real_array(ts, name).ravel()
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] must be finite, got {a[bad[0]]}")
    return a


def planar_shapes(shapes, base=0, tolerance=PLANAR_TOLERANCE, mesh_faces=None, layers=None):
    """Validates k shapes of equal size; returns (list of (n, 2) arrays, Plane, Layers or None).

    2D shapes pass through unchanged (no copy when already C-contiguous float64; Plane and Layers
    None). 3D shapes without mesh_faces must all lie in the plane of shapes[base] (Layers None); with
    mesh_faces (m, 3) (validated here), each loose part may lie in its own plane parallel to the others (Layers.fit).
    Their plane coordinates are returned with the common plane. layers: Layers the caller fitted
    to these 3D shapes (with its own tolerance): used as they are, not fitted again.
    """
    if isinstance(shapes, np.ndarray) and shapes.ndim == 3:
        shapes = list(shapes)
    if isinstance(shapes, (str, bytes)) or not hasattr(shapes, "__len__"):
        raise ValueError(f"shapes must be a sequence of (n, 2) or (n, 3) arrays, got {shapes!r:.60}")
    shapes = [coordinates(s, f"shape {i}", shape=i) for i, s in enumerate(shapes)]
    if not shapes:
        raise ValueError("need at least one shape")
    base = integer(base, "base", 0, len(shapes) - 1) if len(shapes) else base
    n, d = shapes[0].shape
    for i, s in enumerate(shapes):
        if s.shape != (n, d):
            raise invalid(f"has shape {s.shape}, shape 0 has {(n, d)}", shape=i)
    if d == 2:
        if layers is not None:
            raise ValueError("layers are for 3D shapes; these are 2D")
        return [np.ascontiguousarray(s) for s in shapes], None, None
    if layers is not None:
        return layers.check(shapes).to_plane(shapes), layers.plane, layers
    if mesh_faces is None:
        plane = Plane.fit(shapes[base])
        return [plane.to_plane(s, f"shape {i}", tolerance, shape=i) for i, s in enumerate(shapes)], plane, None
    layers = Layers.fit(shapes, faces(mesh_faces, n), base, tolerance)
    return layers.to_plane(shapes), layers.plane, layers
