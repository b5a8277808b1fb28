"""In-betweens of Grease Pencil drawings (Blender 4.3+, Grease Pencil v3) by bdinterp.strokes.

Between two keyframes of a layer, the strokes are paired by order (as Blender's own Interpolate
Sequence pairs them), each pair is interpolated as a thin band through the method, and every new
frame is a copy of the first key (so strokes keep their material and every stroke setting) whose
points are the in-between's: position, radius, opacity and vertex colour.  Everything is computed
for every layer before the first frame is written, so an error changes nothing.
"""

import bpy

from ..core import load_core
from ..view.drawing_bind import read, write
from ..shapes.mesh_io import BakeError
from ..timing import EASINGS

# point attributes blended linearly (name, data type, width); position is the band's
BLENDED = (("radius", 'FLOAT', 1), ("opacity", 'FLOAT', 1), ("vertex_color", 'FLOAT_COLOR', 4))


def why_not(gp_obj=None):
    """'' if gp_obj's drawings can be interpolated (None: if this Blender can at all), else why."""
    if bpy.app.version < (4, 3, 0):
        return "interpolating drawings needs Blender 4.3 or later (Grease Pencil v3)"
    if gp_obj is not None and gp_obj.type != 'GREASEPENCIL':
        return "%s is not a Grease Pencil object" % gp_obj.name
    return ""


def key_frames(layer):
    """The frame numbers of the layer's frames, sorted."""
    return sorted(f.frame_number for f in layer.frames)


def keys_around(layer, frame):
    """(previous, next) frame numbers of the layer around `frame` (previous <= frame < next);
    BakeError when either is missing."""
    numbers = key_frames(layer)
    before = [f for f in numbers if f <= frame]
    after = [f for f in numbers if f > frame]
    if not before or not after:
        raise BakeError("layer %r has no keyframe %s frame %d" % (
            layer.name, "at or before" if not before else "after", frame))
    return before[-1], after[0]


def frame_at(layer, number):
    for f in layer.frames:
        if f.frame_number == number:
            return f
    return None


def _color(drawing, n):
    import numpy as np
    attr = drawing.attributes.get("vertex_color")
    if attr is None:
        return np.zeros((n, 4))
    arr = np.empty(n * 4, dtype=np.float32)
    attr.data.foreach_get("color", arr)
    return arr.reshape(n, 4).astype(np.float64)


