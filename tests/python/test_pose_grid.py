"""Pose parameters (bdinterp.pose_grid): multilinear weights on a grid of poses, wrapping angles,
clamping, groups combined in the blended metric."""
import itertools

import numpy as np
import pytest

import bdinterp
from bdinterp.pose_grid import Parameter, PoseBlender, PoseGrid, combine
from bdinterp_tools import meshes


def bent(V, degrees, thick=1.0):
    """A 4 x 0.5 bar along x (y in [0, 0.5]) thickened by `thick`, then bent along its length by
    `degrees` (the left end stays)."""
    y = (V[:, 1] - 0.25) * thick
    a = np.radians(degrees)
    if abs(a) < 1e-12:
        return np.c_[V[:, 0], y + 0.25]
    radius = 4.0 / a
    r = radius - y
    return np.c_[r * np.sin(V[:, 0] / radius), 0.25 + radius - r * np.cos(V[:, 0] / radius)]


@pytest.fixture(scope="module")
def bar_mesh():
    return meshes.rectangle(4.0, 0.5, 300, seed=5)


@pytest.fixture(scope="module")
def head(bar_mesh):
    """A 3 x 3 grid: bend -60/0/60 degrees x thickness 0.8/1/1.3."""
    V, F = bar_mesh
    shapes, keys = {}, {}
    for bend, thick in itertools.product((-60, 0, 60), (-1, 0, 1)):
        name = "rest" if (bend, thick) == (0, 0) else "b%d_t%d" % (bend, thick)
        shapes[name] = bent(V, bend, {-1: 0.8, 0: 1.0, 1: 1.3}[thick])
        keys[(bend, thick)] = name
    grid = PoseGrid({"bend": [-60, 0, 60], "thick": [-1, 0, 1]}, keys, name="head")
    return PoseBlender(shapes, F, grid, "rest"), shapes, grid


@pytest.fixture(scope="module")
def wheel(bar_mesh):
    """A wrapping parameter: four poses on a full turn (0, 90, 180, 270 degrees)."""
    V, F = bar_mesh
    shapes = {"rest": bent(V, 0)}
    keys = {0: "rest"}
    for turn in (90, 180, 270):
        shapes["w%d" % turn] = bent(V, 100 * np.sin(np.radians(turn)),
                                    1 + 0.2 * np.cos(np.radians(turn)))
        keys[turn] = "w%d" % turn
    grid = PoseGrid([Parameter("turn", [0, 90, 180, 270], wrap=True)], keys, name="wheel")
    return PoseBlender(shapes, F, grid, "rest"), shapes, grid


def size_of(X):
    return float(np.linalg.norm(np.ptp(X, axis=0)))


def test_weights_are_multilinear_and_clamped():
    grid = PoseGrid({"x": [-30, 0, 30], "y": [0, 10]},
                    {(x, y): "%d_%d" % (x, y) for x in (-30, 0, 30) for y in (0, 10)})
    w = grid.weights((15, 2.5))
    assert w == pytest.approx({"0_0": 0.375, "30_0": 0.375, "0_10": 0.125, "30_10": 0.125},
                              abs=1e-15)
    assert grid.weights((99, -5)) == pytest.approx({"30_0": 1.0})  # clamped on both axes
    assert grid.weights({"x": -40}) == pytest.approx({"-30_0": 1.0})  # y left at its first value


def test_wrap_joins_last_cell_to_first():
    p = Parameter("turn", [0, 90, 180, 270], wrap=True)
    assert p.cell(315) == (3, 0, pytest.approx(0.5))
    assert p.cell(-45) == (3, 0, pytest.approx(0.5))
    assert p.cell(360 + 100) == (1, 2, pytest.approx(10 / 90))
    with pytest.raises(ValueError, match="period"):
        Parameter("turn", [0, 90, 180, 270], wrap=True, period=200)


def test_missing_node_is_named():
    grid = PoseGrid({"x": [-30, 0, 30], "y": [-30, 0, 30]},
                    {(x, y): "k" for x in (-30, 0, 30) for y in (-30, 0, 30) if (x, y) != (30, -30)})
    with pytest.raises(ValueError, match=r"node \(x=30, y=-30\) has no pose"):
        grid.require_complete()
    with pytest.raises(ValueError, match=r"node \(x=30, y=-30\) has no pose"):
        grid.weights((20, -20))
    with pytest.raises(ValueError, match="has no value 45"):
        PoseGrid({"x": [0, 30]}, {45: "k"})


