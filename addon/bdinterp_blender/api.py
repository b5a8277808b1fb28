"""Scripting API of the add-on (also what the operators call): validates, then calls solve,
playback, live and distortion.

Usable headless, e.g.::

    blender -b file.blend --python-expr "import bpy, bdinterp_blender as b; \\
        b.bake(bpy.data.objects['Arm'], source='Basis', target='Arm_up', count=8, easing='EASE_IN_OUT'); \\
        bpy.ops.wm.save_mainfile()"

Conventions: shape keys are named by string ('' or None = the reference key); coordinates are
the mesh's local coordinates (the mesh may lie in any plane); every function validates and
computes everything before it touches the file, so an error (BakeError, a ValueError, or
RuntimeError from the solver) leaves the object unchanged.
"""

import time

from .keys import baking, character, export, live, playback, posing
from .view import distortion
from .shapes import mesh_io, solve
from .keys.baking import BakeJob, BakeResult, run, write_key
from .shapes.mesh_io import BakeError
from .names import DEFAULT_TOLERANCE, LIVE_KEY
from .shapes.settings import BakeSettings, anchor_choice
from .shapes.solve import Inputs, max_distortion, pose_weights  # noqa: F401 -- part of the API

__all__ = ["bake", "bake_job", "blend", "clear", "compute_frames", "set_live", "bake_live",
           "show_distortion", "hide_distortion", "bake_for_export", "remove_export_bake",
           "error_bound_factors", "job_of", "settings_of", "add_pose", "torn_joints", "BakeJob", "BakeSettings", "BakeResult",
           "BakeError", "LIVE_KEY", "DEFAULT_TOLERANCE"]


def settings_of(target, options):
    """BakeSettings(target=target, **options): the keyword options of bake() and its siblings are
    BakeSettings' fields (one definition); an unknown one is a BakeError that lists them."""
    fields = BakeSettings.__dataclass_fields__
    unknown = sorted(set(options) - set(fields) | ({"target"} & set(options)))
    if unknown:
        raise BakeError("unknown option%s %s; the options are %s" % (
            "s" * (len(unknown) > 1), ", ".join(map(repr, unknown)),
            ", ".join(f for f in fields if f != "target")))
    return BakeSettings(target=target, **options)


def bake_job(obj, target, **options):
    """The validated BakeJob of a bake (options as in bake()), not yet computed: one object's,
    or, for a list of objects of which several have the target key, the character's."""
    return job_of(obj, settings_of(target, options))


def job_of(obj, settings):
    """The BakeJob of settings (a BakeSettings) for obj or a list of objects (see bake_job)."""
    if isinstance(obj, (list, tuple)):
        objs = character.members(obj, settings.target)
        if len(objs) > 1:
            return character.CharacterBakeJob(objs, settings)
        obj = objs[0] if objs else (obj[0] if obj else None)  # its own errors say what is wrong
    return BakeJob(obj, settings)


def compute_frames(obj, target, progress=None, **options):
    """Compute in-betweens without writing anything.

    Returns (inputs, positions, factors, frames) with frames a (k, n, 3) float64 array in the
    mesh's local coordinates (a list of objects: world coordinates, the objects' vertices one
    after the other, inputs.offsets where each begins).  Options as in bake().
    """
    job = bake_job(obj, target, **options)
    run(job, progress)
    return job.inp, job.positions, job.factors, job.job.frames()


def bake(obj, target, progress=None, **options):
    """Bake in-betweens of `source` -> `target` into new shape keys; return a BakeResult.

    obj: mesh object with shape keys, or a list of them: those that have the target key are
    solved as one cut-out character in world space (pieces of different objects that overlap
    are joined), each written in its own local coordinates, all driven by the slider of the
    first of them; a failure writes into none of them.  target: the target key's name.
    progress(done, total): called after each chunk of frames; returning False cancels
    (BakeError, nothing written).  The options are the fields of BakeSettings (an unknown one
    is refused):
    source: the source key's name (default: the reference key).  count: number of evenly timed
    in-betweens (default 3), or factors: explicit list in (0, 1).
    easing: 'LINEAR', 'EASE_IN', 'EASE_OUT', 'EASE_IN_OUT' or a callable u -> t (custom curve).
    anchor: 'AUTO', a vertex index or a vertex group name (a character: of its first object),
    or (object, vertex index) (a character: of any of its objects); anchor_path: a curve object
    the anchor follows.  method: 'bdi' (default), 'arap' or 'linear'.  planarity: how far
    a vertex may lie off its piece's plane, relative to the mesh size.  drivers (default True):
    a slider drives the keys.
    joints: how pieces (loose parts) are joined (docs/JOINTS.md): 'bones' (each piece hangs from
    the piece of its bone's parent, pinned at the bone's head: an Armature modifier's vertex
    groups or a parent bone), 'pins' (overlapping pieces that turn about a common point in both
    keys), 'auto' (default: bones where every piece has one, else pins; also True) or 'off' (each
    piece on its own rigid path; also False).
    threads: the solver's workers, a frame each at a time (0: one per usable core).

    Keys are named '<target>.bdi.<percent>' (e.g. 'Arm_up.bdi.050'), hold the in-between shape
    and are relative to the source key; an earlier bake of the same pair is replaced (also
    after the target was renamed).  With drivers=True a custom property '<target>.bdi' on the
    object (slider 0..1) drives them with native drivers so that 0 -> 1 plays source ->
    in-betweens -> target, also without the add-on.  The slider drives the target key itself
    only if that has no keyframes, driver or value of its own (else a copy, result.note says so).
    """
    job = bake_job(obj, target, **options)
    run(job, progress)
    return job.finish()


