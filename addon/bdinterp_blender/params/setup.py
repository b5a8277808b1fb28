"""Setting up pose grids: pose_grid() validates everything, makes missing nodes only when asked
(fill), and writes the group's properties; drive_by_bone() binds a parameter to a bone's angle."""

import math

from ..shapes import mesh_io, solve
from ..shapes.mesh_io import BakeError
from ..names import POSE_KEY
from ..shapes.settings import BakeSettings
from . import live


def _objects(objs):
    objs = list(objs) if isinstance(objs, (list, tuple)) else [objs]
    if not objs or len(set(objs)) != len(objs):
        raise BakeError("pose_grid needs one or more distinct mesh objects")
    for obj in objs:
        mesh_io.key_of(obj)
        if not hasattr(obj, "bdi_grids"):
            raise BakeError("pose grids need the bdinterp add-on enabled (Preferences > Add-ons)")
        if obj.bdi.live:  # its live key and the pose key would both add their offsets
            raise BakeError("%s is in live mode: switch that off first" % obj.name)
    return objs


def _parameter(pg, name, spec):
    """A bdinterp Parameter of a pose_grid() parameter: a list of values, or a dict with values,
    wrap and period."""
    if isinstance(spec, dict):
        unknown = set(spec) - {"values", "wrap", "period"}
        if unknown or "values" not in spec:
            raise BakeError("parameter %r: give values (and wrap, period), not %s"
                            % (name, sorted(unknown) or "no values"))
        return pg.Parameter(name, spec["values"], wrap=spec.get("wrap", False),
                            period=spec.get("period"))
    return pg.Parameter(name, spec)


def _grid(params, keys, name, rest):
    pg = solve.core().pose_grid
    if not name or not isinstance(name, str):
        raise BakeError("a pose grid needs a name, got %r" % (name,))
    try:
        return pg.PoseGrid([_parameter(pg, n, s) for n, s in params.items()], keys, name=name,
                           rest=rest)
    except ValueError as exc:
        raise BakeError(str(exc)) from exc


def _check_keys(obj, grid):
    """The nodes obj lacks ([] if none); BakeError for a node naming a key obj has not."""
    blocks = obj.data.shape_keys.key_blocks
    for index, key in sorted(grid.nodes.items()):
        if blocks.get(key) is None:
            raise BakeError("%s: node %s of grid %r names the shape key %r, which %s has not"
                            % (obj.name, grid.describe(index), grid.name, key, obj.name))
    return grid.missing()


def _made_shapes(obj, grid, gaps):
    """{node index: (key name, (n, 3) pose)} of the missing nodes, each the core's blend of its
    row and column neighbours (grid.fill_weights)."""
    plans = {i: grid.fill_weights(i) for i in gaps}  # ValueError names a node it cannot make
    rest = obj.data.shape_keys.reference_key.name
    names = list(dict.fromkeys(k for w in plans.values() for k in w if k != rest))
    inp = solve.Inputs(obj, BakeSettings(), names or [grid.keys()[0]])
    solver = inp.interpolator()
    out = {}
    for index, weights in plans.items():
        vector = [weights.get(n, 0.0) for n in inp.names]
        out[index] = ("%s%s" % (grid.name, grid.describe(index)),
                      solve.blend_shape(inp, vector, solver))
    return out


def _write_group(obj, grid, made, others):
    group = obj.bdi_grids.add()
    group.name = grid.name
    for p, home in zip(grid.params, grid.rest_values()):
        item = group.params.add()
        item.name, item.values, item.wrap = p.name, ",".join(repr(float(x)) for x in p.values), p.wrap
        item.period, item.amount = (p.period if p.wrap else 360.0), home
    nodes = dict(grid.nodes)
    nodes.update({i: name for i, (name, _) in made.items()})
    for index, key in sorted(nodes.items()):
        node = group.nodes.add()
        node.index, node.key = ",".join(str(i) for i in index), key
    group.made = "; ".join("%s -> %r" % (grid.describe(i), name) for i, (name, _) in made.items())
    for other in others:
        group.members.add().obj = other
    return group


