"""The cut-out character (cutout_character.py) as Blender objects: one object whose pieces lie at
their depths, or one object per piece with its own transform (turned out of the XY plane, scaled
unevenly, moved) holding the same world shapes. Used by bake_cutout.py and tests/blender."""

import math

import bpy
import numpy as np
from mathutils import Euler, Matrix, Vector

import cutout_character as cc

# Object transforms (rotation in degrees, scale, location) of the seven-object character: every
# object's local coordinates differ from the world's (turned, scaled unevenly, one mirrored).
TRANSFORMS = {"Torso": ((0, 0, 0), (1, 1, 1), (0, 0, 0)),
              "Head": ((90, 0, 30), (2, 2, 2), (1, -3, 0.5)),
              "EyeL": ((10, 20, 30), (0.5, 0.5, 0.5), (0, 0, 2)),
              "EyeR": ((-30, 45, 0), (-1, 1, 1), (-2, 1, 0)),  # mirrored, as a copied eye
              "UpperArm": ((0, 90, 0), (1.5, 0.7, 1.2), (3, 0, 0)),
              "Forearm": ((0, 0, 135), (1, 1, 1), (0.5, 0.5, -1)),
              "Hand": ((45, 45, 45), (0.8, 1.25, 2.0), (-1, -1, -1))}
TARGET = "Pose"


def new_object(name, source, polygons, target, matrix=None):
    """A linked, selected mesh object with keys 'Basis' (source) and TARGET (value 0), both
    (n, 3) world coordinates, stored in the local coordinates of `matrix` (default identity)."""
    m = np.array(matrix if matrix is not None else Matrix.Identity(4))
    inv = np.linalg.inv(m)
    local = [X @ inv[:3, :3].T + inv[:3, 3] for X in (source, target)]
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in local[0]], [], [tuple(f) for f in polygons])
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    if matrix is not None:
        obj.matrix_world = matrix
    obj.shape_key_add(name="Basis", from_mix=False)
    kb = obj.shape_key_add(name=TARGET, from_mix=False)
    kb.value = 0.0  # Blender 5.0+ gives a new key the value 1
    kb.data.foreach_set("co", local[1].astype(np.float32).ravel())
    obj.select_set(True)
    return obj


def one_object(pieces, name="Character"):
    """The character as one mesh object, made active; (object, {piece: vertex range})."""
    source, target, polygons, ranges = cc.one_mesh(pieces)
    obj = new_object(name, source, polygons, target)
    bpy.context.view_layer.objects.active = obj
    return obj, ranges


def transform(name):
    rot, scale, loc = TRANSFORMS[name]
    return Matrix.LocRotScale(Vector(loc), Euler([math.radians(a) for a in rot]), Vector(scale))


def seven_objects(pieces):
    """One object per piece (named like it), with TRANSFORMS; the first (the torso) active."""
    objs = [new_object(p.name, p.source, p.polygons, p.target, transform(p.name)) for p in pieces]
    bpy.context.view_layer.objects.active = objs[0]
    return objs


def read(obj, key):
    kb = obj.data.shape_keys.key_blocks[key]
    co = np.empty(len(kb.data) * 3, dtype=np.float32)
    kb.data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def world(obj, co):
    m = np.array(obj.matrix_world)
    return co @ m[:3, :3].T + m[:3, 3]


def in_world(objs, keys):
    """Keys `keys` of objects `objs` in world coordinates, the objects' vertices one after the
    other: (frames (k, n, 3), {object name: vertex range}, triangles (m, 3))."""
    offsets = np.cumsum([0] + [len(o.data.vertices) for o in objs])
    ranges = {o.name: range(int(a), int(b)) for o, a, b in zip(objs, offsets[:-1], offsets[1:])}
    frames = np.array([np.concatenate([world(o, read(o, k)) for o in objs]) for k in keys])
    # the pieces' polygons are convex and move rigidly: any triangles of them carry a pin alike
    tris = np.concatenate([cc.fan([tuple(p.vertices) for p in o.data.polygons]) + a
                           for o, a in zip(objs, offsets)])
    return frames, ranges, tris


def baked(obj, target=TARGET):
    """The in-between keys of a bake of `target`, in order."""
    return [kb.name for kb in obj.data.shape_keys.key_blocks if kb.name.startswith(target + ".bdi.")]


def openings(objs, ranges, joints, size, keys):
    """cutout_character.joint_openings of keys `keys` (the in-betweens) of `objs`, whose vertex
    ranges per piece are `ranges` (one object: its pieces' ranges; several: by object name)."""
    X0 = in_world(objs, ["Basis"])[0][0]
    frames, by_object, tris = in_world(objs, keys)
    ranges = ranges or by_object
    tris_of = {name: tris[np.isin(tris[:, 0], list(r))] for name, r in ranges.items()}
    return cc.joint_openings(X0, frames, tris_of, joints, size)


def size_of(pieces):
    """The character's size: its source's bounding-box diagonal."""
    return float(np.linalg.norm(np.ptp(np.concatenate([p.source for p in pieces]), axis=0)))
