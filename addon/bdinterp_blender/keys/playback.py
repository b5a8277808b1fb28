"""Native-driver playback of a bake, so a baked .blend plays without the add-on.

One custom property on the object (the slider, 0..1) drives every baked key of a
source -> target pair with piecewise-linear 'tent' weights (see timing.tent_expressions).  Each
bake is recorded in the object's custom property names.BAKES_PROP (slider -> source, target,
keys, a signature of the target's data), so that it is found again after the target key is
renamed, and reported stale after the target is edited.
"""

import hashlib

from .. import actions, timing
from ..names import BAKES_PROP, SLIDER_SUFFIX


def slider_name(key, source, target):
    """'<target>.bdi' for the usual source = reference key, else '<source>><target>.bdi'."""
    if source == key.reference_key.name:
        return target + SLIDER_SUFFIX
    return "%s>%s%s" % (source, target, SLIDER_SUFFIX)


def _prop_path(prop):
    return '["%s"]' % prop.replace("\\", "\\\\").replace('"', '\\"')


def signature(kb):
    """Short hash of a key's coordinates (float32 as stored)."""
    from ..shapes.mesh_io import read_raw
    return hashlib.sha1(read_raw(kb).tobytes()).hexdigest()[:16]


def inputs_signature(obj, source, target):
    """Short hash of what a bake of obj read: the source's and the target's coordinates and the
    mesh's polygons (so that an edit of either key, or of the topology, makes the bake stale)."""
    import numpy as np
    from ..shapes.mesh_io import read_raw
    key, me = obj.data.shape_keys, obj.data
    loops = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", loops)
    starts = np.empty(len(me.polygons), np.int32)
    me.polygons.foreach_get("loop_start", starts)
    h = hashlib.sha1(np.int64(len(me.vertices)).tobytes() + loops.tobytes() + starts.tobytes())
    for name in (source, target):
        h.update(read_raw(key.key_blocks[name]).tobytes())
    return h.hexdigest()[:16]


def records(obj):
    """{slider: {'source', 'target', 'keys', 'end', 'signature'}} of obj's bakes (plain dicts)."""
    stored = obj.get(BAKES_PROP)
    return {} if stored is None else stored.to_dict()


class Found:
    """A bake of source -> target: slider, keys, end key, and 'renamed'/'stale'/'' status."""

    def __init__(self, slider, record, status):
        self.slider, self.record, self.status = slider, record, status
        self.keys = list(record.get("keys", ()))
        self.end = record.get("end") or None


def find(obj, source, target):
    """The recorded bake of source -> target, or None.  Matched by names first; else a bake whose
    target key no longer exists but whose signature equals `target`'s data (it was renamed)."""
    key = obj.data.shape_keys
    tgt = key.key_blocks.get(target) if key else None
    if tgt is None:
        return None
    recs = records(obj)
    for slider, rec in recs.items():
        if rec.get("source") == source and rec.get("target") == target:
            return Found(slider, rec, "" if _current(obj, rec, tgt) else "stale")
    sig = None
    for slider, rec in recs.items():
        if rec.get("source") == source and rec.get("target") not in key.key_blocks:
            sig = sig or signature(tgt)
            if rec.get("signature") == sig:
                return Found(slider, rec, "renamed")
    return None


def _current(obj, rec, tgt):
    """True if a bake's record matches obj's keys (the inputs' hash: bakes since it was kept)."""
    if rec.get("signature") != signature(tgt):
        return False
    src = obj.data.shape_keys.key_blocks.get(rec.get("source", ""))
    return (not rec.get("inputs") or src is not None
            and rec["inputs"] == inputs_signature(obj, src.name, tgt.name))


def stale_members(obj, found):
    """The names of the objects baked together with obj (a character: its members, obj among them)
    whose bake is stale or gone (their keys edited, or the object or its bake removed)."""
    import bpy
    out = []
    for name in found.record.get("members") or [obj.name]:
        member = bpy.data.objects.get(name)
        key = member.data.shape_keys if member is not None and member.type == 'MESH' else None
        own = find(member, found.record["source"], found.record["target"]) if key else None
        if own is None or own.status == "stale":
            out.append(name)
    return out


def baked_keys(key, source, target):
    """Key blocks of an earlier bake of source -> target (matched by name and relative key)."""
    prefix = target + timing.SEP
    return [kb for kb in key.key_blocks
            if kb.name.startswith(prefix) and kb.relative_key.name == source and kb.name != source]


def _drive(kb, obj, prop, expr):
    kb.driver_remove("value")
    driver = kb.driver_add("value").driver
    driver.type = 'SCRIPTED'
    var = driver.variables.new()
    var.name = "s"
    var.type = 'SINGLE_PROP'
    var.targets[0].id_type = 'OBJECT'
    var.targets[0].id = obj
    var.targets[0].data_path = _prop_path(prop)
    driver.expression = expr


