"""A cut-out character of seven objects (examples/cutout) in live mode and anchored at a vertex of
any of its objects, as one object is: live mode shows the in-betweens a bake of the character
writes, and an anchor vertex (given as object + vertex) stays on its chord or its path."""

import os
import sys

import bpy
import numpy as np
import pytest

from conftest import ROOT, evaluated_co, fcurve, path_object

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

FACTORS = (0.25, 0.5, 0.8)
EXACT = 1e-6       # of the character's size: float32 keys in objects scaled up to 2
LIVE = "bdi.live"


@pytest.fixture
def character():
    pieces = cc.character()[0]
    return cb.seven_objects(pieces), cb.size_of(pieces)


def reference(addon, objs, factors):
    """{object name: [its baked in-between (n, 3) in world coordinates]} of a bake of the
    character at `factors` (no slider: the keys stay at 0 and show nothing); the bake removed."""
    addon.bake(objs, cb.TARGET, factors=list(factors), drivers=False)
    names = cb.baked(objs[0])
    assert len(names) == len(factors)
    out = {o.name: [cb.world(o, cb.read(o, n)) for n in names] for o in objs}
    addon.clear(objs, cb.TARGET)
    assert not cb.baked(objs[0])
    return out


def shown_error(objs, ref, i, size):
    """Largest distance (of the size) of any object's evaluated vertex from in-between i."""
    return max(np.abs(cb.world(o, evaluated_co(o)) - ref[o.name][i]).max() for o in objs) / size


def test_live_character_follows_the_factor_and_its_keyframes(addon, character):
    objs, size = character
    ref = reference(addon, objs, FACTORS)
    addon.set_live(objs, target=cb.TARGET, factor=0.0)
    owner = objs[0]
    assert owner.bdi.live and not any(o.bdi.live for o in objs[1:])
    assert [m.obj for m in owner.bdi.live_objects] == objs[1:]
    assert all(o.data.shape_keys.key_blocks[LIVE].value == 1.0 for o in objs)
    rest = max(np.abs(evaluated_co(o) - cb.read(o, "Basis")).max() for o in objs) / size
    assert rest < EXACT
    for i, t in enumerate(FACTORS):  # the factor set directly (the depsgraph handler)
        owner.bdi.live_factor = t
        assert shown_error(objs, ref, i, size) < EXACT, t
    moved = max(np.abs(ref[o.name][2] - cb.world(o, cb.read(o, "Basis"))).max() for o in objs)
    assert moved > 0.3 * size  # the arm swings: a live mode that ignored the others would fail
    for frame, t in zip((1, 5, 9), FACTORS):  # keyframed (the frame-change handler)
        owner.bdi.live_factor = t
        owner.keyframe_insert("bdi.live_factor", frame=frame)
    for kp in fcurve(owner.animation_data, "bdi.live_factor").keyframe_points:
        kp.interpolation = 'CONSTANT'
    for i, frame in reversed(list(enumerate((1, 5, 9)))):
        bpy.context.scene.frame_set(frame)
        assert shown_error(objs, ref, i, size) < EXACT, frame


