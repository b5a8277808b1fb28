"""Sidebar panel: 3D View > Sidebar (N) > bdinterp.

Icons are ones Blender has from 3.4 through 5.x (tests/blender/test_ui.py checks each against
the running Blender's icon list); text wraps to the region's width.
"""

import json
import textwrap

import bpy

from ..core import PACKAGE
from ..names import LIVE_WARNING

CORE_ERROR = ""  # set by __init__.register when the compiled core does not match this Blender


def wrap_width(context, fallback=48):
    """Characters per line that fit the region (~7 px a character at UI scale 1)."""
    region = getattr(context, "region", None)
    if region is None or region.width <= 1:
        return fallback
    return max(16, int((region.width - 40) / (7.0 * context.preferences.view.ui_scale)))


def draw_message(layout, text, icon='ERROR', width=48):
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, max(8, width))):
        col.label(text=line, icon=icon if i == 0 else 'BLANK1')


def _source_name(obj):
    key = obj.data.shape_keys
    return obj.bdi.source or key.reference_key.name


def _bake_of(obj):
    from ..keys import playback
    if not obj.bdi.target or obj.data.shape_keys.key_blocks.get(_source_name(obj)) is None:
        return None
    return playback.find(obj, _source_name(obj), obj.bdi.target)


class _Panel:
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "bdinterp"

    @classmethod
    def poll(cls, context):
        obj = context.object
        return (not CORE_ERROR and obj is not None and obj.type == 'MESH'
                and obj.data.shape_keys is not None and len(obj.data.shape_keys.key_blocks) >= 2)


class BDINTERP_PT_main(_Panel, bpy.types.Panel):
    bl_label = "bdinterp"

    @classmethod
    def poll(cls, context):
        return True  # always visible: it explains what is missing

    def draw(self, context):
        layout, obj = self.layout, context.object
        if CORE_ERROR:
            draw_message(layout, CORE_ERROR, width=wrap_width(context))
            return
        if obj is None or obj.type != 'MESH':
            draw_message(layout, "Select a flat mesh with shape keys", icon='INFO',
                         width=wrap_width(context))
            return
        key = obj.data.shape_keys
        if key is None or len(key.key_blocks) < 2:
            draw_message(layout, "Add a pose: a key on every selected piece", icon='INFO',
                         width=wrap_width(context))
            layout.operator("bdinterp.add_pose", icon='ADD')
            return
        props = obj.bdi
        col = layout.column(align=True)
        col.prop_search(props, "source", key, "key_blocks", text="Source")
        if not props.source:
            col.label(text="Empty: %s (reference)" % key.reference_key.name, icon='BLANK1')
        row = col.row(align=True)
        row.prop_search(props, "target", key, "key_blocks", text="Target")
        row.operator("bdinterp.add_pose", text="", icon='ADD')
        if props.live:
            draw_message(layout, "Live: %s %s" % (obj.name, LIVE_WARNING), icon='INFO',
                         width=wrap_width(context))


class BDINTERP_PT_inbetweens(_Panel, bpy.types.Panel):
    bl_label = "In-betweens"
    bl_parent_id = "BDINTERP_PT_main"

    def draw(self, context):
        layout, obj = self.layout, context.object
        props = obj.bdi
        layout.prop(props, "use_factors", text="Explicit Factors")
        if not props.use_factors:
            layout.prop(props, "use_error_bound", text="Error Bound")
        layout.prop(props, "factors" if props.use_factors else
                    "error_bound" if props.use_error_bound else "count")
        if not (props.use_factors or props.use_error_bound):
            layout.prop(props, "easing", text="Easing")
            if props.easing == 'CUSTOM':
                node = props.easing_curve.nodes.get("Easing") if props.easing_curve else None
                if node is None:
                    layout.operator("bdinterp.easing_curve_new", icon='ADD')
                else:
                    layout.template_curve_mapping(node, "mapping")
        box = layout.box()
        box.prop(props, "anchor", text="Anchor")
        if props.anchor == 'VERTEX':
            row = box.row(align=True)
            row.prop(props, "anchor_vertex", text="Vertex")
            row.operator("bdinterp.anchor_from_selection", text="", icon='RESTRICT_SELECT_OFF')
            box.prop(props, "anchor_object", text="Of")  # a character's: any of its objects
        elif props.anchor == 'GROUP':
            box.prop_search(props, "anchor_group", obj, "vertex_groups", text="Group")
        box.prop(props, "anchor_path", text="Path")
        layout.prop(props, "drivers", text="Playback Slider")
        together = character_size(context, obj)
        if together > 1:
            draw_message(layout, "Bakes %d selected objects as one character (slider here)"
                         % together, icon='INFO', width=wrap_width(context))
        from .operators import progress_text
        running = progress_text()
        if running:  # the bake runs on a thread: say so where the button was
            draw_message(layout, running, icon='TIME', width=wrap_width(context))
        else:
            row = layout.row(align=True)
            row.scale_y = 1.4
            row.operator("bdinterp.bake", icon='SHAPEKEY_DATA')
            row.operator("bdinterp.clear", text="", icon='TRASH')
        draw_export(layout, obj)
        draw_bake(layout, context, obj)


