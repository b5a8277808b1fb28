"""Measured claims on the example inputs (examples/) and the mesh generators.

Every number asserted here is a property the paper claims for the method
(Secs. 3.1, 4.2, 4.3, 6.3); the baselines are run for contrast.
"""

import functools
import pathlib

import numpy as np
import pytest

import bdinterp
from bdinterp import figures, io
from bdinterp_tools import convergence, meshes

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"
NAMES = ["bar_half_bent", "spiral", "affine", "conformal", "teichmuller",
         "folded", "character", "letter_8", "letter_e", "body_tail"]
TS = np.linspace(0.0, 1.0, 11)

# Discrete bounded distortion holds only up to the discretisation error of
# the discrete conformal map (paper Sec. 4.2: bounded "in the limit of
# refinement"; Fig. 6 / test_convergence_rates: the error is O(h)).  On
# these meshes the pointwise excess K^_t(f) / K(f) - 1 measures <= 3e-4;
# 1% leaves room for other platforms and solver tolerances while the
# baselines exceed the bound by 2% (linear, bar_half_bent) to 10^5 %.
BOUND_TOL = 1e-2


@functools.lru_cache(maxsize=None)
def load(name):
    return io.read_pair(EXAMPLES / name / "source.obj",
                        EXAMPLES / name / "target.obj")


@functools.lru_cache(maxsize=None)
def swept(name):
    X0, X1, F = load(name)
    return figures.sweep(X0, X1, F, TS)


@pytest.mark.parametrize("name", NAMES)
def test_example_files_are_consistent(name):
    X0, X1, F = load(name)
    assert X0.shape == X1.shape and X0.shape[1] == 2
    assert len(X0) <= 3000, "examples stay small so the tests stay fast"
    assert np.all(meshes.signed_areas(X0, F) > 0), "source must be CCW"
    flipped = np.count_nonzero(meshes.signed_areas(X1, F) <= 0)
    if name == "folded":
        assert 8 <= flipped <= 14  # "about 10 folded triangles" (Fig. 10)
    else:
        assert flipped == 0


@pytest.mark.parametrize("name", [n for n in NAMES if n != "folded"])
def test_bdi_distortion_bounded_by_input(name):
    X0, X1, F = load(name)
    K_in = bdinterp.conformal_distortion(X0, X1, F)
    K = swept(name)["bdi"]["K"]
    assert np.max(K) <= np.max(K_in) * (1 + BOUND_TOL)
    # The paper's claim is pointwise: every face, every t.
    assert np.max(K / K_in) <= 1 + BOUND_TOL


@pytest.mark.parametrize("name", [n for n in NAMES if n != "folded"])
def test_bdi_never_flips(name):
    assert np.all(swept(name)["bdi"]["flipped"] == 0)


def test_spiral_baseline_folds_where_bdi_does_not():
    r = swept("spiral")
    baseline_flips = max(r["arap"]["flipped"].max(),
                         r["linear"]["flipped"].max())
    assert baseline_flips > 0
    assert np.all(r["bdi"]["flipped"] == 0)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("method", bdinterp.METHODS)
def test_reproduces_source_and_target(name, method):
    X0, X1, F = load(name)
    frames = swept(name)[method]["frames"]
    scale = np.ptp(X1, axis=0).max()
    np.testing.assert_allclose(frames[0], X0, atol=1e-8 * scale)
    # Folded targets too: the fold region is cut out and filled (docs/FOLDS.md).
    np.testing.assert_allclose(frames[-1], X1, atol=1e-8 * scale)


def test_affine_target_gives_affine_frames():
    # Sec. 3.1 affine reproduction: a constant metric is flat, so every
    # frame is affine with K_t = sqrt(cond((1-t) I + t A^T A)).
    X0, X1, F = load("affine")
    A = np.linalg.lstsq(np.c_[X0, np.ones(len(X0))], X1, rcond=None)[0][:2].T
    r = swept("affine")["bdi"]
    for t, K in zip(TS, r["K"]):
        lam = np.linalg.eigvalsh((1 - t) * np.eye(2) + t * A.T @ A)
        np.testing.assert_allclose(K, np.sqrt(lam[1] / lam[0]), rtol=1e-8)


