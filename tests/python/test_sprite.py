"""mesh_from_image: coverage, quality, topology and a bake of the project's test sprites, and every
bad input's error. Expectations come from the sprites' pixels and from geometry, not from runs."""
import numpy as np
import pytest
from matplotlib.tri import Triangulation
from scipy.spatial import cKDTree

import bdinterp
from bdinterp_tools.sprites import EXPECTED, SPRITES, triangle_angles

pytestmark = pytest.mark.skipif(not getattr(bdinterp._core, "has_sprite_mesher", False),
                                reason="this build has no sprite mesher (no CGAL)")
THRESHOLD, DETAIL, PADDING, MIN_ANGLE = 0.5, 1.0, 1.0, 20.0


@pytest.fixture(scope="module", params=sorted(SPRITES))
def sprite(request):
    image = SPRITES[request.param]()
    return request.param, image, bdinterp.mesh_from_image(image, threshold=THRESHOLD, detail=DETAIL,
                                                          padding=PADDING, min_angle=MIN_ANGLE)


def inside_centres(image):
    """The centres of the pixels at or above the threshold, in the mesh's frame (y up)."""
    h = image.shape[0]
    rows, cols = np.nonzero(image[..., 3] / 255.0 >= THRESHOLD)
    return np.c_[cols + 0.5, h - rows - 0.5]


