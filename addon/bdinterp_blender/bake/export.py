"""Bake for Export: the slider's playback written as F-curves on the baked keys' values.

Blender's glTF, FBX and Alembic exporters carry shape-key values that F-curves animate, not ones
that drivers compute. So the value every driven key has at each frame of a range is sampled and
keyframed (one key a frame, linear between), and the drivers are muted while those F-curves exist
so that Blender shows exactly what is exported. The object's custom property EXPORT_PROP records
what was written, so that remove() takes exactly that away and unmutes the drivers.
"""

from .. import actions
from . import playback
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


def driven_keys(obj):
    """[(key block, its driver F-curve)] of every bake on obj; BakeError where there is no bake,
    a key is missing or undriven, or a slider is not animated."""
    recs = playback.records(obj)
    if not recs:
        raise BakeError("%r has no baked in-betweens: bake them first" % obj.name)
    key, out = obj.data.shape_keys, []
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


def _frame_range(scene, frame_start, frame_end):
    a = scene.frame_start if frame_start is None else int(frame_start)
    b = scene.frame_end if frame_end is None else int(frame_end)
    if b < a:
        raise BakeError("frame range %d..%d is empty" % (a, b))
    return a, b


def _sample(scene, plans, frames):
    """{(object, key name): [value at each frame]} as the slider's drivers set them."""
    import bpy
    values = {(obj.name, kb.name): [] for obj, keys in plans for kb, _ in keys}
    current = scene.frame_current, scene.frame_subframe
    try:
        for f in frames:
            scene.frame_set(f)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            for obj, keys in plans:
                evaluated = obj.data.shape_keys.evaluated_get(depsgraph)
                for kb, _ in keys:
                    values[obj.name, kb.name].append(evaluated.key_blocks[kb.name].value)
    finally:
        scene.frame_set(current[0], subframe=current[1])
    return values


def action_name(obj):
    """The name of obj's export action: its bake's slider (several bakes: their sliders)."""
    return " + ".join(sorted(playback.records(obj)))


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


def _write(obj, keys, frames, values):
    key = obj.data.shape_keys
    anim = key.animation_data
    created = anim.action is None
    if created:
        _new_action(anim, action_name(obj), obj.name)
    written = []
    for kb, driver in keys:
        fc = actions.new_fcurve(anim, kb.path_from_id("value"))
        points = fc.keyframe_points
        points.add(len(frames))
        co = [c for f, v in zip(frames, values[obj.name, kb.name]) for c in (f, v)]
        points.foreach_set("co", co)
        points.foreach_set("interpolation", [LINEAR] * len(frames))
        fc.update()
        driver.mute = True
        written.append(kb.name)
    obj[EXPORT_PROP] = {"keys": written, "action": anim.action.name if created else "",
                        "frames": [frames[0], frames[-1]]}
    return len(written)


def bake(objs, frame_start=None, frame_end=None):
    """Write what the sliders show at every frame of the range (default: the scene's) as linear
    F-curves on the baked keys' values of each object, muting their drivers; an earlier export
    bake is replaced. Returns a message. Everything is checked and sampled before anything is
    written."""
    import bpy
    objs = _objects(objs)
    scene = bpy.context.scene
    a, b = _frame_range(scene, frame_start, frame_end)
    plans = [(obj, driven_keys(obj)) for obj in objs]
    for obj, _ in plans:  # sample what the slider shows, not an earlier export bake
        remove(obj)
    frames = list(range(a, b + 1))
    values = _sample(scene, plans, frames)
    count = sum(_write(obj, keys, frames, values) for obj, keys in plans)
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
