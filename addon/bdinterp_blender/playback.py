"""Native-driver playback of a bake, so a baked .blend plays without the add-on.

One custom property on the object (the slider, 0..1) drives every baked key of a
source -> target pair with piecewise-linear 'tent' weights (see timing.tent_expressions).
"""

from . import timing


def slider_name(key, source, target):
    """'<target>.bdi' for the usual source = reference key, else '<source>><target>.bdi'."""
    if source == key.reference_key.name:
        return target + ".bdi"
    return "%s>%s.bdi" % (source, target)


def _prop_path(prop):
    return '["%s"]' % prop.replace("\\", "\\\\").replace('"', '\\"')


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


def _driven_by(kb, obj, prop):
    """True if kb.value has a driver reading our slider (so it is ours to remove)."""
    anim = kb.id_data.animation_data
    if anim is None:
        return False
    fc = anim.drivers.find(kb.path_from_id("value"))
    return fc is not None and any(t.id == obj and t.data_path == _prop_path(prop)
                                  for v in fc.driver.variables for t in v.targets)


def install(obj, source, target, names, positions, end=None):
    """Drive keys `names` (at slider `positions`) and the target (or `end`); return the slider."""
    key = obj.data.shape_keys
    prop = slider_name(key, source, target)
    if prop not in obj.keys():
        obj[prop] = 0.0
    obj.id_properties_ui(prop).update(
        min=0.0, max=1.0, soft_min=0.0, soft_max=1.0,
        description="bdinterp playback %s -> %s (drives the baked in-between keys)" % (source, target))
    exprs, last = timing.tent_expressions(positions)
    for name, expr in zip(names, exprs):
        _drive(key.key_blocks[name], obj, prop, expr)
    _drive(key.key_blocks[end or target], obj, prop, last)
    return prop


def remove(obj, source, target, keep_slider=True):
    """Remove the bake of source -> target (keys, drivers; the slider unless keep_slider).

    Returns the names of the removed keys.
    """
    key = obj.data.shape_keys
    if key is None:
        return []
    prop = slider_name(key, source, target)
    tgt = key.key_blocks.get(target)
    if tgt is not None and _driven_by(tgt, obj, prop):
        tgt.driver_remove("value")
        tgt.value = 0.0
    removed = []
    for kb in baked_keys(key, source, target):
        kb.driver_remove("value")
        removed.append(kb.name)
        obj.shape_key_remove(kb)
    if not keep_slider and prop in obj.keys():
        del obj[prop]
    return removed
