"""Measurements and figures behind the CLI and the gallery.

The measuring functions (:func:`sweep`, :func:`top_distortion`,
:func:`convergence`) return numpy arrays and do not plot; the figure
functions take their results and return a matplotlib Figure (Agg backend,
nothing is shown).  Distortion is the per-face conformal distortion
K = sigma_max / sigma_min of the map source -> frame.
"""

import sys

import numpy as np

import bdinterp
from bdinterp import meshes

METHODS = ("bdi", "arap", "linear")
LABELS = {"bdi": "BDI (bounded distortion)", "arap": "ARAP (Alexa 2000)",
          "linear": "linear blend"}
COLORS = {"bdi": "tab:blue", "arap": "tab:orange", "linear": "tab:green"}


class Progress:
    """Plain-text progress bar on stderr: ``label [#####.....] 5/10``.

    enabled=None: only when the stream is a terminal (no carriage-return
    clutter in logs and captured output).
    """

    def __init__(self, total, label, stream=None, enabled=None):
        self.total, self.label, self.done = max(1, total), label, 0
        self.stream = sys.stderr if stream is None else stream
        if enabled is None:
            enabled = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.enabled = enabled

    def step(self, n=1):
        self.done = min(self.total, self.done + n)
        if not self.enabled:
            return
        filled = 30 * self.done // self.total
        end = "\n" if self.done == self.total else ""
        bar = "#" * filled + "." * (30 - filled)
        self.stream.write(f"\r{self.label} [{bar}] {self.done}/{self.total}"
                          f"{end}")
        self.stream.flush()


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def to_plane(X, F):
    """2D coordinates (n,2) of a planar shape X (n,2 or n,3).

    3D shapes are projected onto their best-fit plane, with the in-plane
    axes chosen so that the mesh F has positive total area (plots and
    distortion are then as seen from the side the faces point to).
    """
    X = np.asarray(X, dtype=np.float64)
    if X.shape[1] == 2:
        return X
    c = X - X.mean(axis=0)
    basis = np.linalg.svd(c, full_matrices=False)[2][:2]
    Y = c @ basis.T
    if meshes.signed_areas(Y, F).sum() < 0:
        Y[:, 1] = -Y[:, 1]
    return Y


def sweep(source, target, faces, ts, methods=METHODS, anchor=None,
          progress=None):
    """Interpolate at every t in ts with each method and measure.

    Returns dict method -> dict with
      ``frames`` (k,n,d), ``K`` (k,m) per-face distortion w.r.t. source,
      ``flipped`` (k,) faces with area ratio <= 0 (flipped or collapsed),
      ``iterations`` (k,) Newton iterations (bdi only; -1 for baselines).
    ``progress``: optional :class:`Progress`, stepped once per frame.
    """
    ts = np.asarray(ts, dtype=np.float64)
    out = {}
    for method in methods:
        frames, iters = [], []
        if method == "bdi":
            interp = bdinterp.Interpolator([source, target], faces,
                                           anchor=anchor)
        for t in ts:
            if method == "bdi":
                frames.append(interp.at(t))
                iters.append(interp.stats.get("iterations", -1))
            else:
                frames.append(bdinterp.interpolate(source, target, faces, t,
                                                   anchor=anchor,
                                                   method=method))
                iters.append(-1)
            if progress is not None:
                progress.step()
        frames = np.stack(frames)
        out[method] = {
            "frames": frames,
            "K": np.stack([bdinterp.conformal_distortion(source, X, faces)
                           for X in frames]),
            "flipped": np.array([np.count_nonzero(
                bdinterp.area_ratio(source, X, faces) <= 0) for X in frames]),
            "iterations": np.array(iters),
        }
    return out


def normalized_distortion(K):
    """Map K in [1, inf] to [0, 1]: (K - 1) / (K + 1), the modulus of the
    Beltrami coefficient, so curves of different methods share one scale."""
    K = np.asarray(K, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(K), 1.0, (K - 1.0) / (K + 1.0))


def top_distortion(K, n=100):
    """(k, min(n, m)) normalised distortion of the n most distorted faces
    at each t (found separately per t, as in Fig. 13), largest first."""
    K = np.asarray(K, dtype=np.float64)
    n = min(n, K.shape[1])
    return -np.sort(-normalized_distortion(K), axis=1)[:, :n]


