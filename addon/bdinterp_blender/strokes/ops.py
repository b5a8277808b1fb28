"""The Grease Pencil operator (in the Draw and Grease Pencil menus, beside Blender's Interpolate
Sequence) and its sidebar panel, which in Blender before 4.3 says what it needs."""

import bpy

from ..shapes.mesh_io import BakeError
from ..timing import EASINGS
from .drawing import interpolate_drawing, keys_around, why_not

MODES = {'PAINT_GREASE_PENCIL', 'EDIT', 'OBJECT'}   # draw, edit (a Grease Pencil's edit mode is EDIT)
EASING_ITEMS = [(name, name.replace("_", " ").title(), "") for name in EASINGS]


class BDINTERP_OT_interpolate_drawing(bpy.types.Operator):
    """Make in-betweens between the previous and next keyframe of the active layer (or of all
    layers) whose strokes turn and bend with bounded distortion instead of moving on straight lines"""
    bl_idname = "bdinterp.interpolate_drawing"
    bl_label = "Interpolate Sequence (bdinterp)"
    bl_options = {'REGISTER', 'UNDO'}

    layers: bpy.props.EnumProperty(name="Layer", items=[('ACTIVE', "Active", "The active layer"),
                                                         ('ALL', "All", "Every layer with keys there")])
    use_selection: bpy.props.BoolProperty(name="Only Selected", default=False,
                                          description="Interpolate only the selected strokes")
    spacing: bpy.props.EnumProperty(name="Spacing", items=[('COUNT', "Count", "A number of in-betweens"),
                                                           ('STEP', "Step", "An in-between every few frames")])
    count: bpy.props.IntProperty(name="In-betweens", default=3, min=1, soft_max=50)
    step: bpy.props.IntProperty(name="Step", default=1, min=1, soft_max=20)
    easing: bpy.props.EnumProperty(name="Easing", items=EASING_ITEMS)
    fade: bpy.props.BoolProperty(name="Fade Unpaired Strokes", default=False,
                                 description="When the keys have other stroke counts, fade the strokes "
                                             "left over out (or in) instead of refusing")

    @classmethod
    def poll(cls, context):
        reason = why_not(None)
        obj = context.object
        if not reason and (obj is None or obj.type != 'GREASEPENCIL'):
            reason = "the active object is not a Grease Pencil object"
        elif not reason and obj.mode not in MODES:
            reason = "works in Draw, Edit and Object mode"
        elif not reason and obj.data.layers.active is None:
            reason = "the drawing has no active layer"
        if reason:
            cls.poll_message_set(reason)
        return not reason

    def execute(self, context):
        obj = context.object
        active = obj.data.layers.active
        try:
            frame_a, frame_b = keys_around(active, context.scene.frame_current)
            new = interpolate_drawing(obj, frame_a, frame_b, count=self.count,
                                      layers=[active.name] if self.layers == 'ACTIVE' else None,
                                      easing=self.easing, step=self.step if self.spacing == 'STEP' else None,
                                      selected=self.use_selection, fade=self.fade)
        except (BakeError, RuntimeError, ValueError) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        self.report({'INFO'}, "%d in-betweens between frames %d and %d" % (len(new), frame_a, frame_b))
        return {'FINISHED'}


def draw_menu(self, context):
    self.layout.operator(BDINTERP_OT_interpolate_drawing.bl_idname)


class BDINTERP_PT_drawing(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "bdinterp"
    bl_label = "Drawing In-betweens"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type in ('GREASEPENCIL', 'GPENCIL')

    def draw(self, context):
        layout = self.layout
        reason = why_not(None)
        if reason:
            layout.label(text=reason[0].upper() + reason[1:], icon='ERROR')
            return
        layout.operator(BDINTERP_OT_interpolate_drawing.bl_idname, text="Interpolate Sequence")


MENUS = ("VIEW3D_MT_paint_grease_pencil", "VIEW3D_MT_edit_greasepencil")


def register():
    bpy.utils.register_class(BDINTERP_OT_interpolate_drawing)
    bpy.utils.register_class(BDINTERP_PT_drawing)
    for name in MENUS:
        menu = getattr(bpy.types, name, None)
        if menu is not None and why_not(None) == "":
            menu.append(draw_menu)


def unregister():
    for name in MENUS:
        menu = getattr(bpy.types, name, None)
        if menu is not None:
            menu.remove(draw_menu)
    bpy.utils.unregister_class(BDINTERP_PT_drawing)
    bpy.utils.unregister_class(BDINTERP_OT_interpolate_drawing)
