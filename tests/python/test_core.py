"""Properties of the method (paper Secs. 3-5) checked on the Python surface of bdinterp."""
import numpy as np
import pytest

import bdinterp
from bdinterp_tools import meshes


def edge_lengths(X, F):
    e = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    return np.linalg.norm(X[e[:, 0]] - X[e[:, 1]], axis=1)


def map_sequence(name, levels, n0=150):
    center, radius = meshes.MAP_DOMAIN
    for V, F in meshes.disk_sequence(levels, n0=n0, center=center, radius=radius):
        yield V, F, meshes.apply_map(name, V)


# --------------------------------------------------------------------- reproduction and symmetry

@pytest.mark.parametrize("name", ["phi1", "phi2", "phi3"])
def test_source_and_target_reproduction(disk, name):
    V, F = disk
    T = meshes.apply_map(name, V)
    interp = bdinterp.Interpolator([V, T], F)
    for t, expected in ((0.0, V), (1.0, T)):
        X = interp.at(t)
        assert np.abs(X - expected).max() <= 1e-9 * np.abs(expected).max()


def test_symmetry_under_swapping_source_and_target(disk):
    V, F = disk
    T = meshes.apply_map("phi2", V)
    forward, backward = bdinterp.Interpolator([V, T], F), bdinterp.Interpolator([T, V], F)
    for t in (0.2, 0.5, 0.8):
        a, b = edge_lengths(forward.at(t), F), edge_lengths(backward.at(1 - t), F)
        assert np.abs(a / b - 1).max() < 1e-9


def test_affine_reproduction(disk):
    V, F = disk
    A = np.array([[1.4, 0.7], [-0.2, 0.5]])
    T = V @ A.T + [3.0, -1.0]
    for X in bdinterp.Interpolator([V, T], F).frames([0.1, 0.5, 0.9]):
        M, *_ = np.linalg.lstsq(np.c_[V, np.ones(len(V))], X, rcond=None)
        assert np.abs(np.c_[V, np.ones(len(V))] @ M - X).max() < 1e-9


def test_conformal_reproduction_under_refinement():
    # A Moebius target: the discrete K^_t - 1 must go to 0 as the mesh is refined (first order).
    errors = []
    for V, F, T in map_sequence("mobius", 4, n0=100):
        X = bdinterp.interpolate(V, T, F, 0.5)
        errors.append(np.abs(bdinterp.conformal_distortion(V, X, F) - 1).max())
    ratios = np.array(errors[1:]) / errors[:-1]
    assert np.all(ratios < 0.6), errors  # measured ~0.51 per halving of the edge length
    assert errors[-1] < 0.05


# ------------------------------------------------------------------- bounded distortion (Fig. 3)

def test_pointwise_bounded_and_monotone_distortion_under_refinement():
    # Sec. 4.2: K^_t <= K_1 per face holds in the limit of refinement; the worst violation and the
    # worst decrease of K^_t in t (Fig. 3: monotone graphs) must shrink level by level.
    ts = np.linspace(0, 1, 11)
    excess, decrease = [], []
    for V, F, T in map_sequence("phi3", 3):
        K1 = bdinterp.conformal_distortion(V, T, F)
        K = np.array([bdinterp.conformal_distortion(V, X, F)
                      for X in bdinterp.Interpolator([V, T], F).frames(ts)])
        excess.append((K / K1 - 1).max())
        decrease.append((K[:-1] - K[1:]).max())
    assert excess[-1] < 1e-3 and excess[-1] < 0.1 * excess[0], excess
    assert decrease[-1] < 1e-3 and decrease[-1] < 0.1 * decrease[0], decrease


def test_teichmueller_target_is_bounded_exactly(disk):
    # phi1's metric blends stay within K_1 face by face already on a coarse mesh.
    V, F = disk
    T = meshes.apply_map("phi1", V)
    K1 = bdinterp.conformal_distortion(V, T, F)
    for X in bdinterp.Interpolator([V, T], F).frames(np.linspace(0.05, 0.95, 7)):
        assert np.all(bdinterp.conformal_distortion(V, X, F) <= K1 * (1 + 1e-9))


