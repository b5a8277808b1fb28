"""A cut-out face rigged with pose parameters, the way Live2D rigs one (numpy only).

Pieces (loose parts, each at its own depth for draw order): body, head, two eyes, nose, mouth.
Poses:
  head: angle_x (yaw) x angle_y (nod) in {-30, 0, 30}^2. Yaw slides the features over the face as
      if it were a dome (x' = x cos a + z sin a with z = 0.6 (R^2 - r^2) / R: no fold at the rim);
      the nod does the same in y and tilts the whole head by the angle about the neck.
  mouth: open in {0, 1}: the mouth's height x 3, hanging from its top.
  body: turn in {0, 90, 180, 270}, wrapping: the torso narrows and shifts as it turns away.
Used by face_blender.py (the rig in Blender) and pad_figure.py (the gallery picture).
"""

import itertools

import numpy as np

HEAD_C, HEAD_R, NECK = np.array([0.0, 1.2]), 1.0, np.array([0.0, 0.25])
DEPTHS = {"body": -0.01, "head": 0.0, "eye_l": 0.01, "eye_r": 0.01, "nose": 0.02, "mouth": 0.02}
ANGLES = (-30, 0, 30)
TURNS = (0, 90, 180, 270)


def disk(centre, rx, ry, rings, sectors):
    """A triangulated ellipse: a centre vertex and `rings` rings of `sectors` vertices."""
    a = np.linspace(0, 2 * np.pi, sectors, endpoint=False)
    verts = [np.asarray(centre, float)]
    for k in range(1, rings + 1):
        s = k / rings
        verts += list(np.c_[centre[0] + s * rx * np.cos(a), centre[1] + s * ry * np.sin(a)])
    faces = [(0, 1 + j, 1 + (j + 1) % sectors) for j in range(sectors)]
    for k in range(1, rings):
        inner, outer = 1 + (k - 1) * sectors, 1 + k * sectors
        for j in range(sectors):
            j1 = (j + 1) % sectors
            faces += [(inner + j, outer + j, outer + j1), (inner + j, outer + j1, inner + j1)]
    return np.array(verts), faces


def torso(rows=6, cols=10):
    """A trapezoid below the neck: shoulders 2.4 wide at y = 0.45, hips 1.6 wide at y = -1.6."""
    t, s = np.meshgrid(np.linspace(0, 1, rows + 1), np.linspace(-1, 1, cols + 1), indexing="ij")
    half = 1.2 - 0.4 * t
    verts = np.c_[(s * half).ravel(), (0.45 - 2.05 * t).ravel()]
    faces = []
    for i, j in itertools.product(range(rows), range(cols)):
        a, b = i * (cols + 1) + j, (i + 1) * (cols + 1) + j
        faces += [(a, b + 1, b), (a, a + 1, b + 1)]
    return verts, faces


def pieces():
    """{name: (verts (n, 2), faces)} in draw order."""
    return {"body": torso(), "head": disk(HEAD_C, HEAD_R, 1.1 * HEAD_R, 8, 32),
            "eye_l": disk(HEAD_C + [-0.38, 0.2], 0.17, 0.11, 2, 12),
            "eye_r": disk(HEAD_C + [0.38, 0.2], 0.17, 0.11, 2, 12),
            "nose": disk(HEAD_C + [0.0, -0.12], 0.08, 0.2, 2, 10),
            "mouth": disk(HEAD_C + [0.0, -0.55], 0.3, 0.07, 2, 14)}


def mesh():
    """(V (n, 3) with each piece at its depth, faces (m, 3), labels {name: vertex indices})."""
    verts, faces, labels, n = [], [], {}, 0
    for name, (v, f) in pieces().items():
        verts.append(np.c_[v, np.full(len(v), DEPTHS[name])])
        faces += [tuple(n + i for i in tri) for tri in f]
        labels[name] = np.arange(n, n + len(v))
        n += len(v)
    return np.vstack(verts), np.array(faces), labels


def _turn(P, degrees, pivot):
    a = np.radians(degrees)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return (P - pivot) @ R.T + pivot


def head_pose(V, labels, yaw, nod):
    """The head's pieces turned by yaw and nod (degrees); the body stays."""
    out = V.copy()
    idx = np.concatenate([labels[n] for n in ("head", "eye_l", "eye_r", "nose", "mouth")])
    P = V[idx, :2] - HEAD_C
    z = 0.6 * np.clip(HEAD_R ** 2 - (P ** 2).sum(1), 0, None) / HEAD_R
    ay, an = np.radians(yaw), np.radians(nod)
    P = np.c_[P[:, 0] * np.cos(ay) + z * np.sin(ay), P[:, 1] * np.cos(an) - z * np.sin(an)]
    out[idx, :2] = _turn(P + HEAD_C, nod, NECK)
    return out


def mouth_open(V, labels):
    out = V.copy()
    m = labels["mouth"]
    top = V[m, 1].max()
    out[m, 1] = top - 3.0 * (top - V[m, 1])
    return out


def body_turn(V, labels, degrees):
    """The torso turned by `degrees` about the vertical: narrower and shifted as it turns away."""
    out = V.copy()
    b = labels["body"]
    a = np.radians(degrees)
    width = 0.6 + 0.4 * abs(np.cos(a))
    out[b, 0] = V[b, 0] * width + 0.35 * np.sin(a) * (V[b, 1] - 0.45) / -2.05
    return out


def poses():
    """(shapes {key: (n, 3)}, faces, groups: {group: (params, keys)} as pose_grid takes them)."""
    V, F, labels = mesh()
    shapes = {"Basis": V}
    head_keys = {}
    for yaw, nod in itertools.product(ANGLES, ANGLES):
        name = "Basis" if yaw == nod == 0 else "Head_%+d_%+d" % (yaw, nod)
        shapes.setdefault(name, head_pose(V, labels, yaw, nod))
        head_keys[(yaw, nod)] = name
    shapes["Mouth_open"] = mouth_open(V, labels)
    turn_keys = {0: "Basis"}
    for t in TURNS[1:]:
        turn_keys[t] = "Body_%d" % t
        shapes[turn_keys[t]] = body_turn(V, labels, t)
    groups = {"head": ({"angle_x": list(ANGLES), "angle_y": list(ANGLES)}, head_keys),
              "mouth": ({"open": [0, 1]}, {0: "Basis", 1: "Mouth_open"}),
              "body": ({"turn": {"values": list(TURNS), "wrap": True}}, turn_keys)}
    return shapes, F, groups
