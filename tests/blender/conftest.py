"""Fixtures and mesh builders for the Blender tests (run inside Blender by run_blender_tests.py)."""

import glob
import importlib
import json
import math
import os
import subprocess

import bpy
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOL = 1e-6
# Blender 4.2+ with the extension zip (run_blender_tests.py --extension installed it): the add-on is
# the module bl_ext.user_default.bdinterp_blender; with the legacy zip it is bdinterp_blender.
EXTENSION = os.environ.get("BDI_EXTENSION_ZIP")
ADDON_MODULE = "bl_ext.user_default.bdinterp_blender" if EXTENSION else "bdinterp_blender"
# The user folders a child Blender needs to see the installed add-on or extension.
USER_ENV = ("BLENDER_USER_SCRIPTS", "BLENDER_USER_EXTENSIONS", "BLENDER_USER_CONFIG")


def addon_zip():
    path = os.environ.get("BDI_ADDON_ZIP")
    if path:
        return path
    zips = sorted(glob.glob(os.path.join(ROOT, "dist", "bdinterp_blender-*-legacy-*.zip")),
                  key=os.path.getmtime)
    if not zips:
        pytest.exit("no add-on zip: run `/usr/bin/python3 scripts/build_addon.py` first", 2)
    return zips[-1]


@pytest.fixture(scope="package")
def addon():
    """Install the built zip with Blender's own installer (isolated user folder) and enable it
    (an extension zip is installed already, by `blender --command extension install-file`)."""
    import addon_utils
    assert os.environ.get("BLENDER_USER_SCRIPTS"), "run through run_blender_tests.py"
    if not EXTENSION:
        bpy.ops.preferences.addon_install(filepath=addon_zip(), overwrite=True)
    addon_utils.enable(ADDON_MODULE, default_set=True)
    assert addon_utils.check(ADDON_MODULE) == (True, True)
    module = importlib.import_module(ADDON_MODULE)
    import bdinterp_blender  # the scripting name: the same module (an alias for the extension)
    assert bdinterp_blender is module
    user = os.environ["BLENDER_USER_EXTENSIONS" if EXTENSION else "BLENDER_USER_SCRIPTS"]
    assert module.__file__.startswith(user)
    return module


@pytest.fixture(scope="package")
def bd(addon):
    """The bdinterp package the add-on uses (the copy vendored in the zip)."""
    return addon.load_core()


@pytest.fixture(autouse=True)
def empty_file(addon):
    bpy.ops.wm.read_homefile(use_empty=True)
    yield


# ---------------------------------------------------------------- data access

def read_key(obj, name):
    kb = obj.data.shape_keys.key_blocks[name]
    co = np.empty(len(kb.data) * 3, dtype=np.float32)
    kb.data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def triangles(obj):
    me = obj.data
    me.calc_loop_triangles()
    tris = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
    me.loop_triangles.foreach_get("vertices", tris)
    return tris.reshape(-1, 3).astype(np.int64)


def evaluated_co(obj):
    bpy.context.view_layer.update()
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
    ev.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def key_names(obj):
    return [kb.name for kb in obj.data.shape_keys.key_blocks] if obj.data.shape_keys else []


def maxdiff(a, b):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


# ---------------------------------------------------------------- test meshes

def mesh_object(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts], [], [tuple(f) for f in faces])
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return obj


def path_object(points, location=(0.0, 0.0, 0.0)):
    """A poly curve through world `points`, its object at `location` (its points relative to it)."""
    curve = bpy.data.curves.new("Path", 'CURVE')
    spline = curve.splines.new('POLY')
    spline.points.add(len(points) - 1)
    for p, xyz in zip(spline.points, points):
        p.co = (*(np.asarray(xyz) - location), 1.0)
    obj = bpy.data.objects.new("Path", curve)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.update()
    return obj


