"""Pose grids follow their parameters live: the blend is recomputed whenever a parameter's value
changes (set, keyframed, driven: frame change, depsgraph update, render; both told by
changes.py) and after undo.

Per owner object (the one whose Object.bdi_grids holds the groups) a State caches a PoseBlender
(every group combined, one precomputed Interpolator) per member and the raw key data it was built
from. The owner and the objects that are members of every one of its groups share the grid: they
are solved as one character in world space (keys.character.CharacterInputs, as a bake of several
objects is), so their pieces are joined across objects; an object in only some of the groups is
solved on its own. A frame costs the weights, one blend per member and the write into each
object's key 'bdi.pose' (relative to the reference key, value 1), in its own coordinates. An
error is recorded once in Object.bdi_grid_error and printed; the grid then waits for its
definition or its keys to change.
"""

import bpy
from bpy.app.handlers import persistent

from .. import changes
from ..keys import character as characters
from ..keys import live as live_mode
from ..shapes import mesh_io, solve
from ..shapes.mesh_io import BakeError
from ..names import POSE_KEY
from ..shapes.settings import BakeSettings


def definition(obj):
    """The grids of obj, its members' sizes and (objects solved together) their world matrices, as
    plain values (a change rebuilds the State)."""
    return tuple((g.name, tuple((p.name, p.values, p.wrap, p.period) for p in g.params),
                  tuple((n.index, n.key) for n in g.nodes),
                  tuple(m.obj.name for m in g.members if m.obj is not None))
                 for g in obj.bdi_grids) \
        + tuple((o.name, len(o.data.vertices)) for o in members(obj)) + _placement(obj)


def _placement(obj):
    """The world matrices of a shared grid's objects (solved in world space: a move rebuilds)."""
    shared = solved_together(obj)
    return tuple(tuple(map(tuple, o.matrix_world)) for o in shared) if len(shared) > 1 else ()


def core_grid(group):
    """The bdinterp PoseGrid of a group's properties."""
    pg = solve.core().pose_grid
    params = [pg.Parameter(p.name, [float(x) for x in p.values.split(",")], wrap=p.wrap,
                           period=p.period if p.wrap else None) for p in group.params]
    keys = {tuple(float(params[a].values[int(i)]) for a, i in enumerate(n.index.split(","))): n.key
            for n in group.nodes}
    return pg.PoseGrid(params, keys, name=group.name)


def members(obj):
    """{object: [names of the groups it follows]}: obj (every group), then the other objects of
    its groups (each following the groups it is a member of)."""
    out = {obj: [g.name for g in obj.bdi_grids]}
    for g in obj.bdi_grids:
        for m in g.members:
            if m.obj is not None and m.obj != obj:
                out.setdefault(m.obj, []).append(g.name)
    return out


def solved_together(obj):
    """obj, then the other objects that are members of every one of its groups: one character."""
    names = [g.name for g in obj.bdi_grids]
    return [o for o, groups in members(obj).items() if sorted(groups) == sorted(names)]


