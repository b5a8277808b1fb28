"""Benchmark of bounded-distortion in-betweens against the floor (``PYTHONPATH=tools python3 -m bdinterp_tools.bench``).

The *floor* is one CHOLMOD numeric factorisation + one solve of the interior cotan Laplacian of the
mesh (symbolic analysis reused): the cost of a single Newton step. For each mesh (a jittered Delaunay
disk, scipy.spatial.Delaunay via bdinterp_tools.meshes.disk; target: the harmonic map "phi1" of
bdinterp_tools.meshes, turned by 170 degrees) the table gives, as medians of repeated runs:

- linear: a linear vertex blend; poisson: ARAP (Alexa et al.) = one prefactored Poisson solve;
- floor; cold (new t, nothing cached but the symbolic analysis: ``forget()`` first);
- warm (a slider dragged by 0.01 per frame); bake (``frames`` of 101 frames on all cores, per frame);
- ratios cold/floor and warm/floor, Newton steps per frame, warm frames per second;
- py%: what the Python layer (``bdinterp.Interpolator.at``) adds over the C++ frame time;
- peak memory of a fresh process (build + 6 frames) per vertex.

Every BD frame is checked: max |2 pi - angle sum| <= 1e-10, else the run fails.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

from bdinterp import _core
from bdinterp import conformal_distortion
from bdinterp import Interpolator

from .meshes import MAP_DOMAIN, apply_map, disk

TOLERANCE = 1e-10


def make_case(n, seed=3):
    """(V, target, F) for a disk of ~n vertices: the harmonic map "phi1" of bdinterp_tools.meshes (no
    folds, K up to ~2), then turned rigidly by 170 degrees."""
    center, radius = MAP_DOMAIN
    V, F = disk(n, seed=seed, center=center, radius=radius)
    W = apply_map("phi1", V)
    a = np.deg2rad(170.0)
    T = W @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
    return np.ascontiguousarray(V), np.ascontiguousarray(T), np.ascontiguousarray(F, dtype=np.int32)


def _median_time(fn, repeats, min_time=0.0):
    """Median over `repeats` of the mean time of fn() (called until min_time has passed)."""
    out = []
    for _ in range(repeats):
        k, t0 = 0, time.perf_counter()
        while True:
            fn()
            k += 1
            elapsed = time.perf_counter() - t0
            if elapsed >= min_time:
                break
        out.append(elapsed / k)
    return statistics.median(out)


def _check(stats):
    if not stats["residual"] <= TOLERANCE:
        raise RuntimeError(f"accuracy check failed: residual {stats['residual']:.3g} > {TOLERANCE}")


def peak_memory(n):
    """Peak RSS (bytes) of a fresh interpreter that builds the Interpolator and computes 6 frames,
    minus the RSS of a fresh interpreter that only imports bdinterp and builds the mesh."""
    code = (
        "import resource, sys, numpy as np\n"
        "from bdinterp_tools.bench import make_case\n"
        "from bdinterp import _core\n"
        "V, T, F = make_case(%d)\n"
        "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "I = _core.Interpolator([V, T], F)\n"
        "for k in range(6): I.at(0.4 + 0.01 * k)\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, base)\n" % n)
    # The child imports this package and bdinterp from where this process found them.
    here = [os.path.dirname(os.path.dirname(os.path.abspath(m.__file__)))
            for m in (_core, sys.modules[__name__])]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(here + [os.environ.get("PYTHONPATH", "")]))
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=env)
    peak, base = (int(x) for x in res.stdout.split())
    return 1024.0 * peak, 1024.0 * base


def _bake(V, T, F, repeats):
    """Seconds per frame of frames() over 101 frames, on one thread (bake1) and on all (bake)."""
    ts = np.linspace(0.0, 1.0, 101)
    out = np.empty((ts.size * V.shape[0], 2))
    row = {}
    for threads, key in ((1, "bake1"), (0, "bake")):
        options = _core.InterpolatorOptions()
        options.threads = threads
        baker = _core.Interpolator([V, T], F, _core.Anchor.centroid(), options)

        def bake():
            baker.forget()
            baker.frames_into(ts.tolist(), out)
            _check(baker.stats)

        row[key] = _median_time(bake, repeats) / ts.size
    return row


def _python_overhead(V, T, F, repeats):
    """Median of (wall time of the public wrapper's at()) / (C++ time of the same frame) - 1."""
    py = Interpolator([V, T], F)
    t = 0.0
    for _ in range(3):
        t += 0.01
        py.at(t)
    over = []
    for _ in range(max(repeats, 5) * 4):
        t = t + 0.01 if t < 0.98 else 0.02
        t0 = time.perf_counter()
        py.at(t)
        total = time.perf_counter() - t0
        _check(py.stats)
        over.append(total / py.stats["seconds"] - 1.0)
    return statistics.median(over)


def _peak_row(n, nv):
    """Peak memory of a fresh process per vertex, in all and above the import."""
    mem, base = peak_memory(n)
    return {"peak_B_per_vertex": mem / nv, "peak_above_import_B_per_vertex": (mem - base) / nv}


def run_size(n, repeats, big=False):
    V, T, F = make_case(n)
    nv = V.shape[0]
    row = {"vertices": nv, "K_max": float(conformal_distortion(V, T, F).max())}
    core = _core.Interpolator([V, T], F)
    row["floor"] = core.floor_seconds(max(repeats, 3))
    min_time = 0.2 if nv < 100_000 else 0.0

    state = {"t": 0.0, "dt": 0.01}

    def slide():
        t = state["t"] + state["dt"]
        if t > 1.0 + 1e-12 or t < -1e-12:
            state["dt"] = -state["dt"]
            t = state["t"] + state["dt"]
        state["t"] = t
        return t

    warm_iters = []

    def warm():
        core.at(slide())
        st = core.stats
        _check(st)
        warm_iters.append(st["iterations"])

    for _ in range(3):
        warm()
    row["warm"] = _median_time(warm, repeats, min_time)
    row["newton_warm"] = float(np.mean(warm_iters))
    if big:
        return {**row, **_peak_row(n, nv)}

    cold_ts = iter(np.tile([0.5, 0.3, 0.7, 0.15, 0.85], 1000))
    cold_iters = []

    def cold():
        core.forget()
        core.at(float(next(cold_ts)))
        st = core.stats
        _check(st)
        cold_iters.append(st["iterations"])

    row["cold"] = _median_time(cold, repeats, min_time)
    row["newton_cold"] = float(np.mean(cold_iters))

    lin_t = iter(np.tile(np.linspace(0.1, 0.9, 81), 100000))
    row["linear"] = _median_time(lambda: _core.linear_interpolate(V, T, float(next(lin_t))), repeats,
                                 min_time)
    arap = _core.ArapInterpolator(V, T, F)
    row["poisson"] = _median_time(lambda: arap.at(float(next(lin_t))), repeats, min_time)

    row.update(_bake(V, T, F, repeats))
    row["python_overhead"] = _python_overhead(V, T, F, repeats)
    return {**row, **_peak_row(n, nv)}


def format_table(rows):
    head = ("vertices", "K_max", "linear", "poisson", "floor", "cold", "warm", "bake/fr", "cold/fl",
            "warm/fl", "warm_fps", "bake_fps", "bake_x", "newt_c", "newt_w", "py%", "peak_B/v")
    lines = ["| " + " | ".join(head) + " |", "|" + "---:|" * len(head)]

    def ms(x):
        return "-" if x is None else f"{1e3 * x:.3f}"

    def num(x, fmt):
        return "-" if x is None else format(x, fmt)

    for r in rows:
        g = r.get
        cells = [
            str(r["vertices"]), f"{r['K_max']:.2f}", ms(g("linear")), ms(g("poisson")), ms(r["floor"]),
            ms(g("cold")), ms(r["warm"]), ms(g("bake")),
            num(g("cold") and g("cold") / r["floor"], ".2f"), f"{r['warm'] / r['floor']:.2f}",
            f"{1.0 / r['warm']:.0f}", num(g("bake") and 1.0 / g("bake"), ".0f"),
            num(g("bake") and g("bake1") / g("bake"), ".2f"),
            num(g("newton_cold"), ".2f"), f"{r['newton_warm']:.2f}",
            num(g("python_overhead") is not None and 100 * g("python_overhead") or None, ".1f"),
            f"{r['peak_B_per_vertex']:.0f}",
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m bdinterp_tools.bench", description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="5000,50000,500000",
                    help="approximate vertex counts (default 5000,50000,500000)")
    ap.add_argument("--big", default="", help="sizes that only get floor, warm frame and memory "
                    "(e.g. 1000000)")
    ap.add_argument("--repeats", type=int, default=5, help="repetitions; medians are reported")
    ap.add_argument("--json", help="also write the rows to this file")
    args = ap.parse_args(argv)
    rows = []
    sizes = [int(s) for s in args.sizes.split(",") if s]
    big = [int(s) for s in args.big.split(",") if s]
    for n in sizes + big:
        print(f"... {n} vertices", file=sys.stderr, flush=True)
        rows.append(run_size(n, args.repeats, big=n in big and n not in sizes))
    print(f"bdinterp benchmark: medians of {args.repeats} runs, times in ms; every BD frame checked "
          f"(max |2pi - angle sum| <= {TOLERANCE:g}); {_cpu_count()} cores")
    print(format_table(rows))
    print("cold/fl, warm/fl: frame / floor (targets <= 4, <= 1.5); bake: frames(ts), 101 frames on all "
          "cores, per frame; bake_x: speed-up over 1 thread; newt_c/newt_w: Newton steps per cold/warm "
          "frame; py%: Python wrapper over C++ time; peak_B/v: peak RSS of a fresh process per vertex")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


def _cpu_count():
    return os.cpu_count()


if __name__ == "__main__":
    sys.exit(main())
