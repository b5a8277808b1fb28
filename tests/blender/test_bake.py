"""Bake operator through bpy.ops on meshes made here, checked against bdinterp.interpolate."""

import json

import bpy
import numpy as np
import pytest

from conftest import (TOL, bent_strip, evaluated_co, key_names, maxdiff, ngon_xz, read_key,
                      path_object, text_glyph, triangles, two_pieces, add_key)


def configure(obj, target, **settings):
    props = obj.bdi
    props.target = target
    for name, value in settings.items():
        setattr(props, name, value)
    bpy.context.view_layer.objects.active = obj
    return props


def check_baked(bd, obj, source, target, factors, **kw):
    """Every baked key equals bdinterp.interpolate at its factor (to 1e-6), relative to source."""
    S, T, faces = read_key(obj, source), read_key(obj, target), triangles(obj)
    kbs = obj.data.shape_keys.key_blocks
    names = [n for n in key_names(obj) if n.startswith(target + ".bdi.")
             and n != target + ".bdi.100"]  # end key of the playback, see test below
    assert len(names) == len(factors)
    for name, t in zip(names, factors):
        expected = bd.interpolate(S, T, faces, t, **kw)
        assert maxdiff(read_key(obj, name), expected) < TOL, name
        assert kbs[name].relative_key.name == source
    return names


@pytest.mark.parametrize("make,target", [(bent_strip, "Bend"), (text_glyph, "Lean"),
                                         (ngon_xz, "Shear"), (two_pieces, "Move")])
def test_bake_matches_core(bd, make, target):
    obj = make()
    n_poly, co_before = len(obj.data.polygons), read_key(obj, "Basis")
    configure(obj, target, count=4)
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    names = check_baked(bd, obj, "Basis", target, [0.2, 0.4, 0.6, 0.8])
    assert names == ["%s.bdi.%s" % (target, s) for s in ("020", "040", "060", "080")]
    # the mesh itself (n-gons, positions) is not changed by the internal triangulation
    assert len(obj.data.polygons) == n_poly
    assert maxdiff(read_key(obj, "Basis"), co_before) == 0.0


def test_xz_plane_result_stays_in_plane(bd):
    obj = ngon_xz(y=0.3)
    configure(obj, "Shear", count=3)
    bpy.ops.bdinterp.bake()
    for name in key_names(obj)[2:]:
        assert np.allclose(read_key(obj, name)[:, 1], 0.3, atol=1e-6)


def test_rebake_replaces_instead_of_piling_up(bd):
    obj = bent_strip()
    configure(obj, "Bend", count=3)
    bpy.ops.bdinterp.bake()
    assert len(key_names(obj)) == 2 + 3
    configure(obj, "Bend", count=5)
    bpy.ops.bdinterp.bake()
    assert len(key_names(obj)) == 2 + 5
    check_baked(bd, obj, "Basis", "Bend", [1 / 6, 2 / 6, 3 / 6, 4 / 6, 5 / 6])


@pytest.mark.parametrize("easing,fn", [("LINEAR", lambda u: u), ("EASE_IN", lambda u: u * u),
                                       ("EASE_OUT", lambda u: 1 - (1 - u) ** 2),
                                       ("EASE_IN_OUT", lambda u: u * u * (3 - 2 * u))])
def test_easing(bd, easing, fn):
    obj = bent_strip()
    configure(obj, "Bend", count=3, easing=easing)
    bpy.ops.bdinterp.bake()
    check_baked(bd, obj, "Basis", "Bend", [fn(u) for u in (0.25, 0.5, 0.75)])


def test_explicit_factors(bd):
    obj = bent_strip()
    configure(obj, "Bend", use_factors=True, factors="0.1, 0.5,0.125")
    bpy.ops.bdinterp.bake()
    names = check_baked(bd, obj, "Basis", "Bend", [0.1, 0.125, 0.5])
    assert names == ["Bend.bdi.010", "Bend.bdi.012.5", "Bend.bdi.050"]


def test_custom_easing_curve(bd):
    obj = bent_strip()
    configure(obj, "Bend", count=3)
    assert bpy.ops.bdinterp.easing_curve_new() == {'FINISHED'}
    assert obj.bdi.easing == 'CUSTOM'
    mapping = obj.bdi.easing_curve.nodes["Easing"].mapping
    curve = mapping.curves[0]
    curve.points[0].location, curve.points[1].location = (0.0, 0.0), (1.0, 1.0)
    curve.points.new(0.5, 0.8)
    mapping.update()
    mapping.initialize()
    expected = [mapping.evaluate(curve, u) for u in (0.25, 0.5, 0.75)]
    assert abs(expected[1] - 0.8) < 1e-3
    bpy.ops.bdinterp.bake()
    check_baked(bd, obj, "Basis", "Bend", expected)