class Member:
    """The cached blender of one object, or of several solved as one character (objs[0] first):
    their names, the raw keys they were read from (per object), the PoseBlender."""

    def __init__(self, objs, grids):
        self.groups = [g.name for g in grids]
        rest = mesh_io.key_of(objs[0]).reference_key.name
        names = list(dict.fromkeys(k for g in grids for k in g.keys() if k != rest))
        if len(objs) > 1:
            inp = characters.CharacterInputs(objs, BakeSettings(), names)
            parts, self.offsets = inp.parts, inp.offsets
        else:
            inp = solve.Inputs(objs[0], BakeSettings(), names)
            parts, self.offsets = [inp], None
        try:
            # Solved to the tolerance without the refinement: what the refinement changes (the
            # history a frame is solved after shows at ~1e-11 of the size) is far below the float32
            # of Blender's positions, and at 100k vertices it takes 0.4 of a live update.
            self.blender = solve.core().pose_grid.PoseBlender(
                dict(zip(inp.names, inp.shapes)), inp.faces, grids, rest, anchor=inp.anchor,
                joints=inp.joints, layers=inp.layers, refinement=1.0)
        except ValueError as exc:
            raise inp.explain(exc) from exc
        self.objs, self.rest, self.names = [o.name for o in objs], rest, inp.names
        self.name, self.raw = self.objs[0], [p.raw for p in parts]
        self.report = ""

    def unchanged(self):
        import numpy as np
        for name, raws in zip(self.objs, self.raw):
            obj = bpy.data.objects.get(name)
            key = obj.data.shape_keys if obj is not None and obj.type == 'MESH' else None
            blocks = [key.key_blocks.get(n) if key else None for n in self.names]
            if not all(kb is not None and np.array_equal(mesh_io.read_raw(kb), raw)
                       for kb, raw in zip(blocks, raws)):
                return False
        return True

    def local(self, shape):
        """[(object name, its part of a blended shape in its own coordinates)]; every object's
        matrix is read before anything is written."""
        if self.offsets is None:
            return [(self.name, shape)]
        return [(n, characters.to_local(bpy.data.objects[n], shape[a:b]))
                for n, a, b in zip(self.objs, self.offsets[:-1], self.offsets[1:])]


class State:
    """The cached blenders of an owner object's grids (members), the values last written, and
    whether its keys may have been edited (dirty) or it failed (error)."""

    def __init__(self, obj):
        self.definition = definition(obj)
        self.error, self.values, self.dirty, self.members = "", None, False, []
        self.pending = set()  # Keys we wrote that the next depsgraph update will report
        try:
            grids = {g.name: core_grid(g) for g in obj.bdi_grids}
            together = solved_together(obj)
            self.members = [Member(together, [grids[g.name] for g in obj.bdi_grids])] + [
                Member([o], [grids[n] for n in names])
                for o, names in members(obj).items() if o not in together]
        except (BakeError, ValueError) as exc:
            self.error = "%s: %s" % (obj.name, exc) if obj.name not in str(exc) else str(exc)


_states = {}  # owner object name -> State
_failed = set()  # owners whose update raised unexpectedly: the handlers leave them alone
_suspended = []  # non-empty while a grid is being written: no update per property


def suspended():
    """Properties written inside do not update one by one (pose_grid writes a whole group)."""
    return live_mode.suspend(_suspended)


def state_of(obj):
    """obj's State, rebuilt when its grids changed or (after an edit or undo) its keys did."""
    state = _states.get(obj.name)
    if state is not None and state.dirty and not state.error:
        state.dirty = False
        if not all(m.unchanged() for m in state.members):
            state = None
    if state is None or state.definition != definition(obj) or (state.error and state.dirty):
        state = _states[obj.name] = State(obj)
    return state


def points(obj):
    """{group name: (value per parameter)} of obj (pass the evaluated object for animated values)."""
    return {g.name: tuple(p.amount for p in g.params) for g in obj.bdi_grids}


def compute(state, values):
    """[(member name, Blend)] at values {group: point} (writes nothing)."""
    out = []
    for m in state.members:
        try:
            out.append((m.name, m.blender.blend({g: values[g] for g in m.groups})))
        except ValueError as exc:
            raise BakeError("%s: %s" % (m.name, exc)) from exc
    return out


