"""Failures injected where the add-on writes a user's file: an error in the middle of Bake for
Export's sampling (after a frame change) or of its writing, a user's keyframes on a baked key, an
exception of an unexpected type in a bake step, errors in the live-mode and onion-skin handlers.
Each time the scene is compared before and after: every shape key's data and settings, every
F-curve with its points, every driver with its mute, every custom property, the actions."""

import importlib

import bpy
import numpy as np
import pytest

from conftest import bent_strip, fcurve

FRAMES = (1, 12)


def _curves(anim):
    from bdinterp_blender.actions import all_fcurves
    if anim is None:
        return None
    out = {}
    for fc in all_fcurves(anim):
        co = np.empty(len(fc.keyframe_points) * 2)
        fc.keyframe_points.foreach_get("co", co)
        out[fc.data_path, fc.array_index] = (co.tolist(), [k.interpolation for k in fc.keyframe_points],
                                             fc.mute)
    drivers = {(d.data_path, d.array_index): (d.mute, d.driver.expression) for d in anim.drivers}
    return {"action": anim.action.name if anim.action else None, "curves": out, "drivers": drivers}


def _props(owner):
    return {k: (owner[k].to_dict() if hasattr(owner[k], "to_dict") else owner[k])
            for k in owner.keys() if k != "bdi"}


def state():
    """Everything a failed operation must leave as it was, in comparable form."""
    out = {"actions": sorted(a.name for a in bpy.data.actions),
           "frame": bpy.context.scene.frame_current}
    for obj in bpy.data.objects:
        key = obj.data.shape_keys if obj.type == 'MESH' else None
        blocks = {}
        for kb in key.key_blocks if key else ():
            co = np.empty(len(kb.data) * 3, dtype=np.float32)
            kb.data.foreach_get("co", co)
            blocks[kb.name] = {"value": kb.value, "mute": kb.mute, "relative": kb.relative_key.name,
                               "co": co.tobytes()}
        out[obj.name] = {"props": _props(obj), "anim": _curves(obj.animation_data), "keys": blocks,
                         "key anim": _curves(key.animation_data) if key else None}
    return out


def differences(a, b, where=()):
    """The paths (tuples of keys) where nested dicts a and b differ."""
    if isinstance(a, dict) and isinstance(b, dict):
        return [d for k in sorted(set(a) | set(b), key=repr)
                for d in differences(a.get(k, "<missing>"), b.get(k, "<missing>"), where + (k,))]
    return [] if a == b else [(where, a if not isinstance(a, bytes) else "<data>",
                               b if not isinstance(b, bytes) else "<data>")]


def same(before):
    """Assert that the scene is as state() found it (the differences listed otherwise)."""
    found = differences(before, state())
    assert not found, found


def module(addon, name):
    return importlib.import_module(addon.__name__ + "." + name)


@pytest.fixture
def strip(addon):
    """A bent strip baked (4 in-betweens) with its slider keyframed 0 -> 1 over FRAMES."""
    obj = bent_strip()
    result = addon.bake(obj, "Bend", count=4)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAMES
    scene.frame_set(5)
    for frame, value in zip(FRAMES, (0.0, 1.0)):
        obj[result.slider] = value
        obj.keyframe_insert('["%s"]' % result.slider, frame=frame)
    settle()
    return obj


def settle():
    """The current frame evaluated again, so that animated and driven values are stored as shown."""
    bpy.context.scene.frame_set(bpy.context.scene.frame_current)


def fail_at(count, exc, once=False):
    """A wrapper of fn that raises exc from its count-th call on (only then if once); its `calls`
    counts the calls."""
    def wrap(fn):
        def wrapped(*args, **kw):
            wrapped.calls += 1
            if wrapped.calls == count or (wrapped.calls > count and not once):
                raise exc
            return fn(*args, **kw)
        wrapped.calls = 0
        return wrapped
    return wrap


