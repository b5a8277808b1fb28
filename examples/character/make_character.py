"""Build examples/character/{source,target}.obj: a cut-out character.

Run inside Blender (its constrained Delaunay mesher does the meshing)::

    blender --background --factory-startup --python-exit-code 1 \\
        --python examples/character/make_character.py

The outline (head, neck, torso, two arms, two legs) is drawn by hand from
segments and arcs, sampled evenly, filled with jittered lattice points
(tools/bdinterp_tools/meshes.py) and meshed by ``mathutils.geometry.delaunay_2d_cdt``
keeping only triangles inside the outline.  The target pose bends each limb
with a rotation that varies smoothly along it (examples/deform.py): the
right arm curls up and over by 200 degrees, the left arm lowers by 50, the
legs step apart.  No target triangle is flipped.
"""

import importlib.util
import os

import numpy as np
from mathutils import Vector
from mathutils.geometry import delaunay_2d_cdt

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
N_VERTICES = 2000
SEED = 11


def _load(name, path):
    # By file path: Blender's Python cannot import the bdinterp package
    # (its compiled core is built for the system Python).
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


meshes = _load("meshes", os.path.join(ROOT, "tools", "bdinterp_tools", "meshes.py"))
io = _load("io", os.path.join(ROOT, "python", "bdinterp", "io.py"))
deform = _load("deform", os.path.join(ROOT, "examples", "deform.py"))

# Skeleton: limb roots and axes (the outline below is drawn around them).
ARM_Y, ARM_HALF = 1.0, 0.25      # arm centre line height and half width
SHOULDER_X = 1.0                 # torso half width; arms start here
HIP_Y = -1.5                     # torso bottom; legs start here
LEG_X = 0.55                     # leg centre lines at x = +-LEG_X
HAND_X = 5.0                     # hand centres at x = +-HAND_X


def _arc(center, r, a0, a1, step=0.02):
    """Points on a circular arc from angle a0 to a1 (degrees; a1 > a0: CCW)."""
    n = max(2, int(np.ceil(np.radians(abs(a1 - a0)) * r / step)))
    a = np.radians(np.linspace(a0, a1, n))
    return np.asarray(center) + r * np.c_[np.cos(a), np.sin(a)]


def outline():
    """(n,2) CCW outline of the whole character, finely sampled."""
    ya, yb = ARM_Y - ARM_HALF, ARM_Y + ARM_HALF
    hand_c, hand_r = (HAND_X, ARM_Y), 0.4
    hand_a = np.degrees(np.arcsin(ARM_HALF / hand_r))
    head_c, head_r, neck = (0.0, 2.6), 0.75, 0.3
    head_a = np.degrees(np.arcsin(-np.sqrt(head_r ** 2 - neck ** 2) / head_r))
    foot_r = 0.4
    right = np.vstack([
        [[0.0, HIP_Y + 0.05], [LEG_X - foot_r, HIP_Y - 0.1]],   # crotch
        _arc((LEG_X, -4.6), foot_r, 180, 360),                 # right foot
        [[LEG_X + foot_r, HIP_Y - 0.1], [SHOULDER_X, HIP_Y],    # hip
         [SHOULDER_X, ya]],                                     # armpit
        _arc(hand_c, hand_r, -180 + hand_a, 180 - hand_a),      # right hand
        [[SHOULDER_X + 0.1, yb], [0.9 * SHOULDER_X, yb + 0.25],  # shoulder
         [neck, yb + 0.35]],
        _arc(head_c, head_r, head_a, 90),                       # head
    ])
    fine = np.vstack([right[:-1], (right[::-1] * [-1, 1])[:-1]])
    # Dense sampling (step 0.02) so the even resampling follows the arcs.
    return meshes.resample_closed(fine, 0.02)


def mesh_outline(P, n_approx, seed):
    """CCW triangle mesh (V (n,2), F (m,3) int32) filling outline P."""
    h = meshes.lattice_spacing(P, n_approx)
    B = meshes.resample_closed(P, h)
    _, interior, _ = meshes.sample_polygon(B, n_approx, seed, resample=False)
    pts = np.vstack([B, interior])
    loop = list(range(len(B)))
    edges = [(i, (i + 1) % len(B)) for i in loop]
    # output_type 1: only the triangles inside the constraint face.
    verts, _, faces, *_ = delaunay_2d_cdt([Vector(p) for p in pts], edges,
                                          [loop], 1, 1e-9)
    V = np.array([v[:2] for v in verts], dtype=np.float64)
    F = np.array(faces, dtype=np.int32)
    flip = meshes.signed_areas(V, F) < 0
    F[flip] = F[flip][:, [0, 2, 1]]
    used = np.unique(F)
    remap = np.full(len(V), -1, dtype=np.int32)
    remap[used] = np.arange(len(used), dtype=np.int32)
    return V[used], remap[F]


def pose(V):
    """Target pose of the character mesh vertices V (n,2)."""
    arm_len = HAND_X - SHOULDER_X
    # Right arm: 200 degrees CCW, spread over all but the upper arm (so the
    # curled forearm clears the head) and the hand; each cross section
    # turns only a little relative to its neighbours.
    Y = deform.bend(V, (SHOULDER_X, ARM_Y), (1, 0),
                    deform.smooth_ramp(np.radians(200), 0.8, arm_len))
    # Left arm (axis pointing left): CCW = downwards.
    Y = deform.bend(Y, (-SHOULDER_X, ARM_Y), (-1, 0),
                    deform.smooth_ramp(np.radians(50), 0.0, arm_len))
    for side, angle in ((1, 25), (-1, -15)):
        Y = deform.bend(Y, (side * LEG_X, HIP_Y), (0, -1),
                        deform.smooth_ramp(np.radians(angle), 0.0, 2.5),
                        mask=side * V[:, 0] > 0)
    return Y


def main():
    V, F = mesh_outline(outline(), N_VERTICES, SEED)
    Y = pose(V)
    io.write_obj(os.path.join(HERE, "source.obj"), V, F,
                 comment="bdinterp example 'character': source")
    io.write_obj(os.path.join(HERE, "target.obj"), Y, F,
                 comment="bdinterp example 'character': target")
    flipped = np.count_nonzero(meshes.signed_areas(Y, F) <= 0)
    print(f"character: {len(V)} vertices, {len(F)} faces, "
          f"{flipped} flipped in target")


main()
