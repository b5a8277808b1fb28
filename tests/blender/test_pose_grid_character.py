"""A pose grid shared by several objects is solved as one character in world space: two
overlapping objects stay joined at their pin while a parameter turns one of them, and the shown
meshes are the core's blend of the character."""

import math

import bpy
import numpy as np
import pytest

from conftest import add_key, evaluated_co, grid, mesh_object, read_key, triangles

PIN = np.array([0.9, 0.1, 0.0])  # in world space; a vertex of both objects
UPPER_PIN, LOWER_PIN = 1 * 11 + 9, 1 * 11 + 1  # grid(10, 3): vertex j * 11 + i at (0.1 i, 0.1 j)


def world(obj, co):
    m = np.array(obj.matrix_world)
    return co @ m[:3, :3].T + m[:3, 3]


def bent(co):
    """Turned a quarter about PIN, stretched by half beyond x = 1.2 (world)."""
    x = np.where(co[:, 0] > 1.2, 1.2 + 1.5 * (co[:, 0] - 1.2), co[:, 0]) - PIN[0]
    y = co[:, 1] - PIN[1]
    return np.c_[PIN[0] - y, PIN[1] + x, co[:, 2]]


@pytest.fixture
def arm():
    """Upper [0, 1] x [0, 0.3] still; Lower (moved to x = 0.8) overlaps it in [0.8, 1] and turns."""
    verts, quads = grid(10, 3, 1.0, 0.3)
    upper = mesh_object("Upper", verts, quads)
    lower = mesh_object("Lower", verts, quads)
    lower.location = (0.8, 0.0, 0.0)
    bpy.context.view_layer.update()
    add_key(upper, "Bent", verts)
    add_key(lower, "Bent", bent(world(lower, verts)) - [0.8, 0.0, 0.0])
    return upper, lower


def character_blend(bd, objs, weights):
    """The core's blend of the two objects as one mesh in world space."""
    shapes = [np.concatenate([world(o, read_key(o, n)) for o in objs]) for n in ("Basis", "Bent")]
    n = len(objs[0].data.vertices)
    faces = np.concatenate([triangles(objs[0]), triangles(objs[1]) + n])
    return bd.blend(shapes, faces, weights)


@pytest.mark.parametrize("angle", [30.0, 45.0, 80.0])
def test_two_objects_stay_joined_at_their_pin(addon, bd, arm, angle):
    upper, lower = arm
    addon.pose_grid([upper, lower], {"elbow": [0, 90]}, {0: "Basis", 90: "Bent"}, name="arm")
    upper.bdi_grids["arm"].params["elbow"].amount = angle
    shown = np.concatenate([world(o, evaluated_co(o)) for o in arm])
    s = angle / 90
    want = character_blend(bd, arm, [1 - s, s])
    size = np.linalg.norm(np.ptp(want, axis=0))
    assert np.abs(shown - want).max() <= 1e-6 * size
    n = len(upper.data.vertices)
    assert np.linalg.norm(shown[UPPER_PIN] - shown[n + LOWER_PIN]) <= 1e-6 * size
    # Lower turned by about the angle asked for (its edge along x through the pin)
    edge = shown[n + LOWER_PIN + 5] - shown[n + LOWER_PIN]
    assert math.degrees(math.atan2(edge[1], edge[0])) == pytest.approx(angle, abs=3.0)
    # Solved on its own, Lower would leave the pin: the joint is what holds it
    alone = bd.blend([world(lower, read_key(lower, k)) for k in ("Basis", "Bent")],
                     triangles(lower), [1 - s, s])
    assert np.linalg.norm(alone[LOWER_PIN] - shown[UPPER_PIN]) > 1e-3 * size
    report = addon.pose_grid_report(upper)
    assert set(report) == {"Upper", "Lower"} and report["Lower"].startswith("convex blend")


def test_a_moved_object_is_solved_where_it_now_is(addon, bd, arm):
    upper, lower = arm
    addon.pose_grid([upper, lower], {"elbow": [0, 90]}, {0: "Basis", 90: "Bent"}, name="arm")
    upper.bdi_grids["arm"].params["elbow"].amount = 45.0
    evaluated_co(upper)
    upper.location = (0.0, 0.05, 0.0)  # the pin no longer lines up: a new character
    upper.bdi_grids["arm"].params["elbow"].amount = 60.0
    shown = np.concatenate([world(o, evaluated_co(o)) for o in arm])
    want = character_blend(bd, arm, [1 / 3, 2 / 3])
    assert np.abs(shown - want).max() <= 1e-6 * np.linalg.norm(np.ptp(want, axis=0))
