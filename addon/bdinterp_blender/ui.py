"""Sidebar panel: 3D View > Sidebar (N) > bdinterp."""

import textwrap

import bpy

CORE_ERROR = ""  # set by __init__.register when the compiled core does not match this Blender


def draw_message(layout, text, icon='ERROR', width=48):
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, width)):
        col.label(text=line, icon=icon if i == 0 else 'BLANK1')


def _pair_slider(obj):
    from . import playback
    key = obj.data.shape_keys
    if not obj.bdi.target or key.key_blocks.get(obj.bdi.source or key.reference_key.name) is None:
        return None
    prop = playback.slider_name(key, obj.bdi.source or key.reference_key.name, obj.bdi.target)
    return prop if prop in obj.keys() else None


class _Panel:
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "bdinterp"

    @classmethod
    def poll(cls, context):
        obj = context.object
        return (obj is not None and obj.type == 'MESH' and obj.data.shape_keys is not None
                and len(obj.data.shape_keys.key_blocks) >= 2)


class BDINTERP_PT_main(_Panel, bpy.types.Panel):
    bl_label = "bdinterp"

    @classmethod
    def poll(cls, context):
        return True  # always visible: it explains what is missing

    def draw(self, context):
        layout, obj = self.layout, context.object
        if CORE_ERROR:
            draw_message(layout, CORE_ERROR)
            return
        if obj is None or obj.type != 'MESH':
            layout.label(text="Select a planar mesh with shape keys", icon='INFO')
            return
        key = obj.data.shape_keys
        if key is None or len(key.key_blocks) < 2:
            layout.label(text="Add at least two shape keys", icon='INFO')
            return
        props = obj.bdi
        col = layout.column(align=True)
        col.prop_search(props, "source", key, "key_blocks", text="Source")
        col.prop_search(props, "target", key, "key_blocks", text="Target")
        layout.prop(props, "method", text="")


class BDINTERP_PT_inbetweens(_Panel, bpy.types.Panel):
    bl_label = "In-betweens"
    bl_parent_id = "BDINTERP_PT_main"

    def draw(self, context):
        layout, obj = self.layout, context.object
        props = obj.bdi
        row = layout.row(align=True)
        row.prop(props, "use_factors", text="", icon='LINENUMBERS_ON')
        row.prop(props, "factors" if props.use_factors else "count")
        if not props.use_factors:
            layout.prop(props, "easing")
            if props.easing == 'CUSTOM':
                node = props.easing_curve.nodes.get("Easing") if props.easing_curve else None
                if node is None:
                    layout.operator("bdinterp.easing_curve_new", icon='ADD')
                else:
                    layout.template_curve_mapping(node, "mapping")
        box = layout.box()
        box.prop(props, "anchor")
        if props.anchor == 'VERTEX':
            row = box.row(align=True)
            row.prop(props, "anchor_vertex")
            row.operator("bdinterp.anchor_from_selection", text="", icon='RESTRICT_SELECT_OFF')
        elif props.anchor == 'GROUP':
            box.prop_search(props, "anchor_group", obj, "vertex_groups")
        box.prop(props, "anchor_path")
        layout.prop(props, "tolerance")
        layout.prop(props, "drivers")
        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator("bdinterp.bake", icon='SHAPEKEY_DATA')
        row.operator("bdinterp.clear", text="", icon='TRASH')
        slider = _pair_slider(obj)
        if slider:
            layout.prop(obj, '["%s"]' % slider, text="Playback", slider=True)


class BDINTERP_PT_poses(_Panel, bpy.types.Panel):
    bl_label = "Pose Blend"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout, obj = self.layout, context.object
        props, key = obj.bdi, obj.data.shape_keys
        col = layout.column(align=True)
        for i, item in enumerate(props.poses):
            row = col.row(align=True)
            row.prop_search(item, "key", key, "key_blocks", text="")
            row.prop(item, "weight", text="", slider=True)
            row.operator("bdinterp.pose_remove", text="", icon='X').index = i
        col.operator("bdinterp.pose_add", text="Add Active Key", icon='ADD')
        layout.prop(props, "blend_name")
        layout.operator("bdinterp.blend", icon='MOD_SHAPEKEY')


class BDINTERP_PT_live(_Panel, bpy.types.Panel):
    bl_label = "Live"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw_header(self, context):
        self.layout.prop(context.object.bdi, "live", text="")

    def draw(self, context):
        layout, props = self.layout, context.object.bdi
        layout.prop(props, "live_mode", expand=True)
        if props.live_mode == 'INTERPOLATE':
            layout.prop(props, "live_factor")  # keyframable (I over the field)
        else:
            layout.label(text="Weights: see Pose Blend (keyframable)")
        if props.live_error:
            draw_message(layout, props.live_error)


class BDINTERP_PT_distortion(_Panel, bpy.types.Panel):
    bl_label = "Distortion"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        props = context.object.bdi
        self.layout.operator("bdinterp.distortion", depress=props.distortion_visible,
                             text="Hide Distortion" if props.distortion_visible else
                             "Show Distortion of Active Key", icon='MOD_WARP').action = 'TOGGLE'


class BDINTERP_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    def draw(self, context):
        from .core import build_info
        info = build_info()
        if CORE_ERROR:
            draw_message(self.layout, CORE_ERROR, width=90)
        else:
            self.layout.label(text="Compiled core for Python %s (%s)" % (
                info.get("python", "?"), info.get("ext_suffix", "source checkout")), icon='CHECKMARK')


CLASSES = (BDINTERP_PT_main, BDINTERP_PT_inbetweens, BDINTERP_PT_poses, BDINTERP_PT_live,
           BDINTERP_PT_distortion, BDINTERP_AP_preferences)


class degraded:
    """Registered instead of everything else when the core cannot load: explains why."""
    register, unregister = bpy.utils.register_classes_factory((BDINTERP_PT_main, BDINTERP_AP_preferences))


register, unregister = bpy.utils.register_classes_factory(CLASSES)
