"""Shared fixtures: the test meshes come from bdinterp_tools.meshes (jittered Delaunay, never
grid-aligned). tools/ (the repository's non-installed helpers) is put on the path here."""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))

from bdinterp_tools import meshes  # noqa: E402


@pytest.fixture(scope="package")
def disk():
    """(V, F): a jittered Delaunay disk of ~400 vertices on the analytic maps' domain."""
    center, radius = meshes.MAP_DOMAIN
    return meshes.disk(400, seed=3, center=center, radius=radius)


@pytest.fixture(scope="package")
def bar():
    """(V, F, T): a 4 x 0.5 bar and its bend by 250 degrees (the tip turns past 180)."""
    V, F = meshes.rectangle(4.0, 0.5, 600, seed=2)
    angle = np.radians(250)
    radius = 4.0 / angle
    a = V[:, 0] / radius
    r = radius - (V[:, 1] - 0.25)
    T = np.c_[r * np.sin(a), radius - r * np.cos(a)]
    return V, F, T