def convergence(maps=("phi1", "phi2", "phi3"), ts=(0.25, 0.5, 0.75),
                levels=4, n0=100, seed=0, progress=None):
    """Discrete vs continuous distortion under refinement (Fig. 6 left).

    On a refinement sequence of disk meshes (meshes.disk_sequence over
    meshes.MAP_DOMAIN) with target = map(source), compare the BDI frame's
    per-face distortion K^_t(f) with the continuous K_t at the face
    barycentre (meshes.blended_distortion).  Paper eq. (2):
      E2   = sum_f A_f |K_t(f) - K^_t(f)|^2 / sum_f A_f  (A_f: area in frame),
      Einf = max_f |K_t(f) - K^_t(f)|.
    Returns dict with ``vertices`` (levels,), and ``E2``, ``Einf`` arrays
    (len(maps), len(ts), levels).
    """
    center, radius = meshes.MAP_DOMAIN
    seq = meshes.disk_sequence(levels, n0, seed, center=center, radius=radius)
    E2 = np.zeros((len(maps), len(ts), levels))
    Einf = np.zeros_like(E2)
    for i, name in enumerate(maps):
        for j, (V, F) in enumerate(seq):
            interp = bdinterp.Interpolator([V, meshes.apply_map(name, V)], F)
            bary = V[F].mean(axis=1)
            for k, t in enumerate(ts):
                X = interp.at(t)
                err = (meshes.blended_distortion(name, bary, t)
                       - bdinterp.conformal_distortion(V, X, F))
                area = np.abs(meshes.signed_areas(X, F))
                E2[i, k, j] = np.sum(area * err ** 2) / np.sum(area)
                Einf[i, k, j] = np.max(np.abs(err))
                if progress is not None:
                    progress.step()
    return {"maps": tuple(maps), "ts": tuple(ts),
            "vertices": np.array([len(V) for V, _ in seq]),
            "E2": E2, "Einf": Einf}


# ---------------------------------------------------------------- figures

def draw_mesh(ax, X, F, values=None, norm=None, cmap="viridis",
              flipped=None, title=None):
    """Draw mesh X (n,2) F (m,3) on ax, faces coloured by values (m,);
    faces in the boolean mask ``flipped`` are drawn red.  Returns the
    collection for a colour bar (or None)."""
    X = to_plane(X, F)
    coll = None
    edge = dict(edgecolors="k", linewidth=0.1) if len(F) < 2500 else {}
    if values is None and len(F) >= 2500:  # edges would paint it grey
        ax.tripcolor(X[:, 0], X[:, 1], F, facecolors=np.zeros(len(F)),
                     cmap="Greys", vmin=-1, vmax=3)
    elif values is None:
        ax.triplot(X[:, 0], X[:, 1], F, color="0.6", linewidth=0.2)
    else:
        v = np.where(np.isfinite(values), values, np.nanmax(
            np.where(np.isfinite(values), values, np.nan)))
        coll = ax.tripcolor(X[:, 0], X[:, 1], F, facecolors=v, norm=norm,
                            cmap=cmap, **edge)
    if flipped is not None and np.any(flipped):
        ax.tripcolor(X[:, 0], X[:, 1], F[flipped],
                     facecolors=np.zeros(np.count_nonzero(flipped)),
                     cmap="autumn", vmin=0, vmax=1)  # autumn(0) = red
    ax.set_aspect("equal")
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=9)
    return coll


def _plain_ticks(axis, vmax):
    # Log colour bars label minor ticks as 2x10^0 ...; plain numbers read
    # better, but over more than a decade the minor labels collide.
    from matplotlib.ticker import FormatStrFormatter, NullFormatter
    axis.set_major_formatter(FormatStrFormatter("%g"))
    axis.set_minor_formatter(FormatStrFormatter("%g") if vmax <= 10
                             else NullFormatter())


def _k_norm(kmax):
    from matplotlib.colors import LogNorm
    return LogNorm(vmin=1.0, vmax=max(float(kmax), 1.01))


