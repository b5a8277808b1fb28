"""Bakes: a validated BakeJob computed chunk by chunk, then written (keys, drivers, record).

Under api.py (which validates arguments and calls this) and over solve/playback: the only
module that writes baked shape keys.
"""

import json
from dataclasses import dataclass, field
import time

from .. import actions, timing
from ..shapes import mesh_io, solve
from . import playback
from ..names import LIVE_KEY
from ..shapes.settings import from_props
from ..shapes.solve import Inputs, max_distortion


@dataclass
class BakeResult:
    """What a bake wrote: keys, factors, slider positions, slider property, distortion (max K of
    the in-betweens and of the target), folded polygons, seconds, and a note (e.g. why the slider
    did not take over the target key)."""
    source: str
    target: str
    max_distortion: float
    input_distortion: float
    keys: list = field(default_factory=list)
    factors: list = field(default_factory=list)
    positions: list = field(default_factory=list)
    slider: object = None
    folded: list = field(default_factory=list)
    folded_name: str = ""  # how to name folded[0] (several objects: with its object)
    joints: int = 0
    joint_source: str = ""  # where the joints came from ("bones of 'Rig'"); "" found from the keys
    objects: int = 1
    seconds: float = 0.0
    note: str = ""

    @property
    def message(self):
        text = ("Baked %d in-betweens %s -> %s: max distortion %.4g (inputs %.4g)"
                % (len(self.keys), self.source, self.target, self.max_distortion,
                   self.input_distortion))
        if self.objects > 1:
            text += " in %d objects" % self.objects
        if self.joints:
            text += "; %d joint%s between pieces" % (self.joints, "" if self.joints == 1 else "s")
            text += " (%s)" % self.joint_source if self.joint_source else ""
        if self.folded:
            text += "; %d folded polygons (e.g. %s)" % (len(self.folded), self.folded_name
                                                         or "polygon %d" % self.folded[0])
        return text + (" -- " + self.note if self.note else "")

    def summary(self):
        """JSON-able dict (the panel's result box, bake_folder.py's summary)."""
        return {"keys": len(self.keys), "source": self.source, "target": self.target,
                "max_distortion": self.max_distortion, "input_distortion": self.input_distortion,
                "folded": len(self.folded), "seconds": round(self.seconds, 3), "note": self.note,
                "joints": self.joints, "joint_source": self.joint_source, "objects": self.objects}

    def __repr__(self):
        return "BakeResult(%s)" % self.message


class BakeJob:
    """A validated bake, computed chunk by chunk (step()) and written only by finish(): the
    operator steps it from a timer so that Esc can cancel with nothing written."""

    def __init__(self, obj, settings):
        self.started, self.settings = time.perf_counter(), settings
        self.positions, ts = timing.schedule(settings.count, settings.factors, settings.easing)
        self.inp = self.inputs(obj, settings)
        self.names = timing.key_names(self.inp.others[0].name, ts)
        self.factors, self.drivers = ts, settings.drivers
        self.job = solve.FrameJob(self.inp, ts, settings.method,
                                  threads=settings.threads)

    @staticmethod
    def inputs(obj, settings):
        """The validated Inputs of the bake (a character of several objects overrides this)."""
        return Inputs(obj, settings)

    @property
    def total(self):
        return len(self.factors)

    def step(self):
        """Compute the next chunk; returns the number of frames done."""
        return self.job.step()

    @property
    def finished(self):
        return self.job.finished

    def finish(self):
        """Compute what is left, then write keys, drivers and the record; return a BakeResult."""
        inp = self.inp
        frames = list(self.job.frames())
        plan = self.plan(inp.obj, inp, frames, inp.obj)
        result = self.result(inp, plan.frames, plan.note)
        # --- everything computed; from here on the file is modified ---
        result.keys, result.slider = self.write(plan)
        store_result(inp.obj, result.summary())
        return result

    def plan(self, obj, inp, frames, owner):
        """What to write into obj (keys, frames, end key, slider on `owner`), computed, not written."""
        src, tgt = inp.source, inp.others[0]
        found = playback.find(owner, src.name, tgt.name)
        slider = found.slider if found else playback.slider_name(owner.data.shape_keys, src.name,
                                                                 tgt.name)
        note = playback.own_animation(obj, tgt, slider, owner) if self.drivers else ""
        names, end_key = list(self.names), None
        # The slider ends on the target itself only if it is relative to the source and has no
        # animation of its own; otherwise on an end key equal to the target.
        if self.drivers and (tgt.relative_key != src or note):
            end_key = timing.key_name(tgt.name, 1.0)
            names, frames = names + [end_key], frames + [inp.shapes[1]]
        if note:
            note += ", so the slider drives the copy %r instead" % end_key
        return Plan(obj=obj, owner=owner, source=src.name, target=tgt.name, names=names,
                    frames=frames, end_key=end_key, slider=slider, note=note,
                    signature=playback.signature(tgt), members=[obj.name],
                    inputs=playback.inputs_signature(obj, src.name, tgt.name))

    def result(self, inp, frames, note):
        """The BakeResult of frames (keys and slider filled in by write())."""
        return BakeResult(keys=[], factors=self.factors, positions=self.positions,
                          source=inp.source.name, target=inp.others[0].name, slider=None,
                          seconds=time.perf_counter() - self.started,
                          **measures(inp, frames, self.job.solver, note))

    def write(self, plan):
        """Write a plan's keys (and drivers, from the slider on plan.owner): (keys, slider)."""
        obj = plan.obj
        playback.remove(obj, plan.source, plan.target, keep_slider=True)  # the old bake's owner
        written = [write_key(obj, name, plan.source, co) for name, co in zip(plan.names, plan.frames)]
        keys = written[:len(self.positions)]
        if not self.drivers:
            return keys, None
        return keys, playback.install(obj, plan.source, plan.target, keys, self.positions,
                                      end=written[-1] if plan.end_key else None,
                                      signature_=plan.signature, slider=plan.slider, owner=plan.owner,
                                      inputs=plan.inputs, members=plan.members)


