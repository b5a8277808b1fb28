"""Live mode: recompute the exact interpolation/blend on frame or factor changes.

The result goes into the shape key 'bdi.live' (relative to the source, value 1).  Runs from a
frame_change_post handler, which Blender calls for viewport playback and for each frame of
`blender -b file.blend -a` alike; if the handler tags data, Blender re-evaluates the frame
before drawing/rendering it.  On any error live mode turns itself off for that object with one
message (console + panel) instead of failing on every frame.
"""

import bpy
from bpy.app.handlers import persistent

from . import api, mesh_io

_solvers = {}  # object name -> (fingerprint, precomputed bdinterp.Interpolator)


def _anchor(props):
    return {'AUTO': "AUTO", 'VERTEX': props.anchor_vertex,
            'GROUP': props.anchor_group}[props.anchor]


def _solver(obj, inp, mode):
    """Interpolator for these inputs, reused while they do not change (precomputation is the
    expensive part; a frame is then a few Newton steps)."""
    fp = (inp.fingerprint(), mode)
    cached = _solvers.get(obj.name)
    if cached is None or cached[0] != fp:
        solver = api._core().Interpolator(inp.shapes, inp.faces, anchor=inp.anchor, base=0)
        cached = _solvers[obj.name] = (fp, solver)
    return cached[1]


def compute(obj, values=None):
    """(Inputs, result (n,3)) of obj's live settings; factor/weights read from `values` (the
    evaluated object while rendering: animated values are not written back to the original
    there)."""
    props, vals = obj.bdi, (values or obj).bdi
    anchor, path = _anchor(props), props.anchor_path
    if props.live_mode == 'BLEND':
        names, weights = api.pose_weights([(p.key, v.weight) for p, v in zip(props.poses, vals.poses)])
        inp = api.Inputs(obj, props.source, names, anchor, None, props.tolerance)
        return inp, api.blend_shape(inp, weights, _solver(obj, inp, 'BLEND'))
    inp = api.Inputs(obj, props.source, [props.target], anchor, path, props.tolerance)
    t = vals.live_factor
    if props.method != 'bdi':
        return inp, api._solve(inp, [t], props.method)[0]
    try:
        return inp, _solver(obj, inp, 'INTERPOLATE').at(t)
    except ValueError as exc:
        raise mesh_io.BakeError("%s: %s" % (obj.name, exc)) from exc


def update(obj, depsgraph=None):
    """Recompute and write the live key of obj."""
    values = obj.evaluated_get(depsgraph) if depsgraph is not None else obj
    inp, result = compute(obj, values)
    key = obj.data.shape_keys
    kb = key.key_blocks.get(api.LIVE_KEY)
    if kb is None:
        kb = obj.shape_key_add(name=api.LIVE_KEY, from_mix=False)
    if kb.relative_key != inp.source:
        kb.relative_key = inp.source
    if kb.value != 1.0:
        kb.value = 1.0
    mesh_io.write_co(kb, result)
    key.update_tag()
    obj.data.update_tag()


def turn_off(obj, exc):
    message = "bdinterp: live mode turned off for %s: %s" % (obj.name, exc)
    obj.bdi.live_error = message
    obj.bdi.live = False  # on_toggle does nothing when switching off
    _solvers.pop(obj.name, None)
    print(message)


def on_toggle(obj):
    if obj.bdi.live:
        obj.bdi.live_error = ""
        try:
            update(obj)
        except Exception as exc:  # noqa: BLE001 -- any failure must switch live mode off
            turn_off(obj, exc)


def on_property_change(obj):
    if obj.bdi.live:
        on_toggle(obj)


def enable(obj):
    """Switch live mode on (computing once); BakeError with the message if that fails."""
    if obj.bdi.live:
        on_toggle(obj)
    else:
        obj.bdi.live = True
    if obj.bdi.live_error:
        raise mesh_io.BakeError(obj.bdi.live_error)


@persistent
def on_frame_change(scene, depsgraph=None):
    for obj in scene.objects:
        if obj.type == 'MESH' and obj.bdi.live:
            try:
                update(obj, depsgraph)
            except Exception as exc:  # noqa: BLE001
                turn_off(obj, exc)


@persistent
def on_load(*_args):
    _solvers.clear()  # object names may now mean other objects


HANDLERS = ((bpy.app.handlers.frame_change_post, on_frame_change),
            (bpy.app.handlers.load_post, on_load))


def register():
    for handlers, fn in HANDLERS:
        # Drop stale copies left by an earlier load of this module (add-on reload).
        for h in [h for h in handlers if getattr(h, "__name__", "") == fn.__name__
                  and getattr(h, "__module__", "") == fn.__module__]:
            handlers.remove(h)
        handlers.append(fn)


def unregister():
    for handlers, fn in HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
    _solvers.clear()
