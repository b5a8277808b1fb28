"""The properties of pose parameters on an object (Object.bdi_grids): each group's parameters (one
keyframable, drivable value each), the node values and the pose key of every node."""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, FloatProperty, PointerProperty,
                       StringProperty)


def _value_changed(self, context):
    from . import live
    live.on_value_change(self.id_data)


class BDI_GridParam(bpy.types.PropertyGroup):
    # name (inherited): the parameter's name, the key of its data path
    value: FloatProperty(name="Value", default=0.0, update=_value_changed,
                         description="The parameter's value: keyframe it, drive it or set it")
    values: StringProperty(name="Values", description="The node values, comma-separated")
    wrap: BoolProperty(name="Wrap", default=False,
                       description="An angle on a circle: the last value's cell reaches the first")
    period: FloatProperty(name="Period", default=360.0, description="The circle's length (wrap)")


class BDI_GridNode(bpy.types.PropertyGroup):
    index: StringProperty(name="Node", description="The node's index per parameter, comma-separated")
    key: StringProperty(name="Pose", description="The shape key at this node")


class BDI_GridMember(bpy.types.PropertyGroup):
    obj: PointerProperty(type=bpy.types.Object, name="Object")


class BDI_PoseGrid(bpy.types.PropertyGroup):
    # name (inherited): the group's name
    params: CollectionProperty(type=BDI_GridParam)
    nodes: CollectionProperty(type=BDI_GridNode)
    members: CollectionProperty(type=BDI_GridMember,
                                description="The other objects that follow these parameters")
    made: StringProperty(name="Made Nodes", description="Nodes made by fill, and their keys")


CLASSES = (BDI_GridParam, BDI_GridNode, BDI_GridMember, BDI_PoseGrid)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.bdi_grids = CollectionProperty(type=BDI_PoseGrid, name="Pose Grids")
    bpy.types.Object.bdi_grid_error = StringProperty(name="Pose Grid Error")


def unregister():
    del bpy.types.Object.bdi_grid_error
    del bpy.types.Object.bdi_grids
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
