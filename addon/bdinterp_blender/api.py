"""Scripting API of the add-on (also what the operators call).

Usable headless, e.g.::

    blender -b file.blend --python-expr "import bpy, bdinterp_blender as b; \\
        b.bake(bpy.data.objects['Arm'], source='Basis', target='Arm_up', count=8, easing='EASE_IN_OUT'); \\
        bpy.ops.wm.save_mainfile()"

Conventions: shape keys are named by string ('' or None = the reference key); coordinates are
the mesh's local coordinates (the mesh may lie in any plane); every function validates and
computes everything before it touches the file, so an error (BakeError, a ValueError, or
RuntimeError from the solver) leaves the object unchanged.
"""

from . import mesh_io, playback, timing
from .mesh_io import BakeError

LIVE_KEY = "bdi.live"
DEFAULT_TOLERANCE = 1e-4  # planarity, relative to the mesh size


def _core():
    from .core import load_core
    return load_core()


class Inputs:
    """Validated shapes of one request: shapes[0] is the source (base) shape."""

    def __init__(self, obj, source, others, anchor="AUTO", anchor_path=None,
                 tolerance=DEFAULT_TOLERANCE):
        self.obj = obj
        self.key = mesh_io.key_of(obj)
        self.source = mesh_io.key_block(self.key, source)
        if not others:
            raise BakeError("no target shape key given")
        if not all(others):
            raise BakeError("no target shape key chosen")
        self.others = [mesh_io.key_block(self.key, name) for name in others]
        for kb in self.others:
            if kb == self.source:
                raise BakeError("target %r is the source key; pick another target" % kb.name)
        self.names = [self.source.name] + [kb.name for kb in self.others]
        self.shapes = mesh_io.project_planar([mesh_io.read_co(kb) for kb in [self.source] + self.others],
                                             self.names, tolerance)
        self.faces, self.poly = mesh_io.triangles(obj.data)
        self.anchor, self.anchor_id = _resolve_anchor(obj, anchor, anchor_path, len(self.others))

    def fingerprint(self):
        """Cheap identity of the inputs, for caching precomputed solvers (live mode)."""
        import hashlib
        h = hashlib.sha1(self.faces.tobytes())
        for co in self.shapes:
            h.update(co.tobytes())
        h.update(self.anchor_id)
        return h.hexdigest()


def _resolve_anchor(obj, anchor, anchor_path, n_targets):
    """Map the add-on's anchor choice to bdinterp's `anchor` argument.

    anchor: 'AUTO'/None, a vertex index, a vertex group name (its heaviest vertex), or a
    bpy VertexGroup.  anchor_path: optional curve object whose path the anchor (the vertex, or
    the centroid for 'AUTO') follows, in the mesh's local coordinates.
    Returns (anchor argument, bytes identifying it for caches).
    """
    if anchor in (None, "AUTO", "auto"):
        vertex = None
    elif isinstance(anchor, int):
        if not 0 <= anchor < len(obj.data.vertices):
            raise BakeError("anchor vertex %d does not exist (mesh has %d vertices)"
                            % (anchor, len(obj.data.vertices)))
        vertex = anchor
    else:
        vertex = mesh_io.anchor_vertex_of_group(obj, getattr(anchor, "name", anchor))
    if anchor_path is None:
        return vertex, repr(vertex).encode()
    if n_targets != 1:
        raise BakeError("an anchor path works for two shapes only, not for pose blends")
    return _anchor_path(obj, anchor_path, vertex)