def blend(obj, weights, name="Blend.bdi", **options):
    """Bake a pose blend (paper Section 5): one key `name`, relative to the source.

    weights: {pose key name: weight}; see pose_weights() for how the source's weight follows.
    options: source, anchor, planarity and joints as in bake().
    Returns (key name, max distortion of the blend, max distortion of the poses).
    """
    started = time.perf_counter()
    names, ws = pose_weights(weights)
    settings = settings_of("", options)
    inp = Inputs(obj, settings, names)
    solver = inp.interpolator()
    result = solve.blend_shape(inp, ws, solver)
    measures = baking.measures(inp, [result], solver)
    written = write_key(obj, name, inp.source.name, result)
    baking.store_result(obj, BakeResult(
        keys=[written], source=inp.source.name, target="blend of " + ", ".join(names),
        seconds=time.perf_counter() - started, **measures).summary())
    return written, measures["max_distortion"], measures["input_distortion"]


def clear(obj, target, source=None):
    """Remove a bake of source -> target: its keys, their drivers and the slider property.
    obj may be a list of objects (a character): each that has the target key is cleared (the
    shared slider goes with its owner). Returns the names of the removed keys."""
    objs = character.members(obj, target) if isinstance(obj, (list, tuple)) else [obj]
    srcs = [mesh_io.key_block(mesh_io.key_of(o), source).name for o in objs]  # all checked first
    for o in objs:  # export keyframes would outlive the keys they animate
        export.remove(o)
    return [name for o, src in zip(objs, srcs)
            for name in playback.remove(o, src, target, keep_slider=False)]


def set_live(obj, target=None, factor=None, weights=None, source=None, enable=True, anchor=None):
    """Configure and switch live mode (needs the add-on enabled: it lives in handlers).

    target + factor: live interpolation; weights {key: w}: live pose blend.  The result is
    written into the key 'bdi.live' (relative to the source, value 1) whenever the frame, the
    factor/weights (directly, by keyframes or drivers) or the input keys change; keyframe
    obj.bdi.live_factor or obj.bdi.poses[i].weight to animate.  anchor: 'AUTO', 'VERTEX' or
    'GROUP' (with obj.bdi.anchor_vertex / anchor_group).  Everything is validated and the first
    result computed before any setting is written.  Returns the live key name (or None).
    obj may be a list of objects: those that have the target key are one character, solved in
    world space as bake() solves it, each object's result in its own 'bdi.live' key, all following
    the factor (and settings) of the first of them; anchor 'VERTEX' with obj.bdi.anchor_object
    names a vertex of any of them.
    """
    objs = None
    if isinstance(obj, (list, tuple)):
        obj, objs = _live_character(obj, target, weights)
    if not hasattr(obj, "bdi"):
        raise BakeError("live mode needs the bdinterp add-on enabled (Preferences > Add-ons)")
    mesh_io.key_of(obj)
    props = obj.bdi
    items = None if weights is None else list(weights.items() if hasattr(weights, "items") else weights)
    if items is not None:
        pose_weights(items)  # weights >= 0
    settings, values = _live_request(props, target, factor, items, source, anchor)  # anchor valid
    if not enable:
        _write_live_settings(obj, target, factor, items, source, anchor, objs)
        props.live = False
        return None
    state = live.prepare(obj, settings, objs)
    result = live.compute(state, values)
    # --- validated and computed; from here on the file is modified ---
    _write_live_settings(obj, target, factor, items, source, anchor, objs)
    live.switch_on(obj, state, values, result)
    return LIVE_KEY


def _live_request(props, target, factor, items, source, anchor):
    """(live.Settings, values) that the settings would give once written."""
    mode = 'BLEND' if items is not None else ('INTERPOLATE' if target is not None else props.live_mode)
    if items is None:
        items = [(p.key, p.weight) for p in props.poses]
    settings = live.settings_of(
        props, mode=mode, source=props.source if source is None else source,
        target=props.target if target is None else target,
        poses=tuple(name for name, _ in items), anchor=anchor_choice(props, anchor))
    if mode == 'BLEND':
        return settings, tuple(float(w) for _, w in items)
    return settings, (float(props.live_factor if factor is None else factor),)