def read_strokes(drawing, selected=False):
    """(stroke indices, bdinterp Strokes) of a drawing: positions (layer space), radius, opacity and
    vertex colour per point, and whether it is cyclic; selected: only the selected strokes."""
    import numpy as np
    Stroke = load_core().strokes.Stroke
    offsets = np.empty(len(drawing.curve_offsets), dtype=np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    n = int(offsets[-1]) if len(offsets) else 0
    pos = read(drawing, "position", 3).astype(np.float64) if n else np.empty((0, 3))
    values = {"radius": read(drawing, "radius", 1) if drawing.attributes.get("radius") else np.full(n, 0.01),
              "opacity": read(drawing, "opacity", 1) if drawing.attributes.get("opacity") else np.ones(n),
              "vertex_color": _color(drawing, n)}
    flags = [(s.select, s.cyclic) for s in drawing.strokes]
    which = [k for k, (select, _) in enumerate(flags) if select or not selected]
    strokes = []
    for k in which:
        a, b = offsets[k], offsets[k + 1]
        strokes.append(Stroke(pos[a:b], cyclic=flags[k][1],
                              **{name: np.asarray(v[a:b], dtype=np.float64) for name, v in values.items()}))
    return which, strokes


def schedule(frame_a, frame_b, count=3, step=None, easing="LINEAR"):
    """[(frame number, factor t)] of the in-betweens: `count` frames spread evenly (rounded to
    whole frames) or every `step` frames, t = easing of the frame's place between the keys."""
    if frame_b - frame_a < 2:
        raise BakeError("frames %d and %d have no frame between them" % (frame_a, frame_b))
    ease = easing if callable(easing) else EASINGS.get(easing)
    if ease is None:
        raise BakeError("unknown easing %r (use one of %s)" % (easing, ", ".join(EASINGS)))
    span = frame_b - frame_a
    if step is not None:
        if int(step) != step or step < 1:
            raise BakeError("the frame step must be a whole number >= 1, got %r" % (step,))
        numbers = list(range(frame_a + int(step), frame_b, int(step)))
    else:
        if int(count) != count or count < 1:
            raise BakeError("the number of in-betweens must be a whole number >= 1, got %r" % (count,))
        if count > span - 1:
            raise BakeError("%d in-betweens do not fit between frames %d and %d (%d frames)" % (
                count, frame_a, frame_b, span - 1))
        numbers = sorted({frame_a + round(span * j / (count + 1.0)) for j in range(1, int(count) + 1)})
    return [(f, float(ease((f - frame_a) / span))) for f in numbers]


def plane_of(strokes):
    """The strokes' plane: fitted through their points, the layer's XZ plane (where Blender draws
    by default) when they lie on one line."""
    import numpy as np
    bd = load_core()
    pts = np.concatenate([s.points for s in strokes])
    sv = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    if sv[1] > 1e-9 * sv[0]:
        return bd.Plane.fit(pts)
    return bd.Plane(pts.mean(axis=0), np.array([[1.0, 0, 0], [0, 0, 1.0]]), np.array([0.0, -1.0, 0.0]))


def plan_layer(gp_obj, layer, frame_a, frame_b, timing, selected=False, fade=False):
    """Everything one layer gets, computed without writing: (layer, [(frame, strokes)], the
    indices of key a's strokes the in-betweens keep, [(material index, cyclic)] of key b's strokes
    left over, which fade in), None when only selected strokes are asked for and the layer has
    none.  BakeError naming the object, the layer and the frames."""
    where = "%s, layer %r" % (gp_obj.name, layer.name)
    fa, fb = frame_at(layer, frame_a), frame_at(layer, frame_b)
    if fa is None or fb is None:
        raise BakeError("%s has no keyframe at frame %d" % (where, frame_a if fa is None else frame_b))
    inside = [n for n in key_frames(layer) if frame_a < n < frame_b]
    if inside:
        raise BakeError("%s already has frames %s between frames %d and %d: delete them to make new "
                        "in-betweens" % (where, inside, frame_a, frame_b))
    which, a = read_strokes(fa.drawing, selected)
    which_b, b = read_strokes(fb.drawing, selected)
    if selected and not a and not b:
        return None   # nothing selected on this layer: it gets no in-betweens
    bd = load_core()
    try:
        si = bd.strokes.StrokeInterpolator(a, b, plane=plane_of(a + b) if a and b else None, where=where,
                                           keys=("frame %d" % frame_a, "frame %d" % frame_b),
                                           unpaired="fade" if fade else "error")
        frames = si.frames([t for _, t in timing])
    except (ValueError, RuntimeError) as exc:
        raise BakeError(str(exc)) from None
    added = [(fb.drawing.strokes[k].material_index, fb.drawing.strokes[k].cyclic) for k in which_b[len(a):]]
    return layer, [(number, strokes) for (number, _), strokes in zip(timing, frames)], which, added


def write_frame(layer, frame_a, number, strokes, which, added=()):
    """A new breakdown frame `number` of the layer: a copy of key frame_a reduced to the strokes
    `which`, and strokes (material index, cyclic) `added` after them, with the in-between's
    points."""
    import numpy as np
    frame = layer.frames.copy(frame_a, number)
    frame.keyframe_type = 'BREAKDOWN'
    d = frame.drawing
    drop = [k for k in range(len(d.strokes)) if k not in set(which)]
    if drop:
        d.remove_strokes(indices=drop)
    if added:
        d.add_strokes([len(s.points) for s in strokes[len(which):]])
        for stroke, (material, cyclic) in zip(list(d.strokes)[len(which):], added):
            stroke.material_index, stroke.cyclic = material, cyclic
    d.resize_strokes([len(s.points) for s in strokes])
    write(d, "position", 'FLOAT_VECTOR', np.concatenate([s.points for s in strokes]))
    for name, kind, width in BLENDED:
        values = np.concatenate([s.attributes[name] for s in strokes])
        if name == "vertex_color":
            if d.attributes.get(name) is None and not values.any():
                continue   # neither key is tinted: the frame stays without the attribute
            attr = d.attributes.get(name) or d.attributes.new(name, kind, 'POINT')
            attr.data.foreach_set("color", np.ascontiguousarray(values, dtype=np.float32).ravel())
        else:
            write(d, name, kind, values)
    d.tag_positions_changed()


def interpolate_drawing(gp_obj, frame_a, frame_b, count=3, layers=None, easing="LINEAR", step=None,
                        selected=False, fade=False):
    """Bounded-distortion in-betweens of gp_obj's drawings between keyframes frame_a and frame_b,
    as new breakdown frames: `count` of them spread evenly (or one every `step` frames), at the
    factors `easing` gives (a name of timing.EASINGS or a callable).  layers: names (or layers)
    to interpolate; None: every layer with keyframes at both frames.  selected: only the selected
    strokes (a layer with none selected in either key gets no in-betweens).  fade: strokes left
    over when a layer's keys have other stroke counts fade out (the first key's) or in (the
    second key's) where they are drawn, instead of being refused.  Returns the new frame
    numbers.  BakeError (nothing changed) when the strokes cannot be paired or interpolated, or a
    layer has frames between the keys."""
    reason = why_not(None) or ("no Grease Pencil object given" if gp_obj is None else why_not(gp_obj))
    if reason:
        raise BakeError(reason)
    frame_a, frame_b = int(frame_a), int(frame_b)
    if frame_b < frame_a:
        frame_a, frame_b = frame_b, frame_a
    timing = schedule(frame_a, frame_b, count, step, easing)
    if layers is None:
        chosen = [la for la in gp_obj.data.layers
                  if frame_at(la, frame_a) is not None and frame_at(la, frame_b) is not None]
        if not chosen:
            raise BakeError("%s: no layer has keyframes at both frames %d and %d" % (gp_obj.name, frame_a, frame_b))
    else:
        names = [getattr(la, "name", la) for la in layers]
        missing = [n for n in names if n not in gp_obj.data.layers]
        if missing:
            raise BakeError("%s has no layer %s" % (gp_obj.name, ", ".join(repr(n) for n in missing)))
        chosen = [gp_obj.data.layers[n] for n in names]
    plans = [p for p in (plan_layer(gp_obj, la, frame_a, frame_b, timing, selected, fade) for la in chosen) if p]
    if not plans:
        raise BakeError("%s: no stroke is selected on %s" % (gp_obj.name, ", ".join(repr(la.name) for la in chosen)))
    for layer, frames, which, added in plans:
        for number, strokes in frames:
            write_frame(layer, frame_a, number, strokes, which, added)
    gp_obj.data.update_tag()
    return [number for number, _ in timing]
