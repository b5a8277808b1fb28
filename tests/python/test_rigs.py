"""A rig made like a real one: an FK character whose limbs and tail overlap the torso and each other
in the rest pose, every joint turned; the in-betweens against the bones' own (each joint turned by
t times its angle), with the joints found from the pieces' motions and with the joints given."""
import numpy as np
import pytest

import bdinterp
from cutout_meshes import Character, rectangle, turn
from fk_rig import NAMES, POSES, RIG

TS = (0.25, 0.5, 0.75)


def rig():
    pieces = [rectangle(*RIG[n][0], 0.2, seed=i) for i, n in enumerate(NAMES)]
    pins = [(NAMES.index(RIG[n][1]), NAMES.index(n), np.array(RIG[n][2])) for n in NAMES if RIG[n][1]]
    return Character(pieces, pins)


def bones(ch, angles, t):
    """The bones' in-between: every joint turned by t times its angle, children after parents."""
    def place(name, points):
        parent, pin = RIG[name][1], RIG[name][2]
        if parent is None:
            return points
        return place(parent, turn(points, t * angles.get(name, 0.0), pin))
    X = ch.V.copy()
    for k, name in enumerate(NAMES):
        X[ch.ranges[k]] = place(name, ch.V[ch.ranges[k]])
    return X


@pytest.fixture(params=list(POSES))
def posed(request):
    ch = rig()
    return ch, POSES[request.param]


def test_rest_pose_overlaps_like_a_real_rig():
    # The test is only worth its name if limbs overlap the torso beyond their own joints.
    ch = rig()
    boxes = {n: RIG[n][0] for n in NAMES}
    def meets(a, b):
        (x0, y0, w0, h0), (x1, y1, w1, h1) = boxes[a], boxes[b]
        return x0 < x1 + w1 and x1 < x0 + w0 and y0 < y1 + h1 and y1 < y0 + h0
    for name in ("fore_r", "hand_r", "fore_l", "hand_l", "tail_1"):
        assert meets(name, "torso")
    assert len(ch.ranges) >= 9


def test_found_joints_follow_the_bones(posed):
    ch, angles = posed
    I = bdinterp.Interpolator([ch.V, bones(ch, angles, 1.0)], ch.F)
    for t, X in zip(TS, I.frames(TS)):
        err = np.linalg.norm(X - bones(ch, angles, t), axis=1).max() / ch.size
        assert err < 5e-3, (t, err)
        assert err < 1e-8, (t, err)  # pins found exactly: the bones' in-between to roundoff
    lowest = {int(r[0]): NAMES[k] for k, r in enumerate(ch.ranges)}
    found = {lowest[j["child"]]: (lowest[j["parent"]], j["kind"]) for j in I.joints()}
    assert found == {n: (RIG[n][1], "pin") for n in NAMES if RIG[n][1]}
    for j in I.joints():
        assert np.linalg.norm(j["point"] - RIG[lowest[j["child"]]][2]) < 1e-6
        assert j["fit"] < 1e-9


def test_given_joints_follow_the_bones(posed):
    ch, angles = posed
    links = [(int(ch.ranges[p][0]), int(ch.ranges[c][0]), q) for p, c, q in ch.pins]
    I = bdinterp.Interpolator([ch.V, bones(ch, angles, 1.0)], ch.F, joints=links)
    for t, X in zip(TS, I.frames(TS)):
        assert np.linalg.norm(X - bones(ch, angles, t), axis=1).max() / ch.size < 1e-8
    assert [j["kind"] for j in I.joints()] == ["given"] * len(links)
    assert all(j["pin"] for j in I.joints())


def test_still_pieces_stay_exactly_still(posed):
    # The torso and, here, the left arm do not move between the keys.
    ch, angles = posed
    still = {k: v for k, v in angles.items() if not k.endswith("_l")}
    I = bdinterp.Interpolator([ch.V, bones(ch, still, 1.0)], ch.F)
    for X in I.frames(TS):
        for name in ("torso", "upper_l", "fore_l", "hand_l"):
            rows = ch.ranges[NAMES.index(name)]
            assert np.abs(X[rows] - ch.V[rows]).max() / ch.size < 1e-12, name


def test_by_overlap_alone_the_forearm_would_hang_from_the_torso():
    # The rule's reason: the forearm's motion against the torso is no turn about a point inside
    # their overlap, so no joint joins them directly.
    ch, angles = rig(), POSES["limbs_out"]
    I = bdinterp.Interpolator([ch.V, bones(ch, angles, 1.0)], ch.F)
    lowest = {int(r[0]): NAMES[k] for k, r in enumerate(ch.ranges)}
    pairs = {(lowest[j["parent"]], lowest[j["child"]]) for j in I.joints()}
    assert ("torso", "fore_r") not in pairs and ("torso", "hand_r") not in pairs