def draw_export(layout, obj):
    """Bake for Export, or its removal where the keys carry an export bake."""
    from ..keys.export import EXPORT_PROP
    row = layout.row(align=True)
    row.operator("bdinterp.bake_export", icon='EXPORT')
    if obj.get(EXPORT_PROP) is not None:
        row.operator("bdinterp.remove_export", text="", icon='X')


def character_size(context, obj):
    """How many mesh objects a bake solves together: the active one and the selected ones that
    have the target key."""
    from ..keys.character import members, selected_meshes
    return len(members(selected_meshes(context, obj), obj.bdi.target))


def draw_bake(layout, context, obj):
    """The playback slider of the current pair's bake (found also after a rename), its status
    (stale when any object baked with this one changed since: Bake Again), and the result box."""
    width = wrap_width(context)
    found = _bake_of(obj)
    owner = found.record.get("owner", obj.name) if found is not None else obj.name
    if owner != obj.name:  # baked as part of a character: the slider is on another object
        draw_message(layout, "Played by the slider %r of %r" % (found.slider, owner), icon='INFO',
                     width=width)
    elif found is not None and found.slider in obj.keys():
        layout.prop(obj, '["%s"]' % found.slider, text="Playback", slider=True)
        if found.status == "renamed":
            draw_message(layout, "Bake of the renamed target (slider %r); bake again to rename "
                         "its keys" % found.slider, icon='INFO', width=width)
    if found is not None and found.status != "renamed":
        draw_stale(layout, obj, found, owner, width)
    missing = [] if found is None else [name for name in found.keys if name not in
                                        obj.data.shape_keys.key_blocks]
    draw_result(layout, obj.bdi.result, width, missing)


def draw_stale(layout, obj, found, owner, width):
    """'Stale' naming the objects whose keys changed since the bake, with Bake Again."""
    from ..keys.playback import stale_members
    stale = stale_members(obj, found)
    if not stale:
        return
    names = ", ".join(repr(name) for name in stale[:3]) + (" and %d more" % (len(stale) - 3)
                                                            if len(stale) > 3 else "")
    draw_message(layout, "Stale: the keys of %s changed after this bake" % names, icon='ERROR',
                 width=width)
    op = layout.operator("bdinterp.rebake", icon='FILE_REFRESH')
    op.owner, op.slider = owner, found.slider


def draw_result(layout, text, width, missing=()):
    """The result box of the last bake: keys written (and those deleted since), max K against
    the inputs', folded polygons, time, and any note."""
    try:
        r = json.loads(text) if text else None
    except ValueError:
        r = None
    if not r:
        return
    box = layout.box()
    col = box.column(align=True)
    col.label(text="Last bake", icon='INFO')
    col.label(text="%s -> %s" % (r["source"], r["target"]))
    col.label(text="Keys written: %d" % r["keys"])
    if missing:
        draw_message(col, "%d of them deleted since (%s): bake again" % (
            len(missing), ", ".join(missing[:2]) + (", ..." if len(missing) > 2 else "")),
            width=width - 2)
    ok = r["max_distortion"] <= r["input_distortion"] * (1 + 1e-6)
    col.label(text="Max K %.4g (inputs %.4g)" % (r["max_distortion"], r["input_distortion"]),
              icon='CHECKMARK' if ok else 'ERROR')
    col.label(text="Folded polygons: %d" % r["folded"], icon='CHECKMARK' if not r["folded"] else 'ERROR')
    if r.get("objects", 1) > 1:
        col.label(text="Objects: %d (one character)" % r["objects"])
    if r.get("joints"):
        col.label(text="Joints between pieces: %d%s" % (r["joints"], " (%s)" % r["joint_source"]
                                                          if r.get("joint_source") else ""))
    col.label(text="Time: %.2f s" % r["seconds"])
    if r.get("note"):
        draw_message(col, r["note"], icon='INFO', width=width - 2)