def pose_grid(objs, params, keys, name="grid", fill=False):
    """Set up pose parameters on a mesh (or several, the first holding the parameters).

    params: {parameter name: values} in increasing order, or {name: {"values": [...], "wrap": True,
    "period": 360}} for an angle on a circle (1 to 3 parameters, a grid); keys: {node: shape key
    name}, a node being a tuple of values (a number for one parameter), e.g. {(0, 0): "Basis"}.
    Every object needs every key; a node without a key is refused (BakeError naming it) unless
    fill=True, which makes it from its row and column neighbours as a new key per object (listed in
    the group's `made`, and printed). Several grids on one object act together (their differences
    from the reference key added in the blended metric). The shape follows live in the key
    'bdi.pose'. Returns {parameter name: data path of its value on the first object}."""
    objs = _objects(objs)
    grid = _grid(params, keys, name, objs[0].data.shape_keys.reference_key.name)
    owner = objs[0]
    if owner.bdi_grids.get(name) is not None:
        raise BakeError("%s already has a pose grid %r; remove it first" % (owner.name, name))
    made = {}
    for obj in objs:
        gaps = _check_keys(obj, grid)
        if gaps and not fill:
            raise BakeError("%s: grid %r: node %s has no shape key (give one, or fill=True to make "
                            "it from its neighbours)" % (obj.name, name, grid.describe(gaps[0])))
        try:
            made[obj.name] = _made_shapes(obj, grid, gaps) if gaps else {}
        except ValueError as exc:
            raise BakeError("%s: %s" % (obj.name, exc)) from exc
    # --- validated; from here on the file is modified (and restored if the blend fails) ---
    return _commit(objs, grid, made)


def _commit(objs, grid, made):
    written = []
    for obj in objs:
        for name, co in made[obj.name].values():
            written.append((obj, name))
            kb = obj.shape_key_add(name=name, from_mix=False)
            kb.value = 0.0
            mesh_io.write_co(kb, co)
            print("bdinterp: pose grid %r: made %s" % (grid.name, name))
    owner = objs[0]
    live.remove(owner)  # a State cached under this name may be another object's of the same name
    with live.suspended():
        _write_group(owner, grid, made[owner.name], objs[1:])
    state = live.state_of(owner)
    if state.error:
        remove_pose_grid(owner, grid.name)
        for obj, name in written:
            obj.shape_key_remove(obj.data.shape_keys.key_blocks[name])
        raise BakeError(state.error)
    live.update(owner, force=True)
    return {p.name: 'bdi_grids["%s"].params["%s"].amount' % (grid.name, p.name) for p in grid.params}


def remove_pose_grid(obj, name):
    """Remove obj's pose grid `name` (its parameters' animation stays with the object; the keys it
    made stay); the pose key goes with the last grid."""
    index = obj.bdi_grids.find(name)
    if index < 0:
        raise BakeError("%s has no pose grid %r" % (obj.name, name))
    before = list(live.members(obj))
    obj.bdi_grids.remove(index)
    live.remove(obj)
    after = live.members(obj) if len(obj.bdi_grids) else {}
    for other in before:
        kb = other.data.shape_keys.key_blocks.get(POSE_KEY) if other.data.shape_keys else None
        if other not in after and kb is not None:
            other.shape_key_remove(kb)
    if after:
        live.update(obj, force=True)


def pose_grid_report(obj):
    """{object name: how the shown blend relates to the guarantee}: "convex blend: K <= ..." or
    "extrapolated blend: worst K ..., n flipped faces" (groups combined), or the grid's error."""
    if not len(getattr(obj, "bdi_grids", ())):
        raise BakeError("%s has no pose grid" % getattr(obj, "name", obj))
    live.update(obj)
    return live.reports(obj)


def drive_by_bone(obj, grid, param, armature, bone, axis="Z", angles=(-45.0, 45.0)):
    """Drive a parameter by a bone's local rotation about `axis`: angles (degrees) (a0, a1) map
    linearly to the parameter's first and last values (beyond them the grid clamps, or wraps).
    Returns the driver's F-curve."""
    group = obj.bdi_grids.get(grid)
    item = group.params.get(param) if group is not None else None
    if item is None:
        raise BakeError("%s has no pose grid parameter %r in %r" % (obj.name, param, grid))
    if armature is None or armature.type != 'ARMATURE' or armature.data.bones.get(bone) is None:
        raise BakeError("no bone %r in %s" % (bone, getattr(armature, "name", None)))
    if axis not in ("X", "Y", "Z") or angles[0] == angles[1]:
        raise BakeError("axis must be X, Y or Z and the two angles differ, got %r, %r"
                        % (axis, angles))
    values = [float(x) for x in item.values.split(",")]
    lo, hi = values[0], values[-1] if not item.wrap else values[0] + item.period
    a0, a1 = (math.radians(a) for a in angles)
    fcurve = item.driver_add("amount")
    drv = fcurve.driver
    drv.type = 'SCRIPTED'
    var = drv.variables.new()
    var.name, var.type = "angle", 'TRANSFORMS'
    t = var.targets[0]
    t.id, t.bone_target = armature, bone
    t.transform_type, t.transform_space = "ROT_" + axis, 'LOCAL_SPACE'
    drv.expression = "(%r) + (angle - (%r)) * (%r)" % (lo, a0, (hi - lo) / (a1 - a0))
    return fcurve
