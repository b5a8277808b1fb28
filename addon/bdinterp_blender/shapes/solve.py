"""Shapes from shape keys -> frames, blends and their distortion (reads bpy data, never writes it).

The service layer under api.py, live.py and distortion.py: validation (Inputs), the solver calls
(chunked Interpolator.frames() for bakes, blend() for poses) and the translation of where an
InvalidInputError points (its shape, face = a triangle, vertex) into Blender's terms (key names,
polygon indices).
"""

import time

from . import hand_joints, mesh_io, rig
from .mesh_io import BakeError
from ..names import FRAMES_PER_WORKER, STEP_SECONDS


def core():
    from ..core import load_core
    return load_core()


class Inputs:
    """Validated shapes of one request: shapes[0] is the source (base) shape.

    raw: the keys' float32 data as read (live mode compares it to notice key edits); faces: (m, 3)
    triangles; poly: (m,) the polygon of each triangle; names: the keys' names, source first.
    """

    def __init__(self, obj, settings, others=None, layered=True):
        """settings: a BakeSettings (source, anchor, anchor path, planarity, joints); others: the
        keys after the source (default: [settings.target]); layered=False: the shapes as read,
        for a caller that lays out several objects' shapes at once."""
        source, anchor = settings.source, settings.anchor
        others = [settings.target] if others is None else others
        self.obj, self.obj_name = obj, obj.name if obj is not None else "No object"
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
        blocks = [self.source] + self.others
        self.names, self.joint_mode = [kb.name for kb in blocks], settings.joints
        self.raw = [mesh_io.read_raw(kb) for kb in blocks]
        self.faces, self.poly = mesh_io.triangles(obj.data)
        read = [mesh_io.read_shown(obj, kb, r) for kb, r in zip(blocks, self.raw)]
        self.source_read = read[0]  # as read, before layering: the bones' pins are mapped onto it
        self.layers, self.shapes = None, read
        if not layered:
            self.anchor = resolve_anchor(obj, anchor, None, len(self.others))
            self.joints, self.joint_source = False, ""
            return
        self.complete(read, settings, resolve_anchor(obj, anchor, settings.path_object(),
                                                     len(self.others)),
                      [rig.Member(obj, 0, self.source_read, lambda p: p, self.reference_shape)])

    def complete(self, shapes, settings, anchor, members):
        """The steps after reading: `shapes` put into their pieces' planes, the resolved `anchor`
        kept, the joints found for `members` (rig.Member) under settings.joints."""
        self.shapes = self.layered(shapes, settings.planarity)
        self.anchor = anchor
        self.joint_mode = settings.joints
        self.joints, self.joint_source = self.find_joints(members)

    def find_joints(self, members):
        """(bdinterp's joints argument, where they came from) of self.joint_mode (rig.core_joints),
        with the parents set by hand (rig.hand_set) put into that tree (hand_joints.apply): the
        tree the core finds from the keys is asked of it first. Off: no joints, none by hand."""
        labels = self.layers.labels
        joints, source = rig.core_joints(self.joint_mode, members, labels)
        hand = rig.hand_set(members, labels) if self.joint_mode != "off" else []
        if not hand:
            return joints, source
        links = joints if isinstance(joints, list) else []
        if joints is True:
            links = hand_joints.found_links(self.solver_of(True))
        links = hand_joints.apply(links, hand, labels, self.shapes)
        return links, "; ".join(filter(None, [source, "%d set by hand" % len(hand)]))

    def reference_shape(self):
        """(n, 3) the object's reference key as Blender shows it, in its local coordinates."""
        kb = self.key.reference_key
        return mesh_io.read_shown(self.obj, kb, mesh_io.read_raw(kb))

    def layered(self, shapes, tolerance):
        """shapes with every piece put into its plane (mesh_io.project_layers; self.layers: their
        Layers), errors explained."""
        try:
            self.layers, shapes = mesh_io.project_layers(shapes, self.faces, tolerance)
        except ValueError as exc:
            raise self.explain(exc) from exc
        return shapes

    def explain(self, exc):
        """BakeError in Blender's terms, prefixed with the object's name: an InvalidInputError's
        shape -> the key's name, face (a triangle of the tessellation) -> its polygon, vertex ->
        the object's vertex, then its detail; any other error's message as it is."""
        where = [name(i) for name, i in ((self._key_name, getattr(exc, "shape", None)),
                                         (self._polygon, getattr(exc, "face", None)),
                                         (self.vertex_name, getattr(exc, "vertex", None)))
                 if i is not None]
        text = "%s: %s" % (", ".join(where), exc.detail) if where else str(exc)
        if "not planar" in text:  # what to do about it, in Blender's terms
            text += (". To fix it, flatten that key: in Edit Mode with the key active select all "
                     "and scale to 0 across the piece (a front-view piece: S Y 0), or raise "
                     "Planarity under Expert")
        return BakeError("%s: %s" % (self.obj_name, text))

    def vertex_name(self, v):
        """How a message names vertex v of the solved mesh (several objects: which one's)."""
        return "vertex %d" % v

    def polygon_name(self, p):
        """How a message names polygon p of self.poly (several objects: which one's)."""
        return "polygon %d" % p

    def _key_name(self, i):
        return "key %r" % self.names[i] if 0 <= i < len(self.names) else "shape %d" % i

    def _polygon(self, f):
        return "polygon %d" % self.poly[f] if 0 <= f < len(self.poly) else "face %d" % f

    def interpolator(self, threads=0):
        """A precomputed bdinterp.Interpolator of these shapes (base: the source; threads: its
        workers, 0 = one per usable core)."""
        return self.solver_of(self.joints, threads)

    def solver_of(self, joints, threads=0):
        """The Interpolator of these shapes with bdinterp's `joints` argument, errors explained."""
        try:
            return core().Interpolator(self.shapes, self.faces, anchor=self.anchor, base=0,
                                       joints=joints, layers=self.layers, threads=threads)
        except ValueError as exc:
            raise self.explain(exc) from exc