def test_anchor_vertex_and_group(bd):
    obj = bent_strip()
    configure(obj, "Bend", count=2, anchor='VERTEX', anchor_vertex=7)
    bpy.ops.bdinterp.bake()
    check_baked(bd, obj, "Basis", "Bend", [1 / 3, 2 / 3], anchor=7)
    group = obj.vertex_groups.new(name="Hand")
    group.add([3], 0.5, 'REPLACE')
    group.add([11], 1.0, 'REPLACE')
    configure(obj, "Bend", anchor='GROUP', anchor_group="Hand")
    bpy.ops.bdinterp.bake()
    check_baked(bd, obj, "Basis", "Bend", [1 / 3, 2 / 3], anchor=11)


def test_anchor_from_selected_vertex(addon):
    obj = bent_strip()
    configure(obj, "Bend")
    obj.data.vertices.foreach_set("select", [False] * len(obj.data.vertices))
    obj.data.vertices[9].select = True
    assert bpy.ops.bdinterp.anchor_from_selection() == {'FINISHED'}
    assert (obj.bdi.anchor, obj.bdi.anchor_vertex) == ('VERTEX', 9)


def test_anchor_follows_path(bd):
    obj = bent_strip()
    pts = [(0.0, 0.0, 0.0), (0.3, 0.5, 0.0), (0.2, 1.0, 0.0)]
    path = path_object(pts)
    configure(obj, "Bend", count=2, anchor_path=path)
    bpy.ops.bdinterp.bake()
    p = np.array(pts)
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    ts = np.concatenate([[0], np.cumsum(seg)]) / seg.sum()
    anchor = bd.AnchorPath(ts, p, np.zeros(3), vertex=None)
    check_baked(bd, obj, "Basis", "Bend", [1 / 3, 2 / 3], anchor=anchor)


def test_keys_relative_to_another_key(bd):
    """Source is not the reference key; target is relative to a third key: it is read as Blender
    shows it alone at value 1 (reference + key - its relative key), not as its stored coordinates."""
    obj = two_pieces()
    S = read_key(obj, "Move")
    mid = 0.5 * (read_key(obj, "Basis") + S)
    add_key(obj, "Mid", mid)
    tgt = S.copy()
    tgt[:, 0] *= 1.1
    add_key(obj, "Wide", tgt, relative="Mid")
    obj.data.shape_keys.key_blocks["Wide"].value = 1.0
    shown = evaluated_co(obj)  # Blender's own evaluation
    obj.data.shape_keys.key_blocks["Wide"].value = 0.0
    assert maxdiff(shown, tgt) > 0.1  # not the stored coordinates
    configure(obj, "Wide", source="Move", count=2)
    bpy.ops.bdinterp.bake()
    faces = triangles(obj)
    names = [n for n in key_names(obj) if n.startswith("Wide.bdi.") and n != "Wide.bdi.100"]
    assert len(names) == 2
    for name, t in zip(names, [1 / 3, 2 / 3]):
        assert maxdiff(read_key(obj, name), bd.interpolate(S, shown, faces, t)) < TOL, name
    # 'Wide' is relative to 'Mid', not to the source: the playback ends on a baked copy of it
    end = obj.data.shape_keys.key_blocks["Wide.bdi.100"]
    assert end.relative_key.name == "Move" and maxdiff(read_key(obj, end.name), shown) < TOL


def test_undo_restores_key_list(addon):
    obj = bent_strip()
    configure(obj, "Bend", count=3)
    bpy.ops.ed.undo_push(message="before bake")
    before = key_names(obj)
    # As from the UI: EXEC with an undo push (scripts' bpy.ops calls push none by default).
    assert bpy.ops.bdinterp.bake('EXEC_DEFAULT', True) == {'FINISHED'}
    obj = bpy.data.objects["Strip"]
    assert len(key_names(obj)) == len(before) + 3 and "Bend.bdi" in obj.keys()
    bpy.ops.ed.undo()  # one step
    obj = bpy.data.objects["Strip"]
    assert key_names(obj) == before
    assert "Bend.bdi" not in obj.keys()


def _unchanged_after_error(obj, match):
    before = (key_names(obj), [read_key(obj, n).tobytes() for n in key_names(obj)],
              sorted(obj.keys()))
    with pytest.raises(RuntimeError, match=match):
        bpy.ops.bdinterp.bake()
    after = (key_names(obj), [read_key(obj, n).tobytes() for n in key_names(obj)], sorted(obj.keys()))
    assert after == before


