"""Onion skins and motion trails of the in-betweens in the 3D viewport (settings: Scene.bdi_view).

What is drawn (Ghosts: ghost shapes, trails, ticks at the baked keys, in the drawn object's
coordinates) is computed once, kept in GPU batches (overlay.py) and drawn with the object's
matrix.  A redraw after a change compares a cheap request key (objects, settings, topology, an
epoch bumped when the keys' data change) and only recolours; a new view setting solves only
factors the Path has not solved.  Key data are re-read only when a drawn object's keys are
reported edited by someone else than the add-on (changes.py), never on playback or live frames.
An error while computing the ghosts is shown in the panel; one elsewhere in a redraw or the
handler is printed once and the overlay leaves that object alone until a view setting changes or
a file is loaded (no error repeats every redraw).
"""

import hashlib
import time
from collections import Counter, deque

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty

from . import motion_trails
from .ghosts import Ghosts, build, factor_at, selected_vertices
from .. import changes
from ..shapes import mesh_io
from ..names import LIVE_KEY


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


def solve_key(objs):
    """What a Path depends on, cheap to compare: the objects, their settings and topology (vertex,
    face and loop counts), the epoch (bumped when their keys' data change), the joint parents set
    by hand and, for a character
    (solved in world coordinates), the objects' transforms.  One object's transform is not in
    it: its ghosts are drawn with its matrix."""
    return (tuple(o.name for o in objs), motion_trails.settings_of(objs[0].bdi), _epoch[0],
            tuple(getattr(o.bdi.joint_parent, "name", "") for o in objs),
            tuple((len(o.data.vertices), len(o.data.polygons), len(o.data.loops)) for o in objs),
            tuple(tuple(v for row in o.matrix_world for v in row) for o in objs) if len(objs) > 1 else ())


def request_key(objs, view):
    """What the Ghosts depend on: the Path's (solve_key), the view's settings but colours, the
    selection the trails follow; last: the frame (for ghosts of frames; else None)."""
    selected = ()
    if view.trails and view.trail_vertices == 'SELECTED':
        selected = selected_vertices(objs).tobytes()
    settings = (objs[0].bdi.live_mode, view.ghosts, view.ghost_source, view.step, view.trails,
                view.trail_vertices, view.samples, view.frames_before, view.frames_after,
                view.frame_step, selected)
    frame = bpy.context.scene.frame_current if view.ghosts and view.ghost_source == 'FRAMES' else None
    return (solve_key(objs), settings, frame)


counters = Counter()  # for the tests: keys' data 'hashed', Ghosts 'built', 'batches', 'plans' made
_epoch = [0]        # bumped when the data of a drawn object's keys change
_signatures = {}    # object name -> hash of its keys' data (but the live key) and its faces
_failed = {}        # object name -> the error that stopped drawing its overlay (printed once)
_cache = {"key": None, "ghosts": None, "batches": None, "plan": None, "active": None}


def key_signature(obj):
    """A hash of obj's keys' data (but the live key's) and of its mesh's faces."""
    import numpy as np
    counters["hashed"] += 1
    key, h = obj.data.shape_keys, hashlib.sha1()
    for kb in key.key_blocks if key else ():
        if kb.name != LIVE_KEY:
            h.update(kb.name.encode() + kb.vertex_group.encode() + kb.relative_key.name.encode())
            h.update(mesh_io.read_raw(kb).tobytes())
    loops = np.empty(len(obj.data.loops), dtype=np.int32)
    obj.data.loops.foreach_get("vertex_index", loops)
    h.update(loops.tobytes())
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
        old = _cache["ghosts"]
        same = old is not None and _cache["key"] is not None and _cache["key"][0] == key[0]
        path = old.path if same else None
        _cache["key"], _cache["batches"] = key, None
        try:
            if path is None:  # a new Path: what its keys hold now
                for o in objs:
                    _signatures[o.name] = key_signature(o)
            _cache["ghosts"] = build(objs, view, key[-1], path)
            counters["built"] += 1
            _cache["batches"] = overlay.batches(_cache["ghosts"])
            counters["batches"] += 1
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
    counters["plans"] += 1
    return overlay.Plan(batches, ghosts, context.scene.bdi_view, now_factor(objs, ghosts),
                        ghosts.matrix())


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


def on_changes(_scene, _depsgraph, changed):
    """Every update (changes.py): the next redraw checks the request; the keys of a drawn object
    edited by someone else than the add-on (its live key's writes are known and skipped) and
    holding other data than the Path read: bump the epoch, so that the Path is made again."""
    invalidate()
    edited = changed.edited_keys()
    names = [n for n in (_cache["key"][0][0] if _cache["key"] else ()) if n not in _failed]
    for name in names if edited else ():
        try:
            if _edited(bpy.data.objects.get(name), edited):
                _epoch[0] += 1
                return
        except Exception as exc:  # noqa: BLE001 -- said once, not on every update
            _fail(name, exc)


def _edited(obj, keys):
    """True if obj's shape keys are among `keys` (names) and changed since last hashed."""
    key = getattr(getattr(obj, "data", None), "shape_keys", None)
    return key is not None and key.name in keys and _signatures.get(obj.name) != key_signature(obj)


@persistent
def forget(*_args):
    """After an undo the keys may hold anything and the Path's objects are gone: start afresh."""
    _cache.update(key=None, ghosts=None, batches=None, plan=None, active=None)
    _signatures.clear()


@persistent
def on_load(*_args):
    forget()
    _failed.clear()


_handle = []
HANDLERS = ((bpy.app.handlers.undo_post, forget), (bpy.app.handlers.redo_post, forget),
            (bpy.app.handlers.load_post, on_load))


def hook(handles, draw, handlers, changed):
    """Install a viewport overlay: its draw callback (its handle appended to `handles`), its
    (app handler list, function) pairs and its changes.py subscriber."""
    handles.append(bpy.types.SpaceView3D.draw_handler_add(draw, (), 'WINDOW', 'POST_VIEW'))
    for app_handlers, fn in handlers:
        app_handlers.append(fn)
    changes.subscribe(2, changed)


def unhook(handles, handlers, changed):
    """Remove what hook() installed."""
    changes.unsubscribe(changed)
    for handle in handles:
        bpy.types.SpaceView3D.draw_handler_remove(handle, 'WINDOW')
    handles.clear()
    for app_handlers, fn in handlers:
        if fn in app_handlers:
            app_handlers.remove(fn)


def register():
    bpy.utils.register_class(BDI_ViewProps)
    bpy.types.Scene.bdi_view = bpy.props.PointerProperty(type=BDI_ViewProps)
    hook(_handle, draw_callback, HANDLERS, on_changes)


def unregister():
    unhook(_handle, HANDLERS, on_changes)
    on_load()
    del bpy.types.Scene.bdi_view
    bpy.utils.unregister_class(BDI_ViewProps)


def draw_settings(layout, context):
    """The panel's Onion Skins & Trails section (ui.BDINTERP_PT_view)."""
    view = context.scene.bdi_view
    row = layout.row(align=True)
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
