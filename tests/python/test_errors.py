"""An InvalidInputError says where (shape, face, vertex) apart from what, whether
the compiled core or the Python layer refuses; a tolerance no double can reach is refused at once."""
import time

import numpy as np
import pytest

import bdinterp
from bdinterp_tools import meshes


def where(info):
    e = info.value
    return e.shape, e.face, e.vertex


def test_the_message_is_the_location_then_the_detail(disk):
    V, F = disk
    T = V.copy()
    T[9] = np.nan
    with pytest.raises(bdinterp.InvalidInputError) as info:
        bdinterp.Interpolator([V, T], F)
    assert isinstance(info.value, ValueError)  # what callers caught before
    assert where(info) == (1, None, 9)
    assert info.value.detail == "a non-finite coordinate"
    assert str(info.value) == "shape 1, vertex 9: a non-finite coordinate"


def test_core_errors_carry_the_shape_and_the_face_or_vertex(disk):
    V, F = disk
    collapsed = V.copy()
    collapsed[F[5, 2]] = collapsed[F[5, 0]]
    with pytest.raises(bdinterp.InvalidInputError) as info:
        bdinterp.Interpolator([V, V, collapsed], F)  # the core's check (Python passes finite arrays)
    assert info.value.shape == 2 and info.value.vertex is None
    # only a face of the moved vertex can have lost its area
    assert F[5, 2] in F[info.value.face] and info.value.detail == "zero area"
    with pytest.raises(bdinterp.InvalidInputError, match="mirror image") as info:
        bdinterp.Interpolator([V, V * [-1, 1]], F)
    assert where(info) == (1, None, None)


def test_mesh_errors_carry_the_face_or_vertex():
    V = np.array([[0, 0], [1, 0], [0, 1], [-1, 0], [0, -1]], float)
    with pytest.raises(bdinterp.InvalidInputError, match="non-manifold") as info:
        bdinterp.Interpolator([V, V], [[0, 1, 2], [0, 3, 4]])  # two triangles sharing vertex 0 only
    assert where(info) == (None, None, 0)
    with pytest.raises(bdinterp.InvalidInputError) as info:
        bdinterp.Interpolator([V, V], [[0, 1, 2], [0, 3, 7]])  # the Python layer's range check
    assert where(info) == (None, 1, None) and info.value.detail.startswith("a vertex index out of range")


def test_python_layer_errors_carry_the_shape_and_vertex(disk):
    V, F = disk
    B = np.eye(3)[:2]
    bent = V @ B
    bent[7, 2] += 0.01 * np.ptp(V, axis=0).max()
    with pytest.raises(bdinterp.InvalidInputError, match=r"^shape 1, vertex 7: not planar") as info:
        bdinterp.Interpolator([V @ B, bent], F)
    assert where(info) == (1, None, 7)
    with pytest.raises(bdinterp.InvalidInputError, match=r"^shape 1: has shape") as info:
        bdinterp.Interpolator([V, V[:-1]], F)
    assert where(info) == (1, None, None)


def test_the_anchor_vertex_is_checked_once_by_the_core(disk):
    V, F = disk
    n = len(V)
    for anchor in (n, bdinterp.AnchorPath([0, 1], [[0, 0], [1, 0]], [0, 0], vertex=n)):
        with pytest.raises(bdinterp.InvalidInputError,
                           match=rf"^vertex {n}: the anchor vertex is out of range \[0, {n}\)") as info:
            bdinterp.Interpolator([V, 2 * V], F, anchor=anchor)
        assert where(info) == (None, None, n)
    with pytest.raises(ValueError, match="anchor vertex must be an integer"):
        bdinterp.Interpolator([V, 2 * V], F, anchor=2 ** 40)  # not a C int: refused before the core


def test_a_tolerance_no_double_can_reach_is_refused_at_once():
    # The fuzzer's finding: 20 vertices, tol = 1.9e-304 and 24,739 iterations ran a second of futile
    # Newton steps before the SolverError.
    center, radius = meshes.MAP_DOMAIN
    V, F = meshes.disk(20, seed=4, center=center, radius=radius)
    T = meshes.apply_map("phi1", V)
    seconds = []
    for _ in range(3):  # the fastest of three: a loaded machine may stall one call
        start = time.perf_counter()
        with pytest.raises(bdinterp.InvalidInputError, match=r"tolerance 1.9e-304 is below 8.88e-16") as info:
            bdinterp.Interpolator([V, T], F, tol=1.9e-304, max_iterations=24739).at(0.5)
        seconds.append(time.perf_counter() - start)
    assert min(seconds) < 0.01
    assert where(info) == (None, None, None)
    with pytest.raises(bdinterp.InvalidInputError):
        bdinterp.Interpolator([V, T], F, tol=0.99 * 2.0 ** -50)
    interp = bdinterp.Interpolator([V, T], F, tol=1e-14)  # reachable: solves
    interp.at(0.5)
    assert interp.stats.converged and interp.stats.residual <= 1e-14
