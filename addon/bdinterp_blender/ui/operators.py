"""Operators: thin wrappers that read Object.bdi, call api.py and report.

Every operator validates and computes before it writes, so a failure (reported as an error)
changes nothing; each is one undo step.
"""

import threading

import bpy
from bpy.props import EnumProperty, IntProperty

from .. import api
from ..keys.character import selected_meshes
from ..shapes.settings import CURVE_NODE, from_props
from ..keys import posing


def settings_for(props, objs=None):
    """The BakeSettings of a bake of objs from the panel settings props (Object.bdi): the error
    bound's factors are computed for those objects."""
    settings = from_props(props)
    if props.use_error_bound and not props.use_factors:
        if settings.method != 'bdi':
            raise api.BakeError("the error bound measures bdi in-betweens: choose Method bdi")
        settings = settings.but(factors=api.factors_within(objs, settings, props.error_bound))
    return settings


class StepThread:
    """A job's steps (job.step()) on a thread of their own, one at a time, so that the window keeps
    drawing and Esc is answered while a step computes (the core releases the GIL). A cancelled
    job's step in flight ends on its own; its frames are dropped. A step that fails, with an
    exception of any type, ends the job: from then on poll() raises that exception and starts no
    further step."""

    def __init__(self, job):
        self.job, self.thread, self.error = job, None, None

    def poll(self):
        """True once every step is done; else starts the next step when none runs. Raises the
        error of a step that failed (every call after the failure)."""
        if self.thread is not None and self.thread.is_alive():
            return False
        if self.error is not None:
            raise self.error
        if self.job.finished:
            return True
        self.thread = threading.Thread(target=self._step, daemon=True)
        self.thread.start()
        return False

    def _step(self):
        try:
            self.job.step()
        except BaseException as exc:  # noqa: BLE001 -- any type: reported by poll() on the main thread
            self.error = exc


def failure(exc):
    """What an error says to the user: its message, with its type unless it is one of the
    add-on's expected ones (BakeError, the core's ValueError and SolverError)."""
    if isinstance(exc, (ValueError, RuntimeError)):
        return str(exc)
    return "%s: %s" % (type(exc).__name__, exc)


class ObjectOperator:
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.object
        if obj is None or obj.type != 'MESH':
            cls.poll_message_set("Select a mesh object")
            return False
        return True

    def execute(self, context):
        try:
            message = self.run(context, context.object)
        except (ValueError, RuntimeError) as exc:  # BakeError, core ValueError, SolverError
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        if message:
            self.report({'INFO'}, message)
        return {'FINISHED'}


# The bake running from the UI (BDINTERP_OT_bake.modal): (done, total) for the panel, or None.
PROGRESS = {"bake": None}


def progress_text():
    """'Baking k of n (Esc to cancel)' while a bake runs from the UI, else ''."""
    running = PROGRESS["bake"]
    return "Baking %d of %d (Esc to cancel)" % running if running else ""


def _show_progress(context, done, total):
    """The bake's progress in the panel and the status bar (None: the bake has ended)."""
    PROGRESS["bake"] = None if done is None else (done, total)
    workspace = getattr(context, "workspace", None)
    if workspace is not None:
        workspace.status_text_set(progress_text() or None)
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


class _Bake(ObjectOperator):
    """A bake of self.job(context): all at once from scripts, or from the UI on a thread with
    progress and Esc, after asking when the pose tears joints apart (unless confirmed)."""
    confirmed: bpy.props.BoolProperty(name="Torn joints confirmed", options={'HIDDEN', 'SKIP_SAVE'})

    def run(self, context, obj):  # scripts and EXEC_DEFAULT: all at once
        wm = context.window_manager
        job = self.job(context)
        wm.progress_begin(0, job.total)
        try:
            api.run(job, lambda done, total: wm.progress_update(done))
            return job.finish().message
        finally:
            wm.progress_end()

    def invoke(self, context, event):
        """From the UI: the chunks of frames on a thread (StepThread), progress per chunk, Esc
        cancels; the keys are written on the main thread at the end."""
        try:
            self._job = self.job(context)
            torn = [] if self.confirmed else torn_of(self._job)
            self._steps = StepThread(self._job)
        except (ValueError, RuntimeError) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        if torn:  # asked first; the dialog's OK bakes (confirmed)
            bpy.ops.bdinterp.confirm_torn('INVOKE_DEFAULT', report=posing.describe(torn),
                                          rebake=self.bl_idname == "bdinterp.rebake",
                                          owner=getattr(self, "owner", ""),
                                          slider=getattr(self, "slider", ""))
            return {'CANCELLED'}
        wm = context.window_manager
        wm.progress_begin(0, self._job.total)
        _show_progress(context, 0, self._job.total)
        self._timer = wm.event_timer_add(0.01, window=context.window)
        wm.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        _show_progress(context, None, None)

    def modal(self, context, event):
        if event.type == 'ESC':
            self._stop(context)
            self.report({'WARNING'}, "Bake cancelled after %d of %d in-betweens: nothing written"
                        % (self._job.job.done, self._job.total))
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}  # keep the file as it is until the bake is written
        try:
            done = self._steps.poll()
            context.window_manager.progress_update(self._job.job.done)
            if PROGRESS["bake"] != (self._job.job.done, self._job.total):
                _show_progress(context, self._job.job.done, self._job.total)
            if not done:
                return {'RUNNING_MODAL'}
            message = self._job.finish().message
        except Exception as exc:  # noqa: BLE001 -- a step's error of any type ends the bake, said once
            self._stop(context)
            self.report({'ERROR'}, failure(exc))
            return {'CANCELLED'}
        self._stop(context)
        self.report({'INFO'}, message)
        return {'FINISHED'}