def update(obj, depsgraph=None, force=False, reported=True):
    """Recompute and write the pose key of obj's grid members if the values changed (or force);
    returns True if it wrote. reported: the next depsgraph update will report the write (not so
    for writes in frame_change_post). Errors are recorded (Object.bdi_grid_error), never raised."""
    state = state_of(obj)
    if not state.error:
        values = points(obj.evaluated_get(depsgraph) if depsgraph is not None else obj)
        keys = [o.data.shape_keys.key_blocks.get(POSE_KEY)
                for o in (bpy.data.objects.get(n) for m in state.members for n in m.objs)]
        if keys[0] is not None and keys[0].mute:
            return False  # Bake Grid muted it: the baked keys show the grid (unmute to go live)
        if values == state.values and None not in keys and not force:
            return False
        try:
            for (_, blend), m in zip(compute(state, values), state.members):
                for name, co in m.local(blend.shape):
                    target = bpy.data.objects[name]
                    live_mode.write_key(target, m.rest, co, POSE_KEY)
                    if reported:
                        state.pending.add(target.data.shape_keys.name)
                m.report = blend.report()
            state.values = values
        except (BakeError, RuntimeError) as exc:
            state.error = str(exc)
    if obj.bdi_grid_error != state.error:
        if state.error:
            print("bdinterp: pose grid of %s: %s" % (obj.name, state.error))
        try:
            obj.bdi_grid_error = state.error
        except (AttributeError, RuntimeError):  # a handler where Blender forbids writes
            pass
    return not state.error


def reports(obj):
    """{object name: how its last blend relates to the guarantee (Blend.report(), worst K of an
    extrapolated combination)} of obj's grids, or {owner: its error}."""
    state = _states.get(obj.name)
    if state is None:
        return {}
    if state.error:
        return {obj.name: state.error}
    return {n: m.report for m in state.members for n in m.objs}


def remove(obj):
    """Forget obj's cached State (its grids were removed or are set up anew)."""
    _states.pop(obj.name, None)
    _failed.discard(obj.name)


def _guarded(obj, depsgraph, reported=True):
    """update() from a handler: an unexpected error is said once and the object left alone
    (until its grids are set up again, or undo), never raised every frame."""
    if obj.name in _failed:
        return
    try:
        update(obj, depsgraph, reported=reported)
    except Exception as exc:  # noqa: BLE001 -- a handler must not fail every frame
        _failed.add(obj.name)
        print("bdinterp: pose grid of %s stopped: %s: %s" % (obj.name, type(exc).__name__, exc))


def on_value_change(obj):
    if obj.bdi_grids and not _suspended:
        _guarded(obj, None)


def _grid_objects(scene):
    return [o for o in scene.objects if o.type == 'MESH' and len(o.bdi_grids)]


def _mark_edited(edited):
    """Mark the States whose objects' Keys were updated by someone else dirty (their input keys
    are then re-read and compared). Our own writes are reported too; one reported just after
    our write is taken as ours: re-reading nine keys would cost more than the blend (8 ms of
    36 at 5k vertices). So an input key edited by a script together with a parameter change, in
    one update, is noticed at the next key edit or undo. edited: names of the Keys updated."""
    for state in _states.values():
        keys = {getattr(bpy.data.objects[n].data.shape_keys, "name", None)
                for m in state.members for n in m.objs if bpy.data.objects.get(n) is not None}
        if (keys & edited) - state.pending:
            state.dirty = True
        state.pending.clear()


def on_changes(scene, depsgraph, changed):
    """Every frame change and depsgraph update (changes.py)."""
    if depsgraph is not None:
        _mark_edited(changed.keys)
    for obj in _grid_objects(scene):  # writes on a frame change are not reported
        _guarded(obj, depsgraph, reported=not changed.frame)


@persistent
def on_undo(*_args):
    _failed.clear()
    for state in _states.values():
        state.dirty, state.values = True, None


@persistent
def on_load(*_args):
    _states.clear()
    _failed.clear()


HANDLERS = ((bpy.app.handlers.undo_post, on_undo), (bpy.app.handlers.redo_post, on_undo),
            (bpy.app.handlers.load_post, on_load))


def register():
    live_mode.add_handlers(HANDLERS)
    changes.subscribe(0, on_changes)


def unregister():
    changes.unsubscribe(on_changes)
    live_mode.remove_handlers(HANDLERS)
    _states.clear()
