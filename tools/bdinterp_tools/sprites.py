"""Test sprites drawn by the project (RGBA uint8, row 0 at the top): each from an inside test on
4 x 4 sub-samples per pixel (antialiased edges), or drawn pixel by pixel where the point is a hard
edge. EXPECTED: the islands and holes each one has."""
import numpy as np

SUB = 4


def triangle_angles(V, F):
    """(m, 3) interior angles in degrees of the triangles F (m, 3) of V (n, 2)."""
    P = V[F]
    out = []
    for k in range(3):
        u, w = P[:, (k + 1) % 3] - P[:, k], P[:, (k + 2) % 3] - P[:, k]
        cos = (u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.array(out).T


def coverage(h, w, inside):
    """Fraction of each pixel's 4x4 sub-samples where inside(x, y) holds (x right, y down, pixels)."""
    s = (np.arange(SUB) + 0.5) / SUB
    y, x = np.mgrid[0:h, 0:w].astype(float)
    cover = np.zeros((h, w))
    for dy in s:
        for dx in s:
            cover += inside(x + dx, y + dy)
    return cover / SUB ** 2


def rgba(alpha, color=(200, 120, 60)):
    out = np.zeros(alpha.shape + (4,), np.uint8)
    out[..., :3] = color
    out[..., 3] = np.round(np.clip(alpha, 0, 1) * 255).astype(np.uint8)
    return out


def _disc(cx, cy, r):
    return lambda x, y: (x - cx) ** 2 + (y - cy) ** 2 <= r * r


def ring(size=128):
    c = size / 2
    return rgba(coverage(size, size, lambda x, y: _disc(c, c, 0.4 * size)(x, y) & ~_disc(c, c, 0.2 * size)(x, y)))


def letter_b(size=128):
    """A 'B': a stem and two bowls, each bowl with a hole."""
    def inside(x, y):
        stem = (x >= 0.2 * size) & (x <= 0.4 * size) & (y >= 0.1 * size) & (y <= 0.9 * size)
        bowls = [(0.3, 0.3, 0.2), (0.3, 0.7, 0.2)]
        shape = stem.copy()
        for cx, cy, r in bowls:
            bowl = ((x - cx * size) ** 2 / (0.35 * size) ** 2 + (y - cy * size) ** 2 / (r * size) ** 2 <= 1)
            shape |= bowl & (x >= cx * size)
        for cx, cy, r in bowls:
            hole = ((x - cx * size) ** 2 / (0.2 * size) ** 2 + (y - cy * size) ** 2 / (0.1 * size) ** 2 <= 1)
            shape &= ~(hole & (x >= 0.35 * size))
        return shape
    return rgba(coverage(size, size, inside))


def two_islands(size=128):
    return rgba(coverage(size, size, lambda x, y: _disc(0.28 * size, 0.5 * size, 0.2 * size)(x, y)
                           | _disc(0.75 * size, 0.45 * size, 0.15 * size)(x, y)))


def line(size=128):
    """A one-pixel-wide slanted line (hard pixels, 8-connected)."""
    alpha = np.zeros((size, size))
    x = np.arange(int(0.1 * size), int(0.9 * size))
    alpha[np.round(0.3 * size + 0.4 * (x - x[0])).astype(int), x] = 1.0
    return rgba(alpha)


def border(size=128):
    """A disc cut by the image's left and bottom edges."""
    return rgba(coverage(size, size, _disc(0.15 * size, 0.8 * size, 0.45 * size)))


def soft_blob(size=128):
    """A wavy blob whose alpha falls off over ~12 % of its radius."""
    y, x = np.mgrid[0:size, 0:size] + 0.5
    dx, dy = x - size / 2, y - size / 2
    radius = 0.33 * size * (1 + 0.15 * np.sin(3 * np.arctan2(dy, dx)))
    return rgba(np.clip((radius - np.hypot(dx, dy)) / (0.08 * size) + 0.5, 0, 1))


SPRITES = {"ring": ring, "letter_b": letter_b, "two_islands": two_islands, "line": line,
           "border": border, "soft_blob": soft_blob}
EXPECTED = {"ring": (1, 1), "letter_b": (1, 2), "two_islands": (2, 0), "line": (1, 0),
            "border": (1, 0), "soft_blob": (1, 0)}  # (islands, holes)