def torn_of(job):
    """The joints the pose of a character's BakeJob tears apart (posing.torn_joints)."""
    objs = getattr(job, "objects", None)  # a character's (one object has no joints to tear)
    if not objs:
        return []
    return posing.torn_joints(objs, job.inp.others[0].name, job.inp.source.name)


class BDINTERP_OT_bake(_Bake, bpy.types.Operator):
    """Bake bounded-distortion in-betweens of the source and target keys into new shape keys
    (Esc cancels; nothing is written until the last in-between is computed)"""
    bl_idname = "bdinterp.bake"
    bl_label = "Bake In-betweens"

    def job(self, context):
        """The BakeJob of the active object's settings and the selected objects."""
        objs = selected_meshes(context)
        return api.job_of(objs, settings_for(context.object.bdi, objs))


class BDINTERP_OT_rebake(_Bake, bpy.types.Operator):
    """Bake this character (or object) again as it was baked: the same objects, source, target
    and slider, from the settings of the object that holds the slider"""
    bl_idname = "bdinterp.rebake"
    bl_label = "Bake Again"
    owner: bpy.props.StringProperty(name="Slider owner")
    slider: bpy.props.StringProperty(name="Slider")

    def job(self, context):
        from ..keys import playback
        owner = bpy.data.objects.get(self.owner)
        record = playback.records(owner).get(self.slider) if owner is not None else None
        if record is None:
            raise api.BakeError("%r has no bake of the slider %r to bake again"
                                % (self.owner, self.slider))
        objs = [owner] + [o for o in map(bpy.data.objects.get, record.get("members", ()))
                          if o is not None and o != owner]
        settings = settings_for(owner.bdi, objs).but(source=record["source"],
                                                      target=record["target"])
        return api.job_of(objs, settings)


class BDINTERP_OT_bake_live(ObjectOperator, bpy.types.Operator):
    """Turn live mode into baked in-between keys and a playback slider animated like the live
    factor, so that the file plays and renders without the add-on"""
    bl_idname = "bdinterp.bake_live"
    bl_label = "Bake Live to Keys"

    def run(self, context, obj):
        return api.bake_live(obj).message


class BDINTERP_OT_clear(ObjectOperator, bpy.types.Operator):
    """Remove the baked in-betweens of the source and target keys, their drivers and slider
    (of every selected object that has the target key, as the bake made them)"""
    bl_idname = "bdinterp.clear"
    bl_label = "Clear Bake"

    def run(self, context, obj):
        removed = api.clear(selected_meshes(context), obj.bdi.target, obj.bdi.source or None)
        return "Removed %d baked keys" % len(removed)


class BDINTERP_OT_blend(ObjectOperator, bpy.types.Operator):
    """Bake a bounded-distortion blend of the pose keys with their weights into one key"""
    bl_idname = "bdinterp.blend"
    bl_label = "Bake Pose Blend"

    def run(self, context, obj):
        props, s = obj.bdi, from_props(obj.bdi, factors=None)
        name, k_out, k_in = api.blend(obj, [(p.key, p.weight) for p in props.poses],
                                      source=s.source, name=props.blend_name, anchor=s.anchor,
                                      planarity=s.planarity, joints=s.joints)
        return "Baked %s: max distortion %.4g (poses %.4g)" % (name, k_out, k_in)


class BDINTERP_OT_pose_add(ObjectOperator, bpy.types.Operator):
    """Add the active shape key to the poses to blend"""
    bl_idname = "bdinterp.pose_add"
    bl_label = "Add Pose to Blend"

    def run(self, context, obj):
        kb = obj.active_shape_key
        if kb is None:
            raise api.BakeError("no active shape key")
        item = obj.bdi.poses.add()
        item.key, item.weight = kb.name, 0.0
        return None


