"""Motion trails: the paths that vertices follow through the in-betweens, in world space.

The points are the solver's frames (the in-betweens themselves, not a spline through them), for
one object or a cut-out character of several objects solved as one (as a bake solves them).
Reads bpy data, writes nothing; the viewport overlay (onion.py) draws what this computes.
"""

from collections import Counter

from ..keys import character, playback
from ..shapes import mesh_io, solve
from ..shapes.mesh_io import BakeError
from ..shapes.settings import BakeSettings, from_props

# Work done, for the tests: 'paths' validated (the solver built), 'solved' frames computed.
counters = Counter()
MEMO_BYTES = 64 << 20  # frames kept per Path (a trail's samples at 20k vertices: 16 MB)


def settings_of(props):
    """The BakeSettings a Path of the panel settings `props` (Object.bdi, or None: the defaults)
    solves with; factors and easing, which no path depends on, left at their defaults."""
    return from_props(props, factors=None, easing="LINEAR") if props is not None else BakeSettings()


class Path:
    """A validated source -> target interpolation of one object or character (its panel settings):
    objs (first: the one whose settings count), inp (solve.Inputs, world coordinates for a
    character), method, and the solver (a bdinterp.Interpolator for 'bdi', else None).  The
    frames it solved are kept by factor (up to MEMO_BYTES): asking again costs nothing."""

    def __init__(self, obj, target=None, source=None, with_solver=True):
        objs = list(obj) if isinstance(obj, (list, tuple)) else [obj]
        if not objs or objs[0] is None:
            raise BakeError("no object given")
        props = getattr(objs[0], "bdi", None)
        target = target or (props.target if props is not None else "")
        if not target:
            raise BakeError("%s: no target shape key chosen" % objs[0].name)
        settings = settings_of(props).but(target=target)
        settings = settings if source is None else settings.but(source=source)
        self.method = settings.method
        members = character.members(objs, target) if len(objs) > 1 else objs
        if len(members) > 1:
            self.inp = character.CharacterInputs(members, settings)
        else:
            members = [members[0] if members else objs[0]]
            self.inp = solve.Inputs(members[0], settings)
        self.objs, self.found, self._memo, self._baked = members, None, {}, None
        self.solver = self.inp.interpolator() if self.method == "bdi" and with_solver else None
        counters["paths"] += 1

    @property
    def size(self):
        """Number of vertices (all objects' for a character)."""
        return len(self.inp.shapes[0])

    @property
    def local(self):
        """True if the frames are in the object's coordinates (one object; a character is solved
        in world coordinates): drawn with the object's matrix, they follow it when it moves."""
        return len(self.objs) == 1

    def world(self, frames):
        """(k, n, 3) frames of inp (local coordinates of one object) in world coordinates."""
        import numpy as np
        frames = np.asarray(frames, dtype=np.float64)
        if not self.local:
            return frames  # a character is solved in world coordinates
        m = np.array(self.objs[0].matrix_world, dtype=np.float64)
        return frames @ m[:3, :3].T + m[:3, 3]

    def frames(self, ts):
        """(len(ts), n, 3) in-betweens at factors ts, world coordinates."""
        return self.world(self.solved(ts))

    def solved(self, ts):
        """(len(ts), n, 3) in-betweens at factors ts as solved (local coordinates of one object):
        the factors not solved yet in one frames() call, each frame warm-started from the one
        before, as the core computes them alone."""
        import numpy as np
        ts = [float(t) for t in ts]
        new = [t for t in dict.fromkeys(ts) if t not in self._memo]
        if new:
            frames = self._solve(new)
            counters["solved"] += len(new)
            if (len(self._memo) + len(new)) * frames[0].nbytes > MEMO_BYTES:
                self._memo.clear()
            self._memo.update(zip(new, frames))
            if len(new) == len(ts):
                return np.asarray(frames)
        return np.array([self._memo[t] for t in ts]).reshape(len(ts), self.size, 3)

    def _solve(self, ts):
        if self.method != "bdi":
            return list(solve.FrameJob(self.inp, ts, self.method).frames())
        if self.solver is None:
            self.solver = self.inp.interpolator()
        try:
            return list(self.solver.frames(ts))
        except ValueError as exc:
            raise self.inp.explain(exc) from exc

    def vertices(self, vertices=None):
        """(k,) int64 vertex indices: `vertices` checked, or default_vertices()."""
        import numpy as np
        if vertices is None:
            return default_vertices(self)
        v = np.asarray(vertices, dtype=np.int64).ravel()
        bad = v[(v < 0) | (v >= self.size)]
        if len(bad):
            raise BakeError("%s: %s does not exist (the mesh has %d vertices)"
                            % (self.inp.obj_name, self.inp.vertex_name(int(bad[0])), self.size))
        if not len(v):
            raise BakeError("%s: no vertices given for trails" % self.inp.obj_name)
        return v

    def baked(self):
        """(keys (j, n, 3) world coordinates of the recorded bake's in-between keys, in order of
        factor; the key names). Empty when the object has no bake of this source -> target.
        Sets self.found (playback.Found of the bake, or None)."""
        keys, names = self.baked_solved()
        return self.world(keys), names

    def baked_solved(self):
        """baked() in the coordinates the frames are solved in (read once per Path)."""
        import numpy as np
        if self._baked is not None:
            return self._baked
        inp, first = self.inp, self.objs[0]
        found = self.found = playback.find(first, inp.names[0], inp.names[1])
        names = [n for n in (found.keys if found else []) if all(
            n in o.data.shape_keys.key_blocks for o in self.objs)]
        if not names:
            keys = np.empty((0, self.size, 3))
        elif self.local:
            keys = np.array([mesh_io.read_co(first.data.shape_keys.key_blocks[n]) for n in names])
        else:
            keys = np.array([np.concatenate([character.to_world(o, mesh_io.read_co(
                o.data.shape_keys.key_blocks[n])) for o in self.objs]) for n in names])
        self._baked = keys, names
        return self._baked


