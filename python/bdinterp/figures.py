"""The measurements and figures behind the CLI's compare and plot-distortion commands.

The measuring functions (:func:`sweep`, :func:`top_distortion`, :func:`pick_faces`) return numpy
arrays; the figure functions take their results and return a matplotlib Figure (Agg backend, nothing
is shown). matplotlib is imported only when a figure is drawn (the optional extra
``bdinterp[plots]``); without it a clear ImportError says so. Distortion is the per-face conformal
distortion K = sigma_max / sigma_min of the map source -> frame.
"""

import os

import numpy as np

import bdinterp
from bdinterp.constants import METHOD_LABELS, METHODS
from bdinterp.plane import Plane

COLORS = {"bdi": "tab:blue", "arap": "tab:orange", "linear": "tab:green"}


def pyplot():
    """matplotlib.pyplot with the Agg backend; ImportError with the fix if matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("this command draws figures and needs matplotlib, which is not installed "
                          "(Debian: apt-get install python3-matplotlib)") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(fig, path, dpi=120):
    """Writes fig to path (format from the extension; folders created) and closes it."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    pyplot().close(fig)
    print(f"wrote {path}")


def to_plane(X, F, plane=None):
    """2D coordinates (n, 2) of a planar shape X ((n, 2) or (n, 3)). 3D shapes: in `plane` (give the
    source's, view_plane(), so that every panel of a figure is seen in one frame), or else in their
    own plane seen from the side the faces F point to."""
    X = np.asarray(X, dtype=np.float64)
    if X.shape[1] == 2:
        return X
    return (plane or Plane.fit(X, F)).to_plane(X, "shape", tolerance=np.inf)


def view_plane(source, F):
    """The frame in which a figure shows every shape: the source's plane facing its faces (3D), or
    None (2D)."""
    source = np.asarray(source)
    return Plane.fit(source, F) if source.shape[1] == 3 else None


def sweep(source, target, faces, ts, methods=METHODS, anchor=None, progress=None):
    """Frames at every t in ts with each method (bdinterp.frames) and their measurements.

    Returns dict method -> dict with
      ``frames`` (k,n,d), ``K`` (k,m) per-face distortion w.r.t. source,
      ``flipped`` (k,) faces with area ratio <= 0 (flipped or collapsed),
      ``iterations`` the most Newton iterations of a frame (bdi only; -1 for baselines).
    ``progress``: optional object with step(n), stepped by len(ts) per method.
    """
    ts = np.asarray(ts, dtype=np.float64)
    out = {}
    for method in methods:
        iterations = -1
        if method == "bdi":
            interp = bdinterp.Interpolator([source, target], faces, anchor=anchor)
            frames = interp.frames(ts)
            iterations = interp.stats.iterations
        else:
            frames = bdinterp.frames(source, target, faces, ts, method=method)
        if progress is not None:
            progress.step(len(ts))
        out[method] = {
            "frames": frames,
            "K": np.stack([bdinterp.conformal_distortion(source, X, faces) for X in frames]),
            "flipped": np.array([bdinterp.flipped_faces(source, X, faces) for X in frames]),
            "iterations": iterations,
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


# ---------------------------------------------------------------- figures

def draw_mesh(ax, X, F, values=None, norm=None, cmap="viridis",
              flipped=None, title=None, plane=None):
    """Draw mesh X (n,2) F (m,3) on ax, faces coloured by values (m,);
    faces in the boolean mask ``flipped`` are drawn red.  Returns the
    collection for a colour bar (or None)."""
    X = to_plane(X, F, plane)
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
    plt = pyplot()
    ts = np.asarray(ts)
    i = int(np.argmin(np.abs(ts - t)))
    methods = list(result)
    K_in = bdinterp.conformal_distortion(source, target, faces)
    norm = _k_norm(2.0 * np.max(K_in[np.isfinite(K_in)], initial=1.0))
    n = len(methods) + 2
    fig = plt.figure(figsize=(3.0 * n, 6.6))
    grid = fig.add_gridspec(2, n, height_ratios=[1.1, 1])
    axes = [fig.add_subplot(grid[0, c]) for c in range(n)]
    plane = view_plane(source, faces)
    draw_mesh(axes[0], source, faces, np.ones(len(faces)), norm,
              title="source", plane=plane)
    for ax, m in zip(axes[1:], methods):
        r = result[m]
        draw_mesh(ax, r["frames"][i], faces, r["K"][i], norm,
                  flipped=bdinterp.area_ratio(source, r["frames"][i],
                                              faces) <= 0,
                  title=f"{m}, t={ts[i]:g}\nmax K {np.max(r['K'][i]):.3g}, "
                        f"{r['flipped'][i]} flipped", plane=plane)
    coll = draw_mesh(axes[-1], target, faces, K_in, norm,
                     flipped=bdinterp.area_ratio(source, target, faces) <= 0,
                     title=f"target\nmax K {np.max(K_in):.3g}", plane=plane)
    bar = fig.colorbar(coll, ax=axes, shrink=0.7, extend="max",
                       label="K (flipped: red)")
    _plain_ticks(bar.ax.yaxis, norm.vmax)
    ax = fig.add_subplot(grid[1, 1:n - 1])
    for m in methods:
        curve = top_distortion(result[m]["K"], top)
        ax.plot(ts, curve.mean(axis=1), color=COLORS.get(m), label=METHOD_LABELS[m])
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
    plt = pyplot()
    ts = np.asarray(ts)
    sample = np.asarray(sample)
    colors = plt.get_cmap("tab20")(np.arange(len(sample)) % 20)
    picks = np.linspace(0, len(ts) - 1, n_frames + 2).round().astype(int)
    shapes = ([(source, "source")]
              + [(frames[p], f"t={ts[p]:g}") for p in picks[1:-1]]
              + [(target, "target")])
    fig = plt.figure(figsize=(3.0 * len(shapes), 6.4))
    grid = fig.add_gridspec(2, len(shapes), height_ratios=[1, 1.2])
    plane = view_plane(source, faces)
    for c, (X, title) in enumerate(shapes):
        ax = fig.add_subplot(grid[0, c])
        draw_mesh(ax, X, faces, title=title, plane=plane)
        Y = to_plane(X, faces, plane)
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
