"""Operators of posing a cut-out character: Add Pose (a key on every piece), and the dialog that
asks before a pose whose joints come apart is baked (operators.BDINTERP_OT_bake opens it)."""

import textwrap

import bpy

from .. import api
from ..keys.character import selected_meshes


class BDINTERP_OT_confirm_torn(bpy.types.Operator):
    """Some joints of the pose come apart: bake anyway?"""
    bl_idname = "bdinterp.confirm_torn"
    bl_label = "Pieces come apart"
    bl_options = {'INTERNAL'}
    report: bpy.props.StringProperty(options={'SKIP_SAVE'})
    rebake: bpy.props.BoolProperty(options={'SKIP_SAVE'})
    owner: bpy.props.StringProperty(options={'SKIP_SAVE'})
    slider: bpy.props.StringProperty(options={'SKIP_SAVE'})

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self, width=460)

    def draw(self, context):
        col = self.layout.column(align=True)
        text = ("This pose pulls pieces apart where they were joined: %s. Move them back together "
                "in the target key, or press OK to bake anyway." % self.report)
        for i, line in enumerate(textwrap.wrap(text, 60)):
            col.label(text=line, icon='ERROR' if i == 0 else 'BLANK1')

    def execute(self, context):
        """Start the bake asked about (it runs on as its own modal operator)."""
        if self.rebake:
            started = bpy.ops.bdinterp.rebake('INVOKE_DEFAULT', confirmed=True, owner=self.owner,
                                              slider=self.slider)
        else:
            started = bpy.ops.bdinterp.bake('INVOKE_DEFAULT', confirmed=True)
        return {'FINISHED'} if started & {'RUNNING_MODAL', 'FINISHED'} else {'CANCELLED'}


class BDINTERP_OT_add_pose(bpy.types.Operator):
    """Add a pose to the selected character: one new shape key on every selected piece (a copy of
    Basis, made where missing), chosen as the target; then edit the pieces and bake"""
    bl_idname = "bdinterp.add_pose"
    bl_label = "Add Pose"
    bl_options = {'REGISTER', 'UNDO'}
    name: bpy.props.StringProperty(name="Name", description="The new key's name (empty: 'Pose', "
                                   "or 'Pose 2' ... where taken)")

    @classmethod
    def poll(cls, context):
        return any(o.type == 'MESH' for o in context.selected_objects)

    def execute(self, context):
        # the active object (the panel's) and the selected meshes
        objs = [o for o in selected_meshes(context) if o is not None and o.type == 'MESH']
        try:
            name = api.add_pose(objs, self.name or None)
        except (ValueError, RuntimeError) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        self.report({'INFO'}, "Added the key %r to %d pieces: edit them, then bake"
                    % (name, len(objs)))
        return {'FINISHED'}


CLASSES = (BDINTERP_OT_confirm_torn, BDINTERP_OT_add_pose)
register, unregister = bpy.utils.register_classes_factory(CLASSES)
