"""bdinterp.strokes: drawn strokes interpolated as thin bands through the method."""
import numpy as np
import pytest

from bdinterp.strokes import Stroke, StrokeInterpolator, interpolate_strokes, resample

TS = np.linspace(0.0, 1.0, 11)


def turn(points, degrees, about=(0.0, 0.0), shift=(0.0, 0.0)):
    a = np.radians(degrees)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return (np.asarray(points) - about) @ R.T + about + shift


def segments(p):
    return np.linalg.norm(np.diff(p, axis=0), axis=1)


def best_turn(pa, pb):
    a, b = pa - pa.mean(axis=0), pb - pb.mean(axis=0)
    return np.degrees(np.arctan2(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), np.sum(a * b)))


# A zig-zag with sharp corners and uneven spacing, as a hand draws it.
ZIGZAG = np.array([[0, 0], [0.3, 0.1], [1.0, 0.0], [1.4, 0.8], [1.5, 0.9], [2.2, 0.2], [3.0, 1.1],
                   [3.1, 1.0], [3.9, 1.6]], dtype=float)


def test_a_polyline_turned_150_degrees_moves_rigidly():
    target = turn(ZIGZAG, 150, about=(1.0, -2.0), shift=(0.5, 0.25))
    frames = interpolate_strokes([ZIGZAG], [target], TS)
    for t, (s,) in zip(TS, frames):
        assert len(s.points) == len(ZIGZAG)
        np.testing.assert_allclose(segments(s.points), segments(ZIGZAG), rtol=0, atol=1e-9)
        assert best_turn(ZIGZAG, s.points) == pytest.approx(150 * t, abs=1e-7)
    np.testing.assert_allclose(frames[-1][0].points, target, atol=1e-9)
    # Blender's own in-between (every point on its chord) shrinks it half way.
    chord = 0.5 * (ZIGZAG + target)
    assert segments(chord).sum() < 0.3 * segments(ZIGZAG).sum()


def arc(length, degrees, count, start=(0.0, 0.0)):
    """count points along an arc of the given length turning by degrees (0: a straight line)."""
    s = np.linspace(0.0, length, count)
    if degrees == 0:
        return np.stack([s, 0 * s], 1) + start
    r = length / np.radians(degrees)
    a = s / r
    return np.stack([r * np.sin(a), r * (1 - np.cos(a))], 1) + start


def test_a_bent_polyline_keeps_its_length_between_the_keys():
    straight, bent = arc(4.0, 0, 30), turn(arc(5.0, 200, 30), 40, shift=(1.0, 2.0))
    frames = interpolate_strokes([straight], [bent], TS)
    lengths = [s.length for (s,) in frames]
    # bounded distortion: every segment stretches between 1 and the target's stretch (1.249, the
    # same for all), and all of them alike (the chord's segments do not: see below)
    stretch = [segments(s.points) / segments(straight) for (s,) in frames]
    target = segments(bent) / segments(straight)
    for r in stretch:
        assert r.min() >= 1 - 1e-9 and r.max() <= target.max() + 1e-9 and r.max() / r.min() <= 1 + 1e-4
    longer = segments(bent).sum()
    assert lengths[0] == pytest.approx(4.0, abs=1e-9) and lengths[-1] == pytest.approx(longer, abs=1e-9)
    assert min(lengths) >= 4.0 - 1e-9 and max(lengths) <= longer + 1e-9
    assert np.all(np.diff(lengths) > 0)
    # the chord (Blender's in-between) loses length half way, unevenly
    chord = segments(0.5 * (straight + bent)) / segments(straight)
    assert chord.sum() / len(chord) < 0.85 and chord.max() / chord.min() > 1.2


def arm(shoulder, elbow, counts=(20, 15, 8)):
    """Upper arm, forearm and hand meeting end to end: shoulder turn, then the elbow's."""
    upper = arc(2.0, 0, counts[0])
    fore = arc(1.6, 0, counts[1], start=(2.0, 0.0))
    hand = arc(0.5, 0, counts[2], start=(3.6, 0.0))
    fore, hand = turn(fore, 20 + elbow, about=(2.0, 0.0)), turn(hand, 20 + elbow, about=(2.0, 0.0))
    return [turn(s, shoulder) for s in (upper, fore, hand)]


def gaps(strokes):
    """Distances between where the arm's strokes meet: elbow, wrist."""
    return [np.linalg.norm(strokes[0][-1] - strokes[1][0]), np.linalg.norm(strokes[1][-1] - strokes[2][0])]


def test_touching_strokes_stay_together_where_they_meet():
    a, b = arm(0, 0), arm(120, 60, counts=(31, 9, 14))
    si = StrokeInterpolator(a, b)
    assert sorted((p, c) for p, c, _ in si.joints) == [(0, 1), (1, 2)]
    frames = si.frames(TS)
    for t, strokes in zip(TS, frames):
        assert max(gaps([s.points for s in strokes])) <= 1e-3 * si.size
        for s, key in zip(strokes, a):
            assert s.length == pytest.approx(segments(key).sum(), rel=1e-6)
    mid = [s.points for s in si.at(0.5)]
    # the upper arm turns rigidly about the shoulder by half of 120 degrees
    np.testing.assert_allclose(mid[0], turn(arc(2.0, 0, 31), 60), atol=1e-6 * si.size)
    # Strokes interpolated on their own open the elbow.
    apart = StrokeInterpolator(a, b, joints=False)
    assert apart.joints == []
    assert max(gaps([s.points for s in apart.at(0.5)])) > 0.05 * si.size