# ----------------------------------------------------------------------- smoothness (Fig. 5)

def test_smoothness_difference_quotients_converge(disk):
    V, F = disk
    T = meshes.apply_map("phi2", V)
    interp = bdinterp.Interpolator([V, T], F)
    t = 0.4
    X = interp.at(t)
    eps = [1e-1, 1e-2, 1e-3, 1e-4]
    q = [np.linalg.norm(interp.at(t + e) - X) / e for e in eps]
    gaps = np.abs(np.diff(q))
    # First-order convergence: each tenfold smaller step changes the quotient ~10x less.
    assert np.all(gaps[1:] < 0.2 * gaps[:-1]), q
    assert np.isfinite(q[-1]) and q[-1] > 0


# ------------------------------------------------------- squared vs plain lengths (Fig. 6 right)

def test_squared_length_blending_is_invariant_to_triangle_rotation():
    k, t = 0.5, 0.5
    tri = np.array([[0.0, 0.0], [1.0, 0.1], [0.3, 0.8]])
    stretch = np.diag([1 + k, 1 - k])
    K_squared, K_plain = [], []
    for theta in np.linspace(0, np.pi, 13):
        R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
        src = tri @ R.T
        dst = src @ stretch.T
        X = bdinterp.interpolate(src, dst, [[0, 1, 2]], t)
        K_squared.append(bdinterp.conformal_distortion(src, X, [[0, 1, 2]])[0])
        # The alternative: blend plain lengths, build the triangle from them.
        l = (1 - t) * edge_lengths(src, np.array([[0, 1, 2]])) + t * edge_lengths(dst, np.array([[0, 1, 2]]))
        a, b, c = l  # edges (0,1), (0,2), (1,2) from edge_lengths' sorted order
        x = (a * a + b * b - c * c) / (2 * a)
        Y = np.array([[0, 0], [a, 0], [x, np.sqrt(b * b - x * x)]])
        K_plain.append(bdinterp.conformal_distortion(src, Y, [[0, 1, 2]])[0])
    assert np.ptp(K_squared) < 1e-12
    np.testing.assert_allclose(K_squared, np.sqrt(np.linalg.eigvalsh((1 - t) * np.eye(2) + t * stretch @ stretch)[::-1][0]
                                                  / np.linalg.eigvalsh((1 - t) * np.eye(2) + t * stretch @ stretch)[0]))
    assert np.ptp(K_plain) > 1e-2


# ---------------------------------------------------------------------- rotations and anchors

def test_large_rotation_turns_half_way_at_half_time(bar):
    V, F, T = bar
    interp = bdinterp.Interpolator([V, T], F)
    tip = np.argmax(V[:, 0] + V[:, 1])
    root = np.argmin(V[:, 0] + V[:, 1])

    def tip_direction(X):
        # Direction of the bar's far end: the vector between its two tip corners.
        right = V[:, 0] > 4.0 - 1e-9
        top, bottom = np.argmax(np.where(right, V[:, 1], -np.inf)), np.argmin(np.where(right, V[:, 1], np.inf))
        d = X[top] - X[bottom]
        return np.arctan2(d[1], d[0]) - np.pi / 2

    angles = np.unwrap([tip_direction(X) for X in interp.frames(np.linspace(0, 1, 21))])
    assert angles[-1] - angles[0] == pytest.approx(np.radians(250), abs=1e-6)
    assert angles[10] - angles[0] == pytest.approx(np.radians(125), abs=np.radians(10))
    assert np.all(np.diff(angles) > 0)  # turns steadily the long way round, never snaps back
    del tip, root