def add_key(obj, name, co, relative=None):
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    kb = obj.shape_key_add(name=name, from_mix=False)
    kb.value = 0.0  # Blender 5.0+ gives a new key the value 1
    kb.data.foreach_set("co", np.asarray(co, dtype=np.float32).ravel())
    if relative:
        kb.relative_key = obj.data.shape_keys.key_blocks[relative]
    return kb


def fcurve(anim, path):
    """The F-curve of `path` in AnimData `anim`'s action (any Blender: legacy or slotted)."""
    from bdinterp_blender.actions import find_fcurve
    return find_fcurve(anim, path)


def fcurves(anim):
    """Every F-curve of AnimData `anim`'s action that animates its ID."""
    from bdinterp_blender.actions import all_fcurves
    return all_fcurves(anim)


def new_armature(bones, at):
    """Armature object 'Rig' at `at` (3,) with bones [(name, parent or None, head (2,), tail (2,))]
    in world x, y at z = 0, parents before children."""
    arm = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(arm)
    arm.location = at
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode='EDIT')
    for name, parent, head, tail in bones:
        bone = arm.data.edit_bones.new(name)
        bone.head = (head[0] - at[0], head[1] - at[1], -at[2])
        bone.tail = (tail[0] - at[0], tail[1] - at[1], -at[2])
        bone.parent = arm.data.edit_bones[parent] if parent else None
    bpy.ops.object.mode_set(mode='OBJECT')
    return arm


def bone_pieces(arm, pieces, parented=False):
    """One object per piece ((name, (V (n, 2), F)) in draw order, at depth 0.01 per piece), all
    its vertices in the vertex group of its bone (named like the piece) with an Armature modifier
    (parented: the object's parent is its bone instead), as cut-out rigs are made."""
    import mathutils
    objs = []
    for k, (name, (V, F)) in enumerate(pieces):
        obj = mesh_object(name, np.c_[V, np.full(len(V), 0.01 * k)], F)
        if parented:
            obj.parent, obj.parent_type, obj.parent_bone = arm, 'BONE', name
            bpy.context.view_layer.update()
            obj.matrix_world = mathutils.Matrix.Identity(4)
        else:
            obj.vertex_groups.new(name=name).add(list(range(len(V))), 1.0, 'REPLACE')
            obj.modifiers.new("Armature", 'ARMATURE').object = arm
        objs.append(obj)
    return objs


def world(objs):
    """(n, 3) the objects' evaluated vertices in world space, one object after the other."""
    out = []
    for obj in objs:
        m = np.array(obj.matrix_world)
        out.append(evaluated_co(obj) @ m[:3, :3].T + m[:3, 3])
    return np.concatenate(out)


def grid(nx, ny, w, h, x0=0.0, y0=0.0):
    """Quad grid in XY: (verts (n,3), quads)."""
    xs, ys = np.meshgrid(np.linspace(x0, x0 + w, nx + 1), np.linspace(y0, y0 + h, ny + 1))
    verts = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    quads = [(j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i)
             for j in range(ny) for i in range(nx)]
    return verts, quads


