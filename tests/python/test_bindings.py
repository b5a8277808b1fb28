"""Marshalling of the compiled module's classes (the properties themselves are tested in C++ and in
test_core.py / test_api.py; here only that values cross the language boundary intact)."""
import numpy as np
import pytest

import bdinterp
from bdinterp import _core, constants


def test_anchor_path_round_trips():
    pos = np.array([[0.0, 1.0], [2.5, -3.0], [4.0, 0.125]])
    path = _core.AnchorPath([0.0, 0.5, 1.0], pos, [0.0, 1.5, -2.0])
    assert path.t == [0.0, 0.5, 1.0] and path.angle == [0.0, 1.5, -2.0]
    np.testing.assert_array_equal(path.position, pos)
    path.angle = [1.0, 2.0, 3.0]
    assert path.angle == [1.0, 2.0, 3.0]
    with pytest.raises(TypeError):
        _core.AnchorPath([0.0], "not positions", [0.0])


def test_anchor_modes():
    assert _core.Anchor.centroid().mode == _core.Anchor.Mode.Centroid
    v = _core.Anchor.at_vertex(7)
    assert (v.mode, v.vertex) == (_core.Anchor.Mode.Vertex, 7)
    path = _core.AnchorPath([0.0, 1.0], np.zeros((2, 2)), [0.0, 0.0])
    a = _core.Anchor.along(path, 3)
    assert (a.mode, a.vertex, a.path.t) == (_core.Anchor.Mode.Path, 3, [0.0, 1.0])
    assert _core.Anchor.along(path).vertex == -1


def test_options_defaults_are_the_constants():
    o = _core.InterpolatorOptions()
    assert (o.base, o.tolerance, o.max_iterations, o.threads) == (
        0, constants.TOLERANCE, constants.MAX_ITERATIONS, constants.THREADS)
    assert o.reuse_factorization is True and o.strict is False and o.max_flatness > 0
    assert _core.InterpolatorOptions.MAX_THREADS == 1024  # the core alone checks threads against it
    o.tolerance, o.max_iterations, o.threads = 1e-6, 7, 3
    assert (o.tolerance, o.max_iterations, o.threads) == (1e-6, 7, 3)
    with pytest.raises(TypeError):
        o.threads = 2 ** 40  # the Python layer turns this into a ValueError naming threads


def test_frame_stats_is_typed_with_a_dict_view(disk):
    V, F = disk
    interp = bdinterp.Interpolator([V, 1.5 * V], F, threads=2)
    assert interp.threads == 2
    interp.at(0.5)
    st = interp.stats
    assert isinstance(st, bdinterp.FrameStats)
    ints = ("iterations", "broken_triangles", "max_broken_triangles", "line_search_steps", "pieces",
            "factorizations", "chord_steps", "convex_solves", "fold_faces", "fold_free_vertices",
            "joints", "threads")
    floats = ("residual", "flatness", "seconds")
    assert set(st.keys()) == set(ints + floats + ("converged", "warnings", "hole_closure"))
    assert st.converged is True and st.warnings == ""
    assert st.hole_closure == []  # a disk has no holes
    for k in ints:
        assert type(getattr(st, k)) is int and st[k] == getattr(st, k)
    for k in floats:
        assert type(getattr(st, k)) is float and st[k] == getattr(st, k)
    assert st.as_dict() == {k: getattr(st, k) for k in st.keys()}
    assert st.pieces == 1 and "pieces=1" in repr(st) and "warnings=''" in repr(st)
    assert st.convex_solves == 1  # a disk: one convex solve
    assert 1 <= st.threads <= 2
    with pytest.raises(KeyError, match="no field 'nope'"):
        st["nope"]
    with pytest.raises(AttributeError):
        st.iterations = 3  # read-only


def test_options_reach_the_core(disk):
    V, F = disk
    o = _core.InterpolatorOptions()
    o.threads, o.strict, o.max_iterations = 3, True, 9
    core = _core.Interpolator([V, 2 * V], F, _core.Anchor.centroid(), o)
    assert (core.threads, core.options.strict, core.options.max_iterations) == (3, True, 9)
    py = bdinterp.Interpolator([V, 2 * V], F, threads=2, strict=True, tol=1e-9)
    assert (py.threads, py._core.options.strict, py._core.options.tolerance) == (2, True, 1e-9)


def test_frames_into_writes_the_callers_array(disk):
    V, F = disk
    core = _core.Interpolator([V, 2 * V], F)
    out = np.full((2 * len(V), 2), np.nan)
    core.frames_into([0.0, 1.0], out)
    np.testing.assert_allclose(out[:len(V)], V, atol=1e-12)
    with pytest.raises(TypeError):
        core.frames_into([0.0], np.zeros((len(V), 2), dtype=np.float32))  # no silent copy
