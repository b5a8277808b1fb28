"""Bake Grid: a pose grid's in-betweens on a finer grid, as shape keys that drivers blend
multilinearly from the grid's parameters, so that a linear runtime (Blender without the add-on, a
glTF player's morph targets) shows bdinterp's blend within the error reported.

Each fine node's key '<grid>.bake.<i>_<j>' (relative to the reference key) holds bdinterp's blend
at that node; its value is the product of one hat function per parameter (simple driver
expressions: no Python needed to play them). The live key 'bdi.pose' is muted and set to 0 so the
baked keys are what shows; live updates stop until it is unmuted."""

from ..shapes import mesh_io, solve
from ..shapes.mesh_io import BakeError
from ..names import GRID_BAKE_SEP, POSE_KEY
from . import live


def _hat(values, i, wrap, period, x):
    """A simple-expression hat of node i of `values` (1 at it, 0 at its neighbours) in x."""
    up = lambda a, b: "(%s - (%r)) / (%r)" % (x, a, b - a)  # noqa: E731 -- 0 at a, 1 at b
    down = lambda b, c: "((%r) - %s) / (%r)" % (c, x, c - b)  # noqa: E731 -- 1 at b, 0 at c
    v, last = values, len(values) - 1
    if wrap:
        nxt = v[i + 1] if i < last else v[0] + period
        if i == 0:  # reached from the last node across the wrap
            return "max(0, max(%s, %s))" % (down(v[0], nxt), up(v[last], v[0] + period))
        return "max(0, min(%s, %s))" % (up(v[i - 1], v[i]), down(v[i], nxt))
    if i == 0:
        return "min(1, max(0, %s))" % down(v[0], v[1])
    if i == last:
        return "min(1, max(0, %s))" % up(v[i - 1], v[i])
    return "max(0, min(%s, %s))" % (up(v[i - 1], v[i]), down(v[i], v[i + 1]))


def _reduced(name, param):
    """The expression of a wrapping parameter's value brought into [first, first + period)."""
    v0, p = param.values[0], param.period
    return "(fmod(fmod(%s - (%r), %r) + %r, %r) + (%r))" % (name, v0, p, p, p, v0)


def _drive(obj, kb, bake, index, paths):
    fcurve = kb.driver_add("value")
    drv = fcurve.driver
    drv.type = 'SCRIPTED'
    for v in list(drv.variables):
        drv.variables.remove(v)
    terms = []
    for a, (param, path) in enumerate(zip(bake.grid.params, paths)):
        var = drv.variables.new()
        var.name, var.type = "p%d" % a, 'SINGLE_PROP'
        var.targets[0].id, var.targets[0].data_path = obj, path
        x = _reduced(var.name, param) if param.wrap else var.name
        terms.append(_hat([float(x) for x in param.values], index[a], param.wrap, param.period, x))
    drv.expression = " * ".join(terms)
    return drv


def clear_bake(obj, name):
    """Remove the baked keys of grid `name` and their drivers; returns their names."""
    key = obj.data.shape_keys
    gone = [kb for kb in key.key_blocks if kb.name.startswith(name + GRID_BAKE_SEP)]
    names = [kb.name for kb in gone]
    for kb in gone:
        kb.driver_remove("value")
        obj.shape_key_remove(kb)
    return names


def bake_grid(obj, name, n=2, samples=2):
    """Bake the pose grid `name` of obj (its own object) with n fine nodes per cell side; returns
    (the keys written, the largest distance of the linear blend of the baked keys from bdinterp's
    blend relative to the size, checked at `samples` points per fine cell side)."""
    group = obj.bdi_grids.get(name) if hasattr(obj, "bdi_grids") else None
    if group is None:
        raise BakeError("%s has no pose grid %r" % (getattr(obj, "name", obj), name))
    state = live.state_of(obj)
    if state.error:
        raise BakeError(state.error)
    try:
        bake = solve.core().pose_bake.GridBake(state.members[0].blender, name, int(n))
    except ValueError as exc:
        raise BakeError(str(exc)) from exc
    error, _ = bake.error(samples)
    # --- computed; from here on the file is modified ---
    clear_bake(obj, name)
    key = obj.data.shape_keys
    rest = bake.blender.keys[0]
    paths = ['bdi_grids["%s"].params["%s"].amount' % (name, p.name) for p in group.params]
    written = []
    for index in sorted(bake.grid.nodes):
        kb_name = name + GRID_BAKE_SEP + "_".join(str(i) for i in index)
        kb = obj.shape_key_add(name=kb_name, from_mix=False)
        kb.relative_key = key.key_blocks[rest]
        mesh_io.write_co(kb, bake.shapes[index])
        _drive(obj, kb, bake, index, paths)
        written.append(kb_name)
    pose = key.key_blocks.get(POSE_KEY)
    if pose is not None:  # shown by no exporter either (FBX exports a muted key's value)
        pose.mute, pose.value = True, 0.0
    key.update_tag()
    return written, error