@pytest.mark.parametrize("again", [False, True], ids=["first", "over an earlier export bake"])
def test_export_error_mid_sampling_changes_nothing(addon, strip, monkeypatch, again):
    export = module(addon, "keys.export")
    if again:
        addon.bake_for_export([strip])
    before = state()
    monkeypatch.setattr(export, "_read_frame", fail_at(5, MemoryError("injected"))(export._read_frame))
    with pytest.raises(MemoryError, match="injected"):
        addon.bake_for_export([strip])
    same(before)


@pytest.mark.parametrize("call", [1, 3])
def test_export_error_while_writing_undoes_every_change(addon, strip, monkeypatch, call):
    """Over an earlier export bake (its action kept, curves replaced): the 1st or 3rd curve fails."""
    actions = module(addon, "actions")
    addon.bake_for_export([strip], frame_end=8)
    before = state()
    assert len(before["Strip"]["key anim"]["curves"]) == 5  # 4 in-betweens and the target
    failing = fail_at(call, TypeError("injected"), once=True)(actions.set_points)
    monkeypatch.setattr(actions, "set_points", failing)
    with pytest.raises(TypeError, match="injected"):
        addon.bake_for_export([strip])
    same(before)


def test_rebake_keeps_the_action_and_its_name(addon, strip):
    addon.bake_for_export([strip], frame_end=8)
    action = strip.data.shape_keys.animation_data.action.name
    addon.bake_for_export([strip])
    anim = strip.data.shape_keys.animation_data
    assert anim.action.name == action and sorted(a.name for a in bpy.data.actions) == sorted(
        [action, strip.animation_data.action.name])
    curve = fcurve(anim, 'key_blocks["Bend"].value')
    assert [k.co[0] for k in curve.keyframe_points] == list(range(FRAMES[0], FRAMES[1] + 1))


def _user_keys(obj, name, values):
    kb = obj.data.shape_keys.key_blocks[name]
    for frame, value in values.items():
        kb.value = value
        kb.keyframe_insert("value", frame=frame)
    return fcurve(obj.data.shape_keys.animation_data, 'key_blocks["%s"].value' % name)


def test_user_keyframes_on_a_baked_key_refuse_the_export(addon, strip):
    baked = [kb.name for kb in strip.data.shape_keys.key_blocks if kb.name.startswith("Bend.")][1]
    _user_keys(strip, baked, {2: 0.1, 6: 0.9, 9: 0.3})
    settle()
    before = state()
    with pytest.raises(ValueError, match="key %r of 'Strip' already has keyframes" % baked):
        addon.bake_for_export([strip])
    same(before)
    with pytest.raises(RuntimeError, match="already has keyframes"):  # the operator reports it
        bpy.ops.bdinterp.bake_export()
    same(before)


def test_user_curve_on_another_key_survives_export_and_its_removal(addon, strip):
    """A user's keyframes on a key of the same shape keys (one action with the export's curves)."""
    co = np.empty(len(strip.data.vertices) * 3, dtype=np.float32)
    strip.data.shape_keys.key_blocks["Basis"].data.foreach_get("co", co)
    extra = strip.shape_key_add(name="Extra", from_mix=False)
    extra.value = 0.0
    _user_keys(strip, "Extra", {3: 0.25, 7: 0.75, 10: 0.5})
    settle()
    before = state()
    mine = before["Strip"]["key anim"]["curves"][('key_blocks["Extra"].value', 0)]
    addon.bake_for_export([strip])
    during = state()["Strip"]["key anim"]
    assert during["curves"][('key_blocks["Extra"].value', 0)] == mine
    assert during["action"] == before["Strip"]["key anim"]["action"]
    assert len(during["curves"]) == 6
    assert addon.remove_export_bake([strip]) == 1
    same(before)


class _Steps:
    """A bake job whose first step fails with an exception of an unexpected type."""

    def __init__(self, job):
        self.job, self.steps = job, 0

    def __getattr__(self, name):
        return getattr(self.job, name)

    def step(self):
        self.steps += 1
        if self.steps == 1:
            raise KeyError("injected in a step")
        return self.job.step()