def _driver_of(kb):
    anim = kb.id_data.animation_data
    return anim.drivers.find(kb.path_from_id("value")) if anim else None


def _driven_by(kb, obj, prop):
    """True if kb.value has a driver reading our slider on obj (so it is ours to remove)."""
    fc = _driver_of(kb)
    return fc is not None and any(t.id == obj and t.data_path == _prop_path(prop)
                                  for v in fc.driver.variables for t in v.targets)


def own_animation(obj, kb, prop, owner=None):
    """Why the slider (on `owner`, default obj) must not take over kb's value ('' if it may):
    keyframes, a driver that is not ours (ours: from the slider on owner, or on the object that
    held it at the last bake), or a value set by hand."""
    owners = (owner or obj, _recorded_owner(obj, records(obj).get(prop)))
    ours = any(_driven_by(kb, o, prop) for o in owners)
    if actions.find_fcurve(kb.id_data.animation_data, kb.path_from_id("value")):
        return "key %r has keyframes of its own" % kb.name
    if _driver_of(kb) is not None and not ours:
        return "key %r has a driver of its own" % kb.name
    if kb.value != 0.0 and not ours:
        return "key %r has a value set by hand (%.3g)" % (kb.name, kb.value)
    return ""


def install(obj, source, target, names, positions, end=None, signature_="", slider=None,
            owner=None, inputs="", members=()):
    """Drive keys `names` (at slider `positions`) and the target (or `end`) from the custom
    property `slider` (default slider_name()) of `owner` (default obj: several objects baked as
    one character share the active object's slider); record the bake; return the slider's name."""
    key, owner = obj.data.shape_keys, owner or obj
    prop = slider or slider_name(key, source, target)
    if prop not in owner.keys():
        owner[prop] = 0.0
    owner.id_properties_ui(prop).update(
        min=0.0, max=1.0, soft_min=0.0, soft_max=1.0,
        description="bdinterp playback %s -> %s (drives the baked in-between keys)" % (source, target))
    exprs, last = timing.tent_expressions(positions)
    for name, expr in zip(names, exprs):
        _drive(key.key_blocks[name], owner, prop, expr)
    _drive(key.key_blocks[end or target], owner, prop, last)
    record(obj, prop, source, target, names, end, signature_, owner.name, inputs, members)
    if owner != obj and prop in obj.keys():  # obj's own slider of an earlier bake: now unused
        del obj[prop]
    return prop


def record(obj, slider, source, target, keys, end=None, signature_="", owner="", inputs="",
           members=()):
    """Keep a bake of obj: its slider (on `owner`), keys, the hashes of what it read, and the
    objects baked with it (a character's members)."""
    recs = records(obj)
    recs[slider] = {"source": source, "target": target, "keys": list(keys), "end": end or "",
                    "signature": signature_, "owner": owner or obj.name, "inputs": inputs,
                    "members": list(members) or [obj.name]}
    obj[BAKES_PROP] = recs


def remove(obj, source, target, keep_slider=True, owner=None):
    """Remove the bake of source -> target (keys, drivers, record; the slider, on `owner`, default
    the one recorded, unless keep_slider), also when the target was renamed since.  Returns the
    names of the removed keys."""
    key = obj.data.shape_keys
    if key is None:
        return []
    found = find(obj, source, target)
    prop = found.slider if found else slider_name(key, source, target)
    owner = owner or _recorded_owner(obj, found.record if found else None)
    tgt = key.key_blocks.get(target)
    if tgt is not None and _driven_by(tgt, owner, prop):
        tgt.driver_remove("value")
        tgt.value = 0.0
    names = set(found.keys + ([found.end] if found.end else [])) if found else set()
    names |= {kb.name for kb in baked_keys(key, source, target)}
    removed = []
    for name in [kb.name for kb in key.key_blocks if kb.name in names]:
        kb = key.key_blocks[name]
        kb.driver_remove("value")
        removed.append(name)
        obj.shape_key_remove(kb)
    recs = records(obj)
    if recs.pop(prop, None) is not None:
        obj[BAKES_PROP] = recs
    if not keep_slider and owner == obj and prop in owner.keys():  # the owner's own clear only
        del owner[prop]
    return removed


def _recorded_owner(obj, record):
    """The object holding the slider of a bake's record (obj itself unless baked as a character)."""
    name = record.get("owner") if record else None
    if not name or name == obj.name:
        return obj
    import bpy
    return bpy.data.objects.get(name) or obj


# what Bake for Export (export.py) reads of a bake: the slider's data path, a key's driver, the
# object that holds the slider
prop_path, driver_of, recorded_owner = _prop_path, _driver_of, _recorded_owner
