"""Distortion view: per-face conformal distortion of a result key as mesh attributes.

Writes 'bdi_distortion' (FLOAT, face domain: K = sigma_max / sigma_min of the source -> result
map, worst triangle of each face) and 'bdi_distortion_color' (FLOAT_COLOR, corner domain, since
the viewport only shows point/corner colours): blue at K = 1 up to red at the bound.
"""

import bpy
import numpy as np

from . import api, mesh_io, timing

ATTR = "bdi_distortion"
COLOR = "bdi_distortion_color"
_LOW = np.array([0.15, 0.35, 1.0, 1.0])   # K = 1 (conformal)
_HIGH = np.array([1.0, 0.1, 0.05, 1.0])   # K = bound


def per_face(obj, key_name=None):
    """(K per polygon, bound) for key `key_name` (default: the active key) against its relative
    key.  bound: the inputs' max distortion if the key is a bake of a known target, else max K."""
    key = mesh_io.key_of(obj)
    kb = key.key_blocks.get(key_name) if key_name else obj.active_shape_key
    if kb is None:
        raise mesh_io.BakeError("no shape key %r" % key_name if key_name else "no active shape key")
    base = kb.relative_key
    if base == kb:
        raise mesh_io.BakeError("%r is relative to itself; pick a baked or live key" % kb.name)
    faces, poly = mesh_io.triangles(obj.data)
    src = mesh_io.read_co(base)
    k_tri = api._core().conformal_distortion(src, mesh_io.read_co(kb), faces)
    k_poly = np.ones(len(obj.data.polygons))
    np.maximum.at(k_poly, poly, k_tri)
    target = _bound_key(obj, key, kb)
    if target is not None:
        bound = float(np.max(api._core().conformal_distortion(src, mesh_io.read_co(target), faces)))
    else:
        finite = k_poly[np.isfinite(k_poly)]
        bound = float(finite.max()) if finite.size else 1.0
    return k_poly, bound


def _bound_key(obj, key, kb):
    """The target a result key was made from: '<target>.bdi.NNN' or the live target."""
    if kb.name == api.LIVE_KEY and getattr(obj, "bdi", None) and obj.bdi.live_mode == 'INTERPOLATE':
        return key.key_blocks.get(obj.bdi.target)
    if timing.SEP in kb.name:
        return key.key_blocks.get(kb.name.rsplit(timing.SEP, 1)[0])
    return None


def colors(k, bound):
    t = np.clip((k - 1.0) / max(bound - 1.0, 1e-9), 0.0, 1.0)
    t[~np.isfinite(k)] = 1.0  # collapsed faces
    return _LOW + t[:, None] * (_HIGH - _LOW)


def write(obj, key_name=None, visible=True):
    k_poly, bound = per_face(obj, key_name)
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
    rgba = np.repeat(colors(k_poly, bound), loop_total, axis=0)
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
