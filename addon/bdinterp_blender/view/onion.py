"""Onion skins and motion trails of the in-betweens in the 3D viewport (settings: Scene.bdi_view).

What is drawn is computed once (Ghosts: world coordinates of the ghost shapes, the trails, the
ticks at the baked keys) and kept in GPU batches (overlay.py); a redraw compares a cheap request
key (objects, settings, transforms, an epoch bumped when the input or baked keys' data change)
and only recolours.  The depsgraph handler re-reads key data only when Blender reports a shape key
edited, so playback and live mode never pay for it.  An error while computing the ghosts is shown
in the panel; one elsewhere in a redraw or the handler is printed once and the overlay leaves that
object alone until a view setting changes or a file is loaded (no error repeats every redraw).
"""

import hashlib
import time
from collections import deque

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty

from . import motion_trails
from ..shapes import mesh_io
from ..names import LIVE_KEY, SEP


def _redraw(self=None, context=None):
    _failed.clear()  # a view setting changed: try the objects that failed again
    invalidate()
    for window in getattr(bpy.context.window_manager, "windows", ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _color(name, default):
    return FloatVectorProperty(name=name, subtype='COLOR', size=3, min=0.0, max=1.0,
                               default=default, update=_redraw)


class BDI_ViewProps(bpy.types.PropertyGroup):
    ghosts: BoolProperty(name="Onion Skins", default=False, update=_redraw,
                         description="Draw ghosts of the in-betweens of the active object or character")
    ghost_source: EnumProperty(name="Ghosts", update=_redraw, items=[
        ('FACTORS', "Factors", "The exact in-betweens at every Step (computed, also in live mode)"),
        ('BAKED', "Baked Keys", "The baked in-between keys as stored"),
        ('FRAMES', "Frames", "The in-betweens shown at the frames before and after the current "
                             "one (the slider's or live factor's keyframes)")])
    step: FloatProperty(name="Step", default=0.25, min=0.02, max=0.5, update=_redraw,
                        description="Factor between two ghosts")
    frames_before: IntProperty(name="Before", default=2, min=0, max=20, update=_redraw,
                               description="Ghosts of the frames before the current one")
    frames_after: IntProperty(name="After", default=2, min=0, max=20, update=_redraw,
                              description="Ghosts of the frames after the current one")
    frame_step: IntProperty(name="Frame Step", default=1, min=1, max=100, update=_redraw,
                            description="Frames between two ghosts")
    opacity: FloatProperty(name="Opacity", default=0.8, min=0.0, max=1.0, update=_redraw,
                           subtype='FACTOR')
    before_color: _color("Before", (0.25, 0.55, 1.0))
    after_color: _color("After", (1.0, 0.45, 0.15))
    trails: BoolProperty(name="Motion Trails", default=False, update=_redraw,
                         description="Draw the paths of vertices through the in-betweens")
    trail_vertices: EnumProperty(name="Vertices", update=_redraw, items=[
        ('DEFAULT', "Centres and Joints", "Each piece's centre and the joints between pieces"),
        ('SELECTED', "Selected", "The vertices selected in Edit Mode")])
    samples: IntProperty(name="Samples", default=33, min=2, max=257, update=_redraw)
    chords: BoolProperty(name="Linear Chords", default=False, update=_redraw,
                         description="Draw beside each trail the straight path of a linear blend")
    trail_color: _color("Trail", (1.0, 0.85, 0.2))


class Ghosts:
    """Everything the overlay draws, world coordinates: shapes (j, n, 3) at factors (j,), faces
    (m, 3), outline edges (e, 2), trails (s, k, 3), ticks (b, k, 3), chords (2, k, 3); the slider
    (owner object name, property) whose value is the current factor; an error message; the
    motion_trails.Path solved (kept while only the frame changes).  Ghosts of frames have
    `offsets` (j,) in frames from the current one and `span` (their tint fades over it)."""

    def __init__(self, **kw):
        import numpy as np
        empty = np.empty((0, 0, 3))
        self.shapes, self.factors, self.trails, self.ticks, self.chords = empty, [], empty, empty, empty
        self.faces, self.edges = np.empty((0, 3), int), np.empty((0, 2), int)
        self.slider, self.error, self.path, self.offsets, self.span = None, "", None, None, 1.0
        self.__dict__.update(kw)


def drawn_objects(context):
    """The active mesh with a target set, then the selected meshes that have its target key (a
    character, as a bake solves it); [] when there is nothing to draw."""
    obj = context.object
    if obj is None or obj.type != 'MESH' or not hasattr(obj, "bdi") or not obj.bdi.target:
        return []
    if obj.mode == 'EDIT' or obj.data.shape_keys is None:
        return []
    from ..keys.character import members, selected_meshes
    return [obj] + members(selected_meshes(context, obj)[1:], obj.bdi.target)


def _factor_of(name):
    """0.5 of 'Arm.bdi.050' (the factor is in the key's name), None if it is not in it."""
    try:
        return float(name.rsplit(SEP, 1)[1]) / 100.0
    except (IndexError, ValueError):
        return None


def outline(faces):
    """(e, 2) the edges of `faces` that bound only one triangle: each piece's outline."""
    import numpy as np
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique[counts == 1]


def moving_faces(path):
    """The faces of path's mesh that the motion moves (a vertex of theirs is elsewhere in the
    target than in the source): the ghosts tint those only, not the pieces that stand still."""
    import numpy as np
    source, target = path.world(path.inp.shapes[:2])
    size = max(np.ptp(source, axis=0).max(), 1e-12)
    moves = np.linalg.norm(target - source, axis=1) > 1e-6 * size
    faces = np.asarray(path.inp.faces)
    return faces[moves[faces].any(axis=1)]


def selected_vertices(objs):
    """Indices (across the objects, one after the other) of their selected vertices."""
    import numpy as np
    out, offset = [], 0
    for obj in objs:
        sel = np.zeros(len(obj.data.vertices), dtype=bool)
        obj.data.vertices.foreach_get("select", sel)
        out.append(np.flatnonzero(sel) + offset)
        offset += len(sel)
    return np.concatenate(out)


def build(objs, view, frame=None, previous=None):
    """The Ghosts of `objs` (drawn_objects) with the settings `view` (Scene.bdi_view) at the
    scene's `frame`; `previous`: the Ghosts of the same request at another frame, whose Path,
    outline and trails are reused (only the ghosts of frames move with the frame)."""
    import numpy as np
    if previous is not None:
        out = Ghosts(**previous.__dict__)
        frame_ghosts(out, objs, view, frame)
        return out
    solve_needed = view.trails or view.ghost_source != 'BAKED'
    path = motion_trails.Path(objs, with_solver=solve_needed)
    faces = moving_faces(path)
    out = Ghosts(faces=faces, edges=outline(faces) if len(faces) else np.empty((0, 2), int),
                 path=path)
    baked, names = path.baked()
    if path.found is not None:
        out.slider = (path.found.record.get("owner") or objs[0].name, path.found.slider)
    if view.ghosts and view.ghost_source == 'BAKED':
        factors = [_factor_of(n) for n in names]
        if None in factors:  # names not made by a bake: evenly spaced
            factors = list(np.arange(1, len(names) + 1) / (len(names) + 1.0))
        out.shapes, out.factors = baked, factors
    elif view.ghosts and view.ghost_source == 'FRAMES':
        frame_ghosts(out, objs, view, frame)
    elif view.ghosts:
        ts = np.arange(view.step, 1.0 - 1e-9, view.step)
        out.shapes, out.factors = path.frames(ts), list(ts)
    if view.trails:
        trail_points(out, path, view, baked)
    return out


def frame_ghosts(out, objs, view, frame):
    """Set out's ghosts of the frames around `frame` (offsets, span, factors, shapes)."""
    import numpy as np
    step = view.frame_step
    out.offsets = [-k * step for k in range(view.frames_before, 0, -1)] + \
        [k * step for k in range(1, view.frames_after + 1)]
    out.span = (max(view.frames_before, view.frames_after) + 1) * step
    out.factors = [factor_at(objs, out.slider, frame + o) for o in out.offsets]
    out.shapes = out.path.frames(out.factors) if out.offsets else np.empty((0, out.path.size, 3))


def trail_points(out, path, view, baked):
    """Set out.trails, ticks and chords: the paths of the trail vertices of `view`."""
    import numpy as np
    v = None
    if view.trail_vertices == 'SELECTED':
        v = selected_vertices(path.objs)
        if not len(v):
            raise mesh_io.BakeError("no vertex selected: select some in Edit Mode")
    v = path.vertices(v)
    out.trails = path.frames(np.linspace(0.0, 1.0, view.samples))[:, v]
    out.ticks = baked[:, v]
    out.chords = out.trails[[0, -1]]


def factor_at(objs, slider, frame=None):
    """The factor shown at `frame` (None: now): live mode's factor, else the slider's (owner
    object name, property) or 0; at another frame as its F-curve has it (a constant without)."""
    from ..actions import find_fcurve
    props = objs[0].bdi
    if props.live and props.live_mode == 'INTERPOLATE':
        owner, data_path, value = objs[0], "bdi.live_factor", props.live_factor
    else:
        owner = bpy.data.objects.get(slider[0]) if slider is not None else None
        if owner is None:
            return 0.0
        data_path = '["%s"]' % bpy.utils.escape_identifier(slider[1])
        value = float(owner.get(slider[1], 0.0))
    curve = find_fcurve(owner.animation_data, data_path) if frame is not None else None
    return min(1.0, max(0.0, curve.evaluate(frame) if curve is not None else value))


def request_key(objs, view):
    """What the Ghosts depend on, cheap enough to compare whenever a handler invalidated the
    Plan: the Path's settings, the view's; last: the frame (for ghosts of frames; else None)."""
    props = objs[0].bdi
    settings = (motion_trails.settings_of(props), props.live_mode, view.ghosts, view.ghost_source,
                view.step, view.trails, view.trail_vertices, view.samples, view.frames_before,
                view.frames_after, view.frame_step)
    frame = bpy.context.scene.frame_current if view.ghosts and view.ghost_source == 'FRAMES' else None
    return (tuple(o.name for o in objs), settings, _epoch[0],
            tuple(tuple(v for row in o.matrix_world for v in row) for o in objs), frame)


_epoch = [0]        # bumped when the data of a drawn object's keys change
_signatures = {}    # object name -> hash of its keys' data (but the live key)
_failed = {}       # object name -> the error that stopped drawing its overlay (printed once)
_cache = {"key": None, "ghosts": None, "batches": None, "plan": None, "active": None}


def key_signature(obj):
    key = obj.data.shape_keys
    h = hashlib.sha1()
    for kb in key.key_blocks if key else ():
        if kb.name != LIVE_KEY:
            h.update(kb.name.encode())
            h.update(mesh_io.read_raw(kb).tobytes())
    return h.hexdigest()


def current(context):
    """(objs, Ghosts or None, GPU batches or None) for the context, rebuilt if the request changed."""
    from . import overlay
    view = context.scene.bdi_view
    objs = drawn_objects(context) if (view.ghosts or view.trails) else []
    if not objs:
        return objs, None, None
    key = request_key(objs, view)
    if _cache["key"] != key:
        only_frame = _cache["key"] is not None and _cache["key"][:-1] == key[:-1]
        previous = _cache["ghosts"] if only_frame and _cache["ghosts"].path is not None else None
        _cache["key"], _cache["batches"] = key, None
        if previous is None:  # else the epoch is unchanged: the keys are as last hashed
            for o in objs:
                _signatures[o.name] = key_signature(o)
        try:
            _cache["ghosts"] = build(objs, view, key[-1], previous)
            _cache["batches"] = overlay.batches(_cache["ghosts"])
        except Exception as exc:  # noqa: BLE001 -- any error is shown in the panel, once computed
            said = str(exc) if isinstance(exc, (ValueError, RuntimeError)) else "%s: %s" % (
                type(exc).__name__, exc)
            _cache["ghosts"] = Ghosts(error=said)
    return objs, _cache["ghosts"], _cache["batches"]


def now_factor(objs, ghosts):
    """Where the ghosts' tints are measured from: 0 for ghosts of frames (their offsets), else
    the factor shown now."""
    return 0.0 if ghosts.offsets is not None else factor_at(objs, ghosts.slider)


@persistent
def invalidate(*_args):
    """Something drawn may have changed: the next redraw checks the request (and rebuilds)."""
    _cache["plan"] = None


def plan(context):
    """The overlay.Plan of the context (False when there is nothing to draw), rebuilt if need be."""
    from . import overlay
    objs, ghosts, batches = current(context)
    if batches is None:
        return False
    return overlay.Plan(batches, ghosts, context.scene.bdi_view, now_factor(objs, ghosts))


# Seconds of the last redraws that drew something (rebuilds included), for the benchmark.
timings = deque(maxlen=512)


def _fail(name, exc):
    message = "bdinterp: onion skins and trails of %s stopped: %s: %s" % (name, type(exc).__name__, exc)
    _failed[name] = message
    _cache.update(plan=False)
    print(message)


def draw_callback():
    """A redraw (see _draw), never raising: an error stops the overlay of the active object."""
    obj = bpy.context.object
    name = getattr(obj, "name", "")
    if name in _failed:
        return
    try:
        _draw(bpy.context)
    except Exception as exc:  # noqa: BLE001 -- said once, not on every redraw
        _fail(name, exc)


def _draw(context):
    """The Plan as it is, unless a handler said something changed since (or another object
    became active)."""
    started = time.perf_counter()
    if _cache["plan"] is None or context.object != _cache["active"]:
        if getattr(context.scene, "bdi_view", None) is None:
            return
        _cache["plan"], _cache["active"] = plan(context), context.object
    if _cache["plan"]:
        _cache["plan"].draw()
        timings.append(time.perf_counter() - started)


@persistent
def on_depsgraph_update(scene, depsgraph):
    """Anything updated: the next redraw checks the request; a drawn object's keys edited (not the
    live key alone): bump the epoch, so that it rebuilds."""
    invalidate()
    names = [n for n in (_cache["key"][0] if _cache["key"] else ()) if n not in _failed]
    edited = {u.id.original for u in depsgraph.updates
              if isinstance(u.id, bpy.types.Key) and u.is_updated_geometry}
    for name in names if edited else ():
        try:
            if _edited(bpy.data.objects.get(name), edited):
                _epoch[0] += 1
                return
        except Exception as exc:  # noqa: BLE001 -- said once, not on every update
            _fail(name, exc)


def _edited(obj, keys):
    """True if obj's shape keys are among `keys` and their data changed since last hashed."""
    return (obj is not None and getattr(obj.data, "shape_keys", None) in keys
            and _signatures.get(obj.name) != key_signature(obj))


@persistent
def on_load(*_args):
    _cache.update(key=None, ghosts=None, batches=None, plan=None, active=None)
    _signatures.clear()
    _failed.clear()


_handle = []
HANDLERS = ((bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
            (bpy.app.handlers.frame_change_post, invalidate),
            (bpy.app.handlers.undo_post, invalidate), (bpy.app.handlers.redo_post, invalidate),
            (bpy.app.handlers.load_post, on_load))


def register():
    bpy.utils.register_class(BDI_ViewProps)
    bpy.types.Scene.bdi_view = bpy.props.PointerProperty(type=BDI_ViewProps)
    _handle.append(bpy.types.SpaceView3D.draw_handler_add(draw_callback, (), 'WINDOW', 'POST_VIEW'))
    for handlers, fn in HANDLERS:
        handlers.append(fn)


def unregister():
    for handle in _handle:
        bpy.types.SpaceView3D.draw_handler_remove(handle, 'WINDOW')
    _handle.clear()
    for handlers, fn in HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
    on_load()
    del bpy.types.Scene.bdi_view
    bpy.utils.unregister_class(BDI_ViewProps)


def draw_settings(layout, context):
    """The panel's Onion Skins & Trails section (ui.BDINTERP_PT_view)."""
    view = context.scene.bdi_view
    row = layout.column(align=True)  # one above the other: each label whole in a narrow sidebar
    row.prop(view, "ghosts", toggle=True, icon='ONIONSKIN_ON' if view.ghosts else 'ONIONSKIN_OFF')
    row.prop(view, "trails", toggle=True, icon='IPO_BEZIER')
    if view.ghosts:
        col = layout.column(align=True)
        col.prop(view, "ghost_source", expand=True)
        if view.ghost_source == 'FACTORS':
            col.prop(view, "step")
        elif view.ghost_source == 'FRAMES':
            row = col.row(align=True)
            row.prop(view, "frames_before")
            row.prop(view, "frames_after")
            col.prop(view, "frame_step")
        col.prop(view, "opacity", slider=True)
        row = col.row(align=True)
        row.prop(view, "before_color", text="")
        row.prop(view, "after_color", text="")
    if view.trails:
        col = layout.column(align=True)
        col.prop(view, "trail_vertices", text="")
        col.prop(view, "samples")
        row = col.row(align=True)
        row.prop(view, "chords", toggle=True)
        row.prop(view, "trail_color", text="")
    row = layout.row(align=True)  # greyed out before Blender 4.3, the tooltip says why
    row.operator("bdinterp.bind_drawing", icon='GREASEPENCIL')
    row.operator("bdinterp.bind_drawing", text="", icon='X').unbind = True
    failed = _failed.get(getattr(context.object, "name", ""))
    if failed:
        return failed
    ghosts = _cache["ghosts"] if _cache["key"] is not None and (view.ghosts or view.trails) else None
    return ghosts.error if ghosts is not None and ghosts.error else ""