def test_an_end_that_stays_in_both_keys_stays_in_every_inbetween():
    gentle, curled = arc(4.0, -40, 40), turn(arc(4.0, 300, 40), 10)     # a tail's root at the origin
    si = StrokeInterpolator([gentle], [curled])
    assert len(si.still) == 1 and si.joints == []
    for (s,) in si.frames(TS):
        assert np.linalg.norm(s.points[0]) <= 1e-9 * si.size
        assert s.length >= min(segments(gentle).sum(), segments(curled).sum()) - 1e-9
    # on its own path (the method's anchor, the centroid) the root leaves the body
    (alone,) = StrokeInterpolator([gentle], [curled], joints=False).at(0.5)
    assert np.linalg.norm(alone.points[0]) > 0.1 * si.size


def test_a_closed_stroke_stays_closed():
    circle = arc(2 * np.pi, 360, 41)                   # drawn round until its end meets its start
    oval = turn(circle * [2.0, 0.5], 30, shift=(1.0, 0.0))
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], dtype=float)
    si = StrokeInterpolator([circle, square], [oval, turn(square, 150, shift=(5.0, 0.0))])
    for strokes in si.frames(TS):
        assert np.linalg.norm(strokes[0].points[0] - strokes[0].points[-1]) <= 1e-9 * si.size
        np.testing.assert_allclose(segments(strokes[1].points), 1.0, atol=1e-9)   # rigid, closed
    # a cyclic stroke (its closing segment implicit, as Grease Pencil's) keeps that form
    a, b = Stroke(circle[:-1], cyclic=True), Stroke(oval[:-1][::2], cyclic=True)
    (s,) = StrokeInterpolator([a], [b]).at(0.5)
    assert s.cyclic and len(s.points) == 40


def test_crossing_strokes_are_joined_where_they_cross():
    bar = arc(3.0, 0, 13, start=(-1.5, 0.0))
    cross = turn(arc(2.0, 0, 9, start=(-1.0, 0.0)), 90)            # crosses the bar at its middle
    keys_b = [turn(bar, 100, about=(-1.5, 0.0)), turn(turn(cross, 40), 100, about=(-1.5, 0.0))]
    si = StrokeInterpolator([bar, cross], keys_b)
    assert [(p, c) for p, c, _ in si.joints] == [(0, 1)] or [(p, c) for p, c, _ in si.joints] == [(1, 0)]
    for strokes in si.frames(TS):
        b, c = strokes[0].points, strokes[1].points
        # where the bar's middle is, the crossing stroke passes (both are straight)
        mid = b[6]
        d = c[-1] - c[0]
        off = abs(np.cross(d, mid - c[0])) / np.linalg.norm(d)
        assert off <= 1e-3 * si.size


def test_resample_spaces_points_evenly_along_the_arc():
    p = np.array([[0, 0], [1, 0], [1, 0], [1, 3]], dtype=float)        # a repeated point
    q, attrs = resample(p, 9, radius=[1.0, 2.0, 2.0, 5.0])
    np.testing.assert_allclose(segments(q), 0.5, atol=1e-12)
    np.testing.assert_allclose(q[[0, 2, 8]], [[0, 0], [1, 0], [1, 3]], atol=1e-12)
    np.testing.assert_allclose(attrs["radius"][[1, 2, 4]], [1.5, 2.0, 3.0], atol=1e-12)


def test_unequal_counts_are_paired_by_arc_length():
    a = arc(3.0, 0, 7)
    b = turn(arc(3.0, 90, 19), 30, shift=(0.5, 0.5))
    (s0,), (s1,) = interpolate_strokes([Stroke(a, radius=np.linspace(1, 2, 7))],
                                       [Stroke(b, radius=np.full(19, 4.0))], [0.0, 1.0])
    assert len(s0.points) == len(s1.points) == 19
    np.testing.assert_allclose(s1.points, b, atol=1e-9)              # the key with more points, as drawn
    # key a at the arc-length fractions of b's points (evenly spaced there too)
    np.testing.assert_allclose(s0.points, arc(3.0, 0, 19), atol=1e-9)
    np.testing.assert_allclose(s0.attributes["radius"], np.linspace(1, 2, 19), atol=1e-12)


