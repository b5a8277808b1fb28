"""The pieces of a 3D mesh in parallel planes at their own depths (draw order)."""
import numpy as np
import pytest

import bdinterp
import cutout_meshes as cm

# A plane in space: orthonormal rows B (2, 3), its normal and an origin.
B = np.linalg.qr(np.array([[1.0, 0.3, -0.5], [0.2, 1.0, 0.4], [0.1, -0.3, 1.0]]))[0].T[:2]
NORMAL = np.cross(B[0], B[1])
ORIGIN = np.array([1.0, -2.0, 0.5])


def lift(ch, X, depths):
    """X (n, 2) in space: piece k at depths[k] along the normal."""
    d = np.zeros(len(X))
    for rows, depth in zip(ch.ranges, depths):
        d[rows] = depth
    return X @ B + ORIGIN + d[:, None] * NORMAL


@pytest.fixture(scope="module")
def shoulder():
    return cm.shoulder()


def test_each_piece_keeps_its_depth_in_every_frame(shoulder):
    # Before: "shape 0 is not planar: vertex ... is 0.02 off the plane of the base shape".
    ch, T = shoulder
    ts = np.linspace(0, 1, 21)
    for offset in (0.02, 1e-7):  # 1e-7: below the tolerance, which would otherwise flatten it
        X3 = bdinterp.Interpolator([lift(ch, ch.V, [0, offset]), lift(ch, T, [0, offset])], ch.F).frames(ts)
        X2 = bdinterp.Interpolator([ch.V, T], ch.F).frames(ts)
        depth = (X3 - ORIGIN) @ NORMAL
        np.testing.assert_allclose(depth[:, ch.ranges[0]], 0, atol=1e-12)
        np.testing.assert_allclose(depth[:, ch.ranges[1]], offset, rtol=0, atol=1e-12)
        np.testing.assert_allclose((X3 - ORIGIN) @ B.T, X2, rtol=0, atol=1e-9)


def test_depths_that_change_between_keys_blend(shoulder):
    # The arm comes forward from 0.02 to 0.1 in the target: keys exact, depth (1 - t) 0.02 + 0.1 t.
    ch, T = shoulder
    S3, T3 = lift(ch, ch.V, [0, 0.02]), lift(ch, T, [0, 0.1])
    I = bdinterp.Interpolator([S3, T3], ch.F)
    np.testing.assert_allclose(I.at(0), S3, atol=1e-9)
    np.testing.assert_allclose(I.at(1), T3, atol=1e-9)
    np.testing.assert_allclose((I.at(0.25)[ch.ranges[1]] - ORIGIN) @ NORMAL, 0.04, atol=1e-12)
    np.testing.assert_allclose(I.layers.depth[:, 1] - I.layers.depth[:, 0], [0.02, 0.1], atol=1e-12)
    for method in ("arap", "linear"):
        X = bdinterp.frames(S3, T3, ch.F, [0.5], method=method)[0]
        np.testing.assert_allclose((X[ch.ranges[1]] - ORIGIN) @ NORMAL, 0.06, atol=1e-12)


def test_the_tolerance_applies_to_each_piece_in_its_own_plane(shoulder):
    ch, T = shoulder
    S3 = lift(ch, ch.V, [0, 0.02])
    noise = np.random.default_rng(1).uniform(-1, 1, len(S3)) * 0.5e-5 * np.ptp(S3, axis=0).max()
    bdinterp.Interpolator([S3 + noise[:, None] * NORMAL, lift(ch, T, [0, 0.02])], ch.F)  # accepted
    bent = lift(ch, T, [0, 0.02])
    v = ch.ranges[1][7]
    bent[v] += 0.01 * NORMAL
    with pytest.raises(ValueError, match=rf"shape 1, vertex {v}: not planar: 0.01 off the plane "
                                         rf"of its piece"):
        bdinterp.Interpolator([S3, bent], ch.F)


def test_a_piece_in_a_plane_that_is_not_parallel_is_named(shoulder):
    ch, T = shoulder
    S3 = lift(ch, ch.V, [0, 0.02])
    arm = ch.ranges[1]
    tilt = np.radians(3)  # the arm turned by 3 degrees about its long axis (through the shoulder)
    across = (ch.V[arm, 1] - 2.4) * (1 - np.cos(tilt))
    S3[arm] += np.outer((ch.V[arm, 1] - 2.4) * np.sin(tilt), NORMAL) - np.outer(across, B[1])
    with pytest.raises(bdinterp.InvalidInputError, match=r"shape 0, vertex \d+: not planar: .* off the "
                                                         r"plane of its piece, which must be parallel") as info:
        bdinterp.Interpolator([S3, lift(ch, T, [0, 0.02])], ch.F)
    assert info.value.shape == 0 and info.value.vertex in arm  # the tilted piece's vertex


def test_piece_labels_follow_the_faces():
    F = np.array([[0, 1, 2], [5, 6, 7], [2, 1, 3], [7, 6, 8]])
    np.testing.assert_array_equal(bdinterp.layers.piece_labels(10, F), [0, 0, 0, 0, 1, 2, 2, 2, 2, 3])
    with pytest.raises(bdinterp.InvalidInputError, match="non-manifold") as info:
        bdinterp.layers.piece_labels(5, [[0, 1, 2], [0, 3, 4]])  # two triangles meeting at a vertex
    assert info.value.vertex == 0


def test_layers_fitted_by_the_caller_are_used_as_they_are(shoulder):
    # One fit: an application that fitted the layers with its own planarity passes them on.
    ch, T = shoulder
    shapes = [lift(ch, ch.V, [0, 0.02]), lift(ch, T, [0, 0.02])]
    layers = bdinterp.Layers.fit(shapes, ch.F, tolerance=1e-3)
    given = bdinterp.Interpolator(shapes, ch.F, layers=layers)
    assert given.layers is layers
    fitted = bdinterp.Interpolator(shapes, ch.F)
    np.testing.assert_allclose(given.frames([0.3, 0.7]), fitted.frames([0.3, 0.7]), rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="layers are of 2 shapes of %d vertices, not of 3 shapes"
                       % len(ch.V)):
        bdinterp.Interpolator(shapes + [shapes[1]], ch.F, layers=layers)
    with pytest.raises(ValueError, match="layers are for 3D shapes"):
        bdinterp.Interpolator([ch.V, T], ch.F, layers=layers)


def test_planarity_is_one_setting(shoulder):
    # A vertex 3e-4 of the size off its piece's plane: refused by default (1e-4), taken at 1e-3.
    ch, T = shoulder
    shapes = [lift(ch, ch.V, [0, 0.02]), lift(ch, T, [0, 0.02])]
    size = np.ptp(shapes[1], axis=0).max()
    shapes[1][7] += 3e-4 * size * NORMAL
    assert bdinterp.PLANAR_TOLERANCE == 1e-4
    with pytest.raises(ValueError, match="shape 1, vertex 7: not planar"):
        bdinterp.Interpolator(shapes, ch.F)
    assert bdinterp.Interpolator(shapes, ch.F, planarity=1e-3).layers is not None
    with pytest.raises(ValueError, match="planarity must be > 0"):
        bdinterp.Interpolator(shapes, ch.F, planarity=0)