def test_vertex_anchor_and_anchor_path(bar):
    V, F, T = bar
    v = 17
    X = bdinterp.interpolate(V, T, F, 0.3, anchor=v)
    np.testing.assert_allclose(X[v], 0.7 * V[v] + 0.3 * T[v], atol=1e-12)
    path = bdinterp.AnchorPath(ts=[0, 0.5, 1], positions=[[0, 0], [0, 2], [0, 0]], angles=[0, 0, 0])
    with_path = bdinterp.Interpolator([V, T], F, anchor=path)
    plain = bdinterp.Interpolator([V, T], F)
    np.testing.assert_allclose(with_path.at(0), V, atol=1e-9)
    np.testing.assert_allclose(with_path.at(1), T, atol=1e-9)
    np.testing.assert_allclose(with_path.at(0.5) - plain.at(0.5), np.tile([0, 2], (len(V), 1)), atol=1e-9)


# ---------------------------------------------------------------------- several shapes (Sec. 5)

def test_multi_target_reproduction_bound_and_base_invariance(disk):
    V, F = disk
    shapes = [V, meshes.apply_map("phi1", V), meshes.apply_map("phi3", V)]
    K_in = np.max([bdinterp.conformal_distortion(V, S, F) for S in shapes], axis=0)
    w = np.array([0.2, 0.5, 0.3])
    results = []
    for base in range(3):
        interp = bdinterp.Interpolator(shapes, F, base=base)
        for i, S in enumerate(shapes):
            assert np.abs(interp.blend(np.eye(3)[i]) - S).max() < 1e-9 * np.abs(S).max()
        results.append(interp.blend(w))
    # Invariance to the choice of the base shape (Sec. 5): the same in-between, up to rigid motion.
    for X in results[1:]:
        assert np.abs(edge_lengths(X, F) / edge_lengths(results[0], F) - 1).max() < 1e-9
    assert np.all(bdinterp.conformal_distortion(V, results[0], F) <= K_in * 1.05)
    assert bdinterp.blend(shapes, F, w).shape == V.shape


# --------------------------------------------------------------------- API behaviour

def test_frames_match_single_calls_and_report_statistics(disk):
    V, F = disk
    T = meshes.apply_map("phi2", V)
    interp = bdinterp.Interpolator([V, T], F)
    ts = [0.1, 0.35, 0.6]
    frames = interp.frames(ts)
    assert frames.shape == (3, len(V), 2)
    for t, X in zip(ts, frames):
        np.testing.assert_allclose(bdinterp.interpolate(V, T, F, t), X, atol=1e-9)
    interp.at(0.5)
    stats = interp.stats
    assert stats["residual"] <= 1e-10
    assert 1 <= stats["iterations"] <= 6
    assert stats["broken_triangles"] == 0 and stats["flatness"] < 1e-9


def test_planar_3d_input_in_any_plane(bar):
    V, F, T = bar
    # Embed in a tilted plane: rows of B are orthonormal axes.
    B, _ = np.linalg.qr(np.array([[1.0, 0.2, 0.5], [0.3, -0.4, 1.0], [0.1, 1.0, 0.2]]).T)
    B = B.T[:2]
    origin = np.array([1.0, -2.0, 0.5])
    X3 = bdinterp.interpolate(V @ B + origin, T @ B + origin, F, 0.4)
    X2 = bdinterp.interpolate(V, T, F, 0.4)
    assert X3.shape == (len(V), 3)
    np.testing.assert_allclose(edge_lengths(X3, F), edge_lengths(X2, F), rtol=1e-9)
    normal = np.cross(B[0], B[1])
    assert np.abs((X3 - origin) @ normal).max() < 1e-12
    bent = T @ B + origin
    bent[7] += 0.01 * normal
    with pytest.raises(ValueError, match=r"shape 1, vertex 7: not planar: 0.01 off"):
        bdinterp.interpolate(V @ B + origin, bent, F, 0.4)


def test_several_pieces_get_their_own_anchor():
    V, F = meshes.disk(80, seed=1)
    n = len(V)
    R = np.array([[0.0, -1.0], [1.0, 0.0]])
    V2 = np.vstack([V, V + [5, 0]])
    T2 = np.vstack([V, (V @ R.T) + [5, 0]])  # the second piece turns by 90 degrees
    F2 = np.vstack([F, F + n])
    X = bdinterp.interpolate(V2, T2, F2, 0.5)
    np.testing.assert_allclose(X[:n], V, atol=1e-9)  # the first piece does not move
    c = np.cos(np.pi / 4)
    R45 = np.array([[c, -c], [c, c]])
    second = X[n:] - X[n:].mean(axis=0)
    np.testing.assert_allclose(second, (V - V.mean(axis=0)) @ R45.T, atol=1e-9)