def test_fill_from_row_and_column():
    keys = {(x, y): "%d_%d" % (x, y) for x in (0, 1, 3) for y in (0, 1, 2)}
    del keys[(1, 1)]
    grid = PoseGrid({"x": [0, 1, 3], "y": [0, 1, 2]}, keys)
    # row: 2/3 of "0_1" and 1/3 of "3_1" (x = 1 between 0 and 3); column: halves of "1_0", "1_2"
    assert grid.fill_weights((1, 1)) == pytest.approx(
        {"0_1": 1 / 3, "3_1": 1 / 6, "1_0": 0.25, "1_2": 0.25})
    keys[(1, 1)] = "1_1"
    del keys[(3, 2)]
    grid = PoseGrid({"x": [0, 1, 3], "y": [0, 1, 2]}, keys)  # a corner: the parallelogram
    assert grid.fill_weights((2, 2)) == pytest.approx({"1_2": 1.0, "3_1": 1.0, "1_1": -1.0})
    del keys[(1, 1)]
    grid = PoseGrid({"x": [0, 1, 3], "y": [0, 1, 2]}, keys)
    with pytest.raises(ValueError, match=r"node \(x=3, y=2\) has no pose and no neighbours"):
        grid.fill_weights((2, 2))


def test_nodes_are_exact(head, wheel):
    for blender, shapes, grid in (head, wheel):
        for index, key in grid.nodes.items():
            got = blender.blend({grid.name: grid.node_values(index)}).shape
            err = np.abs(got - shapes[key]).max() / size_of(shapes[key])
            assert err <= 1e-9, (key, err)


def test_distortion_within_the_poses(head):
    blender, shapes, grid = head
    worst = 0.0
    for x, y in itertools.product(np.linspace(-70, 70, 8), np.linspace(-1.2, 1.2, 7)):
        b = blender.blend({"head": (x, y)}, measure=True)
        k = bdinterp.conformal_distortion(blender.rest_shape, b.shape, blender.faces)
        assert b.guaranteed and b.flipped == 0
        worst = max(worst, float(np.max(k / blender.k_poses)))
    assert worst <= 1 + 1e-6, worst
    assert blender.k_poses.max() > 1.25  # the thickness poses are not conformal (K = 1.3)


def _largest_move(blender, grid, a, b):
    sa = blender.blend({grid.name: a}).shape
    sb = blender.blend({grid.name: b}).shape
    return np.linalg.norm(sa - sb, axis=1).max() / size_of(blender.rest_shape)


def test_continuous_across_borders_and_wrap(head, wheel):
    blender, _, grid = head
    step = 1e-3 * 120  # 1e-3 of each parameter's range (both span 120 units of bend, 2 of thick)
    for bend in (-60, 0, 60):
        assert _largest_move(blender, grid, (bend - step / 2, 0.3), (bend + step / 2, 0.3)) <= 1e-2
    for thick in (-1, 0, 1):
        assert _largest_move(blender, grid, (20, thick - 1e-3), (20, thick + 1e-3)) <= 1e-2
    blender, _, grid = wheel
    step = 1e-3 * 360
    moves = [_largest_move(blender, grid, x - step / 2, x + step / 2) for x in (0, 90, 180, 270, 360)]
    assert max(moves) <= 1e-2, moves
    # the wrap itself: the last cell ends on the first node's pose
    assert _largest_move(blender, grid, 360 - 1e-9, 0) <= 1e-8


def test_clamped_outside_the_grid(head):
    blender, shapes, grid = head
    far = blender.blend({"head": (200, -7)}).shape
    assert np.abs(far - shapes["b60_t-1"]).max() / size_of(far) <= 1e-9
    edge = blender.blend({"head": (70, 0.5)}).shape
    inside = blender.blend({"head": (60, 0.5)}).shape
    assert np.abs(edge - inside).max() <= 1e-12 * size_of(edge)


def squared_lengths(X, F):
    E = np.unique(np.sort(np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]], axis=1), axis=0)
    d = X[E[:, 1]] - X[E[:, 0]]
    return np.einsum("ij,ij->i", d, d), E


