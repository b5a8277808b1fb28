"""Test meshes with holes: a jittered polar annulus and a jittered grid with two square holes."""
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
