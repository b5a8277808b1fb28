"""In Blender: a pose made the way animators make it -- a grid body with a limb four faces
wide, Blender's own two-bone Armature, automatic (bone heat) or smooth vertex-group weights over
the shoulder, the limb bone rotated about the view axis and applied as a shape key -- folds a few
triangles where the weights blend. It is baked through the panel's operator and through the
scripting API; the in-betweens must reach the key without a pop, turn the limb the pose's way in
proportion to t, and flip nothing away from the folds (the numbers of the issue's "Tests"
paragraph)."""

import json
import math

import bpy
import numpy as np
import pytest
from mathutils import Matrix, Vector

from conftest import grid, key_names, mesh_object, read_key, triangles

CELLS = 8                        # grid cells per unit
SHOULDER = (1.0, 1.5)            # the limb bone's head: the torso's right side, the limb's middle
BLEND = (0.85, 1.25)             # the smooth weights ramp from torso to limb over this x range
COUNT = 19                       # in-betweens 0.05 apart


def body_grid(name="Body"):
    """Torso [0, 1] x [0, 2] and a limb [1, 4] x [1.25, 1.75] (4 faces wide), cut from one quad
    grid of CELLS per unit in the XY plane (the view axis is Z)."""
    verts, quads = grid(4 * CELLS, 2 * CELLS, 4.0, 2.0)
    centre = lambda q: verts[list(q)].mean(axis=0)  # noqa: E731
    keep = [q for q in quads if centre(q)[0] < 1 or 1.25 < centre(q)[1] < 1.75]
    used = sorted({v for q in keep for v in q})
    index = {v: i for i, v in enumerate(used)}
    return mesh_object(name, verts[used], [tuple(index[v] for v in q) for q in keep])


def smooth_weight(x):
    """The limb bone's weight: a smoothstep over BLEND (the torso bone gets 1 - w)."""
    s = np.clip((np.asarray(x) - BLEND[0]) / (BLEND[1] - BLEND[0]), 0.0, 1.0)
    return s * s * (3 - 2 * s)


def rig_and_pose(obj, degrees, weights):
    """Armature 'Rig' (bones Torso, Limb) parented to obj with weights "automatic" (Blender's
    bone heat) or "smooth" (empty bone groups filled with smooth_weight); Limb rotated by
    `degrees` about Z at its head; applied as the shape key 'Swing' (the modifier kept, as an
    animator keeps the rig)."""
    rig = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    torso = rig.data.edit_bones.new("Torso")
    torso.head, torso.tail = (0.5, 0.2, 0.0), (0.5, SHOULDER[1], 0.0)
    limb = rig.data.edit_bones.new("Limb")
    limb.head, limb.tail, limb.parent = (*SHOULDER, 0.0), (4.0, SHOULDER[1], 0.0), torso
    bpy.ops.object.mode_set(mode='OBJECT')
    bpy.ops.object.select_all(action='DESELECT')
    obj.select_set(True)
    rig.select_set(True)
    bpy.context.view_layer.objects.active = rig
    how = 'ARMATURE_AUTO' if weights == "automatic" else 'ARMATURE_NAME'
    assert bpy.ops.object.parent_set(type=how) == {'FINISHED'}
    if weights == "smooth":
        for v, w in enumerate(smooth_weight([v.co.x for v in obj.data.vertices])):
            if w < 1:
                obj.vertex_groups["Torso"].add([v], 1.0 - float(w), 'REPLACE')
            if w > 0:
                obj.vertex_groups["Limb"].add([v], float(w), 'REPLACE')
    head = Vector((*SHOULDER, 0.0))
    bone = rig.pose.bones["Limb"]
    bone.matrix = (Matrix.Translation(head) @ Matrix.Rotation(math.radians(degrees), 4, 'Z')
                   @ Matrix.Translation(-head) @ bone.bone.matrix_local)
    bpy.context.view_layer.update()
    bpy.context.view_layer.objects.active = obj
    obj.shape_key_add(name="Basis", from_mix=False)
    modifier = next(m for m in obj.modifiers if m.type == 'ARMATURE')
    assert bpy.ops.object.modifier_apply_as_shapekey(keep_modifier=True,
                                                     modifier=modifier.name) == {'FINISHED'}
    obj.data.shape_keys.key_blocks[-1].name = "Swing"
    rig.data.pose_position = 'REST'  # the keys alone shape the mesh now


def bone_weights(obj):
    """(n, 2) weights of the groups Torso and Limb (0 where a vertex is not in a group)."""
    W = np.zeros((len(obj.data.vertices), 2))
    column = {obj.vertex_groups["Torso"].index: 0, obj.vertex_groups["Limb"].index: 1}
    for v in obj.data.vertices:
        for g in v.groups:
            W[v.index, column[g.group]] = g.weight
    return W