def _anchor_path(obj, path_obj, vertex):
    import bpy
    import numpy as np
    if path_obj.type != 'CURVE':
        raise BakeError("anchor path %r is not a curve object" % path_obj.name)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = path_obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        # World -> this mesh's local coordinates, where the shapes live.
        to_local = obj.matrix_world.inverted() @ evaluated.matrix_world
        pts = np.array([tuple(to_local @ v.co) for v in mesh.vertices], dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    if len(pts) < 2:
        raise BakeError("anchor path %r has fewer than two points" % path_obj.name)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    ts = np.concatenate([[0.0], np.cumsum(seg)]) / max(seg.sum(), 1e-30)
    angles = np.zeros(len(pts))  # no extra spin: the rotation is blended by the solver
    return (_core().AnchorPath(ts, pts, angles, vertex=vertex),
            repr(vertex).encode() + pts.tobytes())


def _solve(inp, ts, method="bdi", progress=None):
    """Frames at the factors ts, (k, n, 3); progress(done, total) after each."""
    import numpy as np
    bd = _core()
    source, target = inp.shapes[0], inp.shapes[1]
    try:
        if method == "bdi":
            solver = bd.Interpolator([source, target], inp.faces, anchor=inp.anchor)
            solve = solver.at
        else:
            def solve(t):
                return bd.interpolate(source, target, inp.faces, t, anchor=inp.anchor, method=method)
        frames = []
        for i, t in enumerate(ts):
            frames.append(np.asarray(solve(t), dtype=np.float64))
            if progress:
                progress(i + 1, len(ts))
    except ValueError as exc:  # the core names the problem (and indices); keep its words
        raise BakeError("%s: %s" % (inp.obj.name, exc)) from exc
    return np.stack(frames)


def max_distortion(source, results, faces):
    """Largest per-triangle conformal distortion K of any of `results` against `source`."""
    import numpy as np
    bd = _core()
    return max(float(np.max(bd.conformal_distortion(source, r, faces))) for r in results)


class BakeResult:
    """What a bake wrote: keys, factors, slider positions, slider property, distortion."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    @property
    def message(self):
        return ("Baked %d in-betweens %s -> %s: max distortion %.4g (inputs %.4g)"
                % (len(self.keys), self.source, self.target, self.max_distortion,
                   self.input_distortion))

    def __repr__(self):
        return "BakeResult(%s)" % self.message


def compute_frames(obj, target, source=None, count=3, factors=None, easing="LINEAR",
                   anchor="AUTO", anchor_path=None, method="bdi", tolerance=DEFAULT_TOLERANCE,
                   progress=None):
    """Compute in-betweens without writing anything.

    Returns (inputs, positions, factors, frames) with frames a (k, n, 3) float64 array in the
    mesh's local coordinates.  Parameters as in bake().
    """
    positions, ts = timing.schedule(count, factors, easing)
    inp = Inputs(obj, source, [target], anchor, anchor_path, tolerance)
    return inp, positions, ts, _solve(inp, ts, method, progress)


def bake(obj, target, source=None, count=3, factors=None, easing="LINEAR", anchor="AUTO",
         anchor_path=None, method="bdi", tolerance=DEFAULT_TOLERANCE, drivers=True,
         progress=None):
    """Bake in-betweens of `source` -> `target` into new shape keys; return a BakeResult.

    obj: mesh object with shape keys.  target/source: key names (source default: the reference
    key).  count: number of evenly timed in-betweens, or factors: explicit list in (0, 1).
    easing: 'LINEAR', 'EASE_IN', 'EASE_OUT', 'EASE_IN_OUT' or a callable u -> t (custom curve).
    anchor: 'AUTO', a vertex index or a vertex group name; anchor_path: a curve object the
    anchor follows.  method: 'bdi' (default), 'arap' or 'linear'.  tolerance: planarity,
    relative to the mesh size.

    Keys are named '<target>.bdi.<percent>' (e.g. 'Arm_up.bdi.050'), hold the in-between shape
    and are relative to the source key; an earlier bake of the same pair is replaced.  With
    drivers=True a custom property '<target>.bdi' on the object (slider 0..1) drives them with
    native drivers (and the target key) so that 0 -> 1 plays source -> in-betweens -> target,
    also without the add-on.
    """
    inp, positions, ts, frames = compute_frames(obj, target, source, count, factors, easing,
                                                anchor, anchor_path, method, tolerance, progress)
    src, tgt = inp.source, inp.others[0]
    names = timing.key_names(tgt.name, ts)
    # The target key itself ends the playback only if it is relative to the source; otherwise
    # bake an end key equal to the target (relative to the source) and drive that instead.
    end_key = None
    if drivers and tgt.relative_key != src:
        end_key = timing.key_name(tgt.name, 1.0)
        names, frames = names + [end_key], list(frames) + [inp.shapes[1]]
    k_out = max_distortion(inp.shapes[0], frames, inp.faces)
    k_in = max_distortion(inp.shapes[0], [inp.shapes[1]], inp.faces)
    # --- everything computed; from here on the file is modified ---
    src_name, tgt_name = src.name, tgt.name
    playback.remove(obj, src_name, tgt_name, keep_slider=True)
    written = [_write_key(obj, name, src_name, co) for name, co in zip(names, frames)]
    slider = None
    if drivers:
        slider = playback.install(obj, src_name, tgt_name, written[:len(positions)], positions,
                                  end=written[-1] if end_key else None)
    return BakeResult(keys=written[:len(positions)], factors=ts, positions=positions,
                      source=src_name, target=tgt_name, slider=slider,
                      max_distortion=k_out, input_distortion=k_in)


def _write_key(obj, name, source_name, co, value=0.0):
    """Create (or overwrite) key `name` holding `co`, relative to `source_name`."""
    key = obj.data.shape_keys
    kb = key.key_blocks.get(name)
    if kb is None:
        kb = obj.shape_key_add(name=name, from_mix=False)
        kb.value = value
    kb.relative_key = key.key_blocks[source_name]
    mesh_io.write_co(kb, co)
    return kb.name


def pose_weights(weights):
    """{key: w} -> (names, weights incl. the source first).

    Weights are >= 0; the source gets 1 - sum (the paper's base shape S0 with the identity
    map); if they sum to more than 1 they are normalised and the source gets 0.
    """
    items = list(weights.items()) if hasattr(weights, "items") else list(weights)
    if not items:
        raise BakeError("no poses given")
    names = [n for n, _ in items]
    ws = [float(w) for _, w in items]
    if any(w < 0 for w in ws):
        raise BakeError("pose weights must be >= 0 (got %s)" % dict(items))
    total = sum(ws)
    if total > 1.0:
        return names, [0.0] + [w / total for w in ws]
    return names, [1.0 - total] + ws


def blend_shape(inp, all_weights, solver=None):
    """Bounded-distortion blend of inp.shapes with weights (source first)."""
    bd = _core()
    try:
        if solver is not None:
            return solver.blend(all_weights)
        return bd.blend(inp.shapes, inp.faces, all_weights, anchor=inp.anchor, base=0)
    except ValueError as exc:
        raise BakeError("%s: %s" % (inp.obj.name, exc)) from exc


def blend(obj, weights, source=None, name="Blend.bdi", anchor="AUTO",
          tolerance=DEFAULT_TOLERANCE):
    """Bake a pose blend (paper Section 5): one key `name`, relative to the source.

    weights: {pose key name: weight}; see pose_weights() for how the source's weight follows.
    Returns (key name, max distortion of the blend, max distortion of the poses).
    """
    names, ws = pose_weights(weights)
    inp = Inputs(obj, source, names, anchor, None, tolerance)
    result = blend_shape(inp, ws)
    k_out = max_distortion(inp.shapes[0], [result], inp.faces)
    k_in = max_distortion(inp.shapes[0], inp.shapes[1:], inp.faces)
    return _write_key(obj, name, inp.source.name, result), k_out, k_in


def clear(obj, target, source=None):
    """Remove a bake of source -> target: its keys, their drivers and the slider property."""
    key = mesh_io.key_of(obj)
    src = mesh_io.key_block(key, source)
    return playback.remove(obj, src.name, target, keep_slider=False)


def set_live(obj, target=None, factor=None, weights=None, source=None, enable=True, anchor=None):
    """Configure and switch live mode (needs the add-on enabled: it lives in frame handlers).

    target + factor: live interpolation; weights {key: w}: live pose blend.  The result is
    written into the key 'bdi.live' (relative to the source, value 1) on every frame change
    and whenever the factor/weights change; keyframe obj.bdi.live_factor or
    obj.bdi.poses[i].weight to animate.  Returns the live key name (or None when disabled).
    """
    props = obj.bdi
    if source is not None:
        props.source = source
    if target is not None:
        props.target = target
    if anchor is not None:
        props.anchor = anchor
    if weights is not None:
        props.poses.clear()
        for name, w in (weights.items() if hasattr(weights, "items") else weights):
            item = props.poses.add()
            item.key, item.weight = name, w
        props.live_mode = 'BLEND'
    elif target is not None:
        props.live_mode = 'INTERPOLATE'
    if factor is not None:
        props.live_factor = factor
    from . import live as live_mod
    if not enable:
        props.live = False
        return None
    live_mod.enable(obj)  # raises (and stays off) on invalid input
    return LIVE_KEY


def show_distortion(obj, key=None, visible=True):
    """Write per-face conformal distortion of `key` (default: the active key) against its
    relative key into face attribute 'bdi_distortion' and colour attribute
    'bdi_distortion_color'; show it in the viewport. Returns the per-face distortion array."""
    from . import distortion
    return distortion.write(obj, key, visible)


def hide_distortion(obj=None):
    """Switch the viewports (and Workbench renders) back to material colours."""
    from . import distortion
    distortion.set_visible(False, obj)