class BDINTERP_OT_pose_remove(ObjectOperator, bpy.types.Operator):
    """Remove this pose from the blend"""
    bl_idname = "bdinterp.pose_remove"
    bl_label = "Remove Pose"
    index: IntProperty()

    def run(self, context, obj):
        if not 0 <= self.index < len(obj.bdi.poses):
            raise api.BakeError("no pose %d" % self.index)
        obj.bdi.poses.remove(self.index)
        return None


class BDINTERP_OT_anchor_from_selection(ObjectOperator, bpy.types.Operator):
    """Anchor the interpolation at the active (or first) selected vertex"""
    bl_idname = "bdinterp.anchor_from_selection"
    bl_label = "Use Selected Vertex"

    def run(self, context, obj):
        # several objects in edit mode: the vertex may be another object's (of a character)
        others = [o for o in getattr(context, "objects_in_mode", None) or () if o != obj]
        found = next(((o, i) for o in [obj] + others for i in [selected_vertex(o)] if i is not None),
                     None)
        if found is None:
            raise api.BakeError("no vertex selected")
        owner, index = found
        obj.bdi.anchor, obj.bdi.anchor_vertex = 'VERTEX', index
        obj.bdi.anchor_object = owner if owner != obj else None
        return "Anchor: vertex %d%s" % (index, " of %s" % owner.name if owner != obj else "")


def selected_vertex(obj):
    """The active (or first) selected vertex of obj's mesh, or None."""
    if obj.mode == 'EDIT':
        import bmesh
        bm = bmesh.from_edit_mesh(obj.data)
        active = bm.select_history.active
        if isinstance(active, bmesh.types.BMVert):
            return active.index
        return next((v.index for v in bm.verts if v.select), None)
    return next((v.index for v in obj.data.vertices if v.select), None)


class BDINTERP_OT_distortion(ObjectOperator, bpy.types.Operator):
    """Show the per-face conformal distortion of the active baked or live key as colours"""
    bl_idname = "bdinterp.distortion"
    bl_label = "Distortion View"
    action: EnumProperty(items=[('TOGGLE', "Toggle", ""), ('SHOW', "Show", ""), ('HIDE', "Hide", "")])

    def run(self, context, obj):
        show = not obj.bdi.distortion_visible if self.action == 'TOGGLE' else self.action == 'SHOW'
        if not show:
            api.hide_distortion(obj)
            return None
        k = api.show_distortion(obj)
        return "Distortion of %s: max %.4g" % (obj.active_shape_key.name, float(k.max()))


class BDINTERP_OT_easing_curve_new(ObjectOperator, bpy.types.Operator):
    """Create a custom easing curve (x: slider position, y: interpolation factor)"""
    bl_idname = "bdinterp.easing_curve_new"
    bl_label = "New Curve"

    def run(self, context, obj):
        tree = bpy.data.node_groups.new(".bdi_easing_" + obj.name, 'ShaderNodeTree')
        tree.nodes.new('ShaderNodeFloatCurve').name = CURVE_NODE  # default: the diagonal
        obj.bdi.easing_curve, obj.bdi.easing = tree, 'CUSTOM'
        return None


class BDINTERP_OT_bake_export(ObjectOperator, bpy.types.Operator):
    """Write what the playback slider shows at every frame of the scene's range as keyframes on
    the baked keys (drivers muted), so that glTF, FBX and Alembic exports play the in-betweens"""
    bl_idname = "bdinterp.bake_export"
    bl_label = "Bake for Export"

    def run(self, context, obj):
        return api.bake_for_export(export_objects(context))


class BDINTERP_OT_remove_export(ObjectOperator, bpy.types.Operator):
    """Remove the keyframes of Bake for Export and let the playback slider drive the keys again"""
    bl_idname = "bdinterp.remove_export"
    bl_label = "Remove Export Bake"

    def run(self, context, obj):
        return "Removed the export bake of %d objects" % api.remove_export_bake(export_objects(context))


def export_objects(context):
    """The active object and the selected mesh objects that hold a bake."""
    from ..names import BAKES_PROP
    return [o for o in selected_meshes(context) if o == context.object or o.get(BAKES_PROP)]


CLASSES = (BDINTERP_OT_bake, BDINTERP_OT_rebake, BDINTERP_OT_bake_live, BDINTERP_OT_clear, BDINTERP_OT_blend,
           BDINTERP_OT_pose_add, BDINTERP_OT_pose_remove, BDINTERP_OT_anchor_from_selection, BDINTERP_OT_distortion,
           BDINTERP_OT_easing_curve_new, BDINTERP_OT_bake_export, BDINTERP_OT_remove_export)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