def default_vertices(path):
    """Each piece's vertex nearest its centroid, then, for every joint between pieces, the child
    piece's vertex nearest the joint (the points an animator checks first), without repeats."""
    import numpy as np
    X = path.inp.shapes[0]
    labels = np.asarray(path.inp.layers.labels)
    out = []
    for piece in np.unique(labels):
        idx = np.flatnonzero(labels == piece)
        centre = X[idx].mean(axis=0)
        out.append(int(idx[np.argmin(np.linalg.norm(X[idx] - centre, axis=1))]))
    for joint in (path.solver.joints() if path.solver is not None else []):
        idx = np.flatnonzero(labels == labels[joint["child"]])
        out.append(int(idx[np.argmin(np.linalg.norm(X[idx] - np.asarray(joint["point"]), axis=1))]))
    return np.array(list(dict.fromkeys(out)), dtype=np.int64)


def trails(obj, vertices=None, samples=33, target=None, source=None):
    """The paths of `vertices` through the in-betweens: (samples, k, 3) world coordinates.

    obj: a mesh object, or a list of them (those with the target key are solved as one cut-out
    character, as a bake solves them; vertex indices then count the objects' vertices one after
    the other).  Settings (target, source, anchor, method, joints) are obj's panel settings;
    target/source override them.  vertices: indices (default: each piece's centre vertex and the
    vertices at the joints between pieces).  Point i is the in-between at factor i/(samples-1),
    the solver's frame itself.
    """
    import numpy as np
    if int(samples) < 2:
        raise BakeError("trails need at least 2 samples (got %d)" % int(samples))
    path = Path(obj, target, source)
    v = path.vertices(vertices)
    return path.frames(np.linspace(0.0, 1.0, int(samples)))[:, v, :]