def test_live_character_survives_reload_and_follows_a_moved_object(addon, character, tmp_path):
    objs, size = character
    names = [o.name for o in objs]
    addon.set_live(objs, target=cb.TARGET, factor=0.5)
    path = str(tmp_path / "live_character.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = [bpy.data.objects[n] for n in names]
    objs[0].bdi.live_factor = 0.8
    ref = reference_copy(addon, objs, (0.8,))
    assert shown_error(objs, ref, 0, size) < EXACT
    # an object moved: the character is solved again from the world shapes it now has
    hand = bpy.data.objects["Hand"]
    hand.location.x += 0.3
    bpy.context.view_layer.update()
    objs[0].bdi.live_factor = 0.5
    ref = reference_copy(addon, objs, (0.5,))
    assert shown_error(objs, ref, 0, size) < EXACT


def test_an_edited_key_of_another_object_is_noticed(addon, character):
    objs, size = character
    addon.set_live(objs, target=cb.TARGET, factor=0.5)
    bpy.context.view_layer.update()  # live mode's own writes reported: only the edit is left
    hand = objs[-1]
    moved = cb.world(hand, cb.read(hand, cb.TARGET)) + [0.1, 0.0, 0.0]  # in the pieces' plane
    m = np.array(hand.matrix_world)
    local = np.linalg.solve(m[:3, :3], (moved - m[:3, 3]).T).T
    hand.data.shape_keys.key_blocks[cb.TARGET].data.foreach_set("co", local.astype(np.float32).ravel())
    hand.data.shape_keys.update_tag()
    ref = reference_copy(addon, objs, (0.5,))
    assert shown_error(objs, ref, 0, size) < EXACT


def reference_copy(addon, objs, factors):
    """reference() of copies of objs (live mode keeps its own keys and settings as they are)."""
    copies = []
    for o in objs:
        c = o.copy()
        c.data = o.data.copy()
        c.animation_data_clear()
        c.bdi.live = False  # the copied settings would make the copy live too
        c.data.shape_keys.key_blocks[LIVE].value = 0.0
        bpy.context.scene.collection.objects.link(c)
        copies.append(c)
    ref = reference(addon, copies, factors)
    out = {o.name: ref[c.name] for o, c in zip(objs, copies)}
    for c in copies:
        bpy.data.objects.remove(c)
    return out


def test_bake_live_of_a_character_bakes_it_and_removes_every_live_key(addon, character):
    objs, size = character
    ref = reference(addon, objs, (0.25, 0.5, 0.75))
    objs[0].bdi.count = 3
    addon.set_live(objs, target=cb.TARGET, factor=0.5)
    result = addon.bake_live(objs[0])
    assert result.objects == 7 and not objs[0].bdi.live
    assert not any(o.data.shape_keys.key_blocks.get(LIVE) for o in objs)
    names = cb.baked(objs[0])
    for o in objs:
        assert cb.baked(o) == names
        for i, n in enumerate(names):
            assert np.abs(cb.world(o, cb.read(o, n)) - ref[o.name][i]).max() < EXACT * size
    assert shown_error(objs, ref, 1, size) < EXACT  # the slider holds the live factor, 0.5


def test_a_live_pose_blend_or_a_member_live_on_its_own_is_refused(addon, character):
    objs, _ = character
    addon.set_live(objs[3], target=cb.TARGET, factor=0.5)
    with pytest.raises(ValueError, match="EyeR is in live mode of its own: switch that off to "
                                         "make it part of Torso's live character"):
        addon.set_live(objs, target=cb.TARGET, factor=0.5)
    assert not objs[0].bdi.live and len(objs[0].bdi.live_objects) == 0
    addon.set_live(objs[3], enable=False)
    objs[3].shape_key_remove(objs[3].data.shape_keys.key_blocks[LIVE])
    addon.set_live(objs, target=cb.TARGET, factor=0.5)  # and the other way round
    with pytest.raises(ValueError, match="EyeR is part of Torso's live character: switch that "
                                         "off first"):
        addon.set_live(objs[3], target=cb.TARGET, factor=0.2)
    assert not objs[3].bdi.live
    addon.set_live(objs[0], enable=False)
    for o in objs:
        o.shape_key_remove(o.data.shape_keys.key_blocks[LIVE])
    with pytest.raises(ValueError, match="live pose blend works for one object, not for a "
                                         "character of 7"):
        addon.set_live(objs, target=cb.TARGET, weights={cb.TARGET: 0.5})
    assert not any(o.bdi.live or o.data.shape_keys.key_blocks.get(LIVE) for o in objs)


def vertex(obj, key, v):
    """Vertex v of obj's key `key` in world coordinates."""
    return cb.world(obj, cb.read(obj, key))[v]


def along(points, t):
    """The point at arc-length fraction t of the polyline `points`."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = t * seg.sum()
    i = min(int(np.searchsorted(np.cumsum(seg), s)), len(seg) - 1)
    u = (s - seg[:i].sum()) / seg[i]
    return (1 - u) * points[i] + u * points[i + 1]


def as_one_object(addon, objs, piece, v, **kw):
    """In-betweens (world coordinates, the objects' vertices one after the other) of the
    one-object form of the character (its coordinates: the world's) baked with `kw`, anchored
    at vertex v of `piece`."""
    one, ranges = cb.one_object(cc.character()[0], name="One")
    addon.bake(one, cb.TARGET, anchor=ranges[piece][v], **kw)
    return np.array([cb.read(one, n) for n in cb.baked(one)])


def test_a_vertex_of_any_object_anchors_the_character_on_its_chord(addon, character):
    objs, size = character
    by = {o.name: o for o in objs}
    hand, torso = by["Hand"], by["Torso"]
    order = [by["Head"]] + [o for o in objs if o != by["Head"]]  # neither is first
    r = addon.bake(order, cb.TARGET, count=3, anchor=(hand, 2))
    assert r.objects == 7
    src, tgt = vertex(hand, "Basis", 2), vertex(hand, cb.TARGET, 2)
    assert np.linalg.norm(tgt - src) > 0.3 * size
    names = cb.baked(hand)
    for name, t in zip(names, r.factors):
        assert np.linalg.norm(vertex(hand, name, 2) - ((1 - t) * src + t * tgt)) < 1e-6 * size
    frames = cb.in_world(objs, names)[0]
    assert np.abs(frames - as_one_object(addon, objs, "Hand", 2, count=3)).max() < EXACT * size
    # a vertex that does not move stays put (named by its object's name)
    r = addon.bake(order, cb.TARGET, count=3, anchor=("Torso", 40))
    for name in cb.baked(torso):
        assert np.linalg.norm(vertex(torso, name, 40) - vertex(torso, "Basis", 40)) < 1e-6 * size


def test_a_vertex_of_any_object_follows_an_anchor_path(addon, character):
    objs, size = character
    hand = objs[-1]
    assert hand.name == "Hand"
    src, tgt = vertex(hand, "Basis", 2), vertex(hand, cb.TARGET, 2)
    bend = 0.5 * (src + tgt) + np.array([0.2, 0.1, 0.0]) * size  # off the chord, in the plane
    points = np.array([src, bend, tgt])
    path = path_object(points, location=np.array([0.7, -0.4, 0.0]))
    r = addon.bake(objs, cb.TARGET, count=3, anchor=(hand, 2), anchor_path=path)
    names = cb.baked(hand)
    for name, t in zip(names, r.factors):
        assert np.linalg.norm(vertex(hand, name, 2) - along(points, t)) < 1e-6 * size, name
    frames = cb.in_world(objs, names)[0]
    one = as_one_object(addon, objs, "Hand", 2, count=3, anchor_path=path)
    assert np.abs(frames - one).max() < EXACT * size


@pytest.mark.parametrize("anchor, match", [
    (("Nope", 0), r"anchor object 'Nope' is not one of the character's objects \(Torso, "),
    (("Hand", 99), r"anchor: 'Hand' has no vertex 99 \(it has 15\)")])
def test_a_bad_anchor_vertex_is_named_and_changes_nothing(addon, character, anchor, match):
    objs, _ = character
    with pytest.raises(ValueError, match=match):
        addon.bake(objs, cb.TARGET, count=3, anchor=anchor)
    assert not any(cb.baked(o) for o in objs)
    with pytest.raises(ValueError, match=r"a vertex of 'Hand' anchors a character of several "
                                         r"objects, not 'Torso'"):
        addon.bake(objs[0], cb.TARGET, count=3, anchor=("Hand", 2))


def test_a_live_character_anchored_at_a_vertex_of_another_object(addon, character):
    objs, size = character
    owner, hand = objs[0], objs[-1]
    owner.bdi.anchor_object, owner.bdi.anchor_vertex = hand, 2
    addon.set_live(objs, target=cb.TARGET, factor=0.4, anchor='VERTEX')
    src, tgt = vertex(hand, "Basis", 2), vertex(hand, cb.TARGET, 2)
    shown = cb.world(hand, evaluated_co(hand))[2]
    assert np.linalg.norm(shown - (0.6 * src + 0.4 * tgt)) < 1e-6 * size


def test_the_panel_toggle_takes_the_selected_objects_as_the_character(addon, character):
    objs, size = character
    ref = reference(addon, objs, (0.5,))
    owner = objs[0]
    owner.bdi.target = cb.TARGET
    owner.bdi.live = True  # all seven selected, the torso active (as the bake takes them)
    assert not owner.bdi.live_error
    assert sorted(m.obj.name for m in owner.bdi.live_objects) == sorted(o.name for o in objs[1:])
    assert shown_error(objs, ref, 0, size) < EXACT  # the factor's default, 0.5
    owner.bdi.live = False
    for o in objs[1:]:
        o.select_set(False)
    owner.bdi.live = True  # alone now
    assert len(owner.bdi.live_objects) == 0 and not owner.bdi.live_error


def test_use_selected_vertex_of_another_object_in_edit_mode(addon, character):
    objs, _ = character
    hand = objs[-1]
    for o in objs:
        for items in (o.data.polygons, o.data.edges):
            items.foreach_set("select", [False] * len(items))
        o.data.vertices.foreach_set("select", [o == hand and i == 7 for i in range(len(o.data.vertices))])
    bpy.ops.object.mode_set(mode='EDIT')  # the seven objects in edit mode, the torso active
    assert bpy.ops.bdinterp.anchor_from_selection() == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    props = objs[0].bdi
    assert (props.anchor, props.anchor_vertex, props.anchor_object) == ('VERTEX', 7, hand)
    from bdinterp_blender.shapes.settings import from_props
    assert from_props(props).anchor == ("Hand", 7)
