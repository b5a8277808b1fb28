"""Discrete vs continuous distortion under refinement (paper Fig. 6 left).

``PYTHONPATH=tools /usr/bin/python3 -m bdinterp_tools.convergence -o convergence.png [--csv F]``
(formerly ``bdinterp convergence``: it needs scipy for the Delaunay disks, so it lives with the
repository's tools, not in the installed package).
"""
import argparse
import sys

import numpy as np

import bdinterp
from bdinterp import figures

from . import meshes

MAPS = ("phi1", "phi2", "phi3")


def convergence(maps=MAPS, ts=(0.25, 0.5, 0.75), levels=4, n0=100, seed=0, progress=None):
    """On a refinement sequence of disk meshes (meshes.disk_sequence over meshes.MAP_DOMAIN) with
    target = map(source), compare the BDI frame's per-face distortion K^_t(f) with the continuous K_t
    at the face barycentre (meshes.blended_distortion). Paper eq. (2):
      E2   = sum_f A_f |K_t(f) - K^_t(f)|^2 / sum_f A_f  (A_f: area in frame),
      Einf = max_f |K_t(f) - K^_t(f)|.
    Returns dict with ``vertices`` (levels,), and ``E2``, ``Einf`` arrays (len(maps), len(ts), levels).
    """
    center, radius = meshes.MAP_DOMAIN
    seq = meshes.disk_sequence(levels, n0, seed, center=center, radius=radius)
    E2 = np.zeros((len(maps), len(ts), levels))
    Einf = np.zeros_like(E2)
    for i, name in enumerate(maps):
        for j, (V, F) in enumerate(seq):
            frames = bdinterp.Interpolator([V, meshes.apply_map(name, V)], F).frames(ts)
            bary = V[F].mean(axis=1)
            for k, (t, X) in enumerate(zip(ts, frames)):
                err = (meshes.blended_distortion(name, bary, t)
                       - bdinterp.conformal_distortion(V, X, F))
                area = np.abs(meshes.signed_areas(X, F))
                E2[i, k, j] = np.sum(area * err ** 2) / np.sum(area)
                Einf[i, k, j] = np.max(np.abs(err))
            if progress is not None:
                progress.step(len(ts))
    return {"maps": tuple(maps), "ts": tuple(ts),
            "vertices": np.array([len(V) for V, _ in seq]), "E2": E2, "Einf": Einf}


def convergence_figure(data):
    """Fig. 6 left: E2 and Einf vs vertex count, one line per (map, t)."""
    plt = figures.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    styles = ["-", "--", ":", "-."]
    for ax, key in zip(axes, ("E2", "Einf")):
        for i, name in enumerate(data["maps"]):
            for k, t in enumerate(data["ts"]):
                ax.loglog(data["vertices"], data[key][i, k], styles[k % len(styles)], marker="o",
                          markersize=3, color=f"C{i}", label=f"{name}, t={t:g}")
        ax.set_xlabel("vertices")
        ax.set_title(key)
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, ncol=len(data["maps"]))
    fig.tight_layout()
    return fig


def csv_rows(data):
    """The numbers as CSV lines: map,t,vertices,E2,Einf."""
    return ["map,t,vertices,E2,Einf"] + [
        f"{name},{t:g},{n},{data['E2'][i, k, j]:.6g},{data['Einf'][i, k, j]:.6g}"
        for i, name in enumerate(data["maps"])
        for k, t in enumerate(data["ts"])
        for j, n in enumerate(data["vertices"])]


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m bdinterp_tools.convergence",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("--levels", type=int, default=4, metavar="L",
                   help="refinement levels; each has ~4x the vertices (default 4)")
    p.add_argument("--start", type=int, default=100, metavar="N",
                   help="approximate vertex count of level 0 (default 100)")
    p.add_argument("-t", type=float, nargs="+", default=[0.25, 0.5, 0.75],
                   help="t values (default 0.25 0.5 0.75)")
    p.add_argument("--maps", nargs="+", default=list(MAPS), choices=MAPS,
                   help="maps to test (default all three)")
    p.add_argument("--csv", metavar="FILE.csv", help="also write the numbers as CSV")
    p.add_argument("-o", "--output", required=True, metavar="FILE.png", help="the figure")
    args = p.parse_args(argv)
    if args.levels < 1 or args.start < 10:
        p.error("--levels must be >= 1 and --start >= 10")
    data = convergence(args.maps, args.t, args.levels, args.start)
    figures.save(convergence_figure(data), args.output)
    rows = csv_rows(data)
    if args.csv:
        with open(args.csv, "w", encoding="utf-8") as f:
            f.write("\n".join(rows) + "\n")
        print(f"wrote {args.csv}")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
