"""The joint tree a bake will use, drawn in the 3D viewport (Scene.bdi_view_joints, off by default).

For the active object or the character it bakes with (onion.drawn_objects), the solver of the
bake's settings (motion_trails.Path: the same Inputs, joints and hand-set parents as a bake) is
asked for its joints and roots; nothing here finds joints again. The plan, in world space: a dot
at every joint's point, a line from the parent piece's centre to the point and on to the child's
centre, a ring of dots around every root's centre. It is made when the request changes (the
objects, their settings and parents, the keys' epoch) and drawn as it is on every redraw.
"""

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty

from . import motion_trails, onion

RING = 8  # dots around a root's centre

_cache = {"key": None, "plan": None, "batches": None, "error": ""}
_handle = []


@persistent
def refresh(*_args):
    """Something the tree depends on changed: make the plan again at the next redraw."""
    _cache.update(key=None, plan=None, batches=None, error="")
    for window in getattr(bpy.context.window_manager, "windows", ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _centres(X, labels):
    """{piece: the mean of its vertices} of (n, 3) points X."""
    import numpy as np
    return {int(p): X[labels == p].mean(axis=0) for p in np.unique(labels)}


def joint_plan(path):
    """{'dots': (j, 3), 'lines': (4 j, 3) segment ends, 'roots': (r, 3) root centres, 'ring': the
    root marks' dots, 'parents': {child piece: parent piece}} in world space, of the joints and
    roots of path.solver (a motion_trails.Path) in the base (source) shape."""
    import numpy as np
    inp, solver = path.inp, path.solver
    labels = np.asarray(inp.layers.labels)
    world = _to_world(path)
    centre = _centres(world(inp.shapes[0]), labels)
    joints = solver.joints() if solver is not None else []
    roots = solver.joint_roots() if solver is not None else []
    dots = world(np.array([j["point"] for j in joints]).reshape(-1, 3))
    lines = []
    for j, dot in zip(joints, dots):
        lines += [centre[labels[j["parent"]]], dot, dot, centre[labels[j["child"]]]]
    root_at = np.array([centre[labels[r["piece"]]] for r in roots]).reshape(-1, 3)
    size = float(np.linalg.norm(np.ptp(world(inp.shapes[0]), axis=0)))
    a = np.linspace(0, 2 * np.pi, RING, endpoint=False)
    ring = (root_at[:, None, :] + 0.02 * size * np.c_[np.cos(a), np.sin(a), 0 * a][None]).reshape(-1, 3)
    return {"dots": dots, "lines": np.array(lines).reshape(-1, 3), "roots": root_at, "ring": ring,
            "parents": {int(labels[j["child"]]): int(labels[j["parent"]]) for j in joints}}


def _to_world(path):
    """points (k, 3) of the path's solved coordinates -> world (one object: its local ones)."""
    import numpy as np
    if not path.local:
        return lambda X: np.asarray(X, dtype=np.float64)
    m = np.array(path.objs[0].matrix_world, dtype=np.float64)
    return lambda X: np.asarray(X, dtype=np.float64) @ m[:3, :3].T + m[:3, 3]


def request_key(objs):
    """What the plan depends on: onion.solve_key (objects, settings, parents set by hand, epoch,
    a character's transforms) and the drawn object's transform."""
    return onion.solve_key(objs), tuple(v for row in objs[0].matrix_world for v in row)


def current(context):
    """(the plan or None, an error message) for the context, made again if the request changed."""
    objs = onion.drawn_objects(context) if context.scene.bdi_view_joints else []
    if not objs:
        return None, ""
    key = request_key(objs)
    if _cache["key"] != key:
        _cache.update(key=key, plan=None, batches=None, error="")
        try:
            _cache["plan"] = joint_plan(motion_trails.Path(objs))
        except (ValueError, RuntimeError) as exc:  # shown in the panel, once computed
            _cache["error"] = str(exc)
    return _cache["plan"], _cache["error"]


def _batches(plan):
    import numpy as np
    from gpu_extras.batch import batch_for_shader
    from .overlay import shader
    f32 = lambda X: np.ascontiguousarray(X, dtype=np.float32)  # noqa: E731
    return [(batch_for_shader(shader(), kind, {"pos": f32(plan[name])}), colour, width)
            for name, kind, colour, width in (
                ("lines", 'LINES', (0.2, 0.9, 1.0, 0.9), 2.0),
                ("dots", 'POINTS', (1.0, 1.0, 1.0, 1.0), 8.0),
                ("ring", 'POINTS', (1.0, 0.3, 0.3, 1.0), 6.0)) if len(plan[name])]


def draw_callback():
    """A redraw: the plan's batches over the scene; an error is kept for the panel, never raised."""
    import gpu
    from .overlay import shader
    try:
        plan, _ = current(bpy.context)
        if plan is None:
            return
        if _cache["batches"] is None:
            _cache["batches"] = _batches(plan)
    except Exception as exc:  # noqa: BLE001 -- said in the panel, not on every redraw
        _cache["error"] = "%s: %s" % (type(exc).__name__, exc)
        return
    sh = shader()
    gpu.state.blend_set('ALPHA')
    gpu.state.depth_test_set('NONE')
    sh.bind()
    for batch, colour, width in _cache["batches"]:
        gpu.state.line_width_set(width)
        gpu.state.point_size_set(width)
        sh.uniform_float("color", colour)
        batch.draw(sh)
    gpu.state.point_size_set(1.0)
    gpu.state.line_width_set(1.0)
    gpu.state.blend_set('NONE')


def draw_settings(layout, context):
    """The toggle and, for the active object, its joint parent; returns the overlay's error."""
    obj = context.object
    if obj is not None and hasattr(obj, "bdi"):  # empty: Automatic (the tooltip says so)
        layout.prop(obj.bdi, "joint_parent", text="Joint Parent")
    layout.prop(context.scene, "bdi_view_joints", toggle=True, icon='BONE_DATA')
    return _cache["error"] if context.scene.bdi_view_joints else ""


def on_changes(_scene, _depsgraph, changed):
    """Keys edited by someone else than the add-on: the tree may have changed."""
    if _cache["key"] is not None and changed.edited_keys():
        refresh()


HANDLERS = ((bpy.app.handlers.undo_post, refresh), (bpy.app.handlers.redo_post, refresh),
            (bpy.app.handlers.load_post, refresh))


def register():
    bpy.types.Scene.bdi_view_joints = BoolProperty(
        name="Joint Tree", default=False, update=lambda _self, _context: refresh(),
        description="Draw the joint tree a bake will use: joints as dots, parent links as lines, "
                    "roots ringed")
    onion.hook(_handle, draw_callback, HANDLERS, on_changes)


def unregister():
    onion.unhook(_handle, HANDLERS, on_changes)
    _cache.update(key=None, plan=None, batches=None, error="")
    del bpy.types.Scene.bdi_view_joints