def test_unexpected_error_in_a_bake_step_stops_the_job(addon):
    import time
    operators, api = module(addon, "ui.operators"), module(addon, "api")
    obj = bent_strip()
    obj.bdi.target = "Bend"
    before = state()
    job = _Steps(api.job_of([obj], operators.settings_for(obj.bdi, [obj])))
    steps = operators.StepThread(job)
    raised = []
    for _ in range(2000):
        try:
            if steps.poll():
                break
        except KeyError as exc:
            raised.append(exc)
            if len(raised) == 3:
                break
        time.sleep(0.005)
    assert [str(e) for e in raised] == ["'injected in a step'"] * 3  # every poll says it, none steps
    assert job.steps == 1
    assert operators.failure(raised[0]) == "KeyError: 'injected in a step'"
    same(before)


def test_live_handler_error_turns_live_off_once_and_keeps_the_keys(addon, monkeypatch, capsys):
    live = module(addon, "keys.live")
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    obj.bdi.live_factor = 0.6
    before = state()
    capsys.readouterr()
    monkeypatch.setattr(live, "compute", fail_at(1, TypeError("injected"))(live.compute))
    obj.bdi.live_factor = 0.7  # the property handler fails: off, said once
    for frame in (2, 3, 4):
        bpy.context.scene.frame_set(frame)
    assert not obj.bdi.live and "TypeError: injected" in obj.bdi.live_error
    assert capsys.readouterr().out.count("live mode turned off") == 1
    after = state()
    after.pop("frame"), before.pop("frame")
    assert after == before  # the live key as it was at 0.6


def test_live_handler_that_cannot_switch_off_leaves_the_object_alone(addon, monkeypatch, capsys):
    live = module(addon, "keys.live")
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    on_update = fail_at(1, RuntimeError("injected"))(live._on_update)
    monkeypatch.setattr(live, "_on_update", on_update)
    live._failed.add(obj.name)  # as turn_off leaves it when Blender forbids writing the switch
    for frame in (2, 3, 4):
        bpy.context.scene.frame_set(frame)
    assert on_update.calls == 0 and "live mode turned off" not in capsys.readouterr().out
    monkeypatch.undo()
    obj.bdi.live = False
    obj.bdi.live = True  # switching on again tries again
    assert obj.name not in live._failed and obj.bdi.live and not obj.bdi.live_error


def test_onion_skin_errors_are_said_once_and_stop_that_overlay(addon, monkeypatch, capsys):
    onion = module(addon, "view.onion")
    obj = bent_strip()
    addon.bake(obj, "Bend", count=3)
    obj.bdi.target = "Bend"
    bpy.context.scene.bdi_view.ghosts = True
    monkeypatch.setattr(onion, "build", fail_at(1, IndexError("injected build"))(onion.build))
    onion.draw_callback()  # an error computing the ghosts: in the panel
    assert onion._cache["ghosts"].error == "IndexError: injected build"
    monkeypatch.setattr(onion, "plan", fail_at(1, ZeroDivisionError("injected draw"))(onion.plan))
    onion.invalidate()
    capsys.readouterr()
    for _ in range(3):
        onion.draw_callback()
        onion.invalidate()
    assert capsys.readouterr().out.count("ZeroDivisionError: injected draw") == 1
    assert "injected draw" in onion._failed[obj.name]
    monkeypatch.setattr(onion, "key_signature", fail_at(1, KeyError("injected hash"))(onion.key_signature))
    bpy.context.scene.bdi_view.step = 0.2  # a setting changed: drawn again
    assert obj.name not in onion._failed
    for _ in range(3):  # the depsgraph handler hashes the edited keys of the drawn object
        obj.data.shape_keys.key_blocks["Bend"].data[0].co.x += 0.01
        obj.data.shape_keys.update_tag()
        bpy.context.view_layer.update()
    assert capsys.readouterr().out.count("KeyError: 'injected hash'") == 1
