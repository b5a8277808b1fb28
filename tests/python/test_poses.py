"""Poses animators make: still parts stay still under the default anchor (point 3),
mirror-image targets are refused and folded faces are reported (point 4)."""
import numpy as np
import pytest

import bdinterp
from pose_meshes import body_with_limb, curled, skinned_swing

TS = np.linspace(0, 1, 11)


def rigid_fit(A, B):
    """Rotation angle (radians) and translation of the best rigid motion of A onto B."""
    ca, cb = A.mean(0), B.mean(0)
    U, _, Wt = np.linalg.svd((A - ca).T @ (B - cb))
    R = (U @ Wt).T
    return np.arctan2(R[1, 0], R[0, 0]), cb - R @ ca


@pytest.fixture(scope="module")
def body():
    V, F, shoulder = body_with_limb(8, 3.0)
    torso = V[:, 0] < 0.7  # away from the skinning blend zone, which starts at x = 0.85
    size = np.ptp(V, axis=0).max()
    return V, F, shoulder, torso, size


POSES = {
    "arm swung 90": lambda V, s: skinned_swing(V, s, np.pi / 2, blend=(0.75, 1.45)),
    "arm rolled up": lambda V, s: curled(V, s, 2 * np.pi),
    "tail bent 300": lambda V, s: curled(V, s, -np.radians(300)),
}


@pytest.mark.parametrize("pose", POSES)
def test_still_torso_stays_still_at_every_t(body, pose):
    # Before: a body whose arm rolls up turned by 4 degrees and slid by 38 % of its size at t = 0.5.
    V, F, shoulder, torso, size = body
    T = POSES[pose](V, shoulder)
    assert bdinterp.flipped_faces(V, T, F) == 0
    I = bdinterp.Interpolator([V, T], F)
    frames = I.frames(TS)
    np.testing.assert_allclose(frames[0], V, atol=1e-9 * size)
    np.testing.assert_allclose(frames[-1], T, atol=1e-9 * size)
    for t, X in zip(TS, frames):
        angle, shift = rigid_fit(V[torso], X[torso])
        assert abs(np.degrees(angle)) < 0.3, (t, np.degrees(angle))
        assert np.abs(X[torso] - V[torso]).max() < 0.01 * size, t
    # Continuity in t: consecutive frames 0.1 apart move every vertex by a bounded amount.
    steps = np.linalg.norm(np.diff(frames, axis=0), axis=2).max(axis=1)
    assert steps.max() <= 3 * np.median(steps)


def test_still_torso_in_a_three_shape_blend(body):
    V, F, shoulder, torso, size = body
    A, B = POSES["arm swung 90"](V, shoulder), POSES["arm rolled up"](V, shoulder)
    I = bdinterp.Interpolator([V, A, B], F)
    for w in ([0.2, 0.4, 0.4], [1 / 3, 1 / 3, 1 / 3], [0.0, 0.5, 0.5]):
        X = I.blend(w)
        assert np.abs(X[torso] - V[torso]).max() < 0.01 * size, w
    np.testing.assert_allclose(I.blend([0, 0, 1]), B, atol=1e-9 * size)


@pytest.mark.parametrize("pose", [None, "arm rolled up"])
def test_a_shape_that_turns_as_a_whole_still_turns(body, pose):
    V, F, shoulder, torso, size = body
    c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    posed = V if pose is None else POSES[pose](V, shoulder)
    T = posed @ np.array([[c, s], [-s, c]]) + [2.0, 1.0]
    I = bdinterp.Interpolator([V, T], F)
    # Nothing is still: the whole piece anchors. A rigid turn turns rigidly (exact); with the arm
    # rolling up as well, its mean rotation makes the torso lead by 0.36 degrees at t = 0.5.
    tol = 1e-6 if pose is None else 1.0
    for t in (0.25, 0.5, 0.75):
        angle, _ = rigid_fit(V[torso], I.at(t)[torso])
        assert np.degrees(angle) == pytest.approx(90 * t, abs=tol)
    np.testing.assert_allclose(I.at(1.0), T, atol=1e-9 * size)


def test_mirror_image_target_is_refused(body):
    V, F, shoulder, torso, size = body
    mirrored = V * [-1.0, 1.0]
    with pytest.raises(ValueError, match=rf"shape 1: a mirror image of the base shape: {len(F)} of {len(F)} faces"):
        bdinterp.Interpolator([V, mirrored], F)
    with pytest.raises(ValueError, match="mirror image"):
        bdinterp.interpolate(V, POSES["arm swung 90"](V, shoulder) * [1.0, -1.0], F, 0.5)
    # A mirrored base with a mirrored target is a consistent (clockwise) pair, not a reflection.
    X = bdinterp.interpolate(mirrored, POSES["arm swung 90"](V, shoulder) * [-1.0, 1.0], F, 1.0)
    np.testing.assert_allclose(X, POSES["arm swung 90"](V, shoulder) * [-1.0, 1.0], atol=1e-9 * size)


def test_folded_faces_of_each_input_are_reported(body):
    V, F, shoulder, torso, size = body
    T = skinned_swing(V, shoulder, np.radians(200))
    a, b = T[F[:, 1]] - T[F[:, 0]], T[F[:, 2]] - T[F[:, 0]]
    expected = np.flatnonzero(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0)  # signed areas < 0
    assert 0 < len(expected) < len(F) // 4
    I = bdinterp.Interpolator([V, T], F)
    np.testing.assert_array_equal(I.folded_faces(1), expected)
    assert len(I.folded_faces(0)) == 0
    # The folds sit at the joint (the skinning blend zone), not on the torso or the forearm.
    centres = V[F[expected]].mean(axis=1)
    assert centres[:, 0].min() > 0.8 and centres[:, 0].max() < 1.5
    with pytest.raises(ValueError, match="out of range"):
        I.folded_faces(2)


def test_flipped_faces_on_3d_planar_input_with_opposite_plane_fits(body):
    # The two plane fits of a 3D pair can come out with opposite normals; faces must still count
    # as flipped only where the result really reverses them.
    V, F, shoulder, torso, size = body
    T = POSES["arm rolled up"](V, shoulder)
    to3 = lambda X, z: np.c_[X, z * np.ones(len(X))]  # noqa: E731
    assert bdinterp.flipped_faces(to3(V, 0.0), to3(T, 5.0), F) == 0
    np.testing.assert_allclose(bdinterp.area_ratio(to3(V, 0.0), to3(T, 5.0), F),
                               bdinterp.area_ratio(V, T, F), rtol=1e-9)
    assert bdinterp.flipped_faces(to3(V, 0.0), to3(T * [-1, 1], 5.0), F) == len(F)