def compare_figure(source, target, faces, t, ts, result, top=100):
    """Fig. 13 style: source, each method at t, target, coloured by K, and
    below, the normalised distortion of the ``top`` most distorted faces vs
    t.  The colour scale ends at twice the target's largest K (bounded
    distortion stays well inside it; larger values saturate).

    result: the dict from :func:`sweep` over ts (t must be one of ts).
    """
    plt = _pyplot()
    ts = np.asarray(ts)
    i = int(np.argmin(np.abs(ts - t)))
    methods = list(result)
    K_in = bdinterp.conformal_distortion(source, target, faces)
    norm = _k_norm(2.0 * np.max(K_in[np.isfinite(K_in)], initial=1.0))
    n = len(methods) + 2
    fig = plt.figure(figsize=(3.0 * n, 6.6))
    grid = fig.add_gridspec(2, n, height_ratios=[1.1, 1])
    axes = [fig.add_subplot(grid[0, c]) for c in range(n)]
    draw_mesh(axes[0], source, faces, np.ones(len(faces)), norm,
              title="source")
    for ax, m in zip(axes[1:], methods):
        r = result[m]
        draw_mesh(ax, r["frames"][i], faces, r["K"][i], norm,
                  flipped=bdinterp.area_ratio(source, r["frames"][i],
                                              faces) <= 0,
                  title=f"{m}, t={ts[i]:g}\nmax K {np.max(r['K'][i]):.3g}, "
                        f"{r['flipped'][i]} flipped")
    coll = draw_mesh(axes[-1], target, faces, K_in, norm,
                     flipped=bdinterp.area_ratio(source, target, faces) <= 0,
                     title=f"target\nmax K {np.max(K_in):.3g}")
    bar = fig.colorbar(coll, ax=axes, shrink=0.7, extend="max",
                       label="K (flipped: red)")
    _plain_ticks(bar.ax.yaxis, norm.vmax)
    ax = fig.add_subplot(grid[1, 1:n - 1])
    for m in methods:
        curve = top_distortion(result[m]["K"], top)
        ax.plot(ts, curve.mean(axis=1), color=COLORS.get(m), label=LABELS[m])
        ax.plot(ts, curve[:, 0], "--", color=COLORS.get(m), linewidth=0.8)
    ax.set_xlabel("t")
    ax.set_ylabel("(K-1)/(K+1)")
    ax.set_ylim(0, 1)
    ax.set_title(f"normalised distortion of the {top} most distorted faces "
                 f"(solid: mean, dashed: max)", fontsize=9)
    ax.legend(fontsize=8)
    return fig


def distortion_curves_figure(source, target, faces, ts, frames, K, sample,
                             n_frames=3):
    """Fig. 3 style: K(t) of a sample of faces, each line in its face's
    colour; the mesh panels show source, frames and target with the sample
    faces coloured.

    frames (k,n,d) and K (k,m) over ts (from :func:`sweep`); sample: face
    indices.
    """
    plt = _pyplot()
    ts = np.asarray(ts)
    sample = np.asarray(sample)
    colors = plt.get_cmap("tab20")(np.arange(len(sample)) % 20)
    picks = np.linspace(0, len(ts) - 1, n_frames + 2).round().astype(int)
    shapes = ([(source, "source")]
              + [(frames[p], f"t={ts[p]:g}") for p in picks[1:-1]]
              + [(target, "target")])
    fig = plt.figure(figsize=(3.0 * len(shapes), 6.4))
    grid = fig.add_gridspec(2, len(shapes), height_ratios=[1, 1.2])
    for c, (X, title) in enumerate(shapes):
        ax = fig.add_subplot(grid[0, c])
        draw_mesh(ax, X, faces, title=title)
        Y = to_plane(X, faces)
        ax.tripcolor(Y[:, 0], Y[:, 1], faces[sample],
                     facecolors=np.arange(len(sample)) % 20, cmap="tab20",
                     vmin=0, vmax=19)
        # Single faces of a fine mesh are invisible: ring them too.
        c = Y[faces[sample]].mean(axis=1)
        ax.scatter(c[:, 0], c[:, 1], s=40, facecolors="none",
                   edgecolors=colors, linewidths=1.5)
    ax = fig.add_subplot(grid[1, :])
    for j, f in enumerate(sample):
        ax.plot(ts, K[:, f], color=colors[j], linewidth=1.2)
    ax.set_xlabel("t")
    ax.set_ylabel("K of the face")
    ax.set_title(f"conformal distortion of {len(sample)} faces vs t "
                 f"(bounded by the value at t = 1)", fontsize=9)
    return fig


def convergence_figure(data):
    """Fig. 6 left: E2 and Einf vs vertex count, one line per (map, t)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    styles = ["-", "--", ":", "-."]
    for ax, key in zip(axes, ("E2", "Einf")):
        for i, name in enumerate(data["maps"]):
            for k, t in enumerate(data["ts"]):
                ax.loglog(data["vertices"], data[key][i, k],
                          styles[k % len(styles)], marker="o", markersize=3,
                          color=f"C{i}", label=f"{name}, t={t:g}")
        ax.set_xlabel("vertices")
        ax.set_title(key)
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, ncol=len(data["maps"]))
    fig.tight_layout()
    return fig


def pick_faces(K, n):
    """Indices of n faces whose K values (m,) are spread evenly between the
    smallest and largest, so a Fig. 3 plot shows low, medium and high
    distortion alike (ranks would mostly pick the many K ~ 1 faces)."""
    K = np.asarray(K, dtype=np.float64)
    finite = np.flatnonzero(np.isfinite(K))
    order = finite[np.argsort(K[finite], kind="stable")]
    targets = np.linspace(K[order[0]], K[order[-1]], min(n, len(order)))
    pos = np.clip(np.searchsorted(K[order], targets), 0, len(order) - 1)
    return np.unique(order[pos])
