"""The ghosts and trails the overlay draws (onion.py), computed from a motion_trails.Path: in
the coordinates the Path solves in (the drawn object's; world coordinates for a character).
Reads bpy data, writes nothing."""

from dataclasses import dataclass, field

import bpy

from . import motion_trails
from ..shapes import mesh_io
from ..names import SEP


def _array(shape, dtype):
    import numpy as np  # heavy: imported when used
    return np.empty(shape, dtype=dtype)


@dataclass(eq=False)  # compared by identity: the overlay's cache holds one
class Ghosts:
    """Everything the overlay draws, in the coordinates the Path solves in (`matrix`: the drawn
    object's world matrix for one object, read when drawn; None for a character, solved in world
    coordinates): shapes (j, n, 3) at factors (j,), faces (m, 3), outline edges (e, 2), trails
    (s, k, 3), ticks (b, k, 3), chords (2, k, 3); the slider (owner object name, property) whose
    value is the current factor; an error message; the motion_trails.Path solved.  Ghosts of
    frames have `offsets` (j,) in frames from the current one and `span` (their tint fades over
    it)."""
    shapes: object = field(default_factory=lambda: _array((0, 0, 3), float))
    factors: list = field(default_factory=list)
    trails: object = field(default_factory=lambda: _array((0, 0, 3), float))
    ticks: object = field(default_factory=lambda: _array((0, 0, 3), float))
    chords: object = field(default_factory=lambda: _array((0, 0, 3), float))
    faces: object = field(default_factory=lambda: _array((0, 3), int))
    edges: object = field(default_factory=lambda: _array((0, 2), int))
    slider: object = None
    error: str = ""
    path: object = None
    offsets: object = None
    span: float = 1.0

    def in_world(self, points):
        """points (..., 3) of these Ghosts in world coordinates, as drawn now."""
        return self.path.world(points) if self.path is not None else points

    def matrix(self):
        """The model matrix the ghosts are drawn with (None: identity)."""
        return self.path.objs[0].matrix_world if self.path is not None and self.path.local else None


def _factor_of(name):
    """0.5 of 'Arm.bdi.050' (the factor is in the key's name), None if it is not in it."""
    try:
        return float(name.rsplit(SEP, 1)[1]) / 100.0
    except (IndexError, ValueError):
        return None


def outline(faces):
    """(e, 2) the edges of `faces` that bound only one triangle: each piece's outline."""
    import numpy as np
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique[counts == 1]


def selected_vertices(objs):
    """Indices (across the objects, one after the other) of their selected vertices."""
    import numpy as np
    out, offset = [], 0
    for obj in objs:
        sel = np.zeros(len(obj.data.vertices), dtype=bool)
        obj.data.vertices.foreach_get("select", sel)
        out.append(np.flatnonzero(sel) + offset)
        offset += len(sel)
    return np.concatenate(out)


def moving_faces(path):
    """The faces of path's mesh that the motion moves (a vertex of theirs is elsewhere in the
    target than in the source): the ghosts tint those only, not the pieces that stand still."""
    import numpy as np
    source, target = (np.asarray(s, dtype=np.float64) for s in path.inp.shapes[:2])
    size = max(np.ptp(source, axis=0).max(), 1e-12)
    moves = np.linalg.norm(target - source, axis=1) > 1e-6 * size
    faces = np.asarray(path.inp.faces)
    return faces[moves[faces].any(axis=1)]


def build(objs, view, frame=None, path=None):
    """The Ghosts of `objs` (drawn_objects) with the settings `view` (Scene.bdi_view) at the
    scene's `frame`; `path`: the motion_trails.Path of the same objects and settings, if one was
    made already (the frames it solved are not solved again)."""
    import numpy as np
    if path is None:
        path = motion_trails.Path(objs, with_solver=view.trails or view.ghost_source != 'BAKED')
    faces = moving_faces(path)
    out = Ghosts(faces=faces, edges=outline(faces) if len(faces) else np.empty((0, 2), int),
                 path=path)
    baked, names = path.baked_solved()
    if path.found is not None:
        out.slider = (path.found.record.get("owner") or objs[0].name, path.found.slider)
    if view.ghosts and view.ghost_source == 'BAKED':
        factors = [_factor_of(n) for n in names]
        if None in factors:  # names not made by a bake: evenly spaced
            factors = list(np.arange(1, len(names) + 1) / (len(names) + 1.0))
        out.shapes, out.factors = baked, factors
    elif view.ghosts and view.ghost_source == 'FRAMES':
        frame_ghosts(out, objs, view, frame)
    elif view.ghosts:
        ts = np.arange(view.step, 1.0 - 1e-9, view.step)
        out.shapes, out.factors = path.solved(ts), list(ts)
    if view.trails:
        trail_points(out, path, view, baked)
    return out


def frame_ghosts(out, objs, view, frame):
    """Set out's ghosts of the frames around `frame` (offsets, span, factors, shapes)."""
    import numpy as np
    step = view.frame_step
    out.offsets = [-k * step for k in range(view.frames_before, 0, -1)] + \
        [k * step for k in range(1, view.frames_after + 1)]
    out.span = (max(view.frames_before, view.frames_after) + 1) * step
    out.factors = [factor_at(objs, out.slider, frame + o) for o in out.offsets]
    out.shapes = out.path.solved(out.factors) if out.offsets else np.empty((0, out.path.size, 3))


def trail_points(out, path, view, baked):
    """Set out.trails, ticks and chords: the paths of the trail vertices of `view`."""
    import numpy as np
    v = None
    if view.trail_vertices == 'SELECTED':
        v = selected_vertices(path.objs)
        if not len(v):
            raise mesh_io.BakeError("no vertex selected: select some in Edit Mode")
    v = path.vertices(v)
    out.trails = path.solved(np.linspace(0.0, 1.0, view.samples))[:, v]
    out.ticks = baked[:, v]
    out.chords = out.trails[[0, -1]]


def factor_at(objs, slider, frame=None):
    """The factor shown at `frame` (None: now): live mode's factor, else the slider's (owner
    object name, property) or 0; at another frame as its F-curve has it (a constant without)."""
    from ..actions import find_fcurve
    props = objs[0].bdi
    if props.live and props.live_mode == 'INTERPOLATE':
        owner, data_path, value = objs[0], "bdi.live_factor", props.live_factor
    else:
        owner = bpy.data.objects.get(slider[0]) if slider is not None else None
        if owner is None:
            return 0.0
        data_path = '["%s"]' % bpy.utils.escape_identifier(slider[1])
        value = float(owner.get(slider[1], 0.0))
    curve = find_fcurve(owner.animation_data, data_path) if frame is not None else None
    return min(1.0, max(0.0, curve.evaluate(frame) if curve is not None else value))