def resolve_anchor(obj, anchor, anchor_path, n_targets):
    """Map the add-on's anchor choice to bdinterp's `anchor` argument.

    anchor: 'AUTO'/None, a vertex index, a vertex group name (its heaviest vertex), a
    bpy VertexGroup, or (obj or its name, vertex index).  anchor_path: optional curve object
    whose path the anchor (the vertex, or the centroid for 'AUTO') follows, in the mesh's local
    coordinates (obj None: world coordinates, those of a character's shapes).
    """
    if anchor in (None, "AUTO", "auto"):
        vertex = None
    elif isinstance(anchor, tuple):
        if getattr(anchor[0], "name", anchor[0]) != obj.name:
            raise BakeError("anchor: a vertex of %r anchors a character of several objects, not %r"
                            % (getattr(anchor[0], "name", anchor[0]), obj.name))
        vertex = own_vertex(obj, anchor[1])
    elif isinstance(anchor, int):
        vertex = anchor  # the core checks the range (explain() names the vertex)
    else:
        vertex = mesh_io.anchor_vertex_of_group(obj, getattr(anchor, "name", anchor))
    if anchor_path is None:
        return vertex
    if n_targets != 1:
        raise BakeError("an anchor path works for two shapes only, not for pose blends")
    return _anchor_path(obj, anchor_path, vertex)


def own_vertex(obj, vertex):
    """Vertex index `vertex` of obj's mesh, checked (BakeError naming the object)."""
    if not isinstance(vertex, int) or not 0 <= vertex < len(obj.data.vertices):
        raise BakeError("anchor: %r has no vertex %r (it has %d)"
                        % (obj.name, vertex, len(obj.data.vertices)))
    return vertex


