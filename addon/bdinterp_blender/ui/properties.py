"""Per-object settings: one PropertyGroup at Object.bdi (saved in the .blend)."""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       IntProperty, PointerProperty, StringProperty)

from ..names import DEFAULT_TOLERANCE

EASING_ITEMS = [
    ('LINEAR', "Linear", "Evenly spaced in-betweens"),
    ('EASE_IN', "Ease In", "Slow start"),
    ('EASE_OUT', "Ease Out", "Slow end"),
    ('EASE_IN_OUT', "Ease In-Out", "Slow start and end"),
    ('CUSTOM', "Custom Curve", "Spacing given by a curve (x: slider position, y: factor)"),
]
ANCHOR_ITEMS = [
    ('AUTO', "Automatic", "Centroid and global rotation are blended"),
    ('VERTEX', "Vertex", "This vertex's position and the orientation of its faces are blended"),
    ('GROUP', "Vertex Group", "Use the heaviest vertex of a vertex group"),
]
# bdinterp.METHODS, spelt out (a test keeps them equal): the enum exists at registration, before
# the compiled core is loaded.
METHOD_ITEMS = [
    ('bdi', "Bounded Distortion", "Metric blending + conformal flattening (the paper)"),
    ('arap', "As-Rigid-As-Possible", "Alexa et al. 2000, for comparison"),
    ('linear', "Linear", "Plain vertex blend, for comparison"),
]


def _live_changed(self, context):
    from ..keys import live
    live.on_property_change(self.id_data)


def _live_toggled(self, context):
    from ..keys import live
    live.on_toggle(self.id_data)


def _parent_changed(self, context):
    """A joint parent set by hand: the joint tree's overlay and the live characters it is in."""
    from ..view import joint_view, onion
    joint_view.refresh()
    onion.invalidate()
    _live_changed(self, context)


class BDI_PoseItem(bpy.types.PropertyGroup):
    key: StringProperty(name="Pose", description="Shape key used as a pose", update=_live_changed)
    weight: FloatProperty(name="Weight", min=0.0, max=1.0, default=0.0, update=_live_changed,
                          description="Weight of this pose (the source gets 1 - sum)")


class BDI_ObjectItem(bpy.types.PropertyGroup):
    obj: PointerProperty(type=bpy.types.Object, name="Object", update=_live_changed,
                         description="Another object of this object's live character")


class BDI_ObjectProps(bpy.types.PropertyGroup):
    source: StringProperty(name="Source", description="Source key (empty: the reference key)",
                           update=_live_changed)
    target: StringProperty(name="Target", description="Target shape key", update=_live_changed)
    count: IntProperty(name="In-betweens", min=1, soft_max=32, default=3,
                       description="Number of in-betweens to bake")
    use_factors: BoolProperty(name="Explicit Factors", default=False,
                              description="Bake at the listed factors instead of a count")
    factors: StringProperty(name="Factors", default="0.25, 0.5, 0.75",
                            description="Interpolation factors in (0, 1), separated by commas")
    use_error_bound: BoolProperty(name="Error Bound", default=False,
                                  description="Bake the fewest in-betweens whose linear blend stays "
                                              "within the error bound of the exact in-between")
    error_bound: FloatProperty(name="Error Bound", min=1e-5, max=0.5, default=0.005, precision=4,
                               step=0.01, description="Largest distance of the linear blend of "
                               "neighbouring keys from the exact in-between, relative to the "
                               "character's size (0.005 = 0.5 %)")
    easing: EnumProperty(name="Easing", items=EASING_ITEMS, default='LINEAR')
    easing_curve: PointerProperty(type=bpy.types.NodeTree, name="Easing Curve",
                                  description="Node group holding the custom easing curve")
    anchor: EnumProperty(name="Anchor", items=ANCHOR_ITEMS, default='AUTO', update=_live_changed)
    anchor_vertex: IntProperty(name="Vertex", min=0, default=0, update=_live_changed)
    anchor_group: StringProperty(name="Group", update=_live_changed)
    anchor_path: PointerProperty(type=bpy.types.Object, name="Path", update=_live_changed,
                                 poll=lambda self, obj: obj.type == 'CURVE',
                                 description="Optional curve whose path the anchor follows")
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default='bdi', update=_live_changed)
    tolerance: FloatProperty(name="Planarity", min=0.0, default=DEFAULT_TOLERANCE, precision=6,
                             update=_live_changed,
                             description="Allowed distance of a key from the plane, relative to "
                                         "the mesh size")
    # numbered so that a file saved with the on/off switch reads on as AUTO, off as OFF
    joints: EnumProperty(name="Joints", default='AUTO', update=_live_changed, items=[
        ('AUTO', "Automatic", "The armature's bones where every piece has a bone, else pins found "
                         "from the keys", 1),
        ('BONES', "Bones", "Each piece hangs from the piece of its bone's parent, pinned at the "
                           "bone's head (Armature modifier's vertex groups, or a parent bone)", 3),
        ('PINS', "Pins", "Pieces that overlap and turn about a common point in both keys stay "
                         "joined there", 2),
        ('OFF', "Off", "Each piece follows its own rigid path", 0)])
    drivers: BoolProperty(name="Playback Slider", default=True,
                          description="Drive the baked keys from one slider with native drivers")
    poses: CollectionProperty(type=BDI_PoseItem)
    blend_name: StringProperty(name="Result Key", default="Blend.bdi")
    live: BoolProperty(name="Live", default=False, update=_live_toggled,
                       description="Recompute the exact interpolation on frame/factor changes")
    live_mode: EnumProperty(name="Live Mode", update=_live_changed, items=[
        ('INTERPOLATE', "Interpolate", "Source -> target at the live factor"),
        ('BLEND', "Pose Blend", "Blend of the poses with their weights")])
    live_factor: FloatProperty(name="Factor", default=0.5, soft_min=0.0, soft_max=1.0,
                               update=_live_changed, description="Keyframe to animate")
    live_error: StringProperty(name="Live Error")
    result: StringProperty(name="Last Result", description="Summary of the last bake (JSON)")
    live_objects: CollectionProperty(type=BDI_ObjectItem, name="Live Character",
                                     description="The other objects that live mode solves with "
                                                 "this one as one character (this one's factor)")
    anchor_object: PointerProperty(type=bpy.types.Object, name="Anchor Object",
                                   update=_live_changed, poll=lambda self, obj: obj.type == 'MESH',
                                   description="The object whose vertex anchors a character of "
                                               "several objects (empty: this one)")
    distortion_visible: BoolProperty(name="Distortion Shown", default=False)
    joint_parent: PointerProperty(type=bpy.types.Object, name="Joint Parent", update=_parent_changed,
                                  poll=lambda self, obj: obj.type == 'MESH' and obj != self.id_data,
                                  description="The object of the character this piece hangs from "
                                              "in the joint tree (empty: Automatic, as the joints "
                                              "are found or the bones say)")


CLASSES = (BDI_PoseItem, BDI_ObjectItem, BDI_ObjectProps)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.bdi = PointerProperty(type=BDI_ObjectProps)


def unregister():
    del bpy.types.Object.bdi
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