def test_conformal_target_gives_conformal_frames():
    # K = 1 maps blend to K = 1 maps (up to the input's own discretisation:
    # the target's straight-edged triangles give K <= 1.14 already).
    X0, X1, F = load("conformal")
    K_in = bdinterp.conformal_distortion(X0, X1, F)
    K = swept("conformal")["bdi"]["K"]
    assert np.max(K) <= np.max(K_in) * (1 + BOUND_TOL)
    assert np.max(K[len(TS) // 2]) < np.max(K_in)


def test_bar_left_half_stays_rigid():
    # Fig. 11 local support: the part one bar width away from the bend
    # (x < 3; the bend starts at x = 4) moves rigidly.  The conformal factor
    # decays like exp(-pi d / width) away from the curved part; measured
    # residual 1.5e-5 of the bar width, asserted 1e-3.
    X0, X1, F = load("bar_half_bent")
    left = X0[:, 0] < 3.0
    for X in swept("bar_half_bent")["bdi"]["frames"]:
        a = X0[left] - X0[left].mean(axis=0)
        b = X[left] - X[left].mean(axis=0)
        u, _, vt = np.linalg.svd(a.T @ b)
        assert np.max(np.abs(a @ (u @ vt) - b)) < 1e-3


def test_convergence_rates():
    # Fig. 6 left: discrete distortion -> continuous under refinement.  The
    # edge length halves per level; measured E2 ratio ~0.25 (O(h^2)) and
    # Einf ratio ~0.5 (O(h)); asserted with margin.
    d = convergence.convergence(levels=3, n0=100, ts=(0.25, 0.75))
    assert np.all(np.diff(d["vertices"]) > 0)
    assert np.all(d["E2"][..., 1:] / d["E2"][..., :-1] < 0.4)
    assert np.all(d["Einf"][..., 1:] / d["Einf"][..., :-1] < 0.7)


# ------------------------------------------------------- mesh generators

@pytest.mark.parametrize("make", [
    lambda s: meshes.disk(300, s),
    lambda s: meshes.rectangle(3.0, 1.0, 300, s),
    lambda s: meshes.disk(300, s, center=(1.0, 1.0), radius=0.5),
])
def test_generators_deterministic_ccw_and_sized(make):
    V, F = make(5)
    V2, F2 = make(5)
    assert np.array_equal(V, V2) and np.array_equal(F, F2)
    assert V.dtype == np.float64 and V.shape[1] == 2
    assert F.dtype == np.int32 and F.shape[1] == 3
    assert np.all(meshes.signed_areas(V, F) > 0)
    assert np.array_equal(np.unique(F), np.arange(len(V)))
    assert 200 <= len(V) <= 450
    assert not np.array_equal(make(6)[0], V)


def test_disk_sequence_halves_edges():
    seq = meshes.disk_sequence(3, 80, seed=1, center=(1.0, 1.0), radius=1.0)

    def edge_lengths(V, F):
        e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
        return np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1)

    for (V, F), (V2, F2) in zip(seq, seq[1:]):
        assert len(F2) == 4 * len(F)
        assert np.all(meshes.signed_areas(V2, F2) > 0)
        ratio = edge_lengths(V2, F2).max() / edge_lengths(V, F).max()
        assert 0.45 < ratio < 0.55
        on_circle = np.unique(meshes.boundary_edges(F2))
        np.testing.assert_allclose(
            np.linalg.norm(V2[on_circle] - 1.0, axis=1), 1.0)


@pytest.mark.parametrize("name", sorted(meshes.MAPS))
def test_map_jacobian_and_distortion(name):
    center, radius = meshes.MAP_DOMAIN
    X = meshes.disk(100, 0, center=center, radius=radius)[0]
    eps = 1e-6
    f = functools.partial(meshes.apply_map, name)
    fd = np.stack([f(X + d) - f(X - d) for d in ([eps, 0.0], [0.0, eps])],
                  axis=2) / (2 * eps)
    np.testing.assert_allclose(meshes.map_jacobian(name, X), fd, atol=1e-6)
    # Teichmueller maps alpha m + beta conj(m) have constant
    # K = (|alpha| + |beta|) / (|alpha| - |beta|) at t = 1, and K_0 = 1.
    alpha, beta = meshes.MAPS[name][:2]
    np.testing.assert_allclose(meshes.blended_distortion(name, X, 1.0),
                               (alpha + beta) / (alpha - beta))
    np.testing.assert_allclose(meshes.blended_distortion(name, X, 0.0), 1.0)
