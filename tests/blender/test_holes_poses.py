"""Letters with holes baked through the panel's operator and the scripting
API (before: "pieces with holes are not supported"), and a mirrored target's clear error."""

import bpy
import numpy as np
import pytest

from conftest import TOL, add_key, key_names, maxdiff, read_key, text_glyph, triangles


def loops_of(faces):
    """Number of boundary loops of a triangle list (edges used once, chained)."""
    edges = {}
    for a, b, c in faces:
        for u, v in ((a, b), (b, c), (c, a)):
            edges[(min(u, v), max(u, v))] = edges.get((min(u, v), max(u, v)), 0) + 1
    nxt = {}
    for (u, v), n in edges.items():
        if n == 1:
            nxt.setdefault(u, []).append(v)
            nxt.setdefault(v, []).append(u)
    seen, loops = set(), 0
    for start in nxt:
        if start in seen:
            continue
        loops += 1
        stack = [start]
        while stack:
            w = stack.pop()
            if w not in seen:
                seen.add(w)
                stack.extend(nxt[w])
    return loops


# Not "B": Blender's fan triangulation of it (106 vertices, 108 faces, slivers down to an area /
# edge^2 of 0.003) under this target (K up to 10.9) breaks one triangle in the flattened metric at
# t = 0.5, which flips it: the coarse-mesh limitation of the method (README, Limitations), not the
# holes (closed to 1e-11 there).
@pytest.mark.parametrize("char,holes", [("e", 1), ("8", 2)])
def test_operator_bakes_letters_with_holes(bd, char, holes):
    obj = text_glyph("Glyph_" + char, char)
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Lean"), triangles(obj)
    assert loops_of(faces) >= 1 + holes  # the glyph really has its holes (a piece may be more)
    obj.bdi.target, obj.bdi.count = "Lean", 3
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    names = [n for n in key_names(obj) if n.startswith("Lean.bdi.") and n != "Lean.bdi.100"]
    assert len(names) == 3
    for name, t in zip(names, (0.25, 0.5, 0.75)):
        X = read_key(obj, name)
        assert maxdiff(X, bd.interpolate(S, T, faces, t)) < TOL, name
        assert bd.flipped_faces(S, X, faces) == 0
        K, KT = bd.conformal_distortion(S, X, faces), bd.conformal_distortion(S, T, faces)
        assert np.max(K) <= np.max(KT) * 1.01


def test_scripting_api_bakes_a_letter_with_a_hole(addon, bd):
    obj = text_glyph("Glyph_e", "e")
    result = addon.bake(obj, target="Lean", count=4)
    assert len(result.keys) == 4
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Lean"), triangles(obj)
    for name, t in zip(result.keys, result.factors):
        assert maxdiff(read_key(obj, name), bd.interpolate(S, T, faces, t)) < TOL
    assert result.max_distortion <= result.input_distortion * 1.01


def test_mirrored_target_is_refused_with_a_clear_message(addon):
    obj = text_glyph("Glyph_e", "e")
    S = read_key(obj, "Basis")
    add_key(obj, "Mirror", S * [-1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="mirror image"):
        addon.bake(obj, target="Mirror", count=2)
    assert not any(n.startswith("Mirror.bdi.") for n in key_names(obj))