def _anchor_path(obj, path_obj, vertex):
    import bpy
    import numpy as np
    if path_obj.type != 'CURVE':
        raise BakeError("anchor path %r is not a curve object" % path_obj.name)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = path_obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        # World -> this mesh's local coordinates, where the shapes live (None: stay in world).
        to_local = evaluated.matrix_world if obj is None else \
            obj.matrix_world.inverted() @ evaluated.matrix_world
        pts = np.array([tuple(to_local @ v.co) for v in mesh.vertices], dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    if len(pts) < 2:
        raise BakeError("anchor path %r has fewer than two points" % path_obj.name)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    ts = np.concatenate([[0.0], np.cumsum(seg)]) / max(seg.sum(), 1e-30)
    angles = np.zeros(len(pts))  # no extra spin: the rotation is blended by the solver
    return core().AnchorPath(ts, pts, angles, vertex=vertex)


def workers(threads=0):
    """The solver's workers for `threads` (0: one per usable core)."""
    return threads or core().threading_info()["usable_cores"]


def frames_per_call(threads=0):
    """The most frames a step() of a FrameJob computes: FRAMES_PER_WORKER for each worker (threads,
    0 = one per usable core), so that each worker warm-starts along its frames."""
    return FRAMES_PER_WORKER * workers(threads)


class FrameJob:
    """The frames of inp at factors ts, computed chunk by chunk (step()), so that a caller can show
    progress and cancel between chunks.  'bdi' goes through Interpolator.frames() (warm-started,
    on `threads` workers, 0 = every usable core; its stats.threads: the threads that ran);
    'arap'/'linear' through bdinterp.frames(method=...), the package's one frames API.  A step:
    a frame per worker first, then as many rounds of a frame per worker as fit in STEP_SECONDS (at
    most frames_per_call)."""

    def __init__(self, inp, ts, method="bdi", threads=0):
        self.inp, self.ts, self.method = inp, list(ts), method
        self.workers = workers(threads)
        self.chunk, self.next = frames_per_call(threads), self.workers
        self.done, self._parts = 0, []
        # the workers by number: a step's round of a frame per worker runs on all of them
        self._solver = inp.interpolator(self.workers) if method == "bdi" else None

    @property
    def finished(self):
        return self.done >= len(self.ts)

    @property
    def solver(self):
        """The bdinterp.Interpolator of a 'bdi' job (None for the baselines)."""
        return self._solver

    def step(self):
        """Compute the next chunk; returns the number of frames done so far."""
        import numpy as np
        ts = self.ts[self.done:self.done + self.next]
        inp, started = self.inp, time.perf_counter()
        try:
            if self._solver is not None:
                part = self._solver.frames(ts)
            else:
                part = core().frames(inp.shapes[0], inp.shapes[1], inp.faces, ts,
                                     anchor=inp.anchor, method=self.method)
        except ValueError as exc:  # the core names the problem (and indices); keep its words
            raise inp.explain(exc) from exc
        self._parts.append(np.asarray(part, dtype=np.float64))
        self.done += len(ts)
        per_round = (time.perf_counter() - started) / -(-len(ts) // self.workers)  # a frame a worker
        rounds = max(1, int(STEP_SECONDS / max(per_round, 1e-9)))
        self.next = min(self.chunk, rounds * self.workers)
        return self.done

    def frames(self):
        """(k, n, 3) once finished (computing what is left)."""
        import numpy as np
        while not self.finished:
            self.step()
        return np.concatenate(self._parts) if self._parts else np.empty((0,) + self.inp.shapes[0].shape)


def flat(shapes, faces, layers=None):
    """Plane coordinates (n, 2) of 3D shapes whose pieces may lie in parallel planes (the plane
    of `layers`, default fitted to shapes[0]'s pieces; depths dropped): the core's distortion
    measures take one plane."""
    import numpy as np
    return (layers or core().Layers.fit(shapes[:1], faces, tolerance=np.inf)).to_plane(shapes)


def distortion(source, shape, faces):
    """(m,) conformal distortion K of every triangle of source -> shape (layered pieces too)."""
    s, x = flat([source, shape], faces)
    return core().conformal_distortion(s, x, faces)


def max_distortion(source, results, faces, layers=None):
    """Largest per-triangle conformal distortion K of any of `results` against `source` (layers:
    their Layers, e.g. Inputs.layers, else fitted)."""
    import numpy as np
    flats = flat([source] + list(results), faces, layers)
    return max(float(np.max(core().conformal_distortion(flats[0], r, faces))) for r in flats[1:])


def folded_polygons(inp, results):
    """Sorted polygon indices with a triangle flipped or collapsed (area ratio <= 0) in any result."""
    import numpy as np
    bd = core()
    flats = flat([inp.shapes[0]] + list(results), inp.faces, inp.layers)
    bad = np.zeros(len(inp.faces), dtype=bool)
    for r in flats[1:]:
        bad |= np.asarray(bd.area_ratio(flats[0], r, inp.faces)) <= 0.0
    return sorted(set(int(p) for p in inp.poly[bad]))


def input_folds(inp, solver):
    """"key 'Swing' has 4 folded polygons near vertex 312" for every input after the source with
    triangles folded against it (Interpolator.folded_faces), joined by '; '; "" when none is."""
    out = []
    for i, name in enumerate(inp.names[1:], start=1):
        tris = solver.folded_faces(i)
        if len(tris):
            polys = sorted(set(int(p) for p in inp.poly[tris]))
            out.append("key %r has %d folded polygon%s near %s"
                       % (name, len(polys), "" if len(polys) == 1 else "s",
                          inp.vertex_name(int(inp.faces[tris[0], 0]))))
    return "; ".join(out)


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
    """Bounded-distortion blend of inp.shapes with weights (source first), (n, 3)."""
    try:
        if solver is not None:
            return solver.blend(all_weights)
        return core().blend(inp.shapes, inp.faces, all_weights, anchor=inp.anchor, base=0)
    except ValueError as exc:
        raise inp.explain(exc) from exc