def bent_strip(name="Strip", angle=math.radians(90)):
    """A subdivided plane bent with a Simple Deform modifier, applied as the shape key 'Bend'."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=16, y_subdivisions=4, size=2.0)
    obj = bpy.context.object
    obj.name = name
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3) * [1.0, 0.2, 1.0]  # a long strip (2 x 0.4), like an arm
    obj.data.vertices.foreach_set("co", co.ravel())
    obj.data.update()
    obj.shape_key_add(name="Basis", from_mix=False)
    mod = obj.modifiers.new("Bend", 'SIMPLE_DEFORM')
    mod.deform_method, mod.deform_axis, mod.angle = 'BEND', 'Z', angle
    bpy.ops.object.modifier_apply_as_shapekey(modifier="Bend")
    assert key_names(obj) == ["Basis", "Bend"]
    return obj


def text_glyph(name="Glyph", char="S"):
    """A filled text glyph converted to a mesh; target: a smooth shear + stretch."""
    bpy.ops.object.text_add()
    txt = bpy.context.object
    txt.data.body = char
    bpy.ops.object.convert(target='MESH')
    obj = bpy.context.object
    obj.name = name
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.remove_doubles(threshold=1e-5)
    bpy.ops.object.mode_set(mode='OBJECT')
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    x, y = co[:, 0], co[:, 1]
    target = np.stack([1.2 * x + 0.5 * y * y, 0.8 * y + 0.2 * x, co[:, 2]], axis=1)
    add_key(obj, "Lean", target)
    return obj


def ngon_xz(name="Ngon", y=0.3):
    """N-gons (a concave L hexagon, a pentagon, a quad) in the plane y = const (XZ plane)."""
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2),   # L (concave hexagon)
           (3, 0), (3.5, 1), (2.5, 1.6),                       # pentagon with 2, 1 -> shares edge 1-2
           (-1, 0), (-1, 2)]                                   # quad left of the L
    verts = [(px, y, pz) for px, pz in pts]
    faces = [(0, 1, 2, 3, 4, 5), (1, 6, 7, 8, 2), (9, 0, 5, 10)]
    obj = mesh_object(name, verts, faces)
    v = np.array(verts)
    x, z = v[:, 0], v[:, 2]
    add_key(obj, "Shear", np.stack([x + 0.3 * z, v[:, 1], 1.1 * z + 0.05 * x * x], axis=1))
    return obj


def two_pieces(name="Pieces"):
    """Two separate grids in one mesh, each with its own deformation."""
    va, fa = grid(6, 3, 1.5, 0.6)
    vb, fb = grid(4, 4, 1.0, 1.0, x0=2.5)
    verts = np.vstack([va, vb])
    faces = fa + [tuple(i + len(va) for i in f) for f in fb]
    obj = mesh_object(name, verts, faces)
    tgt = verts.copy()
    a = np.arange(len(verts)) < len(va)
    tgt[a, 1] += 0.3 * tgt[a, 0] ** 2                              # piece A bends
    c, s = math.cos(0.8), math.sin(0.8)                            # piece B rotates + stretches
    bx, by = tgt[~a, 0] - 3.0, tgt[~a, 1] - 0.5
    tgt[~a, 0], tgt[~a, 1] = 3.0 + 1.3 * (c * bx - s * by), 0.5 + (s * bx + c * by)
    add_key(obj, "Move", tgt)
    return obj


# ---------------------------------------------------------------- other Blender processes

def run_blender(args, env_drop=USER_ENV, timeout=300):
    """Run another (headless) Blender; by default without our user folders, i.e. without the
    add-on.  Returns the CompletedProcess; stdout lines 'JSON:...' carry results.
    With the user folders (env_drop=()) an extension is enabled in the child, because (unlike a
    legacy add-on on the scripts path) it is importable only then: `--addons bdinterp_blender`
    becomes `--addons bl_ext.user_default.bdinterp_blender`."""
    env = {k: v for k, v in os.environ.items() if k not in env_drop}
    if EXTENSION and "BLENDER_USER_EXTENSIONS" in env:
        args = list(args)
        if "--addons" in args and args[args.index("--addons") + 1] == "bdinterp_blender":
            args[args.index("--addons") + 1] = ADDON_MODULE
        else:
            args = ["--addons", ADDON_MODULE] + args
    proc = subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", *args],
                          capture_output=True, text=True, timeout=timeout, env=env)
    return proc


def json_lines(proc):
    out = [json.loads(line[5:]) for line in proc.stdout.splitlines() if line.startswith("JSON:")]
    assert out, "no result from child Blender:\n%s\n%s" % (proc.stdout[-3000:], proc.stderr[-3000:])
    return out


def write_child_script(tmp_path, body):
    path = os.path.join(str(tmp_path), "child.py")
    with open(path, "w") as f:
        f.write("import bpy, json, sys\nimport numpy as np\n" + body)
    return path
