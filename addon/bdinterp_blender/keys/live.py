"""Live mode: the exact interpolation/blend recomputed whenever its inputs change.

The result goes into the shape key 'bdi.live' (relative to the source, value 1), on every frame
change (playback, `blender -b file.blend -a`, scrubbing) and depsgraph update (the factor or a
weight changed directly, by a driver, by an F-curve edit; undo), both told by changes.py.  Per object a
State caches the validated shapes and the precomputed Interpolator; a frame then costs the
solve, a comparison of the factor/weights with the last ones written, and the foreach_set.  The
cache is rebuilt when a setting changes and re-checked (the input keys re-read and compared)
when the depsgraph reports the object's shape keys updated (writes made in frame_change_post,
i.e. during playback, are not reported, so playback never pays for the check).
On any error live mode turns itself off for that object with one message (console + panel); an
object whose error could not even switch it off (Blender forbids writes in some handlers) is left
alone by the handlers until live mode is switched on again, so that no error repeats every frame.
"""

from collections import namedtuple
from contextlib import contextmanager

import bpy
from bpy.app.handlers import persistent

from . import character
from .. import changes
from ..shapes import mesh_io, solve
from ..shapes.mesh_io import BakeError
from ..names import LIVE_KEY, LIVE_WARNING
from ..shapes.settings import from_props

# A live request: the mode ('INTERPOLATE' or 'BLEND') and its BakeSettings (compared to notice changes).
Settings = namedtuple("Settings", "mode bake")


class State:
    """Cached inputs of one live object: settings, Inputs (no bpy references kept), solver."""

    def __init__(self, settings, inp, solver):
        self.settings, self.inp, self.solver = settings, inp, solver
        for part in [inp] + list(getattr(inp, "parts", ())):  # may dangle after undo: names only
            part.obj = part.key = part.source = part.others = None
        self.values = None      # factor / weights last written
        self.dirty = False      # the object's shape keys may have been edited: re-read, compare
        self.members = ()       # a character: its objects' names and matrices (a change rebuilds)


_states = {}   # object name -> State
_failed = set()  # names of objects whose live mode failed: the handlers leave them alone
_suspended = []  # non-empty while api.set_live writes several settings: no recompute per write


def settings_of(props, **changes):
    """The live Settings of the panel settings `props` (Object.bdi), with `changes` of its
    BakeSettings."""
    blend = changes.pop("mode", props.live_mode) == 'BLEND'
    if not blend:
        changes["poses"] = ()
    return Settings('BLEND' if blend else 'INTERPOLATE',
                    from_props(props, factors=None, easing="LINEAR", **changes))


def prepare(obj, settings, objs=None):
    """Validate `settings` for obj and precompute (BakeError naming what is wrong); writes nothing.
    objs: the objects of obj's character (default: those it holds, see character_objects)."""
    objs = character_objects(obj, settings.bake.target) if objs is None else objs
    for o in objs or [obj]:  # the pose grids' key and the live key would both add their offsets
        if len(getattr(o, "bdi_grids", ())):
            raise BakeError("%s has pose grids: remove them first to use live mode" % o.name)
    if len(objs) > 1 and settings.mode != 'BLEND':
        return prepare_character(objs, settings)
    owner = next((o for o in bpy.data.objects if o != obj and getattr(o, "bdi", None) is not None
                  and o.bdi.live and any(m.obj == obj for m in o.bdi.live_objects)), None)
    if owner is not None:  # two live modes would write its live key in turn
        raise BakeError("%s is part of %s's live character: switch that off first"
                        % (obj.name, owner.name))
    bake = settings.bake
    if settings.mode == 'BLEND':
        if not bake.poses:
            raise BakeError("%s: live pose blend has no poses; add some under Pose Blend" % obj.name)
        inp = solve.Inputs(obj, bake.but(anchor_path=None), list(bake.poses))
        return State(settings, inp, inp.interpolator())
    inp = solve.Inputs(obj, bake)
    return State(settings, inp, inp.interpolator() if bake.method == 'bdi' else None)


def character_objects(obj, target, others=None):
    """obj and the other objects of its live character (others, default: obj.bdi.live_objects)
    that have the target key, obj first; [] when that is not several objects led by obj."""
    others = [m.obj for m in obj.bdi.live_objects] if others is None else list(others)
    objs = character.members([obj] + others, target)
    return objs if len(objs) > 1 and objs[0] == obj else []


def _signature(objs):
    """The objects' names, matrices and joint parents set by hand: a change rebuilds the State."""
    return tuple((o.name, tuple(tuple(row) for row in o.matrix_world),
                  getattr(o.bdi.joint_parent, "name", "")) for o in objs)


