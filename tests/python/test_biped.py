"""A whole FK biped (tests/python/biped.py) through a walk, a run, a jump and a fall: every piece
against the bones' own in-between (every bone's angle and offset blended by t), with the joints
found from the keys and with the bones' links given; and the rules it needs one by one: a chain
joined to nothing still rooted where it turns, a knee drawn with a gap, a hip that slides."""
import numpy as np
import pytest

import bdinterp
from biped import BONES, PIECES, POSES, bone_motion, pins, posed, rigid_fit_error
from cutout_meshes import Character, rectangle, turn

TS = (0.25, 0.5, 0.75)
# Bounds relative to the size: every piece within 0.5 %; in the fall (the root travels
# and turns by 90 degrees: two keys do not fix its path) after the best rigid fit, 1.5 % without.
LIMIT, FALL_RAW = 5e-3, 1.5e-2


def biped_character():
    """The biped's sprites meshed at cells of about 0.12 (the size is 10.2)."""
    rects = [BONES[name][2] for name in PIECES]
    return Character([rectangle(*r, 0.12, seed=k) for k, r in enumerate(rects)], pins())


@pytest.fixture(scope="module")
def biped():
    return biped_character()


def errors(ch, pose, frames):
    """Per t: (largest distance from the bones' in-between, the same after the best rigid fit of
    the whole character), relative to the size."""
    out = []
    for t, X in zip(TS, frames):
        Y = posed(ch, pose, t)
        out.append((np.linalg.norm(X - Y, axis=1).max() / ch.size, rigid_fit_error(X, Y) / ch.size))
    return out


def root_links(ch):
    """The bones' links as given joints: each piece hangs from the piece of its nearest ancestor
    bone with a sprite, else (through the sprite-less bones) from the torso, at its own bone's
    pivot; the torso travels on the root bone's path."""
    first = {name: int(ch.ranges[k][0]) for k, name in enumerate(PIECES)}
    links = [(-1, first["torso"], np.array(BONES["root"][1]))]
    for name in PIECES:
        parent = BONES[name][0]
        while parent is not None and BONES[parent][2] is None:
            parent = BONES[parent][0]
        if name != "torso":
            links.append((first[parent or "torso"], first[name], np.array(BONES[name][1])))
    return links


@pytest.mark.parametrize("name", list(POSES))
def test_biped_follows_the_bones_with_the_joints_found(biped, name):
    ch, pose = biped, POSES[name]
    I = bdinterp.Interpolator([ch.V, posed(ch, pose, 1.0)], ch.F)
    frames = I.frames(TS)
    for t, (raw, fitted) in zip(TS, errors(ch, pose, frames)):
        if name == "fall":
            assert fitted < LIMIT and raw < FALL_RAW, (t, raw, fitted)
        else:
            assert raw < LIMIT, (t, raw)
    assert max(ch.pin_drift(frames)) < 1e-9  # every bone's pin, the knee's and elbow's gaps too
    assert len(I.joint_roots()) == 1  # one tree: the legs hang from the body through the hip


@pytest.mark.parametrize("name", list(POSES))
def test_biped_follows_the_bones_with_the_bones_given(biped, name):
    ch, pose = biped, POSES[name]
    I = bdinterp.Interpolator([ch.V, posed(ch, pose, 1.0)], ch.F, joints=root_links(ch))
    for t, (raw, _) in zip(TS, errors(ch, pose, I.frames(TS))):
        assert raw < LIMIT, (t, raw)
    assert [r["reason"] for r in I.joint_roots()] == ["path"]


def test_the_linear_blend_is_far_from_the_bones(biped):
    # What the bounds above are worth: the vertices' linear blend misses the bones by far more.
    ch = biped
    for name, pose in POSES.items():
        T = posed(ch, pose, 1.0)
        worst = max(np.linalg.norm((1 - t) * ch.V + t * T - posed(ch, pose, t), axis=1).max()
                    for t in TS) / ch.size
        assert worst > 0.02, name


def test_the_biped_is_drawn_like_a_painted_one():
    # The gaps and the sprite-less bones the rules are for.
    assert len(PIECES) >= 15
    for child in ("shin_l", "fore_r"):
        parent, (x, y) = BONES[child][0], BONES[child][1]
        for bone in (parent, child):
            x0, y0, w, h = BONES[bone][2]
            assert not (x0 < x < x0 + w and y0 < y < y0 + h), (bone, child)
    assert BONES["hip"][2] is None and BONES["root"][2] is None
    assert all(POSES[n]["hip"][1] != (0, 0) for n in POSES)
    R, _ = bone_motion(POSES["fall"], 1.0)["torso"]
    assert np.isclose(np.degrees(np.arctan2(R[1, 0], R[0, 0])), -90)


def test_still_pieces_stay_exactly_still(biped):
    # In the walk the torso does not move: it roots the tree, exactly where it is.
    ch = biped
    I = bdinterp.Interpolator([ch.V, posed(ch, POSES["walk"], 1.0)], ch.F)
    rows = ch.ranges[PIECES.index("torso")]
    for X in I.frames(TS):
        assert np.abs(X[rows] - ch.V[rows]).max() / ch.size < 1e-12
    assert [(r["piece"], r["reason"]) for r in I.joint_roots()] == [(rows[0], "still")]