# ------------------------------------------------------------------------------- bad input

def test_invalid_input_raises_value_error_naming_the_culprit(disk):
    V, F = disk
    T = meshes.apply_map("phi1", V)
    cases = [
        (lambda: bdinterp.interpolate(V, T[:-1], F, 0.5), "shape 1: has shape"),
        (lambda: bdinterp.interpolate(V, T, np.vstack([F, [[0, 1, len(V)]]]), 0.5),
         rf"face {len(F)}: a vertex index out of range"),
        (lambda: bdinterp.interpolate(V, T, np.vstack([F, [[4, 4, 5]]]), 0.5), "repeats a vertex"),
        (lambda: bdinterp.interpolate(V, T, F.astype(float), 0.5), "integer"),
        (lambda: bdinterp.interpolate(V, np.where(np.arange(len(V))[:, None] == 9, np.nan, T), F, 0.5),
         "shape 1, vertex 9: a non-finite coordinate"),
        (lambda: bdinterp.interpolate(V, T, F, np.nan), "t must be finite"),
        (lambda: bdinterp.blend([V, T], F, [0.5, 0.6]), "sum to 1"),
        (lambda: bdinterp.interpolate(V, T, F, 0.5, anchor=len(V)), "anchor vertex"),
        (lambda: bdinterp.interpolate(V, T, F, 0.5, method="magic"), "method"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()


def test_topology_errors(disk):
    V, F = disk
    collapsed = V.copy()
    collapsed[F[5, 2]] = collapsed[F[5, 0]]
    # every face holding both vertices collapses; the message names the first (which depends on
    # how this scipy's Delaunay numbered the faces)
    first = min(f for f in range(len(F)) if {F[5, 0], F[5, 2]} <= set(F[f]))
    with pytest.raises(ValueError, match=r"shape 0, face %d: zero area" % first) as info:
        bdinterp.interpolate(collapsed, V, F, 0.5)
    assert (info.value.shape, info.value.face, info.value.vertex) == (0, first, None)
    extra = np.vstack([F, F[:1]])  # a duplicated face makes three faces share its edges
    with pytest.raises(ValueError, match="shared by 3 faces|same direction"):
        bdinterp.interpolate(V, V, extra, 0.5)
    holed = np.delete(F, [len(F) // 2], axis=0)  # remove an interior face: a hole (now supported,
    # tests/python/test_holes.py); two equal shapes give that shape back
    assert np.abs(bdinterp.interpolate(V, V, holed, 0.5) - V).max() <= 1e-9


def test_extrapolation_that_breaks_the_metric_is_a_value_error(disk):
    V, F = disk
    T = V * [3.0, 0.3]
    assert np.isfinite(bdinterp.interpolate(V, T, F, 1.05)).all()
    with pytest.raises(bdinterp.InvalidInputError, match="invalid metric") as info:
        bdinterp.interpolate(V, T, F, -2.0)
    assert 0 <= info.value.face < len(F) and str(info.value) == f"face {info.value.face}: {info.value.detail}"


def test_solver_error_is_a_runtime_error(disk):
    V, F = disk
    T = meshes.apply_map("phi3", V)
    assert issubclass(bdinterp.SolverError, RuntimeError)
    with pytest.raises(bdinterp.SolverError, match="did not converge"):
        bdinterp.Interpolator([V, T], F, max_iterations=1, tol=1e-15).at(0.5)


def test_random_corruptions_never_crash_and_never_return_nan():
    # Fuzz: corrupted indices, extra/missing faces, wild or non-finite targets, collapsed faces and
    # extrapolation. Each call returns finite points or raises ValueError / SolverError.
    rng = np.random.default_rng(7)
    V0, F0 = meshes.disk(60, seed=2)
    outcomes = set()
    for _ in range(400):
        V, F = V0.copy(), F0.copy()
        T = V * rng.uniform(0.3, 3, 2) + rng.normal(0, 0.05, V.shape)
        kind = rng.integers(0, 7)
        if kind == 0:
            F[rng.integers(len(F)), rng.integers(3)] = rng.integers(-3, len(V) + 3)
        elif kind == 1:
            F = np.vstack([F, rng.integers(0, len(V), (rng.integers(1, 4), 3))])
        elif kind == 2:
            F = F[rng.permutation(len(F))[:rng.integers(1, len(F))]]
        elif kind == 3:
            T[rng.integers(len(V))] = rng.normal(0, 10, 2)
        elif kind == 4:
            V[rng.integers(len(V))] = V[rng.integers(len(V))]
        elif kind == 5:
            T[rng.integers(len(V))] = [np.inf, 0]
        t = rng.choice([0.5, -1.0, 2.0, 0.0, 1.0, rng.uniform(-3, 4)])
        try:
            X = bdinterp.interpolate(V, T, F, t)
            assert np.isfinite(X).all()
            outcomes.add("ok")
        except ValueError:
            outcomes.add("ValueError")
        except bdinterp.SolverError:
            outcomes.add("SolverError")
    assert {"ok", "ValueError"} <= outcomes


def test_pieces_without_interior_vertices():
    # A quad split in two has no interior vertex: nothing to flatten, the metric blend is the answer.
    V = np.array([[0, 0], [1, 0], [0, 1], [1, 1.0]])
    F = [[0, 1, 2], [1, 3, 2]]
    X = bdinterp.interpolate(V, V * [3, 1], F, 0.5)
    np.testing.assert_allclose(edge_lengths(X, np.array(F)), edge_lengths(V * [np.sqrt(5), 1], np.array(F)))


def test_parallel_frames_match_sequential_frames(disk):
    V, F = disk
    T = meshes.apply_map("phi2", V)
    ts = np.linspace(0, 1, 17)
    one = bdinterp.Interpolator([V, T], F, threads=1).frames(ts)
    two = bdinterp.Interpolator([V, T], F, threads=2).frames(ts)
    # Different warm starts, same solution to the solver's tolerance.
    assert np.abs(one - two).max() < 1e-8 * np.abs(one).max()
    with pytest.raises(ValueError, match="threads"):
        bdinterp.Interpolator([V, T], F, threads=-1)


def _frame_in_child(V, F, T, queue):
    interp = bdinterp.Interpolator([V, T], F)
    queue.put(float(np.abs(interp.at(0.6)).max()))


# Python 3.12+ warns on any fork of a multi-threaded process: what this test checks is that bdinterp's
# pool survives exactly that.
@pytest.mark.filterwarnings("ignore:This process .* is multi-threaded:DeprecationWarning")
def test_forked_children_can_interpolate_after_the_parent_did():
    # A parent that ran multi-threaded frames, then fork() (multiprocessing's default on Linux): the
    # child must not wait for the parent's threads, which fork() does not copy.
    import multiprocessing
    V, F = meshes.disk(3000)
    T = meshes.apply_map("phi2", V)
    parent = bdinterp.Interpolator([V, T], F)
    expected = np.abs(parent.at(0.6)).max()
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=_frame_in_child, args=(V, F, T, queue))
    child.start()
    child.join(60)
    hung = child.is_alive()
    if hung:
        child.kill()
    assert not hung and child.exitcode == 0
    assert abs(queue.get(timeout=5) - expected) < 1e-8 * expected


def test_flipped_faces_counts_reflected_faces(disk):
    V, F = disk
    mirrored = V * [-1, 1]
    assert bdinterp.flipped_faces(V, V * [2, 1], F) == 0
    assert bdinterp.flipped_faces(V, mirrored, F) == len(F)
    partly = V.copy()
    partly[F[0, 0]] = V[F[0, 1]]  # collapses the faces around that edge
    assert bdinterp.flipped_faces(V, partly, F) >= 1