def signed_areas(X, tris):
    a, b = X[tris[:, 1], :2] - X[tris[:, 0], :2], X[tris[:, 2], :2] - X[tris[:, 0], :2]
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def near(tris, faces, rings=2):
    """Faces within `rings` vertex-sharing steps of `faces` (a boolean mask)."""
    mask = np.zeros(len(tris), bool)
    mask[faces] = True
    for _ in range(rings):
        mask |= np.isin(tris, np.unique(tris[mask])).any(axis=1)
    return mask


def limb_angle(X, base):
    """Direction (degrees) of the forearm (x in [2.5, 4] of the rest pose, turned rigidly by the
    skinning): the line from its start to its tip."""
    start, tip = np.abs(base[:, 0] - 2.5) < 1e-6, np.abs(base[:, 0] - 4.0) < 1e-6
    d = X[tip, :2].mean(axis=0) - X[start, :2].mean(axis=0)
    return math.degrees(math.atan2(d[1], d[0]))


@pytest.fixture(params=[(w, d) for w in ("smooth", "automatic") for d in (160, 200)],
                ids=lambda p: "%s-%d" % p)
def swing(request):
    weights, degrees = request.param
    obj = body_grid()
    rig_and_pose(obj, degrees, weights)
    return obj, degrees, weights


def test_the_rig_makes_a_linear_blend_skinned_key_that_folds(swing):
    """The test pose itself: Blender's armature moves each vertex by the weighted mean of the
    two bones' matrices (linear blend skinning), and the key folds a few faces."""
    obj, degrees, _ = swing
    S, T, tris = read_key(obj, "Basis"), read_key(obj, "Swing"), triangles(obj)
    W = bone_weights(obj)
    assert W.sum(axis=1).min() > 0.9
    w = (W[:, 1] / W.sum(axis=1))[:, None]
    a = math.radians(degrees)
    R = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    lbs = SHOULDER + ((S[:, :2] - SHOULDER) @ R.T) * w + (S[:, :2] - SHOULDER) * (1 - w)
    assert np.abs(T[:, :2] - lbs).max() < 1e-5 and np.abs(T[:, 2]).max() < 1e-6
    folded = np.flatnonzero(signed_areas(T, tris) < 0)
    assert 0 < len(folded) < len(tris) // 10
    # Only where the weights blend (a face whose vertices all follow one bone moves rigidly):
    # around the shoulder, and with bone heat also down the torso's side next to the limb bone.
    blends = (w[:, 0] > 1e-3) & (w[:, 0] < 1 - 1e-3)
    assert np.all(blends[tris[folded]].any(axis=1))


def bake_swing(addon, obj, how):
    """Bake 'Swing' with COUNT in-betweens through the panel's operator or the scripting API;
    returns the keys' names and the message naming the folds."""
    if how == "operator":
        obj.bdi.target, obj.bdi.count, obj.bdi.easing = "Swing", COUNT, 'LINEAR'
        bpy.context.view_layer.objects.active = obj
        assert bpy.ops.bdinterp.bake() == {'FINISHED'}
        names = [n for n in key_names(obj) if n.startswith("Swing.bdi.") and n != "Swing.bdi.100"]
        return names, json.loads(obj.bdi.result)["note"]
    result = addon.bake(obj, target="Swing", count=COUNT)
    return list(result.keys), result.message


def baked(addon, obj, how):
    """Bake the fixture's pose; returns (source, key, triangles, frames = source, the COUNT
    in-betweens and the key, the message naming the folds)."""
    S, T, tris = read_key(obj, "Basis"), read_key(obj, "Swing"), triangles(obj)
    names, message = bake_swing(addon, obj, how)
    assert len(names) == COUNT
    return S, T, tris, [S] + [read_key(obj, n) for n in names] + [T], message


@pytest.mark.parametrize("how", ["operator", "api"])
def test_skinned_pose_bake_names_the_folds_and_flips_nothing_else(addon, bd, swing, how):
    obj, degrees, _ = swing
    S, T, tris, frames, message = baked(addon, obj, how)
    # The bake names the key's folded polygons: how many, and a vertex of one of them.
    me = obj.data
    poly = np.array([lt.polygon_index for lt in me.loop_triangles])
    folded = np.flatnonzero(signed_areas(T, tris) < 0)
    polys = sorted(set(poly[folded].tolist()))
    assert "key 'Swing' has %d folded polygons near vertex " % len(polys) in message
    vertex = int(message.split("near vertex ")[1].split(";")[0].split()[0])
    assert any(vertex in me.polygons[p].vertices for p in polys)
    # No in-between flips a face outside a two-face neighbourhood of the key's folds.
    away = ~near(tris, folded)
    for t, X in zip(np.linspace(0, 1, COUNT + 2)[1:-1], frames[1:-1]):
        assert np.all(bd.area_ratio(S, X, tris)[away] > 0), t


