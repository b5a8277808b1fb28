"""A whole FK biped built like a painted one (tests/python/test_biped.py, tests/blender/test_biped.py):
17 rectangular sprites on a skeleton whose root and hip bones have no sprite; poses as each bone's
angle (degrees, counter-clockwise, relative to its parent) and offset (its pivot's shift in its
parent's frame), and the bones' own in-between: every angle and offset blended by t.

The sprites overlap as painted ones do (the limbs lie over the torso's edges, the eyes over the
head), the left knee and the right elbow are drawn with a gap (their pivot lies between the two
sprites, in neither), and the thighs hang from the hip bone, which the poses translate."""
import numpy as np

# bone: (parent, pivot in the rest pose, sprite rectangle (x0, y0, width, height) or None)
BONES = {
    "root": (None, (0.0, 0.0), None),
    "torso": ("root", (0.0, 0.0), (-1.0, -0.4, 2.0, 3.6)),
    "hip": ("root", (0.0, -0.2), None),
    "neck": ("torso", (0.0, 3.0), (-0.3, 2.9, 0.6, 0.8)),
    "head": ("neck", (0.0, 3.55), (-0.9, 3.45, 1.8, 1.7)),
    "eye_l": ("head", (-0.4, 4.4), (-0.55, 4.25, 0.3, 0.3)),
    "eye_r": ("head", (0.4, 4.4), (0.25, 4.25, 0.3, 0.3)),
    "thigh_l": ("hip", (-0.5, -0.2), (-0.8, -2.4, 0.6, 2.6)),     # knee drawn with a gap:
    "shin_l": ("thigh_l", (-0.5, -2.415), (-0.78, -4.5, 0.56, 2.07)),  # pivot in neither sprite
    "foot_l": ("shin_l", (-0.5, -4.35), (-0.8, -4.7, 1.0, 0.45)),
    "thigh_r": ("hip", (0.5, -0.2), (0.2, -2.5, 0.6, 2.7)),
    "shin_r": ("thigh_r", (0.5, -2.42), (0.22, -4.5, 0.56, 2.15)),
    "foot_r": ("shin_r", (0.5, -4.35), (0.2, -4.7, 1.0, 0.45)),
    "upper_l": ("torso", (-0.95, 2.8), (-1.3, 1.1, 0.5, 1.9)),
    "fore_l": ("upper_l", (-1.05, 1.15), (-1.3, -0.75, 0.5, 1.95)),
    "hand_l": ("fore_l", (-1.05, -0.6), (-1.25, -1.1, 0.4, 0.6)),
    "upper_r": ("torso", (0.95, 2.8), (0.8, 1.18, 0.5, 1.82)),      # elbow drawn with a gap:
    "fore_r": ("upper_r", (1.05, 1.16), (0.8, -0.75, 0.5, 1.89)),   # pivot in neither sprite
    "hand_r": ("fore_r", (1.05, -0.6), (0.85, -1.1, 0.4, 0.6)),
}
PIECES = [name for name, (_, _, rect) in BONES.items() if rect is not None]

# pose: bone -> angle (degrees) or (angle, (dx, dy)); bones not named keep their rest pose
POSES = {
    "walk": dict(hip=(0, (0.02, -0.06)), neck=4, head=-6, thigh_l=28, shin_l=-35, foot_l=12,
                 thigh_r=-22, shin_r=-40, foot_r=18, upper_l=-30, fore_l=-35, hand_l=-10,
                 upper_r=25, fore_r=40, hand_r=12),
    "run": dict(root=(-12, (0.15, 0.12)), hip=(0, (0.05, -0.1)), neck=8, head=9, thigh_l=75,
                shin_l=-110, foot_l=25, thigh_r=-45, shin_r=-70, foot_r=30, upper_l=-65, fore_l=100,
                hand_l=20, upper_r=55, fore_r=95, hand_r=-15),
    "jump": dict(root=(0, (0.0, 1.3)), hip=(0, (0.0, 0.08)), neck=-10, head=15, thigh_l=70,
                 shin_l=-120, foot_l=45, thigh_r=85, shin_r=-150, foot_r=50, upper_l=-150,
                 fore_l=-30, hand_l=-20, upper_r=140, fore_r=40, hand_r=25),
    "fall": dict(root=(-90, (0.25, -0.45)), hip=(0, (-0.06, 0.1)), neck=-25, head=-20, thigh_l=80,
                 shin_l=-95, foot_l=30, thigh_r=110, shin_r=-130, foot_r=40, upper_l=-120,
                 fore_l=-60, hand_l=-25, upper_r=150, fore_r=70, hand_r=30),
}


def _rotation(degrees):
    a = np.radians(degrees)
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def bone_motion(pose, t):
    """bone -> (R, c): the bone's world motion x -> R x + c at t (every angle and offset times t)."""
    out = {}
    for name, (parent, pivot, _) in BONES.items():  # parents come first
        value = pose.get(name, 0.0)
        angle, offset = value if isinstance(value, tuple) else (value, (0.0, 0.0))
        pivot = np.asarray(pivot)
        R = _rotation(t * angle)
        c = pivot + t * np.asarray(offset) - R @ pivot  # turn about the pivot, then shift it
        if parent is not None:
            Rp, cp = out[parent]
            R, c = Rp @ R, Rp @ c + cp
        out[name] = (R, c)
    return out


def posed(ch, pose, t):
    """The bones' in-between of character ch (rig_character()) at t: each piece by its bone."""
    motions = bone_motion(pose, t)
    X = ch.V.copy()
    for k, name in enumerate(PIECES):
        R, c = motions[name]
        X[ch.ranges[k]] = ch.V[ch.ranges[k]] @ R.T + c
    return X


def pins():
    """(parent piece, child piece, pivot) for every bone whose parent bone has a sprite."""
    out = []
    for k, name in enumerate(PIECES):
        parent = BONES[name][0]
        if BONES[parent][2] is not None:
            out.append((PIECES.index(parent), k, np.array(BONES[name][1])))
    return out


def rigid_fit_error(X, Y):
    """The largest distance between X (n, 2) moved by its best rigid fit onto Y and Y (n, 2)."""
    a, b = X - X.mean(0), Y - Y.mean(0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    D = np.diag([1.0, np.sign(np.linalg.det(U @ Vt))])
    return float(np.linalg.norm(a @ (U @ D @ Vt) - b, axis=1).max())
