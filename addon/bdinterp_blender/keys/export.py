"""Bake for Export: the slider's playback written as F-curves on the baked keys' values.

Blender's glTF, FBX and Alembic exporters carry shape-key values that F-curves animate, not ones
that drivers compute. So the value every driven key has at each frame of a range is sampled and
keyframed (one key a frame, linear between), and the drivers are muted while those F-curves exist
so that Blender shows exactly what is exported; the object's other shown keys are keyed at their
values too (glTF animates a mesh's morph weights all at once). The object's custom property
EXPORT_PROP records what was written, so that remove() takes exactly that away and unmutes the
drivers. Bake for Export never replaces F-curves it did not write (see bake()).
"""

from .. import actions
from . import playback
from ..names import GRID_BAKE_SEP
from ..shapes.mesh_io import BakeError

EXPORT_PROP = "bdi_export"
LINEAR = 1  # index of 'LINEAR' in Keyframe.interpolation's items (foreach_set takes indices)


def _objects(objs):
    objs = list(objs) if isinstance(objs, (list, tuple)) else [objs]
    if not objs:
        raise BakeError("no objects given")
    for obj in objs:
        if obj is None or obj.type != 'MESH' or obj.data.shape_keys is None:
            raise BakeError("%r is not a mesh object with shape keys"
                            % (getattr(obj, "name", obj),))
    return objs


def _animated(owner, prop):
    """True if the slider `prop` on `owner` has keyframes or a driver."""
    path = playback.prop_path(prop)
    anim = owner.animation_data
    return (actions.find_fcurve(anim, path) is not None
            or (anim is not None and anim.drivers.find(path) is not None))


def _grid_keys(obj):
    """[(key block, its driver F-curve)] of the keys of a baked pose grid (Bake Grid) on obj."""
    out = [(kb, playback.driver_of(kb)) for kb in obj.data.shape_keys.key_blocks
           if GRID_BAKE_SEP in kb.name]
    return [(kb, fc) for kb, fc in out if fc is not None]


def driven_keys(obj):
    """[(key block, its driver F-curve)] of every bake on obj (in-betweens and baked pose grids);
    BakeError where there is none, a key is missing or undriven, or a slider is not animated."""
    recs, grid = playback.records(obj), _grid_keys(obj)
    if not recs and not grid:
        raise BakeError("%r has no baked in-betweens or baked pose grid: bake them first" % obj.name)
    key, out = obj.data.shape_keys, grid
    for slider, rec in recs.items():
        owner = playback.recorded_owner(obj, rec)
        if not _animated(owner, slider):
            raise BakeError("the slider %r on %r is not animated: keyframe it over the frames "
                            "to export first" % (slider, owner.name))
        for name in list(rec.get("keys", ())) + [rec.get("end") or rec.get("target")]:
            kb = key.key_blocks.get(name)
            driver = playback.driver_of(kb) if kb is not None else None
            if driver is None:
                raise BakeError("key %r of %r (bake of slider %r) is missing or has no driver: "
                                "bake again" % (name, obj.name, slider))
            out.append((kb, driver))
    return out


def static_keys(obj, driven):
    """[(key block, None)] of obj's other shown keys: not the reference, not muted, not driven, not
    keyframed but by an earlier export bake. glTF animates a mesh's morph weights all in one, so
    they are keyed too (at their constant values)."""
    key, ours = obj.data.shape_keys, _ours(obj)
    skip = {kb.name for kb, _ in driven}
    return [(kb, None) for kb in key.key_blocks
            if kb != key.reference_key and not kb.mute and kb.name not in skip
            and playback.driver_of(kb) is None
            and (kb.name in ours
                 or actions.find_fcurve(key.animation_data, kb.path_from_id("value")) is None)]


def _frame_range(scene, frame_start, frame_end):
    a = scene.frame_start if frame_start is None else int(frame_start)
    b = scene.frame_end if frame_end is None else int(frame_end)
    if b < a:
        raise BakeError("frame range %d..%d is empty" % (a, b))
    return a, b


