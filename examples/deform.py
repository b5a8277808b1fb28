"""Smooth bending deformations used to pose the examples (numpy only, so
Blender's Python can import it too).

A limb is a region described in a local frame: s along its axis from a
root point, v across.  :func:`bend` rotates the limb's cross sections by a
smoothly varying angle theta(s) and lays them along the bent centre line,
like a chain of many small bones.  Its Jacobian is (stretch - v w theta')
along the limb and w across (w = width factor), so it stays orientation
preserving while |v theta'| < stretch, i.e. while the limb is thinner than
its smallest radius of curvature.
"""

import numpy as np


def smooth_ramp(total, s0, s1):
    """theta(s): 0 before s0, ``total`` after s1, C1 smoothstep between.

    A zero slope at s0 means the bent part joins the static part without a
    kink (the local-support example relies on that).
    """
    def theta(s):
        x = np.clip((np.asarray(s, float) - s0) / (s1 - s0), 0.0, 1.0)
        return total * x * x * (3.0 - 2.0 * x)
    return theta


def bend(X, root, axis, theta, *, stretch=1.0, width=None, mask=None):
    """Bend the points of X (n,2) with s > 0 along ``axis`` from ``root``.

    theta : callable, angle (radians, CCW) of the cross section at s >= 0,
        theta(0) should be 0 so points at the root do not move.
    stretch : scale of lengths along the limb.
    width : optional callable w(s) > 0 scaling the limb's thickness.
    mask : optional (n,) bool restricting which points belong to the limb
        (points with s <= 0 never move).
    Returns the bent copy of X (n,2).
    """
    X = np.asarray(X, dtype=np.float64)
    root = np.asarray(root, float)
    d = np.asarray(axis, float) / np.linalg.norm(axis)
    n = np.array([-d[1], d[0]])
    s = (X - root) @ d
    v = (X - root) @ n
    sel = s > 0 if mask is None else (s > 0) & mask
    # Centre line c(s) = stretch * integral of (cos theta, sin theta): a fine
    # trapezoid rule, interpolated (error far below the mesh spacing).
    grid = np.linspace(0.0, max(s.max(), 0.0) + 1e-9, 4001)
    th = theta(grid)
    ds = np.diff(grid)
    cx = np.r_[0, np.cumsum(0.5 * ds * (np.cos(th[1:]) + np.cos(th[:-1])))]
    cy = np.r_[0, np.cumsum(0.5 * ds * (np.sin(th[1:]) + np.sin(th[:-1])))]
    ss, vv = s[sel], v[sel]
    t = theta(ss)
    w = vv * (1.0 if width is None else width(ss))
    along = stretch * np.interp(ss, grid, cx) - w * np.sin(t)
    across = stretch * np.interp(ss, grid, cy) + w * np.cos(t)
    Y = X.copy()
    Y[sel] = root + along[:, None] * d + across[:, None] * n
    return Y