def _live_character(objs, target, weights):
    """(the object that holds the live settings, the character's objects or [] for one object)
    of a list of objects given to set_live()."""
    first = next((o for o in objs if o is not None), None)
    name = target if target is not None else getattr(getattr(first, "bdi", None), "target", "")
    members = character.members(objs, name)
    if len(members) < 2:
        return (members[0] if members else first), []
    if weights is not None:
        raise BakeError("a live pose blend works for one object, not for a character of %d"
                        % len(members))
    return members[0], members


def _write_live_settings(obj, target, factor, items, source, anchor, objs=None):
    props = obj.bdi
    with live.suspended():
        if objs is not None:
            live.set_members(obj, objs)
        if source is not None:
            props.source = source
        if target is not None:
            props.target = target
        if anchor is not None:
            props.anchor = anchor
        if items is not None:
            props.poses.clear()
            for name, w in items:
                item = props.poses.add()
                item.key, item.weight = name, w
            props.live_mode = 'BLEND'
        elif target is not None:
            props.live_mode = 'INTERPOLATE'
        if factor is not None:
            props.live_factor = factor


def bake_live(obj, count=None):
    """Bake obj's live mode into keys that play without the add-on, then switch it off and remove
    the live key.  Live interpolation: in-betweens at `count` evenly spaced factors (default: the
    panel's In-betweens) and the playback slider with the live factor's keyframes or driver
    copied onto it.  Live pose blend: one key per distinct set of weights over the scene's frame
    range, keyframed (constant) to show on its frames.  A live character is baked as bake() bakes
    it, and every object's live key removed.  Returns the BakeResult."""
    props = getattr(obj, "bdi", None)
    objs = live.character_objects(obj, props.target) if props is not None and props.live \
        and props.live_mode != 'BLEND' else []
    if not objs:
        return baking.bake_live(obj, count)
    result = baking.bake_live(obj, count, job_of=lambda _obj, settings: job_of(objs, settings))
    live.remove_keys(objs[1:])
    return result


def add_pose(objs, name=None):
    """A new pose of a cut-out character in one step: a shape key `name` (default 'Pose', or
    'Pose 2' ... where taken) on every mesh of objs, a copy of its reference key (Basis made
    where missing), active and chosen as each object's target; edit it, then bake. Returns the
    name; BakeError, nothing changed, if a mesh has that key already."""
    return posing.add_pose(objs, name)


def torn_joints(objs, target, source=None):
    """The joints of the character objs (pieces joined where they overlap in the source key) that
    the pose source -> target tears apart: [(piece, the piece it hangs from, how far apart, in
    world units)], furthest first; [] when every joint holds."""
    return posing.torn_joints(objs, target, source)


def show_distortion(obj, key=None, visible=True):
    """Write per-face conformal distortion of `key` (default: the active key) against its
    relative key into face attribute 'bdi_distortion' and colour attribute
    'bdi_distortion_color' (blue: no worse than the inputs, red: worse); show it in the
    viewport. Returns the per-face distortion array."""
    return distortion.write(obj, key, visible)


def hide_distortion(obj=None):
    """Switch the viewports (and Workbench renders) back to material colours."""
    distortion.set_visible(False, obj)


def bake_for_export(objs, *, frame_start=None, frame_end=None):
    """Write what the playback sliders show at every frame of frame_start..frame_end (default:
    the scene's range) as linear F-curves on the baked keys' values of each object in `objs` (one
    object or a list, e.g. every object of a character), one keyframe a frame, so that Blender's
    glTF, FBX and Alembic exporters carry the animation; the sliders' drivers are muted while
    those F-curves exist. Refuses (BakeError, nothing changed) where an object has no bake or a
    slider has no keyframes or driver. Returns a message."""
    return export.bake(objs, frame_start, frame_end)


def remove_export_bake(objs):
    """Remove the F-curves of bake_for_export() and unmute the sliders' drivers; returns how many
    objects had an export bake."""
    objs = objs if isinstance(objs, (list, tuple)) else [objs]
    return sum(export.remove(o) for o in objs)


def error_bound_factors(obj, target, error, **options):
    """The in-between factors (sorted, in (0, 1)) of the fewest keys whose linear blend stays
    within `error` x the size of the exact in-between (bdinterp's Interpolator.keyframes) of
    source -> target of obj (or a character: a list of objects); bake(factors=...) bakes them. At
    least one: the middle, where the blend of source and target alone is within the bound.
    options: source, anchor, anchor_path, planarity and joints as in bake()."""
    return factors_within(obj, settings_of(target, options), error)


def factors_within(obj, settings, error):
    """error_bound_factors of the source -> target, anchor, anchor path, planarity and joints of
    `settings` (a BakeSettings, e.g. the panel's)."""
    job = job_of(obj, settings.but(count=1, factors=None, easing="LINEAR", method="bdi"))
    keys = job.job.solver.keyframes(error)  # the job's Interpolator, precomputed once
    return [float(t) for t in keys[1:-1]] or [0.5]