class BDINTERP_PT_expert(_Panel, bpy.types.Panel):
    bl_label = "Expert"
    bl_parent_id = "BDINTERP_PT_inbetweens"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout, props = self.layout, context.object.bdi
        split = self.layout.split(factor=0.3)  # "Method" in full beside a wide drop-down
        split.label(text="Method")
        split.prop(props, "method", text="")
        layout.prop(props, "tolerance", text="Planarity")
        layout.prop(props, "joints", text="Joints")
        from ..view import joint_view
        error = joint_view.draw_settings(layout, context)
        if error:
            draw_message(layout, error, width=wrap_width(context))


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
            row.prop_search(item, "key", key, "key_blocks", text="Pose")
            row.prop(item, "weight", text="Weight", slider=True)
            row.operator("bdinterp.pose_remove", text="", icon='X').index = i
        col.operator("bdinterp.pose_add", text="Add Active Key", icon='ADD')
        layout.prop(props, "blend_name", text="Key")
        layout.operator("bdinterp.blend", icon='SHAPEKEY_DATA')


class BDINTERP_PT_live(_Panel, bpy.types.Panel):
    bl_label = "Live"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw_header(self, context):
        self.layout.prop(context.object.bdi, "live", text="")

    def draw(self, context):
        layout, props = self.layout, context.object.bdi
        width = wrap_width(context)
        layout.prop(props, "live_mode", expand=True)
        if props.live_mode == 'INTERPOLATE':
            layout.prop(props, "live_factor", text="Factor")  # keyframable (I over the field)
        else:
            layout.label(text="Weights: see Pose Blend (keyframable)")
        if props.live:
            if props.live_objects:
                draw_message(layout, "A character: %d more objects follow this factor"
                             % len(props.live_objects), icon='INFO', width=width)
            draw_message(layout, "This object " + LIVE_WARNING, icon='INFO', width=width)
            layout.operator("bdinterp.bake_live", icon='SHAPEKEY_DATA')
        if props.live_error:
            draw_message(layout, props.live_error, width=width)


class BDINTERP_PT_distortion(_Panel, bpy.types.Panel):
    bl_label = "Distortion"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        props = context.object.bdi
        self.layout.operator("bdinterp.distortion", depress=props.distortion_visible,
                             text="Hide Distortion" if props.distortion_visible else
                             "Show Distortion of Active Key", icon='MOD_WARP').action = 'TOGGLE'
        if props.distortion_visible:
            col = self.layout.column(align=True)
            col.label(text="Blue: no worse than the inputs")
            col.label(text="Red: worse (2x the inputs' K)")


class BDINTERP_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = PACKAGE  # the add-on's own name, as Blender lists it

    def draw(self, context):
        from ..core import build_info
        info = build_info()
        if CORE_ERROR:
            draw_message(self.layout, CORE_ERROR, width=wrap_width(context, 90))
        else:
            self.layout.label(text="Compiled core for Python %s (%s)" % (
                info.get("python", "?"), info.get("ext_suffix", "source checkout")), icon='CHECKMARK')


class BDINTERP_PT_view(_Panel, bpy.types.Panel):
    bl_label = "Onion Skins & Trails"
    bl_parent_id = "BDINTERP_PT_main"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        from ..view import onion
        error = onion.draw_settings(self.layout, context)
        if error:
            draw_message(self.layout, error, width=wrap_width(context))


PANELS = (BDINTERP_PT_main, BDINTERP_PT_inbetweens, BDINTERP_PT_expert, BDINTERP_PT_poses,
          BDINTERP_PT_live, BDINTERP_PT_distortion, BDINTERP_PT_view)
CLASSES = PANELS + (BDINTERP_AP_preferences,)
class degraded:
    """Registered instead of everything else when the core cannot load: explains why."""
    register, unregister = bpy.utils.register_classes_factory((BDINTERP_PT_main, BDINTERP_AP_preferences))


register, unregister = bpy.utils.register_classes_factory(CLASSES)