def arm(shoulder_y):
    """Upper arm, forearm and hand, joined to nothing that stays still; the shoulder (0, shoulder_y)
    lies at the upper arm's top end (3.0: on its outline; 3.05: just outside it). The second pose
    of a cut-out add-on's sample character: -60, 100 and -30 degrees."""
    pieces = [rectangle(-0.3, 1.0, 0.6, 2.0, 0.1, 1), rectangle(-0.3, -1.0, 0.6, 2.1, 0.1, 2),
              rectangle(-0.35, -1.8, 0.7, 0.9, 0.1, 3)]
    q = [np.array([0.0, shoulder_y]), np.array([0.0, 1.05]), np.array([0.0, -0.9])]
    ch = Character(pieces, [(0, 1, q[1]), (1, 2, q[2])])

    def bones(t):
        angles = [-60 * t, 100 * t, -30 * t]
        X = ch.V.copy()
        for k in range(3):
            P = ch.V[ch.ranges[k]]
            for a, c in reversed(list(zip(angles[:k + 1], q[:k + 1]))):
                P = turn(P, a, c)
            X[ch.ranges[k]] = P
        return X
    return ch, bones


@pytest.mark.parametrize("shoulder_y", [3.0, 3.05])
def test_a_chain_joined_to_nothing_still_turns_about_its_own_end(shoulder_y):
    ch, bones = arm(shoulder_y)
    I = bdinterp.Interpolator([ch.V, bones(1.0)], ch.F)
    for t, X in zip(TS, I.frames(TS)):
        assert np.linalg.norm(X - bones(t), axis=1).max() / ch.size < 1e-8, t
    (root,) = I.joint_roots()
    assert root["piece"] == 0 and root["reason"] == "turns"  # the upper arm, not the hand
    assert np.linalg.norm(root["point"] - [0.0, shoulder_y]) < 1e-9


def test_a_knee_drawn_with_a_gap_is_a_pin(biped):
    ch = biped
    I = bdinterp.Interpolator([ch.V, posed(ch, POSES["run"], 1.0)], ch.F)
    first = {int(ch.ranges[k][0]): name for k, name in enumerate(PIECES)}
    knee = [j for j in I.joints() if first[j["child"]] == "shin_l"]
    assert len(knee) == 1 and first[knee[0]["parent"]] == "thigh_l" and knee[0]["kind"] == "pin"
    assert np.linalg.norm(knee[0]["point"] - BONES["shin_l"][1]) < 1e-6


def test_an_eye_on_the_head_is_glued_at_its_own_middle_vertex(biped):
    # An eye lies wholly inside the head: their overlap is the eye itself, so the joint sits at the
    # eye's vertex nearest the mean of its vertices, whatever the head's triangles under it.
    ch = biped
    I = bdinterp.Interpolator([ch.V, posed(ch, POSES["run"], 1.0)], ch.F)
    first = {int(ch.ranges[k][0]): name for k, name in enumerate(PIECES)}
    for eye in ("eye_l", "eye_r"):
        (joint,) = [j for j in I.joints() if first[j["child"]] == eye]
        assert first[joint["parent"]] == "head" and joint["kind"] == "glued"
        E = ch.V[ch.ranges[PIECES.index(eye)]]
        middle = E[np.argmin(np.linalg.norm(E - E.mean(axis=0), axis=1))]
        assert np.linalg.norm(joint["point"] - middle) < 1e-12


def hip(slide):
    """A torso and a thigh hung from a hip the rig translates by `slide` (in the torso's frame)
    while the thigh turns by 60 degrees; returns the character and the bones' in-between."""
    pieces = [rectangle(-1.0, -0.4, 2.0, 3.6, 0.12, 1), rectangle(-0.8, -2.4, 0.6, 2.6, 0.12, 2)]
    ch = Character(pieces, [])
    pivot = np.array([-0.5, -0.2])

    def bones(t):
        X = ch.V.copy()
        X[ch.ranges[1]] = turn(ch.V[ch.ranges[1]], 60 * t, pivot) + t * np.asarray(slide)
        return X
    return ch, bones


@pytest.mark.parametrize("slide", [(0.0, 0.0), (0.06, -0.1), (-0.1, 0.05)])
def test_a_hip_that_slides_keeps_the_thigh_on_the_torso(slide):
    # A joint whose pivot slides: the offset blended in the parent's frame (or a pin near it). The
    # error bound of either for a slide s and a relative turn phi: |s| tan(phi / 4) / 2.
    ch, bones = hip(slide)
    I = bdinterp.Interpolator([ch.V, bones(1.0)], ch.F)
    (joint,) = I.joints()
    bound = np.linalg.norm(slide) * np.tan(np.radians(60) / 4) / 2 + 1e-9 * ch.size
    for t, X in zip(TS, I.frames(TS)):
        err = np.linalg.norm(X - bones(t), axis=1).max()
        assert err <= bound and err / ch.size < LIMIT, (t, err, bound)
    assert I.joint_roots()[0]["reason"] == "still"


def test_a_root_path_is_checked_like_a_link(biped):
    ch = biped
    keys, torso = [ch.V, posed(ch, POSES["run"], 1.0)], int(ch.ranges[0][0])
    with pytest.raises(ValueError, match=r"joint link 0: vertex -2 out of range"):
        bdinterp.Interpolator(keys, ch.F, joints=[(-2, torso, (0.0, 0.0))])
    with pytest.raises(ValueError, match=r"joint link 1: its child piece already hangs from link 0"):
        bdinterp.Interpolator(keys, ch.F, joints=[(-1, torso, (0.0, 0.0)), (-1, torso + 1, (0.0, 0.0))])