def test_attributes_blend_linearly():
    a = [Stroke(arc(1.0, 0, 5), radius=np.full(5, 0.1), opacity=np.linspace(0, 1, 5),
                color=np.tile([1.0, 0, 0, 1], (5, 1)))]
    b = [Stroke(turn(arc(1.0, 0, 5), 90), radius=np.full(5, 0.3), opacity=np.ones(5),
                color=np.tile([0.0, 0, 1, 0.5], (5, 1)))]
    (s,) = StrokeInterpolator(a, b).at(0.25)
    np.testing.assert_allclose(s.attributes["radius"], 0.15, atol=1e-15)
    np.testing.assert_allclose(s.attributes["opacity"], 0.75 * np.linspace(0, 1, 5) + 0.25, atol=1e-15)
    np.testing.assert_allclose(s.attributes["color"], np.tile([0.75, 0, 0.25, 0.875], (5, 1)), atol=1e-15)


def test_3d_strokes_are_interpolated_in_their_plane():
    a, b = arm(0, 0), arm(120, 60)
    to3d = lambda s: np.stack([s[:, 0], np.full(len(s), 0.5), s[:, 1]], 1)   # noqa: E731 (XZ plane)
    flat = StrokeInterpolator(a, b).at(0.5)
    space = StrokeInterpolator([to3d(s) for s in a], [to3d(s) for s in b]).at(0.5)
    for f, s in zip(flat, space):
        np.testing.assert_allclose(s.points, to3d(f.points), atol=1e-9)


@pytest.mark.parametrize("stroke, message", [
    (np.zeros((4, 2)), "stroke 1 of key b: the stroke has zero length"),
    (np.zeros((1, 2)), "stroke 1 of key b: a stroke needs at least 2 points, it has 1"),
    (np.array([[0, 0], [1, np.nan], [2, 0]]), "stroke 1 of key b: point 1 is not finite"),
])
def test_degenerate_strokes_are_refused(stroke, message):
    with pytest.raises(ValueError, match=message):
        StrokeInterpolator([ZIGZAG, ZIGZAG], [ZIGZAG, stroke])


def test_a_stroke_count_mismatch_names_the_strokes_left_over():
    with pytest.raises(ValueError, match=r"layer 'Arm': frame 1 has 3 strokes and frame 9 has 1: "
                                         r"strokes \[1, 2\] of frame 1 have no partner"):
        StrokeInterpolator([ZIGZAG] * 3, [ZIGZAG], where="layer 'Arm'", keys=("frame 1", "frame 9"))


def test_strokes_left_over_fade_out_or_in_on_request():
    bar = Stroke(arc(1.0, 0, 5), opacity=np.full(5, 0.8))
    extra = Stroke(arc(1.0, 90, 6, start=(2.0, 0.0)), opacity=np.full(6, 0.5))
    turned = Stroke(turn(arc(1.0, 0, 5), 90), opacity=np.full(5, 0.8))
    (bar_t, out), = StrokeInterpolator([bar, extra], [turned], unpaired="fade").frames([0.25])
    np.testing.assert_allclose(segments(bar_t.points), 0.25, atol=1e-9)
    np.testing.assert_allclose(out.points, extra.points)                 # as drawn, fading out
    np.testing.assert_allclose(out.attributes["opacity"], 0.75 * 0.5)
    (_, appearing), = StrokeInterpolator([turned], [bar, extra], unpaired="fade").frames([0.25])
    np.testing.assert_allclose(appearing.attributes["opacity"], 0.25 * 0.5)
    (only,), = StrokeInterpolator([], [extra], unpaired="fade").frames([0.5])   # nothing to pair
    np.testing.assert_allclose(only.attributes["opacity"], 0.25)
    with pytest.raises(ValueError, match="unpaired must be one of"):
        StrokeInterpolator([bar], [bar], unpaired="drop")


def test_a_stroke_that_turns_back_on_itself_is_refused():
    hairpin = np.array([[0, 0], [1, 0], [0, 1e-13]])
    with pytest.raises(ValueError, match="stroke 0: key a: the stroke turns back on itself near point"):
        StrokeInterpolator([hairpin], [hairpin])


def test_the_meeting_grid_misses_no_close_segments():
    """Candidate pairs of the grid against every pair of segments, with one long stroke across
    forty short ones (it lies in every cell it covers; the cells stay as fine as the short ones)."""
    from bdinterp import _stroke_geometry as geo
    rng = np.random.default_rng(2)
    strokes = [np.cumsum(rng.normal(0, 0.3, (rng.integers(2, 30), 2)), axis=0) + rng.uniform(0, 6, 2)
               for _ in range(40)] + [np.array([[-5.0, -5.0], [12.0, 12.0]])]
    pairs, owner = geo.near_segments(strokes, 0.05)
    a, b = np.concatenate([p[:-1] for p in strokes]), np.concatenate([p[1:] for p in strokes])
    i, j = np.triu_indices(len(a), 1)
    i, j = i[owner[i] != owner[j]], j[owner[i] != owner[j]]
    d, _, _ = geo.segment_distances(a[i], b[i], a[j], b[j])
    close = set(zip(i[d <= 0.05].tolist(), j[d <= 0.05].tolist()))
    assert len(close) > 100 and close <= set(map(tuple, np.sort(pairs, axis=1).tolist()))
    assert len(pairs) < 0.1 * len(i)     # and far fewer than all pairs
