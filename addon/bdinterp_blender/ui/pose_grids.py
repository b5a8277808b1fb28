"""Pose grids in the panel: their properties (Object.bdi_grids: each group's parameters, one
keyframable, drivable value each, the node values and the pose key of every node), the operators
(each one undo step; a failure changes nothing and reports why) and the panel section."""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, IntProperty,
                       PointerProperty, StringProperty)

from ..shapes.mesh_io import BakeError
from ..params import bake_grid, live as grid_live, setup
from .operators import ObjectOperator


def _value_changed(self, context):
    grid_live.on_value_change(self.id_data)


class BDI_GridParam(bpy.types.PropertyGroup):
    # name (inherited): the parameter's name, the key of its data path
    # "amount", not "value": Blender 3.4's glTF exporter takes any F-curve path ending in "value"
    # for a shape key's weight
    amount: FloatProperty(name="Value", default=0.0, update=_value_changed,
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


def parse_params(text):
    """"angle_x = -30, 0, 30; turn = 0, 90, 180, 270 wrap" -> pose_grid's params."""
    out = {}
    for part in filter(str.strip, text.split(";")):
        name, sep, values = part.partition("=")
        if not sep or not name.strip():
            raise BakeError("parameters: write name = values; got %r" % part.strip())
        wrap = values.strip().endswith("wrap")
        values = values.strip()[:-4] if wrap else values
        try:
            numbers = [float(x) for x in values.split(",")]
        except ValueError as exc:
            raise BakeError("parameter %r: values must be numbers, got %r"
                            % (name.strip(), values.strip())) from exc
        out[name.strip()] = {"values": numbers, "wrap": True} if wrap else numbers
    return out


def parse_keys(text):
    """"-30, -30: Look_down_left; 0, 0: Basis" -> pose_grid's keys."""
    out = {}
    for part in filter(str.strip, text.split(";")):
        node, sep, key = part.partition(":")
        try:
            values = tuple(float(x) for x in node.split(","))
        except ValueError as exc:
            raise BakeError("keys: write values: key name; got %r" % part.strip()) from exc
        if not sep or not key.strip():
            raise BakeError("keys: node %r has no key name" % node.strip())
        out[values if len(values) > 1 else values[0]] = key.strip()
    return out


class BDINTERP_OT_pose_grid_add(ObjectOperator, bpy.types.Operator):
    """Set up a pose grid: parameters whose values name shape keys at the grid's nodes (the
    selected meshes follow the active one's parameters)"""
    bl_idname = "bdinterp.pose_grid_add"
    bl_label = "Add Pose Grid"

    name: StringProperty(name="Name", default="grid")
    params: StringProperty(name="Parameters", default="angle_x = -30, 0, 30",
                           description="name = values; ... (append 'wrap' for an angle on a circle)")
    keys: StringProperty(name="Keys", default="0: Basis",
                         description="node values: shape key; ... (one value per parameter)")
    fill: BoolProperty(name="Fill Missing Nodes", default=False,
                       description="Make a node without a key from its row and column neighbours")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self, width=420)

    def run(self, context, obj):
        others = [o for o in context.selected_objects if o != obj and o.type == 'MESH']
        paths = setup.pose_grid([obj] + others, parse_params(self.params), parse_keys(self.keys),
                                name=self.name, fill=self.fill)
        made = obj.bdi_grids[self.name].made
        return "Pose grid %r: %s%s" % (self.name, ", ".join(paths), "; made " + made if made else "")


class BDINTERP_OT_pose_grid_remove(ObjectOperator, bpy.types.Operator):
    """Remove the pose grid (the keys stay)"""
    bl_idname = "bdinterp.pose_grid_remove"
    bl_label = "Remove Pose Grid"

    name: StringProperty(name="Name")

    def run(self, context, obj):
        setup.remove_pose_grid(obj, self.name)


class BDINTERP_OT_pose_grid_bone(ObjectOperator, bpy.types.Operator):
    """Drive the parameter by a bone's rotation: two angles map to its first and last values"""
    bl_idname = "bdinterp.pose_grid_bone"
    bl_label = "Drive by Bone"

    grid: StringProperty(name="Grid")
    param: StringProperty(name="Parameter")
    armature: StringProperty(name="Armature")
    bone: StringProperty(name="Bone")
    axis: EnumProperty(name="Axis", items=[(a, a, "") for a in "XYZ"], default='Z')
    angle0: FloatProperty(name="Angle at First Value", default=-45.0)
    angle1: FloatProperty(name="Angle at Last Value", default=45.0)

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self, width=360)

    def draw(self, context):
        layout = self.layout
        layout.prop_search(self, "armature", bpy.data, "objects")
        arm = bpy.data.objects.get(self.armature)
        if arm is not None and arm.type == 'ARMATURE':
            layout.prop_search(self, "bone", arm.data, "bones")
        for name in ("axis", "angle0", "angle1"):
            layout.prop(self, name)

    def run(self, context, obj):
        setup.drive_by_bone(obj, self.grid, self.param, bpy.data.objects.get(self.armature),
                            self.bone, self.axis, (self.angle0, self.angle1))
        return "%s driven by %s" % (self.param, self.bone)


class BDINTERP_OT_pose_grid_bake(ObjectOperator, bpy.types.Operator):
    """Bake the grid's in-betweens on a finer grid as keys that drivers blend linearly (plays and
    exports without the add-on)"""
    bl_idname = "bdinterp.pose_grid_bake"
    bl_label = "Bake Grid"

    name: StringProperty(name="Name")
    n: IntProperty(name="Per Cell Side", min=1, soft_max=8, default=2)

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def run(self, context, obj):
        keys, error = bake_grid.bake_grid(obj, self.name, self.n)
        return "Baked %d keys; largest error %.3g of the size" % (len(keys), error)


class BDINTERP_PT_pose_grids(bpy.types.Panel):
    bl_space_type, bl_region_type, bl_category = 'VIEW_3D', 'UI', "bdinterp"
    bl_label = "Pose Grids"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == 'MESH'

    def draw(self, context):
        layout, obj = self.layout, context.object
        layout.operator("bdinterp.pose_grid_add", icon='ADD')
        for group in obj.bdi_grids:
            box = layout.box()
            row = box.row()
            row.label(text=group.name, icon='MESH_GRID')
            row.operator("bdinterp.pose_grid_bake", text="", icon='SHAPEKEY_DATA').name = group.name
            row.operator("bdinterp.pose_grid_remove", text="", icon='X').name = group.name
            for item in group.params:
                row = box.row(align=True)
                row.prop(item, "amount", text=item.name)  # keyframable, drivable
                op = row.operator("bdinterp.pose_grid_bone", text="", icon='BONE_DATA')
                op.grid, op.param = group.name, item.name
            if group.made:
                box.label(text="Made: " + group.made, icon='INFO')
        if obj.bdi_grid_error:
            layout.label(text=obj.bdi_grid_error, icon='ERROR')
        elif len(obj.bdi_grids):
            for name, text in grid_live.reports(obj).items():
                layout.label(text="%s: %s" % (name, text), icon='INFO')


CLASSES = (BDI_GridParam, BDI_GridNode, BDI_GridMember, BDI_PoseGrid, BDINTERP_OT_pose_grid_add,
           BDINTERP_OT_pose_grid_remove, BDINTERP_OT_pose_grid_bone, BDINTERP_OT_pose_grid_bake,
           BDINTERP_PT_pose_grids)


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