def away_bounds(bd, S, T, tris, frames):
    """Over the in-betweens, outside two faces around the key's folds: the largest K over the
    inputs' K of the face (the source's is 1), and the smallest and largest area over the
    face's smaller and larger input area."""
    away = ~near(tris, np.flatnonzero(signed_areas(T, tris) < 0))
    k_in = np.maximum(bd.conformal_distortion(S, T, tris), 1.0)[away]
    a_s, a_t = np.abs(signed_areas(S, tris))[away], np.abs(signed_areas(T, tris))[away]
    k = [np.max(bd.conformal_distortion(S, X, tris)[away] / k_in) for X in frames[1:-1]]
    a = [signed_areas(X, tris)[away] for X in frames[1:-1]]
    return {"K / input K": float(max(k)),
            "area / smaller input area": float(min(np.min(x / np.minimum(a_s, a_t)) for x in a)),
            "area / larger input area": float(max(np.max(x / np.maximum(a_s, a_t)) for x in a))}


def measure(bd, S, T, tris, frames, swing_deg):
    """The issue's numbers for baked frames (source, in-betweens, key): error at t = 1 (x size),
    largest / median step, forearm angles (unwrapped, degrees) and their largest deviation from
    the proportional swing."""
    size = float(np.ptp(S, axis=0).max())
    steps = [float(np.linalg.norm(b - a, axis=1).max()) for a, b in zip(frames, frames[1:])]
    angles = np.degrees(np.unwrap(np.radians([limb_angle(X, S) for X in frames])))
    angles -= angles[0]
    ts = np.linspace(0.0, 1.0, len(frames))
    return {"error at t = 1": float(np.abs(bd.interpolate(S, T, tris, 1.0) - T).max()) / size,
            "max / median step": max(steps) / float(np.median(steps)),
            "forearm angles": np.round(angles, 1).tolist(),
            "deviation": float(np.abs(angles - ts * swing_deg).max()),
            "monotone": bool(np.all(np.diff(angles) * np.sign(swing_deg) > 0))}


@pytest.mark.parametrize("how", ["operator", "api"])
def test_skinned_pose_bakes_to_the_key_the_pose_way(addon, bd, swing, how):
    obj, degrees, _ = swing
    S, T, tris, frames, _ = baked(addon, obj, how)
    # The pose's way is the skinned joint's: linear blend skinning blends the bone's matrix with
    # the identity, whose rotation angle runs from 0 to the bone's angle taken in (-180, 180] --
    # a bone turned by 200 degrees makes the same key as one turned by -160 (clockwise).
    swing_deg = (degrees + 180) % 360 - 180
    m = measure(bd, S, T, tris, frames, swing_deg)
    why = "measured: " + json.dumps(m)
    # The key is reproduced at t = 1 (the paper's Lagrange property); no pop: the last in-between
    # is as close to the key as any two frames 0.05 apart are to each other. (Before the fold
    # formulation of docs/FOLDS.md: 1.1 .. 1.4 x the size off at t = 1, the forearm at 24 .. 46 of
    # 160 degrees at t = 0.95, then a pop of 51 .. 91 x the median step.)
    assert m["error at t = 1"] <= 1e-9, why
    assert m["max / median step"] <= 3, why
    # The forearm turns the pose's way, monotonically and within 20 degrees of t x the swing.
    assert m["forearm angles"][-1] == pytest.approx(swing_deg, abs=0.5), why
    assert m["monotone"] and m["deviation"] <= 20, why


@pytest.mark.parametrize("how", ["operator", "api"])
def test_skinned_pose_keeps_k_and_areas_away_from_the_folds(addon, bd, swing, how):
    """Away from the folds the frames are those of a valid pair: K within the inputs' per face
    (up to the 1 % discretisation allowance of the other bakes) and no face shrinking to half
    its smaller input area or growing to twice its larger one."""
    # The smooth weights (a function of x alone) turn the torso's right column, down to the hip,
    # partly about the shoulder: the key shears its faces to K = 15 .. 34 without folding them.
    # The paper's length blend grew them to 2.36 x their larger input area at 160 degrees, 8+
    # faces from any fold; they now join the fold region (docs/FOLDS.md, "sheared faces"):
    # measured 0.91 .. 1.26 x and K 1.00002 x the inputs'.
    obj = swing[0]
    S, T, tris, frames, _ = baked(addon, obj, how)
    m = away_bounds(bd, S, T, tris, frames)
    why = "measured: " + json.dumps(m)
    assert m["K / input K"] <= 1.01, why
    assert m["area / smaller input area"] >= 0.5 and m["area / larger input area"] <= 2, why
