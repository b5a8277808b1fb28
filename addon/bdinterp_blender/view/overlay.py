"""GPU drawing of onion.Ghosts with Blender's gpu module: the batches are made once per Ghosts, a
Plan colours them and places them (the drawn object's matrix) when something changed (a ghost's
tint follows its distance in factor, or in frames, from the shown shape), and a redraw only draws
the Plan."""

import gpu
from gpu_extras.batch import batch_for_shader

_shader = []


def shader():
    """The built-in uniform-colour shader (named '3D_UNIFORM_COLOR' before Blender 4.0)."""
    if not _shader:
        try:
            _shader.append(gpu.shader.from_builtin('UNIFORM_COLOR'))
        except (ValueError, TypeError):
            _shader.append(gpu.shader.from_builtin('3D_UNIFORM_COLOR'))
    return _shader[0]


def _segments(paths):
    """(s, k, 3) polylines -> (2 (s-1) k, 3) endpoints of their segments, for a LINES batch."""
    import numpy as np
    a, b = paths[:-1], paths[1:]
    return np.stack([a, b], axis=2).reshape(-1, 3)


def batches(ghosts):
    """{'fills': [...], 'outlines': [...], 'trails', 'ticks', 'chords'} GPU batches of `ghosts`."""
    import numpy as np
    sh = shader()
    faces = np.ascontiguousarray(ghosts.faces, dtype=np.int32)
    edges = np.ascontiguousarray(ghosts.edges, dtype=np.int32)
    out = {"fills": [], "outlines": [], "trails": None, "ticks": None, "chords": None}
    for shape in ghosts.shapes if len(faces) else ():  # nothing moves: no ghost to tint
        pos = np.ascontiguousarray(shape, dtype=np.float32)
        out["fills"].append(batch_for_shader(sh, 'TRIS', {"pos": pos}, indices=faces))
        out["outlines"].append(batch_for_shader(sh, 'LINES', {"pos": pos}, indices=edges))
    if ghosts.trails.size:
        out["trails"] = batch_for_shader(sh, 'LINES', {"pos": _segments(ghosts.trails).astype(np.float32)})
        out["chords"] = batch_for_shader(sh, 'LINES', {"pos": _segments(ghosts.chords).astype(np.float32)})
        if ghosts.ticks.size:
            out["ticks"] = batch_for_shader(sh, 'POINTS', {"pos": ghosts.ticks.reshape(-1, 3).astype(np.float32)})
    return out


def tint(view, at, now, span=1.0):
    """(r, g, b, strength) of a ghost at `at` (factor, or frame offset) when the shape shown is at
    `now`: the Before or After colour, stronger the nearer it is (fading over `span`)."""
    colour = view.before_color if at < now else view.after_color
    strength = view.opacity * max(0.15, 1.0 - abs(at - now) / span)
    return (colour[0], colour[1], colour[2], strength)


class Plan:
    """One redraw's work, decided when something changed: the ghosts' batches with their colours,
    then the trails' (chords, paths, ticks); draw() only binds, sets colours and draws."""

    def __init__(self, batch_set, ghosts, view, now, matrix=None):
        self.ghosts, self.lines, self.points = [], [], []
        self.matrix = matrix.copy() if matrix is not None else None
        times = ghosts.factors if ghosts.offsets is None else ghosts.offsets
        for fill, edges, at in zip(batch_set["fills"], batch_set["outlines"], times):
            r, g, b, a = tint(view, at, now, ghosts.span)
            self.ghosts += [(fill, (r, g, b, 0.18 * a)), (edges, (r, g, b, a))]
        trail = tuple(view.trail_color) + (1.0,)
        if batch_set["trails"] is not None:
            if view.chords:
                self.lines.append((batch_set["chords"], (0.75, 0.75, 0.75, 0.6)))
            self.lines.append((batch_set["trails"], trail))
        if batch_set["ticks"] is not None:
            self.points.append((batch_set["ticks"], trail))

    def __bool__(self):
        return bool(self.ghosts or self.lines)

    def draw(self):
        """Draw (POST_VIEW: world coordinates) over the scene, blended."""
        sh = shader()
        gpu.matrix.push()
        if self.matrix is not None:  # the ghosts are in the drawn object's coordinates
            gpu.matrix.multiply_matrix(self.matrix)
        gpu.state.blend_set('ALPHA')
        gpu.state.depth_test_set('NONE')
        sh.bind()
        _draw_each(sh, self.ghosts)
        gpu.state.line_width_set(2.0)
        _draw_each(sh, self.lines)
        gpu.state.point_size_set(7.0)
        _draw_each(sh, self.points)
        gpu.state.point_size_set(1.0)
        gpu.state.line_width_set(1.0)
        gpu.state.blend_set('NONE')
        gpu.matrix.pop()


def _draw_each(sh, items):
    """Draw each (batch, colour) of items with the bound shader sh."""
    for batch, colour in items:
        sh.uniform_float("color", colour)
        batch.draw(sh)