def prepare_character(objs, settings):
    """The State of a character of several objects (objs[0] holds the settings and the factor),
    solved in world space as a bake solves it (character.CharacterInputs)."""
    for other in objs[1:]:  # two live modes would write its live key in turn
        if other.bdi.live:
            raise BakeError("%s is in live mode of its own: switch that off to make it part of "
                            "%s's live character" % (other.name, objs[0].name))
    inp = character.CharacterInputs(objs, settings.bake)
    state = State(settings, inp, inp.interpolator() if settings.bake.method == 'bdi' else None)
    state.members = _signature(objs)
    return state


def set_members(obj, objs):
    """Record objs (obj first; [] for obj alone) as obj's live character."""
    obj.bdi.live_objects.clear()
    for other in objs[1:]:
        obj.bdi.live_objects.add().obj = other


def _members(obj, settings):
    return _signature(character_objects(obj, settings.bake.target)) if settings.mode != 'BLEND' else ()


def remove_keys(objs):
    """Remove the live key of each of objs (a baked character's other objects)."""
    for obj in objs:
        kb = obj.data.shape_keys.key_blocks.get(LIVE_KEY) if obj.data.shape_keys else None
        if kb is not None:
            obj.shape_key_remove(kb)


def _objects(obj, state):
    """The objects whose keys `state` reads and writes (obj, or a character's)."""
    return [bpy.data.objects.get(name) for name, *_ in state.members] or [obj]


def _values(props):
    if props.live_mode == 'BLEND':
        return tuple(p.weight for p in props.poses)
    return (props.live_factor,)


def _unchanged(obj, state):
    """True if the input keys (of every object of a character) still hold the data the state was
    built from."""
    parts = getattr(state.inp, "parts", [state.inp])
    return all(o is not None and _same_keys(o, part)
               for o, part in zip(_objects(obj, state), parts))


def _same_keys(obj, inp):
    import numpy as np
    key = obj.data.shape_keys
    for name, raw in zip(inp.names, inp.raw):
        kb = key.key_blocks.get(name) if key else None
        if kb is None or len(kb.data) * 3 != raw.size or not np.array_equal(mesh_io.read_raw(kb), raw):
            return False
    return True


def _state(obj):
    settings = settings_of(obj.bdi)
    state = _states.get(obj.name)
    if state is not None and state.settings == settings and state.dirty:
        state.dirty = False
        if not _unchanged(obj, state):
            state = None
    if state is None or state.settings != settings or state.members != _members(obj, settings):
        state = _states[obj.name] = prepare(obj, settings)
    return state


def compute(state, values):
    """The live result (n, 3) for factor/weights `values` (writes nothing)."""
    inp = state.inp
    if state.settings.mode == 'BLEND':
        names, weights = solve.pose_weights(list(zip(inp.names[1:], values)))
        return solve.blend_shape(inp, weights, state.solver)
    if state.solver is None:
        return solve.FrameJob(inp, values, state.settings.bake.method).frames()[0]
    try:
        return state.solver.at(values[0])
    except ValueError as exc:
        raise inp.explain(exc) from exc


def update(obj, depsgraph=None, force=False):
    """Recompute and write obj's live key if its inputs changed (or force).  The factor/weights
    are read from the evaluated object: while rendering, animated values are not written back to
    the original.  Returns True if it wrote."""
    state = _state(obj)
    values = _values((obj.evaluated_get(depsgraph) if depsgraph is not None else obj).bdi)
    key = obj.data.shape_keys
    kb = key.key_blocks.get(LIVE_KEY)
    if kb is not None and values == state.values and not force:
        return False
    write(obj, state, values, compute(state, values))
    return True


def write(obj, state, values, result):
    """Write `result` into obj's live key (created if missing); a character's world result into
    each of its objects' live keys, in the object's own coordinates."""
    objs = _objects(obj, state)
    if state.members:  # every object's coordinates before any is written
        offsets = state.inp.offsets
        local = [character.to_local(o, result[a:b]) for o, a, b in zip(objs, offsets[:-1], offsets[1:])]
    else:
        local = [result]
    for o, co in zip(objs, local):
        write_key(o, state.inp.names[0], co)
    state.values = values


def write_key(obj, source, co, name=LIVE_KEY):
    """Write co into obj's key `name` (default: the live key; created if missing, value 1),
    relative to the key `source`."""
    key = obj.data.shape_keys
    kb = key.key_blocks.get(name)
    if kb is None:
        kb = obj.shape_key_add(name=name, from_mix=False)
    if kb.relative_key.name != source:
        kb.relative_key = key.key_blocks[source]
    if kb.value != 1.0:
        kb.value = 1.0
    mesh_io.write_co(kb, co)
    key.update_tag()
    changes.wrote(key)