def test_two_groups_add_their_metrics(disk):
    """Two groups of affine poses: the combination's metric is the rest's plus each group's
    difference, g = I + a (A^T A - I) + b (B^T B - I), a flat metric: the blend is the affine
    map with that metric (affine reproduction), so every edge e has length^2 e^T g e."""
    V, F = disk
    A = np.array([[1.6, 0.4], [0.0, 1.0]])
    B = np.array([[1.0, 0.0], [0.3, 0.7]])
    shapes = {"rest": V, "a": V @ A.T, "b": V @ B.T}
    groups = [PoseGrid({"pa": [0, 1]}, {0: "rest", 1: "a"}, name="A"),
              PoseGrid({"pb": [0, 1]}, {0: "rest", 1: "b"}, name="B")]
    blender = PoseBlender(shapes, F, groups, "rest")
    for a, b in ((0.5, 0.5), (1.0, 1.0), (0.3, 0.9)):
        out = blender.blend({"A": a, "B": b})
        g = np.eye(2) + a * (A.T @ A - np.eye(2)) + b * (B.T @ B - np.eye(2))
        l2, E = squared_lengths(out.shape, F)
        d = V[E[:, 1]] - V[E[:, 0]]
        expected = np.einsum("ij,jk,ik->i", d, g, d)
        assert np.abs(l2 / expected - 1).max() <= 1e-8
        lam = np.linalg.eigvalsh(g)
        if a + b > 1:  # the rest's weight 1 - a - b is negative: an extrapolation, measured
            assert not out.guaranteed and out.scale == 1.0
            assert out.k_max == pytest.approx(np.sqrt(lam[1] / lam[0]), rel=1e-6)
        else:
            assert out.guaranteed


def test_combination_out_of_range_is_reported_not_raised(disk):
    V, F = disk
    squash = np.diag([0.25, 1.0])  # both groups squash x: together 1 + 2 (0.0625 - 1) < 0
    shapes = {"rest": V, "a": V @ squash, "b": V @ squash}
    groups = [PoseGrid({"pa": [0, 1]}, {0: "rest", 1: "a"}, name="A"),
              PoseGrid({"pb": [0, 1]}, {0: "rest", 1: "b"}, name="B")]
    blender = PoseBlender(shapes, F, groups, "rest")
    out = blender.blend({"A": 1, "B": 1})
    assert 0 < out.scale < 1 and out.flipped == 0 and np.isfinite(out.k_max)
    assert "refused" in out.report()
    assert combine([{"a": 1.0}, {"b": 1.0}], "rest") == {"rest": -1.0, "a": 1.0, "b": 1.0}


def test_bake_grid_error_shrinks_with_n(head):
    from bdinterp.pose_bake import GridBake, fine_values
    blender, shapes, grid = head
    assert fine_values(grid.params[0], 2) == [-60, -30, 0, 30, 60]
    errors = []
    for n in (1, 2, 4):
        bake = GridBake(blender, "head", n)
        for index, key in grid.nodes.items():  # the grid's own nodes keep their poses
            fine = tuple(i * n for i in index)
            assert np.abs(bake.shapes[fine] - shapes[key]).max() <= 1e-9 * size_of(shapes[key])
        errors.append(bake.error(samples=2)[0])
    # the linear blend of turned poses cuts corners: the error falls about 4x per halving
    assert errors[0] > 1e-3 and errors[1] < 0.4 * errors[0] and errors[2] < 0.4 * errors[1], errors


def test_three_parameters_are_trilinear():
    values = {"x": [0, 1], "y": [0, 2], "z": [0, 4]}
    grid = PoseGrid(values, {n: "%d%d%d" % n for n in itertools.product([0, 1], [0, 2], [0, 4])})
    w = grid.weights((0.25, 1.0, 3.0))
    want = {"%d%d%d" % (x, y, z): (0.25 if x else 0.75) * 0.5 * (0.75 if z else 0.25)
            for x, y, z in itertools.product([0, 1], [0, 2], [0, 4])}
    assert w == pytest.approx(want, abs=1e-15)
    with pytest.raises(ValueError, match="1 to 3 parameters"):
        PoseGrid({"a": [0, 1], "b": [0, 1], "c": [0, 1], "d": [0, 1]}, {})
