"""Cut-out characters made of loose pieces, each placed on the geodesic of its rigid motion
(point 1) and joined to the pieces it overlaps (point 2). Expectations are analytic: a piece that
turns about a pin keeps the pin; pieces pinned together in both keys stay pinned; a still torso
stays still."""
import numpy as np
import pytest

import bdinterp
import cutout_meshes as cm

TS = np.linspace(0, 1, 21)
PIN = 0.005  # the bound: pins within 0.5 % of the character's size


def edge_lengths(X, F):
    E = np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]
    return np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1)


@pytest.fixture(scope="module")
def pendulum():
    V, F, T, pivot, length = cm.pendulum()
    return V, F, T, pivot, length, bdinterp.Interpolator([V, T], F).frames(TS)


def test_pendulum_keeps_its_pivot(pendulum):
    # Before: the pivot left the pivot by 0.37 of the bar's length half way (the chord of centroids).
    V, F, T, pivot, length, X = pendulum
    size = np.linalg.norm(np.ptp(V, axis=0))
    at = cm.Character([(V, F)], []).carried(X, 0, pivot)
    assert np.linalg.norm(at - pivot, axis=1).max() < PIN * size
    # Rigidly turned by 150 t about the pivot: every vertex where that rotation puts it (so the keys
    # are exact and the steps even); the same frames from the target back to the source.
    for t, x in zip(TS, X):
        np.testing.assert_allclose(x, cm.turn(V, 150 * t, pivot), atol=1e-9 * size)
    steps = cm.steps(X)
    assert steps.max() <= 1.5 * np.median(steps)
    back = bdinterp.Interpolator([T, V], F).frames(1 - TS)
    np.testing.assert_allclose(back, X, rtol=0, atol=1e-9 * size)


def test_rigid_turn_past_half_a_turn_takes_the_short_way():
    # A rigid target turned by 200 degrees is the same shape as one turned by -160: the keys cannot
    # tell them apart, so the bar turns by -160 t, about the same pivot. (A turn the keys do carry,
    # unwrapped across a piece's faces, keeps its size: RigidMotion.TwoKeysTurnAboutTheFixedPoint.)
    V, F, _, pivot, _ = cm.pendulum()
    X = bdinterp.Interpolator([V, cm.turn(V, 200, pivot)], F).frames([0.25, 0.5])
    for t, x in zip((0.25, 0.5), X):
        np.testing.assert_allclose(x, cm.turn(V, -160 * t, pivot), atol=1e-9 * np.ptp(V))


CASES = {"shoulder": cm.shoulder, "chain": cm.chain, "head with eyes": cm.head_with_eyes}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    ch, T = CASES[request.param]()
    return request.param, ch, T, bdinterp.Interpolator([ch.V, T], ch.F).frames(TS)


def test_pins_stay_pinned(case):
    # Before (chord placement): the shoulder's pin opened by 13.5 % of the size, the chain's
    # shoulder, elbow and wrist by 1.7, 11 and 6.9 %, the eyes by 1.2 %.
    name, ch, T, X = case
    assert max(ch.pin_drift(X)) < PIN, name


def test_keys_exact_and_steps_even(case):
    name, ch, T, X = case
    np.testing.assert_allclose(X[0], ch.V, rtol=0, atol=1e-9)
    np.testing.assert_allclose(X[-1], T, rtol=0, atol=1e-9)
    steps = cm.steps(X)
    assert steps.max() <= 1.5 * np.median(steps), name


def test_pieces_keep_the_shape_they_have_alone(case):
    name, ch, T, X = case
    for rows, faces in zip(ch.ranges, ch.face_ranges):
        F = ch.F[faces] - rows[0]
        alone = bdinterp.Interpolator([ch.V[rows], T[rows]], F).frames(TS)
        for x, y in zip(X, alone):
            np.testing.assert_allclose(edge_lengths(x[rows], F), edge_lengths(y, F), rtol=0, atol=1e-9)


@pytest.mark.parametrize("make", [cm.shoulder, cm.chain])
def test_still_torso_stays_still(make):
    ch, T = make()
    torso = ch.ranges[0]
    for x in bdinterp.Interpolator([ch.V, T], ch.F).frames(TS):
        assert abs(cm.rigid_angle(ch.V[torso], x[torso])) < 0.3
        assert np.abs(x[torso] - ch.V[torso]).max() < 1e-9 * ch.size


def test_two_key_symmetry(case):
    name, ch, T, X = case
    back = bdinterp.Interpolator([T, ch.V], ch.F).frames(1 - TS)
    np.testing.assert_allclose(back, X, rtol=0, atol=1e-9 * ch.size)


