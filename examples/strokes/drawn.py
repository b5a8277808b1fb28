"""Two drawings as an animator draws them, in two keys each, as plain numpy (no Blender): an arm
of three strokes (upper arm, forearm, hand) swinging by 120 degrees at the shoulder and 60 more at
the elbow, the second key drawn with other point counts; and a tail of one stroke that curls up.
Points are 2D (x, z of Blender's front view); every stroke carries a radius and an opacity per
point.  Used by tests/blender/test_strokes.py and scripts/strokes_gallery.py."""
import numpy as np

SHOULDER_TURN, ELBOW_TURN = 120.0, 60.0
ARM_COUNTS = ((20, 15, 8), (31, 9, 14))   # points per stroke in key 1 and key 2


def turn(points, degrees, about=(0.0, 0.0)):
    a = np.radians(degrees)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return (np.asarray(points, dtype=float) - about) @ R.T + about


def arc(start, heading, length, bend, count):
    """count points along a curve from start, leaving at `heading` degrees, `length` long, whose
    direction turns by `bend` degrees on the way (evenly: a circular arc; 0: a straight line)."""
    s = np.linspace(0.0, 1.0, count)
    if abs(bend) < 1e-12:
        d = np.stack([s * length, 0 * s], 1)
    else:
        b = np.radians(bend)
        r = length / b
        d = np.stack([r * np.sin(b * s), r * (1 - np.cos(b * s))], 1)
    return turn(d, heading) + start


def arm_key(key):
    """[(points (n, 2), radius (n,), opacity (n,))] of the arm in key 0 or 1."""
    counts = ARM_COUNTS[key]
    upper = arc((0.0, 0.0), -90.0, 2.0, 0.0, counts[0])            # hanging down from the shoulder
    fore = arc(upper[-1], -70.0, 1.6, 0.0, counts[1])              # bent 20 degrees at the elbow
    hand = arc(fore[-1], -70.0, 0.6, 50.0, counts[2])              # a curled hand
    if key == 1:
        elbow = turn(upper[-1], SHOULDER_TURN)
        upper = turn(upper, SHOULDER_TURN)
        fore, hand = (turn(turn(s, SHOULDER_TURN), ELBOW_TURN, about=elbow) for s in (fore, hand))
    out = []
    for s in (upper, fore, hand):
        u = np.linspace(0.0, 1.0, len(s))
        radius = 0.02 + 0.03 * u if key == 0 else np.full(len(s), 0.03)
        opacity = np.ones(len(s)) if key == 0 else np.full(len(s), 0.5)
        out.append((s, radius, opacity))
    return out


def tail_key(key):
    """[(points, radius, opacity)] of a tail: a gentle curve in key 0, curled up in key 1."""
    if key == 0:
        points = arc((0.0, 0.0), 10.0, 4.0, -40.0, 40)
    else:
        points = arc((0.0, 0.0), 10.0, 4.0, 300.0, 40)
    u = np.linspace(0.0, 1.0, len(points))
    return [(points, 0.08 - 0.06 * u, np.ones(len(points)))]


def length(points):
    return float(np.linalg.norm(np.diff(np.asarray(points, dtype=float), axis=0), axis=1).sum())