def test_error_non_planar_key_says_by_how_much(addon):
    obj = bent_strip()
    bad = read_key(obj, "Bend")
    bad[5, 2] += 0.05
    add_key(obj, "Bumpy", bad)
    configure(obj, "Bumpy")
    _unchanged_after_error(obj, r"Strip: key 'Bumpy', vertex 5: not planar: 0\.05 off the plane")
    # and what to do about it
    _unchanged_after_error(obj, r"\. To fix it, flatten that key: in Edit Mode .* or raise "
                                r"Planarity under Expert$")


def test_automatic_joints_are_called_automatic(addon):
    items = bpy.types.Object.bl_rna.properties["bdi"].fixed_type.properties["joints"].enum_items
    assert items["AUTO"].name == "Automatic"


def test_error_mesh_without_keys(addon):
    bpy.ops.mesh.primitive_plane_add()
    obj = bpy.context.object
    obj.bdi.target = "Key 1"
    with pytest.raises(RuntimeError, match="no shape keys"):
        bpy.ops.bdinterp.bake()
    assert obj.data.shape_keys is None


def test_error_target_is_source(addon):
    obj = bent_strip()
    configure(obj, "Basis")
    _unchanged_after_error(obj, "is the source key")
    configure(obj, "Bend", source="Bend")
    _unchanged_after_error(obj, "is the source key")


def test_error_bad_factors_and_missing_target(addon):
    obj = bent_strip()
    configure(obj, "Bend", use_factors=True, factors="0.5, 1.5")
    _unchanged_after_error(obj, "strictly between 0 and 1")
    configure(obj, "Nope", use_factors=False)
    _unchanged_after_error(obj, "no shape key named 'Nope'")


def test_error_from_core_changes_nothing(addon):
    """A target with a collapsed triangle is rejected by the core; nothing is written."""
    obj = bent_strip()
    bad = read_key(obj, "Basis")
    f = obj.data.polygons[0].vertices
    bad[f[1]] = bad[f[0]]
    add_key(obj, "Collapsed", bad)
    configure(obj, "Collapsed")
    _unchanged_after_error(obj, ".")


def test_operator_reports_distortion(addon, bd):
    obj = bent_strip()
    result = addon.bake(obj, target="Bend", count=3, drivers=False)
    # undriven keys are made at 0 (Blender 5.0+ would give them 1): the mesh shows what it showed
    assert [obj.data.shape_keys.key_blocks[n].value for n in result.keys] == [0.0, 0.0, 0.0]
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    k_in = float(np.max(bd.conformal_distortion(S, T, faces)))
    k_out = max(float(np.max(bd.conformal_distortion(S, read_key(obj, n), faces))) for n in result.keys)
    assert result.input_distortion == pytest.approx(k_in, rel=1e-9)
    assert result.max_distortion == pytest.approx(k_out, rel=1e-5)
    assert "max distortion" in result.message
    assert k_out <= k_in * (1 + 1e-6)  # the paper's bound, on real data


def test_a_folded_target_is_reported_by_key_polygons_and_vertex(addon):
    """A target key with folded triangles bakes, and the result names the key, how many polygons
    fold and a vertex near them ('target has 4 folded faces near vertex 312')."""
    obj = bent_strip()
    base = read_key(obj, "Basis")
    co = base.copy()
    v = 25  # an interior vertex of the 17 x 5 grid; pushed across its neighbour 26
    co[v, :2] += 1.6 * (base[26, :2] - base[v, :2])
    add_key(obj, "Fold", co)
    tris = triangles(obj)

    def signed(X):
        a, b = X[tris[:, 1], :2] - X[tris[:, 0], :2], X[tris[:, 2], :2] - X[tris[:, 0], :2]
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]

    folded = signed(base) * signed(co) < 0
    me = obj.data
    me.calc_loop_triangles()
    poly = np.array([lt.polygon_index for lt in me.loop_triangles])
    polys = sorted(set(poly[folded].tolist()))
    assert polys, "the test pose must fold"
    result = addon.bake(obj, source="Basis", target="Fold", count=2)
    assert "key 'Fold' has %d folded polygon" % len(polys) in result.message
    vertex = int(result.message.split("near vertex ")[1].split(";")[0].split()[0])
    assert any(vertex in me.polygons[p].vertices for p in polys)
    assert "key 'Fold' has" in json.loads(obj.bdi.result)["note"]