@dataclass
class Plan:
    """What BakeJob.write() writes into one object (see BakeJob.plan): keys `names` with `frames`
    relative to `source`, an `end_key` copy of the target or None, the slider on `owner`; the
    record's hashes (the target's `signature`, the `inputs` read) and the objects baked together
    (`members`: a character's, each one's edit makes the bake stale)."""
    obj: object
    owner: object
    source: str
    target: str
    names: list
    frames: list
    end_key: object
    slider: str
    note: str
    signature: object
    members: list = None
    inputs: str = ""


def measures(inp, shapes, solver=None, note=""):
    """A bake's summary of `shapes` (the results, e.g. in-betweens or a blend) as BakeResult
    fields: the largest distortion K of the results and of the inputs, folded polygons, the
    joints the solver used and where they came from, and a note on the inputs' folds followed by
    `note`."""
    folded = solve.folded_polygons(inp, shapes)
    stats = solver.stats if solver is not None else None
    folds = solve.input_folds(inp, solver) if solver is not None else ""
    return dict(max_distortion=max_distortion(inp.shapes[0], shapes, inp.faces, inp.layers),
                input_distortion=max_distortion(inp.shapes[0], inp.shapes[1:], inp.faces, inp.layers),
                folded=folded, folded_name=inp.polygon_name(folded[0]) if folded else "",
                joints=stats.joints if stats else 0,
                joint_source=inp.joint_source if stats and stats.joints else "",
                note="; ".join(text for text in (folds, note) if text))


def store_result(obj, summary):
    """Keep a bake's summary for the panel's result box (Object.bdi.result, JSON)."""
    if hasattr(obj, "bdi"):  # the settings exist only while the add-on is registered
        obj.bdi.result = json.dumps(summary)


def run(job, progress):
    """Step `job` to the end; progress(done, total) after each chunk, False cancels."""
    while not job.finished:
        done = job.step()
        if progress is not None and progress(done, job.total) is False:
            raise mesh_io.BakeError("bake cancelled after %d of %d in-betweens; nothing written"
                            % (done, job.total))


def write_key(obj, name, source_name, co, value=0.0):
    """Create (or overwrite) key `name` holding `co`, relative to `source_name`."""
    key = obj.data.shape_keys
    kb = key.key_blocks.get(name)
    if kb is None:
        kb = obj.shape_key_add(name=name, from_mix=False)
        kb.value = value
    kb.relative_key = key.key_blocks[source_name]
    mesh_io.write_co(kb, co)
    return kb.name




def _copy_fcurve(src, dst):
    """Copy keyframes (with handles and interpolation) or a driver from F-curve src to dst."""
    if src.driver is not None and dst.driver is not None:
        d_src, d_dst = src.driver, dst.driver
        d_dst.type, d_dst.expression = d_src.type, d_src.expression
        for var in d_src.variables:
            new = d_dst.variables.new()
            new.name, new.type = var.name, var.type
            for t_src, t_dst in zip(var.targets, new.targets):
                if var.type == 'SINGLE_PROP':
                    t_dst.id_type = t_src.id_type
                t_dst.id, t_dst.data_path = t_src.id, t_src.data_path
                t_dst.bone_target, t_dst.transform_type = t_src.bone_target, t_src.transform_type
                t_dst.transform_space = t_src.transform_space
        return
    dst.keyframe_points.add(len(src.keyframe_points))
    for a, b in zip(src.keyframe_points, dst.keyframe_points):
        b.co, b.interpolation, b.easing = a.co, a.interpolation, a.easing
        b.handle_left_type, b.handle_right_type = a.handle_left_type, a.handle_right_type
        b.handle_left, b.handle_right = a.handle_left, a.handle_right
    dst.extrapolation = src.extrapolation
    dst.update()


