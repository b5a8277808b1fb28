"""Several mesh objects baked as one cut-out character.

The objects that have the target key are solved as one mesh in world space, so that pieces of
different objects overlap and are joined like pieces of one object; each object's in-betweens
are written back in its own local coordinates, driven by one slider on the active object.
"""

from ..shapes import rig, solve
from .baking import BakeJob, store_result
from ..shapes.mesh_io import BakeError


def to_world(obj, co):
    import numpy as np
    m = np.array(obj.matrix_world, dtype=np.float64)
    return co @ m[:3, :3].T + m[:3, 3]


def to_local(obj, co):
    import numpy as np
    m = np.array(obj.matrix_world, dtype=np.float64)
    return np.linalg.solve(m[:3, :3], (co - m[:3, 3]).T).T


def selected_meshes(context, obj=None):
    """obj (default: the active object), then the other selected mesh objects by name: a bake
    solves those of them that have the target key (members) as one character."""
    obj = context.object if obj is None else obj
    selected = getattr(context, "selected_objects", None) or ()
    others = (o for o in selected if o.type == 'MESH' and o != obj)
    return [obj] + sorted(others, key=lambda o: o.name)


def members(objects, target):
    """The mesh objects of `objects` (in order, once each) that have the shape key `target`."""
    out = []
    for obj in objects:
        key = obj.data.shape_keys if obj is not None and obj.type == 'MESH' else None
        if key is not None and key.key_blocks.get(target or "") is not None and obj not in out:
            out.append(obj)
    return out


# What a character takes from its first object's Inputs as they are.
KEYS_OF_FIRST = ("obj", "key", "source", "others", "names")


class CharacterInputs(solve.Inputs):
    """The Inputs of several objects as one mesh in world space: shapes (k, n, 3) concatenated in
    the order of `parts` (each object's own validated Inputs), faces renumbered; obj is the first
    object (the active one, whose slider plays the bake)."""

    def __init__(self, objs, settings):
        import numpy as np
        parts = settings.but(anchor="AUTO", anchor_path=None, joints="off")
        self.parts = [solve.Inputs(obj, parts, layered=False) for obj in objs]
        for name in KEYS_OF_FIRST:  # the first object's keys name the character's (its slider)
            setattr(self, name, getattr(self.parts[0], name))
        self.obj_name, self.raw = "character of %d objects" % len(objs), None  # raw: in parts
        self.offsets = np.cumsum([0] + [len(p.shapes[0]) for p in self.parts])
        self.faces = np.concatenate([p.faces + o for p, o in zip(self.parts, self.offsets)])
        # polygons numbered across the objects, so that folds count each object's apart
        self.poly_offsets = np.cumsum([0] + [len(p.obj.data.polygons) for p in self.parts])
        self.poly = np.concatenate([p.poly + o for p, o in zip(self.parts, self.poly_offsets)])
        self.face_offsets = np.cumsum([0] + [len(p.faces) for p in self.parts])
        world = [np.concatenate([to_world(p.obj, p.shapes[i]) for p in self.parts])
                 for i in range(len(self.names))]
        # the shapes are in world space: so is the anchor path (no object's matrix)
        self.complete(world, settings, solve.resolve_anchor(
            None, self.stacked_vertex(settings.anchor), settings.path_object(), 1), [rig.Member(
                p.obj, int(o), p.source_read, lambda x, obj=p.obj: to_world(obj, x),
                p.reference_shape) for p, o in zip(self.parts, self.offsets)])

    def stacked_vertex(self, anchor):
        """The character's vertex index of `anchor`: 'AUTO'/None (None), (object or its name,
        vertex index) of a member, or a vertex index or vertex group name of the first object
        (whose vertices come first)."""
        if anchor in (None, "AUTO", "auto"):
            return None
        if not isinstance(anchor, tuple):
            return solve.resolve_anchor(self.parts[0].obj, anchor, None, 1)
        obj, vertex = anchor
        name = getattr(obj, "name", obj)
        for part, offset in zip(self.parts, self.offsets):
            if part.obj.name == name:
                return int(offset) + solve.own_vertex(part.obj, vertex)
        raise BakeError("anchor object %r is not one of the character's objects (%s)"
                        % (name, ", ".join(p.obj.name for p in self.parts)))

    def _part(self, index, offsets):
        import numpy as np
        i = int(np.searchsorted(offsets, index, side="right")) - 1
        return self.parts[i], index - int(offsets[i])

    def vertex_name(self, v):
        if not 0 <= v < self.offsets[-1]:
            return "vertex %d" % v
        part, local = self._part(v, self.offsets)
        return "vertex %d of %r" % (local, part.obj_name)

    def polygon_name(self, p):
        if not 0 <= p < self.poly_offsets[-1]:
            return "polygon %d" % p
        part, local = self._part(p, self.poly_offsets)
        return "polygon %d of %r" % (local, part.obj_name)

    def _polygon(self, f):
        if not 0 <= f < self.face_offsets[-1]:
            return "face %d" % f
        part, local = self._part(f, self.face_offsets)
        return "polygon %d of %r" % (part.poly[local], part.obj_name)

    def local(self, frames):
        """[(part, its frames (k, n_i, 3) in its object's local coordinates)] of world frames."""
        import numpy as np
        frames = np.asarray(frames, dtype=np.float64).reshape(-1, self.offsets[-1], 3)
        return [(p, [to_local(p.obj, X[a:b]) for X in frames])
                for p, a, b in zip(self.parts, self.offsets[:-1], self.offsets[1:])]


class CharacterBakeJob(BakeJob):
    """BakeJob of several objects: computed once for all, written into each (one slider, on the
    first object, drives every object's keys)."""

    def __init__(self, objs, settings):
        self._objs = members(objs, settings.target)
        super().__init__(self._objs[0], settings)

    def inputs(self, obj, settings):
        return CharacterInputs(self._objs, settings)

    @property
    def objects(self):
        """The character's objects (those with the target key), the slider's owner first."""
        return list(self._objs)

    def finish(self):
        """Compute what is left, plan every object, then write them all; a BakeResult."""
        inp = self.inp
        frames = list(self.job.frames())
        plans = [self.plan(part.obj, part, local, inp.obj) for part, local in inp.local(frames)]
        for plan in plans:  # each member's record names them all: one's edit makes all stale
            plan.members = [o.name for o in self._objs]
        ends = [inp.shapes[1]] if any(p.end_key for p in plans) else []
        result = self.result(inp, frames + ends, "; ".join(
            "%s: %s" % (p.obj.name, p.note) for p in plans if p.note))
        result.objects = len(plans)
        # --- everything computed; from here on the file is modified ---
        for plan in plans:
            keys, slider = self.write(plan)
            result.keys = result.keys or keys
            result.slider = result.slider or slider
        for plan in plans:
            store_result(plan.obj, result.summary())
        return result
