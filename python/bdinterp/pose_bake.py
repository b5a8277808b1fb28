"""Baking a pose grid for runtimes that blend poses linearly (Live2D, Inochi2D, glTF morph targets).

A runtime blends the poses of its cell linearly in vertex positions, so anything that turns shrinks
in between. Baking in-between poses on a finer grid (n nodes per cell side, each the bounded-
distortion blend there) bounds that: the runtime's multilinear blend of the fine poses stays within
error() of bdinterp's blend (n = 1 is the runtime's blend of the grid's own poses).
"""
import itertools

import numpy as np

from .pose_grid import Parameter, PoseGrid


def fine_values(param, n):
    """The node values of `param` with n - 1 more between each two (the wrap's cell included)."""
    v = list(param.values) + ([param.values[0] + param.period] if param.wrap else [])
    out = [a + (b - a) * k / n for a, b in zip(v[:-1], v[1:]) for k in range(n)]
    return out if param.wrap else out + [v[-1]]


class GridBake:
    """The fine poses of one group of a PoseBlender: grid (a PoseGrid whose keys are the fine
    node indices), shapes {fine index: (n, d) pose}; the other groups stay at rest."""

    def __init__(self, blender, group, n):
        if not isinstance(n, int) or n < 1:
            raise ValueError(f"n (fine nodes per cell side) must be an integer >= 1, got {n!r}")
        by_name = {g.name: g for g in blender.groups}
        if group not in by_name:
            raise ValueError(f"no pose group {group!r} (groups: {sorted(by_name)})")
        self.blender, self.group, self.n = blender, group, n
        coarse = by_name[group]
        params = [Parameter(p.name, fine_values(p, n), wrap=p.wrap, period=p.period)
                  for p in coarse.params]
        indices = list(itertools.product(*(range(p.values.size) for p in params)))
        self.grid = PoseGrid(params, {tuple(p.values[i] for p, i in zip(params, index)): index
                                      for index in indices}, name=group)
        self.shapes = {index: blender.blend({group: self.grid.node_values(index)}).shape
                       for index in indices}

    def linear(self, point):
        """The runtime's blend at `point`: the fine poses' multilinear blend, linear in positions."""
        return sum(w * self.shapes[key] for key, w in self.grid.weights(point).items())

    def error(self, samples=4):
        """(largest distance of a vertex between linear() and bdinterp's blend, relative to the
        size, the point where it is): checked at `samples` points per fine cell side."""
        axes = [fine_values(p, samples) for p in self.grid.params]
        size = float(np.linalg.norm(np.ptp(self.blender.rest_shape, axis=0)))
        worst, where = 0.0, None
        for point in itertools.product(*axes):
            exact = self.blender.blend({self.group: point}).shape
            err = float(np.linalg.norm(self.linear(point) - exact, axis=1).max()) / size
            if err > worst:
                worst, where = err, point
        return worst, where