def turn_off(obj, exc):
    """Live mode off for obj after exc, said once (console and panel)."""
    message = "bdinterp: live mode turned off for %s: %s" % (obj.name, _said(exc))
    _failed.add(obj.name)
    _states.pop(obj.name, None)
    print(message)
    try:
        obj.bdi.live_error = message
        obj.bdi.live = False  # on_toggle does nothing when switching off
    except Exception:  # noqa: BLE001 -- no writes here: _failed keeps the handlers off it
        pass


def _said(exc):
    return str(exc) if isinstance(exc, (ValueError, RuntimeError)) else "%s: %s" % (type(exc).__name__, exc)


def _safe_update(obj, depsgraph=None, force=False):
    _guarded(obj, lambda: update(obj, depsgraph, force))


def _guarded(obj, work):
    """work() for obj's live mode unless it failed before; any error turns it off, once."""
    if obj.name in _failed:
        return
    try:
        work()
    except Exception as exc:  # noqa: BLE001 -- any failure must switch live mode off, once
        turn_off(obj, exc)


def on_toggle(obj):
    if _suspended:
        return
    if obj.bdi.live:
        _failed.discard(obj.name)
        obj.bdi.live_error = ""
        _from_selection(obj)
        _safe_update(obj, force=True)
    else:
        _states.pop(obj.name, None)


def _from_selection(obj):
    """Switched on (the panel's toggle): the selected meshes that have the target key are obj's
    character, as the bake takes them (obj alone when none is)."""
    others = character.selected_meshes(bpy.context, obj)[1:]
    with suspended():
        set_members(obj, character_objects(obj, obj.bdi.target, others))


def on_property_change(obj):
    if obj.bdi.live and not _suspended:
        _safe_update(obj)


@contextmanager
def suspend(flags):
    """Appends to the list `flags` while inside: a handler that sees it non-empty waits."""
    flags.append(True)
    try:
        yield
    finally:
        flags.pop()


def suspended():
    """Settings written inside do not recompute one by one (api.set_live writes several)."""
    return suspend(_suspended)


def switch_on(obj, state, values, result):
    """Live mode on with a prepared State and its first result (see api.set_live)."""
    _states[obj.name] = state
    _failed.discard(obj.name)
    with suspended():
        obj.bdi.live, obj.bdi.live_error = True, ""
    write(obj, state, values, result)


def _live_objects(scene):
    return [o for o in scene.objects if o.type == 'MESH' and o.bdi.live]


def _keys_edited(obj, state, edited):
    return any(getattr(getattr(o, "data", None), "shape_keys", None) is not None
               and o.data.shape_keys.name in edited for o in _objects(obj, state))


def _on_update(obj, edited, depsgraph):
    state = _states.get(obj.name)
    if state is not None and _keys_edited(obj, state, edited):
        # Our own write of the live key is reported too (at the next update), and an edit made
        # by a script before this evaluation looks the same: re-check (the input keys'
        # foreach_get, ~0.7 ms per key at 20k vertices) rather than trust a flag.  Writes made on
        # a frame change (playback) are not reported: playback never pays for it.
        state.dirty = True
    update(obj, depsgraph)


def on_changes(scene, depsgraph, changed):
    """Every frame change and depsgraph update (changes.py): recompute what changed."""
    for obj in _live_objects(scene):
        _guarded(obj, lambda obj=obj: _on_update(obj, changed.keys, depsgraph))


@persistent
def on_undo(*_args):
    for state in _states.values():  # the keys, factor and live key may all be older now
        state.dirty, state.values = True, None


@persistent
def on_load(*_args):
    _states.clear()  # object names may now mean other objects
    _failed.clear()
    for scene in bpy.data.scenes:
        for obj in _live_objects(scene):
            print("bdinterp: %s in scene %s %s" % (obj.name, scene.name, LIVE_WARNING))


HANDLERS = ((bpy.app.handlers.undo_post, on_undo), (bpy.app.handlers.redo_post, on_undo),
            (bpy.app.handlers.load_post, on_load))


def add_handlers(pairs):
    """Append each (handler list, function) of pairs, replacing stale copies of the function."""
    for handlers, fn in pairs:
        # Drop stale copies left by an earlier load of this module (add-on reload).
        for h in [h for h in handlers if getattr(h, "__name__", "") == fn.__name__
                  and getattr(h, "__module__", "") == fn.__module__]:
            handlers.remove(h)
        handlers.append(fn)


def remove_handlers(pairs):
    for handlers, fn in pairs:
        if fn in handlers:
            handlers.remove(fn)


def register():
    add_handlers(HANDLERS)
    changes.subscribe(0, on_changes)


def unregister():
    changes.unsubscribe(on_changes)
    remove_handlers(HANDLERS)
    _states.clear()
    _failed.clear()