def _factor_curve(obj):
    """(kind, F-curve) animating obj.bdi.live_factor: ('driver', fc), ('action', fc) or (None, None)."""
    anim = obj.animation_data
    if anim is None:
        return None, None
    fc = anim.drivers.find("bdi.live_factor")
    if fc is not None:
        return "driver", fc
    fc = actions.find_fcurve(anim, "bdi.live_factor")
    return ("action", fc) if fc is not None else (None, None)


def bake_live(obj, count=None, job_of=BakeJob):
    """See api.bake_live: live interpolation -> in-betweens + slider animated like the factor;
    live pose blend -> one key per distinct set of weights in the scene's frame range. job_of:
    makes the BakeJob from BakeJob's arguments (a character's: api.job_of of its objects)."""
    props = getattr(obj, "bdi", None)
    if props is None or not props.live:
        raise mesh_io.BakeError("%s is not in live mode" % getattr(obj, "name", "No object"))
    if props.live_mode == 'BLEND':
        return _bake_live_blend(obj, props)
    job = job_of(obj, from_props(props, count=count or props.count, factors=None,
                                 easing="LINEAR", drivers=True))
    kind, curve = _factor_curve(obj)
    result = job.finish()
    path = '["%s"]' % result.slider
    obj[result.slider] = min(1.0, max(0.0, props.live_factor))
    if kind == "driver":
        obj.driver_remove(path)
        _copy_fcurve(curve, obj.driver_add(path))
    elif kind == "action":
        _copy_fcurve(curve, actions.new_fcurve(obj.animation_data, path))
    _live_off(obj)
    result.note = (result.note + "; " if result.note else "") + (
        "the slider %r plays it (%s)" % (result.slider, {"driver": "driven like the live factor",
                                                          "action": "keyframed like the live factor"}
                                         .get(kind, "set to the live factor")))
    store_result(obj, result.summary())
    return result


def _live_off(obj):
    obj.bdi.live = False
    key = obj.data.shape_keys
    if key.key_blocks.get(LIVE_KEY) is not None:
        obj.shape_key_remove(key.key_blocks[LIVE_KEY])


def _weights_per_frame(obj, props, frames):
    """The live pose weights at each frame, as Blender evaluates them: from their F-curves, or, when
    a driver sets one, from the evaluated object at each frame (the scene's frame is restored)."""
    import bpy
    anim = obj.animation_data
    paths = ["bdi.poses[%d].weight" % i for i in range(len(props.poses))]
    if anim is None or not any(anim.drivers.find(p) for p in paths):
        curves = [actions.find_fcurve(anim, p) for p in paths]
        return [tuple(c.evaluate(f) if c is not None else p.weight for c, p in zip(curves, props.poses))
                for f in frames]
    scene, out = bpy.context.scene, []
    current = scene.frame_current
    try:
        for f in frames:
            scene.frame_set(f)
            ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
            out.append(tuple(p.weight for p in ev.bdi.poses))
    finally:
        scene.frame_set(current)
    return out


def _bake_live_blend(obj, props):
    """One key 'bdi.live.<first frame>' per distinct set of weights over the scene's frames,
    keyframed (constant) to 1 on its frames and 0 elsewhere: plays without the add-on."""
    import bpy
    started, scene = time.perf_counter(), bpy.context.scene
    frames = list(range(scene.frame_start, scene.frame_end + 1))
    per_frame = _weights_per_frame(obj, props, frames)
    distinct = sorted(set(per_frame), key=per_frame.index)
    settings = from_props(props, factors=None, easing="LINEAR", anchor_path=None)
    inp = Inputs(obj, settings, list(settings.poses))
    solver = inp.interpolator()
    shapes = [solve.blend_shape(inp, solve.pose_weights(list(zip(inp.names[1:], w)))[1], solver)
              for w in distinct]
    m = measures(inp, shapes, solver, "one key per distinct set of weights over frames %d-%d, "
                 "keyframed" % (frames[0], frames[-1]))
    # --- everything computed; from here on the file is modified ---
    source, key = inp.source.name, obj.data.shape_keys
    for kb in [kb for kb in key.key_blocks if kb.name.startswith(LIVE_KEY + ".")]:
        obj.shape_key_remove(kb)
    names = []
    for w, co in zip(distinct, shapes):
        name = write_key(obj, "%s.%04d" % (LIVE_KEY, frames[per_frame.index(w)]), source, co)
        _keyframe_steps(key.key_blocks[name], frames, [1.0 if pw == w else 0.0 for pw in per_frame])
        names.append(name)
    _live_off(obj)
    result = BakeResult(keys=names, factors=[], positions=[], source=source, target="pose blend",
                        slider=None, seconds=time.perf_counter() - started, **m)
    store_result(obj, result.summary())
    return result


def _keyframe_steps(kb, frames, values):
    """Constant keyframes of kb.value: one at the first frame and wherever the value changes."""
    last = None
    for f, v in zip(frames, values):
        if v != last:
            kb.value = v
            kb.keyframe_insert("value", frame=f)
            last = v
    path = kb.path_from_id("value")
    for kp in actions.find_fcurve(kb.id_data.animation_data, path).keyframe_points:
        kp.interpolation = 'CONSTANT'