def test_joints_are_reported_and_can_be_switched_off():
    # Before joints, each piece turned about its own fixed point: the chain's elbow opened by 6.5 %
    # of the size and the wrist by 59 % (the hand, turned 195 degrees in all, went the short way).
    ch, T = cm.chain()
    I = bdinterp.Interpolator([ch.V, T], ch.F)
    X = I.frames(TS)
    assert I.stats.joints == 3 and I.stats.pieces == 4
    # The tree from the still torso down the arm, each joint the pin it turns about.
    found = I.joints()
    assert [(j["parent"], j["child"]) for j in found] == [(ch.ranges[k][0], ch.ranges[k + 1][0]) for k in range(3)]
    for j, (_, _, pin) in zip(found, ch.pins):
        assert j["pin"]
        np.testing.assert_allclose(j["point"], pin, atol=1e-9)
    off = bdinterp.Interpolator([ch.V, T], ch.F, joints=False)
    Y = off.frames(TS)
    assert off.stats.joints == 0
    assert max(ch.pin_drift(X)) < PIN < max(ch.pin_drift(Y))
    # Only the placement differs: every piece has the same edge lengths either way.
    np.testing.assert_allclose(edge_lengths(X[10], ch.F), edge_lengths(Y[10], ch.F), rtol=0, atol=1e-9)


def test_pieces_that_do_not_overlap_have_no_joints():
    V, F, T, pivot, _ = cm.pendulum()
    ch = cm.Character([(V, F), (V + [3.0, 0.0], F)], [])
    I = bdinterp.Interpolator([ch.V, ch.pose([None, lambda P: cm.turn(P, 90, [3.0, 0.0])])], ch.F)
    I.at(0.5)
    assert I.stats.joints == 0


def test_pose_blend_exact_at_poses_and_continuous():
    # Three poses of the pendulum: as drawn, swung by 100 and by -60 degrees about the pivot (no two
    # more than 180 apart, so every base measures the same turns). Motions about one fixed point
    # commute, so the blend in se(2) turns by the weights' blend of the angles about the pivot,
    # whichever pose is the base.
    V, F, _, pivot, _ = cm.pendulum()
    T, U = cm.turn(V, 100, pivot), cm.turn(V, -60, pivot)
    for base in (0, 1, 2):
        I = bdinterp.Interpolator([V, T, U], F, base=base)
        for w in ([1, 0, 0], [0, 1, 0], [0, 0, 1], [0.2, 0.5, 0.3], [0.5, -0.2, 0.7]):
            angle = 100 * w[1] - 60 * w[2]
            np.testing.assert_allclose(I.blend(w), cm.turn(V, angle, pivot), atol=1e-9 * np.ptp(V))


def base_dependence(scale):
    """The largest distance, relative to the size, between blends of three pendulum poses (turned
    by 100 scale about the pivot, by -60 scale about (1, -2) then shifted by scale (0.5, 0.3))
    computed from each base, over 12 weights."""
    V, F, _, pivot, _ = cm.pendulum()
    size = np.linalg.norm(np.ptp(V, axis=0))
    T = cm.turn(V, 100 * scale, pivot)
    U = cm.turn(V, -60 * scale, [1.0, -2.0]) + np.multiply(scale, [0.5, 0.3])
    weights = [[0.2, 0.5, 0.3], [1 / 3, 1 / 3, 1 / 3], [0.5, 0.5, 0], [0, 0.5, 0.5]]
    weights += np.random.default_rng(0).dirichlet([1, 1, 1], 8).tolist()
    X = [bdinterp.Interpolator([V, T, U], F, base=b).blend for b in range(3)]
    return max(np.abs(X[b](w) - X[0](w)).max() for b in (1, 2) for w in weights) / size


def test_pose_blend_depends_on_the_base_to_third_order():
    # The se(2) sum relative to the base is exact at every pose but, for motions about different
    # fixed points, depends on the base. Changing the base multiplies every motion by the same
    # motion on the right; in the Baker-Campbell-Hausdorff series of the sum the second-order
    # brackets then cancel (the weights sum to 1), so halving the poses divides the dependence by
    # about 8. docs/JOINTS.md: 6.5 % of the size for these large poses, 0.1 % at a quarter of them.
    full, half, quarter = base_dependence(1.0), base_dependence(0.5), base_dependence(0.25)
    assert full < 0.08 and quarter < 0.0015
    assert full / half > 6 and half / quarter > 6


