"""The settings of a bake: one frozen BakeSettings, made from the panel's Object.bdi here (and
nowhere else) or from api.bake's arguments, and passed as one value through the jobs, the
characters, live mode, trails and onion skins (reads bpy data, never writes it)."""

from dataclasses import dataclass, replace

from . import rig
from .. import timing
from .mesh_io import BakeError
from ..names import DEFAULT_TOLERANCE

CURVE_NODE = "Easing"  # the node of Object.bdi.easing_curve that holds the custom easing curve


@dataclass(frozen=True)
class BakeSettings:
    """target/source: key names (source None: the reference key); count evenly timed
    in-betweens through `easing` (a name of timing.EASINGS or a callable u -> t), or `factors`
    (a tuple in (0, 1)); anchor: 'AUTO', a vertex index, a vertex group's name or (object name,
    vertex); anchor_path: the name of a curve object the anchor follows, or None; method: 'bdi',
    'arap' or 'linear'; planarity: how far a vertex may lie off its piece's plane, relative to
    the mesh size; drivers: a slider drives the keys; joints: 'auto', 'bones', 'pins' or 'off';
    poses: the pose keys of a pose blend; threads: the solver's workers (0: one per usable
    core)."""
    target: str = ""
    source: object = None
    count: int = 3
    factors: object = None
    easing: object = "LINEAR"
    anchor: object = "AUTO"
    anchor_path: object = None
    method: str = "bdi"
    planarity: float = DEFAULT_TOLERANCE
    drivers: bool = True
    joints: str = "auto"
    poses: tuple = ()
    threads: int = 0

    def __post_init__(self):
        object.__setattr__(self, "source", self.source or None)  # '' is the reference key too
        path = self.anchor_path
        object.__setattr__(self, "anchor_path", getattr(path, "name", path))  # no bpy reference
        object.__setattr__(self, "joints", rig.joint_mode(self.joints))
        if self.factors is not None:
            object.__setattr__(self, "factors", tuple(float(f) for f in self.factors))

    def but(self, **changes):
        """These settings with `changes`."""
        return replace(self, **changes)

    def path_object(self):
        """The anchor path's curve object, or None; BakeError if it is gone."""
        if self.anchor_path is None:
            return None
        import bpy
        obj = bpy.data.objects.get(self.anchor_path)
        if obj is None:
            raise BakeError("the anchor path %r is no longer in the file" % self.anchor_path)
        return obj


def from_props(props, **changes):
    """The BakeSettings of the panel settings `props` (Object.bdi), with `changes` (a field given
    there is not read from the panel: live mode's every frame reads neither factors nor easing)."""
    if "factors" not in changes:
        changes["factors"] = timing.parse_factors(props.factors) if props.use_factors else None
    if "easing" not in changes:
        changes["easing"] = easing_of(props)
    panel = dict(target=props.target, source=props.source, count=props.count,
                 anchor=anchor_choice(props), anchor_path=props.anchor_path, method=props.method,
                 planarity=props.tolerance, drivers=props.drivers, joints=props.joints,
                 poses=tuple(p.key for p in props.poses))
    return BakeSettings(**{**panel, **changes})


def easing_of(props):
    """A preset's name, or a callable for the custom curve (BakeError when it is used without
    one: see timing.schedule)."""
    if props.easing != 'CUSTOM':
        return props.easing
    tree = props.easing_curve
    node = tree.nodes.get(CURVE_NODE) if tree else None
    if node is None:
        return _no_curve
    mapping = node.mapping
    mapping.initialize()
    return lambda u: mapping.evaluate(mapping.curves[0], u)


def _no_curve(u):
    raise BakeError("custom easing needs a curve: press 'New Curve' first")


def anchor_choice(props, kind=None):
    """The anchor argument of the panel settings `props` (Object.bdi): 'AUTO', the vertex index
    or the vertex group's name, for kind (default props.anchor) 'AUTO', 'VERTEX' or 'GROUP'; a
    vertex of another object (props.anchor_object): (its name, the index)."""
    kind = kind or props.anchor
    if kind not in ('AUTO', 'VERTEX', 'GROUP'):
        raise BakeError("anchor must be 'AUTO', 'VERTEX' or 'GROUP', got %r" % (kind,))
    other = getattr(props, "anchor_object", None)
    if kind == 'VERTEX' and other is not None and other != props.id_data:
        return (other.name, props.anchor_vertex)
    return {'AUTO': "AUTO", 'VERTEX': props.anchor_vertex, 'GROUP': props.anchor_group}[kind]
