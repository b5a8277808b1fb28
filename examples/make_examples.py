"""Regenerate the example inputs examples/<name>/{source,target}.obj.

Usage (from the repository root)::

    /usr/bin/python3 examples/make_examples.py [NAME ...]

Without names every example except ``character`` is rebuilt; ``character``
is meshed by Blender's constrained Delaunay mesher, see
examples/character/make_character.py.  Everything is seeded, so a rerun
writes identical files.  See examples/README.md for what each one shows.
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
sys.path.insert(0, HERE)

from bdinterp import io  # noqa: E402
from bdinterp_tools import meshes  # noqa: E402
from deform import bend, smooth_ramp  # noqa: E402


def bar_half_bent():
    """8 x 1 bar; only the right half bends (by 120 degrees): local support."""
    V, F = meshes.rectangle(8.0, 1.0, 900, seed=1, origin=(0.0, -0.5))
    Y = bend(V, (4.0, 0.0), (1.0, 0.0), smooth_ramp(np.radians(120), 0, 4))
    return V, F, Y


def spiral():
    """20 x 1 bar rolled into a 1.5-turn spiral (curvature growing along the
    bar), 20% longer and tapering to half its width at the tip.

    The rotation reaches 540 degrees; the stretch along / shrink across
    makes the linear blend flip triangles (not merely collapse them) where
    the rotation passes 180 and 540 degrees.
    """
    L = 20.0
    V, F = meshes.rectangle(L, 1.0, 1200, seed=3, origin=(0.0, -0.5))
    Y = bend(V, (0.0, 0.0), (1.0, 0.0),
             lambda s: 3.0 * np.pi * (np.asarray(s) / L) ** 2,
             stretch=1.2, width=lambda s: 1.0 - 0.5 * s / L)
    return V, F, Y


def affine():
    """Disk under a global affine map (K = 2.2 everywhere): Fig. 4."""
    V, F = meshes.disk(400, seed=4)
    A = np.array([[1.6, 0.5], [0.1, 0.7]])
    return V, F, V @ A.T + [3.0, 0.5]


def _mapped_square(name, n, seed):
    # The square inscribed in meshes.MAP_DOMAIN: away from the map's pole,
    # and its straight sides show how the map bends lines (as in Fig. 9).
    (cx, cy), r = meshes.MAP_DOMAIN
    a = r * np.sqrt(0.5)
    V, F = meshes.rectangle(2 * a, 2 * a, n, seed, origin=(cx - a, cy - a))
    return V, F, meshes.apply_map(name, V)


def conformal():
    """Square under the Moebius map (4z+5)/(3z+1): K = 1 (Fig. 9, B)."""
    return _mapped_square("mobius", 600, seed=5)


def teichmuller():
    """Square under phi3 of Sec. 4.3, a Teichmueller map, K = 2 (Fig. 9)."""
    return _mapped_square("phi3", 600, seed=6)


def folded(n_folds=10, seed=7):
    """A smoothly warped rectangle with about ``n_folds`` flipped triangles.

    Interior vertices, far apart from each other, are pushed across the
    opposite edge of one of their triangles until at least ``n_folds``
    faces are flipped (Fig. 10, bottom row).
    """
    V, F = meshes.rectangle(4.0, 2.0, 700, seed=seed)
    x, y = V[:, 0], V[:, 1]
    Y = np.c_[x + 0.15 * np.sin(1.5 * y), y + 0.25 * np.sin(1.2 * x)]
    rng = np.random.default_rng(seed)
    interior = np.setdiff1d(np.arange(len(V)),
                            meshes.boundary_edges(F).ravel())
    spacing = np.sqrt(16.0 / len(F))  # ~ edge length: area 8, m faces
    moved = []
    for f in rng.permutation(len(F)):
        if np.count_nonzero(meshes.signed_areas(Y, F) < 0) >= n_folds:
            break
        a, b, c = F[f]
        if a not in interior or any(
                np.linalg.norm(V[a] - V[m]) < 4 * spacing
                for m in moved):
            continue
        # Mirror a to just beyond edge bc: this face flips, a few of a's
        # other faces may too.
        e = Y[c] - Y[b]
        foot = Y[b] + e * np.dot(Y[a] - Y[b], e) / np.dot(e, e)
        Y[a] = foot + 0.3 * (foot - Y[a])
        moved.append(a)
    return V, F, Y


def _body_mesh(outline, n_approx, seed):
    """Delaunay mesh of a non-convex outline (n,2): boundary samples spaced like the jittered
    interior lattice, faces with their centroid outside dropped; checked to be one disk whose
    boundary is the sampled outline (Delaunay keeps every outline segment here)."""
    B, I, _ = meshes.sample_polygon(outline, n_approx, seed)
    V, F = meshes._delaunay(np.concatenate([B, I]), outline=outline)
    edges = len(np.unique(np.sort(np.r_[F[:, :2], F[:, 1:], F[:, ::2]], axis=1), axis=0))
    assert len(meshes.boundary_edges(F)) == len(B) and len(V) - edges + len(F) == 1
    return V, F


SHOULDER = np.array([1.0, 1.5])


def skinned_swing(degrees=200.0, blend=(0.85, 1.25), seed=9):
    """A torso [0, 1] x [0, 2] with an arm [1, 4] x [1.25, 1.75], posed the way an armature
    poses it: two-bone linear blend skinning, the arm bone turned by ``degrees`` about the
    shoulder, smoothstep weights over x in ``blend``. The joint folds a few triangles; since skinning blends the bone's matrix with the identity, 200 degrees gives the
    same key as -160 (the arm swings clockwise)."""
    outline = np.array([(0, 0), (1, 0), (1, 1.25), (4, 1.25), (4, 1.75), (1, 1.75), (1, 2),
                        (0, 2)], dtype=float)
    V, F = _body_mesh(outline, 900, seed)
    s = np.clip((V[:, 0] - blend[0]) / (blend[1] - blend[0]), 0.0, 1.0)
    w = (s * s * (3 - 2 * s))[:, None]
    a = np.radians(degrees)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    Y = SHOULDER + (1 - w) * (V - SHOULDER) + w * ((V - SHOULDER) @ R.T)
    return V, F, Y


def body_tail(degrees=300.0, seed=10):
    """A body [0, 2] x [0, 1] with a tail [2, 5] x [0.35, 0.65] that curls up by ``degrees``
    (a smooth ramp along it, deform.bend); the body does not move."""
    outline = np.array([(0, 0), (2, 0), (2, 0.35), (5, 0.35), (5, 0.65), (2, 0.65), (2, 1),
                        (0, 1)], dtype=float)
    V, F = _body_mesh(outline, 900, seed)
    Y = bend(V, (2.0, 0.5), (1.0, 0.0), smooth_ramp(np.radians(degrees), 0, 3),
             mask=V[:, 0] > 2.0)
    return V, F, Y


def cutout():
    """A cut-out character of seven loose pieces at depths 0, 0.01, ..., 0.06 (draw order): the
    arm raised 150 degrees at the shoulder, the elbow bent 90, the head tilted 30 (the
    pieces and the pins are in cutout/cutout_character.py)."""
    sys.path.insert(0, os.path.join(HERE, "cutout"))
    import cutout_character as cc
    V, Y, polygons, _ = cc.one_mesh(cc.character()[0])
    return V, cc.fan(polygons), Y


EXAMPLES = {f.__name__: f for f in (bar_half_bent, spiral, affine, conformal,
                                    teichmuller, folded, skinned_swing, body_tail, cutout)}


def write_example(name, V, F, Y):
    """Write examples/<name>/source.obj and target.obj; print a summary."""
    out = os.path.join(HERE, name)
    os.makedirs(out, exist_ok=True)
    io.write_obj(os.path.join(out, "source.obj"), V, F,
                 comment=f"bdinterp example '{name}': source")
    io.write_obj(os.path.join(out, "target.obj"), Y, F,
                 comment=f"bdinterp example '{name}': target")
    flipped = np.count_nonzero(meshes.signed_areas(Y, F) <= 0)
    print(f"{name}: {len(V)} vertices, {len(F)} faces, "
          f"{flipped} flipped in target")


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or list(EXAMPLES)
    for name in names:
        if name not in EXAMPLES:
            raise SystemExit(f"unknown example '{name}' (known: "
                             f"{', '.join(EXAMPLES)}; 'character' is made "
                             f"by examples/character/make_character.py)")
        write_example(name, *EXAMPLES[name]())


if __name__ == "__main__":
    main()
