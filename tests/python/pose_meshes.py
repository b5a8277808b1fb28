"""Test meshes of poses: a jittered polar annulus, a grid with two square holes, a body with a
limb (arm or tail) and its poses (rigid swing, linear-blend-skinned swing, curl)."""
import numpy as np


def _split(quads, rng):
    """Each quad (a, b, c, d), counter-clockwise, split along a random diagonal."""
    faces = []
    for a, b, c, d in quads:
        faces += [[a, b, c], [a, c, d]] if rng.random() < 0.5 else [[a, b, d], [b, c, d]]
    return np.array(faces, dtype=np.int64)


def annulus(nr, nt=None, r0=0.4, r1=1.0, seed=0):
    """Annulus r0 <= |x| <= r1: nr rings of nt cells; interior vertices jittered by 0.2 of a cell."""
    nt = nt or 6 * nr
    rng = np.random.default_rng(seed)
    r, th = np.meshgrid(np.linspace(r0, r1, nr + 1), np.linspace(0, 2 * np.pi, nt, endpoint=False),
                        indexing="ij")
    r[1:-1] += rng.uniform(-0.2, 0.2, r[1:-1].shape) * (r1 - r0) / nr
    th[1:-1] += rng.uniform(-0.2, 0.2, th[1:-1].shape) * 2 * np.pi / nt
    V = np.c_[(r * np.cos(th)).ravel(), (r * np.sin(th)).ravel()]
    idx = lambda i, j: i * nt + j % nt  # noqa: E731
    quads = [(idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j))
             for i in range(nr) for j in range(nt)]
    return V, _split(quads, rng)


def two_holes(n, seed=0):
    """[0, 2] x [0, 1] on a 2n x n grid without the cells of two squares of side 1/4 (the holes),
    interior vertices jittered; unused vertices are dropped."""
    rng = np.random.default_rng(seed)
    nx, ny = 2 * n, n
    x, y = np.meshgrid(np.linspace(0, 2, nx + 1), np.linspace(0, 1, ny + 1))
    V = np.c_[x.ravel(), y.ravel()]
    inner = np.ones((ny + 1, nx + 1), bool)
    inner[[0, -1], :] = inner[:, [0, -1]] = False
    V[inner.ravel()] += rng.uniform(-0.15, 0.15, (inner.sum(), 2)) / n

    def in_hole(i, j):  # cell (i, j) has its centre in a hole
        cx, cy = (i + 0.5) / n, (j + 0.5) / n
        return abs(cy - 0.5) < 0.125 and (abs(cx - 0.5) < 0.125 or abs(cx - 1.5) < 0.125)

    quads = [(j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i)
             for j in range(ny) for i in range(nx) if not in_hole(i, j)]
    F = _split(quads, rng)
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def _grid_cells(nx, ny, width, height, keep, rng, jitter=0.15):
    """Jittered (nx+1) x (ny+1) grid over [0, width] x [0, height], the cells (i, j) with
    keep(x, y) at their centre, randomly split; unused vertices dropped."""
    x, y = np.meshgrid(np.linspace(0, width, nx + 1), np.linspace(0, height, ny + 1))
    V = np.c_[x.ravel(), y.ravel()]
    V += rng.uniform(-jitter, jitter, V.shape) * [width / nx, height / ny]
    hx, hy = width / nx, height / ny
    quads = [(j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i)
             for j in range(ny) for i in range(nx) if keep((i + 0.5) * hx, (j + 0.5) * hy)]
    F = _split(quads, rng)
    used = np.unique(F)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def body_with_limb(n=8, limb_length=3.0, seed=0):
    """A torso [0, 1] x [0, 2] with a limb of width 0.25 leaving its right side at y in
    [1.5, 1.75] and reaching x = 1 + limb_length; n cells per unit. Returns V, F and the
    shoulder (the limb's centre line at x = 1)."""
    rng = np.random.default_rng(seed)
    width = 1 + limb_length
    nx, ny = int(round(width * n)), 2 * n
    keep = lambda x, y: x < 1 or 1.5 < y < 1.75 + 1e-9  # noqa: E731
    V, F = _grid_cells(nx, ny, width, 2.0, keep, rng, jitter=0.1)
    return V, F, np.array([1.0, 1.625])


def _smoothstep(s):
    s = np.clip(s, 0, 1)
    return s * s * (3 - 2 * s)


def skinned_swing(V, shoulder, angle, blend=(0.85, 1.25)):
    """Two-bone linear blend skinning: the limb (bone 2) turns by `angle` about the shoulder, the
    torso (bone 1) stays; weights ramp smoothly over x in `blend` (folds at the joint for large
    angles, as Blender's armatures make)."""
    w = _smoothstep((V[:, 0] - blend[0]) / (blend[1] - blend[0]))[:, None]
    c, s = np.cos(angle), np.sin(angle)
    turned = (V - shoulder) @ np.array([[c, s], [-s, c]]) + shoulder
    return (1 - w) * V + w * turned


def curled(V, shoulder, total, start=1.0):
    """The limb (x > start) bent along its length by `total` radians (an arm rolling up, a tail
    curling); the torso is untouched."""
    x = V[:, 0] - start
    radius = (V[:, 0].max() - start) / abs(total)
    a = np.clip(x, 0, None) / radius * np.sign(total)
    r = radius - np.sign(total) * (V[:, 1] - shoulder[1])
    out = V.copy()
    limb = x > 0
    out[limb, 0] = start + r[limb] * np.sin(np.abs(a[limb]))
    out[limb, 1] = shoulder[1] + np.sign(total) * (radius - r[limb] * np.cos(a[limb]))
    return out