def test_a_piece_that_slides_over_its_parent_blends_its_offset():
    # The head tilts by 40 degrees about the neck and the right eye also slides by (0.3, -0.2) over
    # it: no pin (no common fixed point), so the eye keeps its overlap point's offset, blended in
    # the head's frame: at t it is the eye moved by t (0.3, -0.2), tilted by 40 t about the neck.
    ch, T = cm.head_with_eyes()
    eye = ch.ranges[2]
    slide = np.array([0.3, -0.2])
    T = T.copy()
    T[eye] = cm.turn(ch.V[eye] + slide, 40, [0.0, 0.0])
    I = bdinterp.Interpolator([ch.V, T], ch.F)
    for t, x in zip(TS, I.frames(TS)):
        np.testing.assert_allclose(x[eye], cm.turn(ch.V[eye] + t * slide, 40 * t, [0.0, 0.0]), atol=1e-9)
    assert I.stats.joints == 2
    # Neither eye turns against the head: both joints are points of the overlap, not pins.
    assert [j["pin"] for j in I.joints()] == [False, False]
    assert off_joints(ch, T) == []


def off_joints(ch, T):
    return bdinterp.Interpolator([ch.V, T], ch.F, joints=False).joints()


def test_layered_character_keeps_its_joints_and_depths():
    # The chain in space with every piece 0.02 in front of its parent (draw order): the pins hold
    # in the plane and each piece keeps its depth.
    import test_layers as tl
    ch, T = cm.chain()
    depths = [0.0, 0.02, 0.04, 0.06]
    X = bdinterp.Interpolator([tl.lift(ch, ch.V, depths), tl.lift(ch, T, depths)], ch.F).frames(TS)
    assert max(ch.pin_drift((X - tl.ORIGIN) @ tl.B.T)) < PIN
    for rows, d in zip(ch.ranges, depths):
        np.testing.assert_allclose((X[:, rows] - tl.ORIGIN) @ tl.NORMAL, d, atol=1e-12)
    # Joint points in space, on the child's plane.
    I = bdinterp.Interpolator([tl.lift(ch, ch.V, depths), tl.lift(ch, T, depths)], ch.F)
    points = [j["point"] for j in I.joints()]
    expect = [q @ tl.B + tl.ORIGIN + d * tl.NORMAL for (_, _, q), d in zip(ch.pins, depths[1:])]
    np.testing.assert_allclose(points, expect, atol=1e-9)


def test_a_bending_arm_keeps_its_pin():
    # The arm swung 150 degrees about the shoulder pin also bends (each point turned about the pin
    # by up to 60 degrees more along the arm): the pieces are not rigid, yet the pin is one of both
    # keys. In between it stays as joined as the keys themselves have it through the triangles
    # (the bend is not affine inside the pin's triangle: a gap of 4e-5 of the size in the target).
    ch, T = cm.shoulder()
    arm, (_, _, pin) = ch.ranges[1], ch.pins[0]
    P = ch.V[arm] - pin
    a = np.radians(60) * P[:, 0] / 4.0
    T = T.copy()
    T[arm] = cm.turn(np.c_[np.cos(a) * P[:, 0] - np.sin(a) * P[:, 1], np.sin(a) * P[:, 0] + np.cos(a) * P[:, 1]]
                     + pin, 150, pin)
    key_gap = ch.pin_drift([T])[0]
    I = bdinterp.Interpolator([ch.V, T], ch.F)
    assert I.joints()[0]["pin"]
    assert ch.pin_drift(I.frames(TS))[0] <= 1.5 * key_gap + 1e-12
    assert key_gap < 1e-4


def test_the_joints_option_is_validated():
    ch, T = cm.shoulder()
    with pytest.raises(ValueError, match="joints must be True, False or a non-empty sequence"):
        bdinterp.Interpolator([ch.V, T], ch.F, joints="yes")
    with pytest.raises(ValueError, match="joint link 0: its child piece|joint link 1: its child piece"):
        bdinterp.Interpolator([ch.V, T], ch.F, joints=[(0, int(ch.ranges[1][0]), [0.0, 0.0]),
                                                      (0, int(ch.ranges[1][0]), [0.0, 0.0])])
    with pytest.raises(ValueError, match="joint link 0: its parent and child vertices are in one piece"):
        bdinterp.Interpolator([ch.V, T], ch.F, joints=[(0, 1, [0.0, 0.0])])
    assert bdinterp.Interpolator([ch.V, T], ch.F).layers is None  # 2D input has no layers
