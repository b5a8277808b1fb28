"""Cut-out characters: loose rectangular pieces overlapping where they are pinned, posed
by turning each piece rigidly about its pins, and the measures the tests apply to their frames."""
import numpy as np


def rectangle(x0, y0, width, height, cell, seed=0):
    """[x0, x0 + width] x [y0, y0 + height] on a grid of about `cell`-sized cells, interior vertices
    jittered by 0.15 of a cell (the outline stays straight), quads split along random diagonals."""
    rng = np.random.default_rng(seed)
    nx, ny = max(1, int(round(width / cell))), max(1, int(round(height / cell)))
    x, y = np.meshgrid(np.linspace(0, width, nx + 1), np.linspace(0, height, ny + 1))
    V = np.c_[x.ravel(), y.ravel()]
    inner = np.ones((ny + 1, nx + 1), bool)
    inner[[0, -1], :] = inner[:, [0, -1]] = False
    V[inner.ravel()] += rng.uniform(-0.15, 0.15, (inner.sum(), 2)) * [width / nx, height / ny]
    faces = []
    for j in range(ny):
        for i in range(nx):
            a, b = j * (nx + 1) + i, j * (nx + 1) + i + 1
            c, d = b + nx + 1, a + nx + 1
            faces += [[a, b, c], [a, c, d]] if rng.random() < 0.5 else [[a, b, d], [b, c, d]]
    return V + [x0, y0], np.array(faces, dtype=np.int64)


def turn(points, angle_deg, pivot):
    """points (n, 2) turned by angle_deg (counter-clockwise) about pivot (2,)."""
    a = np.radians(angle_deg)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    return (np.asarray(points) - pivot) @ R.T + pivot


class Character:
    """Pieces (V_k, F_k) as loose parts of one mesh V (n, 2), F (m, 3); piece k's vertices are
    rows ranges[k] and its faces face_ranges[k]. pins: (parent, child, point (2,)) in the source."""

    def __init__(self, pieces, pins):
        self.ranges, self.face_ranges, Vs, Fs = [], [], [], []
        nv = nf = 0
        for V, F in pieces:
            self.ranges.append(np.arange(nv, nv + len(V)))
            self.face_ranges.append(np.arange(nf, nf + len(F)))
            Vs.append(V)
            Fs.append(F + nv)
            nv, nf = nv + len(V), nf + len(F)
        self.V, self.F = np.vstack(Vs), np.vstack(Fs)
        self.pins = pins
        self.size = float(np.linalg.norm(np.ptp(self.V, axis=0)))

    def pose(self, motions):
        """The target: piece k moved by motions[k], a function of (n_k, 2) points, or None (still)."""
        T = self.V.copy()
        for k, m in enumerate(motions):
            if m is not None:
                T[self.ranges[k]] = m(self.V[self.ranges[k]])
        return T

    def carried(self, frames, piece, point):
        """(len(frames), 2): where the piece's triangle containing `point` in the source (by its
        barycentric coordinates there; the nearest triangle if none contains it) carries it."""
        faces = self.F[self.face_ranges[piece]]
        a, b, c = (self.V[faces[:, k]] for k in range(3))
        M = np.stack([b - a, c - a], axis=2)  # (m, 2, 2)
        lam = np.linalg.solve(M, (point - a)[..., None])[..., 0]
        bary = np.c_[1 - lam.sum(1), lam]
        f = int(np.argmax(bary.min(axis=1)))  # the containing triangle (or the least outside)
        X = np.asarray(frames)
        return np.einsum("k,jkd->jd", bary[f], X[:, faces[f], :])

    def pin_drift(self, frames):
        """Per pin: the largest distance, over the frames, between where the parent and where the
        child carry the pin, relative to the character's size."""
        return [float(np.linalg.norm(self.carried(frames, p, q) - self.carried(frames, c, q),
                                     axis=1).max()) / self.size for p, c, q in self.pins]


def shoulder(cell=0.25):
    """A 4 x 6 torso and a 4 x 0.8 arm overlapping it at the shoulder (x in [1.5, 2]); the target
    swings the arm by 150 degrees about the pin (2, 2.4) inside that overlap."""
    ch = Character([rectangle(-2, -3, 4, 6, cell, 1), rectangle(1.5, 2, 4, 0.8, cell / 2, 2)],
                   [(0, 1, np.array([1.75, 2.4]))])
    return ch, ch.pose([None, lambda P: turn(P, 150, [1.75, 2.4])])


def chain(cell=0.25):
    """Torso, upper arm, forearm and hand, each overlapping the next by 0.5 at a pin: shoulder
    (1.75, 2.4), elbow (5.25, 2.4), wrist (8.75, 2.4); the target bends them by 60, 90 and 45."""
    pins = [np.array([1.75, 2.4]), np.array([5.25, 2.4]), np.array([8.75, 2.4])]
    pieces = [rectangle(-2, -3, 4, 6, cell, 1), rectangle(1.5, 2, 4, 0.8, cell / 2, 2),
              rectangle(5, 2, 4, 0.8, cell / 2, 3), rectangle(8.5, 1.9, 1.5, 1.0, cell / 2, 4)]
    ch = Character(pieces, [(0, 1, pins[0]), (1, 2, pins[1]), (2, 3, pins[2])])

    def bent(k):  # piece k turned at the joints before it: shoulder, then elbow, then wrist
        angles = [60, 90, 45][:k]

        def motion(P):
            for a, q in reversed(list(zip(angles, pins))):
                P = turn(P, a, q)
            return P
        return motion
    return ch, ch.pose([None, bent(1), bent(2), bent(3)])


def head_with_eyes(cell=0.25):
    """A 4 x 5 head and two 0.6 x 0.6 eyes laid over it; the target tilts the head and the eyes by
    40 degrees about the neck (0, 0), the middle of the head's lower edge."""
    pieces = [rectangle(-2, 0, 4, 5, cell, 1), rectangle(-1.3, 3, 0.6, 0.6, cell / 2, 2),
              rectangle(0.7, 3, 0.6, 0.6, cell / 2, 3)]
    ch = Character(pieces, [(0, 1, np.array([-1.0, 3.3])), (0, 2, np.array([1.0, 3.3]))])
    tilt = lambda P: turn(P, 40, [0.0, 0.0])  # noqa: E731
    return ch, ch.pose([tilt, tilt, tilt])


def pendulum(cell=0.125):
    """A 0.5 x 4 bar hanging from its pivot (0, 0), the middle of its top end; the target swings it
    by 150 degrees about the pivot. Returns (V, F, T, pivot, length)."""
    V, F = rectangle(-0.25, -4, 0.5, 4, cell, 5)
    return V, F, turn(V, 150, [0.0, 0.0]), np.zeros(2), 4.0


def rigid_angle(A, B):
    """The angle (degrees) of the rotation that best maps points A (n, 2) onto B (n, 2)."""
    a, b = A - A.mean(0), B - B.mean(0)
    return float(np.degrees(np.arctan2((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum(),
                                       (a * b).sum())))


def steps(frames):
    """(len(frames) - 1,) the largest vertex displacement between consecutive frames."""
    X = np.asarray(frames)
    return np.linalg.norm(np.diff(X, axis=0), axis=2).max(axis=1)