def _ours(obj):
    """The key names whose value F-curves obj's export bake wrote (its record), a set."""
    record = obj.get(EXPORT_PROP)
    return set(record.to_dict().get("keys", ())) if record is not None else set()


def _refuse_foreign(plans):
    """BakeError naming the first baked key whose value is keyframed by anything but obj's own
    export bake (a user's F-curve is never replaced)."""
    for obj, keys in plans:
        ours, anim = _ours(obj), obj.data.shape_keys.animation_data
        for kb, _ in keys:
            if kb.name not in ours and actions.find_fcurve(anim, kb.path_from_id("value")) is not None:
                raise BakeError("key %r of %r already has keyframes that Bake for Export did not "
                                "write: delete them (or move them to another action) to export the "
                                "slider's playback" % (kb.name, obj.name))


def _read_frame(depsgraph, plans, values):
    """Append what each driven key shows in depsgraph to values[(object, key name)]."""
    for obj, keys in plans:
        evaluated = obj.data.shape_keys.evaluated_get(depsgraph)
        for kb, _ in keys:
            values[obj.name, kb.name].append(evaluated.key_blocks[kb.name].value)


def _sample(scene, plans, frames):
    """{(object, key name): [value at each frame]} as the slider's drivers set them. Drivers that
    an earlier export bake muted are unmuted meanwhile (a driver overrides the F-curve on its
    path); the frame and every mute are restored whatever happens."""
    import bpy
    values = {(obj.name, kb.name): [] for obj, keys in plans for kb, _ in keys}
    current = scene.frame_current, scene.frame_subframe
    mutes = [(driver, driver.mute) for obj, keys in plans for kb, driver in keys
             if driver is not None and kb.name in _ours(obj)]  # else the user's choice
    try:
        for driver, _ in mutes:
            driver.mute = False
        for f in frames:
            scene.frame_set(f)
            _read_frame(bpy.context.evaluated_depsgraph_get(), plans, values)
    finally:
        for driver, mute in mutes:
            driver.mute = mute
        scene.frame_set(current[0], subframe=current[1])
    return values


def action_name(obj):
    """The name of obj's export action: its bake's slider, or its baked pose grid (several: all
    of them), what the user sees in the panel."""
    grids = {kb.name.split(GRID_BAKE_SEP)[0] for kb, _ in _grid_keys(obj)}
    return " + ".join(sorted(playback.records(obj)) + sorted(grids)) or obj.name


def _new_action(anim, name, piece):
    """anim's export action named `name`: where actions have slots (Blender 4.4+) the one that
    the character's other pieces use (a slot each), so that an exporter sees one action; before,
    one action per piece, named after the slider and the piece."""
    import bpy
    if actions.slotted():
        shared = bpy.data.actions.get(name)
        if shared is None or not shared.get(EXPORT_PROP):
            shared = bpy.data.actions.new(name)
            shared[EXPORT_PROP] = True
        anim.action = shared
    else:
        anim.action = bpy.data.actions.new("%s|%s" % (name, piece))


def _write(obj, keys, frames, values, undo):
    """Replace obj's export bake by F-curves of values; each change is undone by a function
    appended to `undo` (run in reverse if a later one fails)."""
    key = obj.data.shape_keys
    anim, ours = key.animation_data, _ours(obj)
    record = obj[EXPORT_PROP].to_dict() if EXPORT_PROP in obj else None
    action = record.get("action", "") if record else ""
    if anim.action is None:
        _new_action(anim, action_name(obj), obj.name)
        action = anim.action.name
        undo.append(lambda: _drop_action(anim))
    for name in sorted(ours - {kb.name for kb, _ in keys}):  # keys no longer baked
        kb = key.key_blocks.get(name)
        if kb is not None:
            _unwrite(anim, kb.path_from_id("value"), undo)
    for kb, driver in keys:
        path = kb.path_from_id("value")
        if kb.name in ours:
            _unwrite(anim, path, undo)
        fc = actions.new_fcurve(anim, path)
        undo.append(lambda path=path: _remove_curve(anim, path))
        actions.set_points(fc, {"co": [c for f, v in zip(frames, values[obj.name, kb.name])
                                       for c in (f, v)], "interpolation": [LINEAR] * len(frames)})
        if driver is not None:  # None: a key shown at a constant value (static_keys)
            undo.append(lambda driver=driver, mute=driver.mute: setattr(driver, "mute", mute))
            driver.mute = True
    obj[EXPORT_PROP] = {"keys": [kb.name for kb, _ in keys], "action": action,
                        "frames": [frames[0], frames[-1]]}
    undo.append(lambda: _set_record(obj, record))
    return len(keys)


