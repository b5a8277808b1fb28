"""Distortion view: per-face conformal distortion of a result key as mesh attributes.

Writes 'bdi_distortion' (FLOAT, face domain: K = sigma_max / sigma_min of the source -> result
map, worst triangle of each face) and 'bdi_distortion_color' (FLOAT_COLOR, corner domain, since
the viewport only shows point/corner colours).  The colour compares each face with the same face
in the inputs (the target, or the worst pose): blue where the result is no worse than the inputs
(the paper's bound holds face by face), up to red at twice the inputs' K.  A single scale for the
whole mesh (the target's worst face) left every face but one blue on real data.
"""

import bpy

from ..shapes import mesh_io, solve
from .. import timing
from ..names import DISTORTION_ATTR as ATTR, DISTORTION_COLOR as COLOR, LIVE_KEY

_LOW = (0.15, 0.35, 1.0, 1.0)   # no worse than the inputs
_HIGH = (1.0, 0.1, 0.05, 1.0)   # twice the inputs' K (or collapsed)
_RED_RATIO = 2.0


def _per_polygon(k_tri, poly, n_poly):
    import numpy as np
    out = np.ones(n_poly)
    np.maximum.at(out, poly, k_tri)
    return out


def per_face(obj, key_name=None):
    """(K per polygon of the key, K per polygon of its inputs or None) for key `key_name`
    (default: the active key) against its relative key."""
    import numpy as np
    key = mesh_io.key_of(obj)
    kb = key.key_blocks.get(key_name) if key_name else obj.active_shape_key
    if kb is None:
        raise mesh_io.BakeError("%s has no shape key %r" % (obj.name, key_name) if key_name
                                else "%s has no active shape key" % obj.name)
    base = kb.relative_key
    if base == kb:
        raise mesh_io.BakeError("%r is relative to itself; pick a baked or live key" % kb.name)
    faces, poly = mesh_io.triangles(obj.data)
    src, n_poly = mesh_io.read_co(base), len(obj.data.polygons)
    k_poly = _per_polygon(solve.distortion(src, mesh_io.read_co(kb), faces), poly, n_poly)
    inputs = _input_keys(obj, key, kb)
    if not inputs:
        return k_poly, None
    k_in = np.max([_per_polygon(solve.distortion(src, mesh_io.read_co(i), faces), poly, n_poly)
                   for i in inputs], axis=0)
    return k_poly, k_in


def _input_keys(obj, key, kb):
    """The keys a result key was made from: the target of '<target>.bdi.NNN' or of live mode,
    the poses of a live or baked pose blend."""
    props = getattr(obj, "bdi", None)
    names = []
    if props is not None and kb.name == LIVE_KEY:
        names = [props.target] if props.live_mode == 'INTERPOLATE' else [p.key for p in props.poses]
    elif props is not None and kb.name == props.blend_name:
        names = [p.key for p in props.poses]
    elif timing.SEP in kb.name:
        names = [kb.name.rsplit(timing.SEP, 1)[0]]
    return [key.key_blocks[n] for n in names if n in key.key_blocks]


def colors(k, k_in=None):
    """RGBA per face: k against k_in (per face), or against k's own largest finite value."""
    import numpy as np
    if k_in is None:
        finite = k[np.isfinite(k)]
        t = np.clip((k - 1.0) / max((finite.max() if finite.size else 1.0) - 1.0, 1e-9), 0.0, 1.0)
    else:
        ratio = k / np.maximum(k_in, 1.0)
        t = np.clip(np.log(np.maximum(ratio, 1.0) / (1.0 + 1e-6)) / np.log(_RED_RATIO), 0.0, 1.0)
    t[~np.isfinite(k)] = 1.0  # collapsed faces
    low, high = np.array(_LOW), np.array(_HIGH)
    return low + t[:, None] * (high - low)


def write(obj, key_name=None, visible=True):
    import numpy as np
    k_poly, k_in = per_face(obj, key_name)
    mesh = obj.data
    attr = mesh.attributes.get(ATTR)
    if attr is not None and (attr.domain != 'FACE' or attr.data_type != 'FLOAT'):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(ATTR, 'FLOAT', 'FACE')
    attr.data.foreach_set("value", k_poly.astype(np.float32))
    col = mesh.color_attributes.get(COLOR)
    if col is None:
        col = mesh.color_attributes.new(COLOR, 'FLOAT_COLOR', 'CORNER')
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    rgba = np.repeat(colors(k_poly, k_in), loop_total, axis=0)
    col.data.foreach_set("color", rgba.astype(np.float32).ravel())
    mesh.color_attributes.active_color = col
    mesh.update()
    set_visible(visible, obj)
    return k_poly


def set_visible(visible, obj=None):
    """Show (attribute colours) or hide (material colours) in every 3D view and in Workbench
    renders of the current scene."""
    color_type = 'VERTEX' if visible else 'MATERIAL'
    shadings = [bpy.context.scene.display.shading]
    for window in getattr(bpy.context.window_manager, "windows", []):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                shadings += [s.shading for s in area.spaces if s.type == 'VIEW_3D']
    for shading in shadings:
        shading.color_type = color_type
    if obj is not None and hasattr(obj, "bdi"):  # not registered when used as a plain module
        obj.bdi.distortion_visible = visible