def edges(F):
    """Unique edges (sorted pairs) and how many faces each borders."""
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def boundary_distance(points, V, F):
    """Distance from each point to the mesh's boundary edges."""
    e, count = edges(F)
    a, b = V[e[count == 1, 0]], V[e[count == 1, 1]]
    ab = b - a
    t = np.clip(((points[:, None, :] - a) * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
    return np.linalg.norm(a + t[..., None] * ab - points[:, None, :], axis=-1).min(axis=1)


def test_coverage(sprite):
    name, image, mesh = sprite
    centres = inside_centres(image)
    tri = Triangulation(mesh.vertices[:, 0], mesh.vertices[:, 1], mesh.faces)
    outside = centres[tri.get_trifinder()(centres[:, 0], centres[:, 1]) < 0]
    # A centre outside the mesh lies within `detail` of it (the simplified outline strays that far).
    if len(outside):
        assert boundary_distance(outside, mesh.vertices, mesh.faces).max() <= DETAIL, name
    # No vertex is farther than padding + detail + 1 pixels from such a centre.
    far = cKDTree(centres).query(mesh.vertices)[0].max()
    assert far <= PADDING + DETAIL + 1, (name, far)


def test_topology_kept(sprite):
    name, _, mesh = sprite
    V, F = mesh.vertices, mesh.faces
    e, count = edges(F)
    assert count.max() <= 2, name  # a manifold
    # Islands: connected components; holes: boundary loops beyond one per island (Euler: V - E + F).
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    n = len(V)
    adjacency = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    islands = connected_components(adjacency, directed=False)[0]
    holes = islands - (n - len(e) + len(F))
    assert (islands, holes) == EXPECTED[name]
    assert (mesh.islands, mesh.holes) == EXPECTED[name]


def test_quality(sprite):
    name, _, mesh = sprite
    V, F = mesh.vertices, mesh.faces
    smallest = triangle_angles(V, F).min(axis=1)
    assert (smallest < MIN_ANGLE - 1e-6).mean() <= 0.01, (name, np.sort(smallest)[:5])
    assert smallest.min() >= MIN_ANGLE / 2, (name, smallest.min())
    e, count = edges(F)
    interior = e[count == 2]
    assert np.linalg.norm(V[interior[:, 0]] - V[interior[:, 1]], axis=1).max() <= mesh.spacing * (1 + 1e-9)
    # The outline's vertices: those on the mesh's boundary (the outline split to the spacing).
    boundary = len(np.unique(e[count == 1]))
    assert len(V) <= 3 * mesh.area / (0.866 * mesh.spacing ** 2) + boundary, name


def test_frame_uvs_and_orientation(sprite):
    name, image, mesh = sprite
    h, w = image.shape[:2]
    P = mesh.vertices[mesh.faces]
    signed = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    assert signed.min() > 0, name  # counter-clockwise, nothing degenerate
    np.testing.assert_allclose(mesh.uvs, mesh.vertices / [w, h])
    assert mesh.area == pytest.approx(signed.sum() / 2)
    assert mesh.size == (w, h)


def test_y_up_and_default_spacing():
    # A square in the image's top-left corner: its vertices are high up (y up) and on the left; the
    # outline of hard pixels at threshold 0.5 runs halfway between centres: on the pixels' edges.
    image = np.zeros((100, 200), np.float32)
    image[10:40, 20:80] = 1.0
    mesh = bdinterp.mesh_from_image(image, padding=0.0, detail=0.25)
    lo, hi = mesh.vertices.min(0), mesh.vertices.max(0)
    np.testing.assert_allclose([lo[0], hi[0], lo[1], hi[1]], [20, 80, 60, 90], atol=1e-6)
    assert mesh.spacing == pytest.approx(60 / 12)  # a twelfth of the larger side of the sprite
    coarse = bdinterp.mesh_from_image(image, padding=0.0, detail=0.25, spacing_divisions=4)
    assert coarse.spacing == pytest.approx(60 / 4) and len(coarse.faces) < len(mesh.faces)
    assert bdinterp.mesh_from_image(image, padding=0.0, spacing=7.0).spacing == 7.0


def test_options_are_the_cores_with_its_defaults():
    """One definition of the options: the C++ struct's, defaults included (docs/SPRITES.md)."""
    o = bdinterp.SpriteMeshOptions()
    assert (o.threshold, o.spacing, o.spacing_divisions, o.detail, o.padding, o.min_angle,
            o.min_area) == (0.5, 0.0, 12.0, 1.0, 1.0, 20.0, 4.0)


def test_ring_area_analytic():
    # Sub-pixel tracing: the ring's mesh area is pi (R^2 - r^2) (antialiased alpha, no padding).
    image = SPRITES["ring"](256)
    mesh = bdinterp.mesh_from_image(image, padding=0.0, detail=0.1)
    assert mesh.area == pytest.approx(np.pi * (102.4 ** 2 - 51.2 ** 2), rel=2e-3)


def test_small_islands_and_holes_dropped():
    image = np.zeros((64, 64), np.float32)
    image[10:50, 10:50] = 1.0
    image[20:21, 20:21] = 0.0  # a one-pixel hole
    image[56:58, 56:58] = 1.0  # a 2 x 2 speck
    mesh = bdinterp.mesh_from_image(image, padding=0.0, min_area=6.0)
    assert (mesh.islands, mesh.holes, mesh.dropped_islands, mesh.dropped_holes) == (1, 0, 1, 1)
    kept = bdinterp.mesh_from_image(image, padding=0.0, min_area=0.1)
    assert (kept.islands, kept.holes) == (2, 1)


def test_png_path(tmp_path):
    from PIL import Image
    Image.fromarray(SPRITES["ring"]()).save(tmp_path / "ring.png")
    a = bdinterp.mesh_from_image(tmp_path / "ring.png")
    b = bdinterp.mesh_from_image(SPRITES["ring"]())
    np.testing.assert_array_equal(a.faces, b.faces)
    np.testing.assert_allclose(a.vertices, b.vertices)


def test_bent_sprite_bakes_within_target_distortion():
    # The line sprite bent into an arc (a conformal-ish bend with a stretch): every in-between's K
    # stays within the target's (bounded distortion, the method's guarantee).
    mesh = bdinterp.mesh_from_image(SPRITES["soft_blob"](), spacing=8.0)
    V, F = mesh.vertices, mesh.faces
    x = V[:, 0] - V[:, 0].min()
    radius = 120.0
    a, r = x / radius, radius - (V[:, 1] - V[:, 1].mean())
    T = np.c_[r * np.sin(a), 1.2 * (radius - r * np.cos(a))]
    target_k = bdinterp.conformal_distortion(V, T, F).max()
    interp = bdinterp.Interpolator([V, T], F)
    for t in np.linspace(0.1, 0.9, 5):
        X = interp.at(t)
        assert bdinterp.flipped_faces(V, X, F) == 0
        assert bdinterp.conformal_distortion(V, X, F).max() <= target_k * (1 + 1e-6), t


@pytest.mark.parametrize("image, kwargs, message", [
    (np.zeros((32, 32), np.float32), {}, "no pixel has alpha"),
    (np.ones((1, 1), np.float32), {}, "1x1 pixels"),
    (np.full((8, 8), np.nan, np.float32), {}, "is NaN"),
    (np.ones((8, 8), np.float32), {"threshold": 0.0}, "threshold must lie in"),
    (np.ones((8, 8), np.float32), {"threshold": 1.5}, "threshold must lie in"),
    (np.ones((8, 8), np.float32), {"spacing": -2.0}, "spacing must be a positive"),
    (np.ones((8, 8), np.float32), {"min_angle": 40.0}, "min_angle must lie in"),
    (np.ones((8, 8), np.float32), {"spacing_divisions": 0.5}, "spacing_divisions must be >= 1"),
    (np.ones((8, 8), np.float32), {"spacng": 3.0}, "unknown option spacng"),
    (np.ones((8, 8), np.float32), {"threshold": "high"}, "threshold must be a number"),
    (np.ones((8, 8, 3), np.float32), {}, "shape (8, 8, 3)"),
])
def test_bad_input(image, kwargs, message):
    with pytest.raises(bdinterp.InvalidInputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        bdinterp.mesh_from_image(image, **kwargs)


def test_bad_files(tmp_path):
    text = tmp_path / "notes.png"
    text.write_text("not a picture")
    with pytest.raises(bdinterp.InvalidInputError, match="notes.png.*is not an image"):
        bdinterp.mesh_from_image(text)
    with pytest.raises(bdinterp.InvalidInputError, match="no image file"):
        bdinterp.mesh_from_image(tmp_path / "missing.png")