def _unwrite(anim, path, undo):
    """Remove the export F-curve at path and unmute its driver, undoably."""
    fc, driver = actions.find_fcurve(anim, path), anim.drivers.find(path)
    if fc is not None:
        points = actions.points_of(fc)
        actions.action_fcurves(anim).remove(fc)
        undo.append(lambda: actions.set_points(actions.new_fcurve(anim, path), points))
    if driver is not None:
        undo.append(lambda mute=driver.mute: setattr(anim.drivers.find(path), "mute", mute))
        driver.mute = False


def _remove_curve(anim, path):
    curves = actions.action_fcurves(anim)
    fc = curves.find(path) if curves is not None else None
    if fc is not None:
        curves.remove(fc)


def _drop_action(anim):
    import bpy
    action, anim.action = anim.action, None
    if action is not None and action.users == 0:
        bpy.data.actions.remove(action)


def _set_record(obj, record):
    if record is None:
        obj.pop(EXPORT_PROP, None)
    else:
        obj[EXPORT_PROP] = record


def bake(objs, frame_start=None, frame_end=None):
    """Write what the sliders show at every frame of the range (default: the scene's) as linear
    F-curves on the baked keys' values of each object, muting their drivers; an earlier export
    bake is replaced. Returns a message.

    A transaction: everything is checked and every frame sampled (the sliders' drivers, not an
    earlier export bake) before anything is written, and if writing fails every change made is
    undone, so that on any error the file is as it was (an earlier export bake included). A baked
    key whose value already has an F-curve that is not this export's own (keyframes a user set)
    is refused with a BakeError naming it: user curves are never replaced or deleted."""
    import bpy
    objs = _objects(objs)
    scene = bpy.context.scene
    a, b = _frame_range(scene, frame_start, frame_end)
    plans = [(obj, driven_keys(obj)) for obj in objs]
    plans = [(obj, keys + static_keys(obj, keys)) for obj, keys in plans]
    _refuse_foreign(plans)
    frames = list(range(a, b + 1))
    values = _sample(scene, plans, frames)
    undo = []
    try:
        count = sum(_write(obj, keys, frames, values, undo) for obj, keys in plans)
    except BaseException:
        for step in reversed(undo):
            step()
        raise
    return "Baked %d keys of %d objects for export, frames %d-%d" % (count, len(objs), a, b)


def remove(obj):
    """Remove obj's export bake (its F-curves, and the action if the bake made it) and unmute the
    slider's drivers; True if there was one."""
    import bpy
    record = obj.get(EXPORT_PROP)
    if record is None:
        return False
    record = record.to_dict()
    key = obj.data.shape_keys
    anim = key.animation_data if key else None
    curves = actions.action_fcurves(anim)
    for name in record.get("keys", ()):
        kb = key.key_blocks.get(name) if key else None
        if kb is None:
            continue
        path = kb.path_from_id("value")
        fc = curves.find(path) if curves is not None else None
        if fc is not None:
            curves.remove(fc)
        driver = anim.drivers.find(path)
        if driver is not None:
            driver.mute = False
    action = bpy.data.actions.get(record.get("action") or "")
    if action is not None and anim is not None and anim.action == action and not actions.all_fcurves(anim):
        anim.action = None
        if action.users == 0:
            bpy.data.actions.remove(action)
    del obj[EXPORT_PROP]
    return True
