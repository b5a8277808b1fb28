"""F-curves of an ID's action in every Blender the add-on supports (3.4 to 5.x).

Up to 4.3 an Action holds its F-curves itself (``action.fcurves``). 4.4 made actions slotted: the
F-curves that animate one ID live in the channelbag of the ID's slot (``anim.action_slot``); the
flat ``action.fcurves`` stayed as a proxy for the first slot in 4.4/4.5 and is gone in 5.0. So
everything that reads or writes an action's F-curves goes through here.
"""


def _anim_utils():
    """bpy_extras.anim_utils if it knows slotted actions (4.4+), else None."""
    try:
        from bpy_extras import anim_utils
    except ImportError:  # outside Blender (the structure tests parse this file only)
        return None
    return anim_utils if hasattr(anim_utils, "action_get_channelbag_for_slot") else None


def slotted():
    """True where an action has slots, one per ID it animates (Blender 4.4+)."""
    return _anim_utils() is not None


def action_fcurves(anim, create=False):
    """The F-curve collection that animates `anim`'s ID in its action (it has find/new/remove), or
    None where there is no action (or, unless `create`, no channelbag for the ID's slot yet).
    `anim` is an AnimData or None. create=True makes the action, slot and channelbag as needed."""
    if anim is None:
        return None
    if anim.action is None:
        if not create:
            return None
        import bpy
        anim.action = bpy.data.actions.new(anim.id_data.name + "Action")
    utils = _anim_utils()
    if utils is None:
        return anim.action.fcurves
    slot = anim.action_slot
    if slot is None:
        if not create:
            return None
        slot = _new_slot(anim)
    bag = utils.action_get_channelbag_for_slot(anim.action, slot)
    if bag is None and create:
        bag = _ensure_channelbag(utils, anim.action, slot)
    return bag.fcurves if bag is not None else None


def find_fcurve(anim, data_path, index=0):
    """The F-curve of `data_path` (array `index`) in `anim`'s action, or None."""
    curves = action_fcurves(anim)
    return curves.find(data_path, index=index) if curves is not None else None


def new_fcurve(anim, data_path):
    """A new F-curve for `data_path` in `anim`'s action (made if need be); an old one is replaced."""
    curves = action_fcurves(anim, create=True)
    old = curves.find(data_path)
    if old is not None:
        curves.remove(old)
    return curves.new(data_path)


def all_fcurves(anim):
    """The F-curves of `anim`'s action that animate its ID (a list; empty without an action)."""
    curves = action_fcurves(anim)
    return list(curves) if curves is not None else []


def _new_slot(anim):
    """A slot for anim's ID in its action, assigned (4.4+: an action may animate several IDs)."""
    slot = anim.action.slots.new(anim.id_data.id_type, anim.id_data.name)
    anim.action_slot = slot
    return slot


def _ensure_channelbag(utils, action, slot):
    """The channelbag of `slot`, made with its layer and strip where missing."""
    if hasattr(utils, "action_ensure_channelbag_for_slot"):  # 5.0+
        return utils.action_ensure_channelbag_for_slot(action, slot)
    layer = action.layers[0] if action.layers else action.layers.new("Layer")
    strip = layer.strips[0] if layer.strips else layer.strips.new(type='KEYFRAME')
    return strip.channelbags.new(slot)


# Keyframe attributes that make a curve's shape: (name, values per point); enums go as indices.
_POINT_ATTRS = (("co", 2), ("handle_left", 2), ("handle_right", 2), ("interpolation", 1),
                ("easing", 1), ("handle_left_type", 1), ("handle_right_type", 1), ("type", 1))


def points_of(fc):
    """{attribute: flat list} of every keyframe point of F-curve fc (see set_points)."""
    points, out = fc.keyframe_points, {}
    for name, size in _POINT_ATTRS:
        values = [0] * (len(points) * size)
        points.foreach_get(name, values)
        out[name] = values
    return out


def set_points(fc, snapshot):
    """Give F-curve fc (with no points) the keyframe points of points_of's snapshot {attribute:
    flat list}, "co" and any others of _POINT_ATTRS (those missing keep Blender's defaults)."""
    points = fc.keyframe_points
    points.add(len(snapshot["co"]) // 2)
    for name, values in snapshot.items():
        points.foreach_set(name, values)
    fc.update()
