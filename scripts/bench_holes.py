"""Warm frames of a piece with holes against a disk of the same size (a warm examples/letter_8
frame is meant to cost at most 1.3x a warm disk frame of the same vertex count).

    /usr/bin/python3 scripts/bench_holes.py [--rounds 5] [--threads N] LABEL=PYTHONPATH [LABEL=PYTHONPATH ...]

Each LABEL's bdinterp (its PYTHONPATH) runs in a child process, the labels taking turns round after
round, so that builds compared share the machine's state. A warm frame is at(t) on a slider: t
from 0.30 to 0.70 in steps of 0.01 after a first at(0.29); a cold frame is at(0.5) after forget().
Prints per label and mesh the median milliseconds per frame, and per warm frame the Newton steps (the
most of one convex solve, stats.iterations) and the convex solves (stats.convex_solves; "-" for a
build without that count).
"""
import json
import pathlib
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _disk(n_vertices):
    """A jittered grid over [0, 2] x [0, 1.1] with about n_vertices vertices, bent by a wave."""
    sys.path[:0] = [str(ROOT / "tests" / "python")]
    import pose_meshes
    # The grid (nx + 1) x (ny + 1) closest to n_vertices with cells about square.
    shapes = [(abs((nx + 1) * (round(n_vertices / (nx + 1))) - n_vertices), nx, round(n_vertices / (nx + 1)) - 1)
              for nx in range(2, n_vertices) if 1.5 <= nx / max(round(n_vertices / (nx + 1)) - 1, 1) <= 2.5]
    _, nx, ny = min(shapes)
    V, F = pose_meshes._grid_cells(nx, ny, 2.0, 1.1, lambda x, y: True, np.random.default_rng(0))
    T = V.copy()
    T[:, 1] += 0.4 * np.sin(np.pi * V[:, 0])
    return V, T, F


def _slider(I):
    """One warm slider on a fresh Interpolator: the seconds, Newton steps and convex solves (nan
    where the build does not count them) of each warm frame."""
    I.at(0.29)
    warm, steps, solves = [], [], []
    for t in np.arange(0.30, 0.705, 0.01):
        s = time.perf_counter()
        I.at(t)
        warm.append(time.perf_counter() - s)
        stats = I.stats.as_dict()
        steps.append(stats["iterations"])
        solves.append(stats.get("convex_solves", np.nan))
    return warm, steps, solves


def child(threads, sliders):
    import bdinterp
    import bdinterp.io
    X0, X1, F = bdinterp.io.read_pair(ROOT / "examples/letter_8/source.obj", ROOT / "examples/letter_8/target.obj")
    cases = {"letter_8": (X0, X1, F), "disk": _disk(len(X0))}
    warm = {name: ([], [], []) for name in cases}
    # The meshes take turns slider by slider, so that both meet the VM's speed phases alike.
    for _ in range(sliders):
        for name, (A, B, F) in cases.items():
            for into, values in zip(warm[name], _slider(bdinterp.Interpolator([A, B], F, threads=threads))):
                into.extend(values)
    out = {}
    for name, (A, B, F) in cases.items():
        I = bdinterp.Interpolator([A, B], F, threads=threads)
        cold = []
        for _ in range(5):
            I._core.forget()  # the Python class has no forget()
            s = time.perf_counter()
            I.at(0.5)
            cold.append(time.perf_counter() - s)
        out[name] = {"vertices": len(A), "warm_ms": 1e3 * float(np.median(warm[name][0])),
                     "cold_ms": 1e3 * float(np.median(cold)), "warm_steps": float(np.mean(warm[name][1])),
                     "warm_solves": float(np.mean(warm[name][2]))}
    print(json.dumps(out))


def main():
    args = sys.argv[1:]
    options = {"--rounds": 5, "--threads": 0, "--sliders": 5}
    while args[:1] and args[0] in options:
        options[args[0]] = int(args[1])
        args = args[2:]
    rounds, threads, sliders = options["--rounds"], options["--threads"], options["--sliders"]
    labels = [a.split("=", 1) for a in args]
    results = {label: [] for label, _ in labels}
    for _ in range(rounds):
        for label, path in labels:
            env = {"PYTHONPATH": path, "PATH": "/usr/bin:/bin"}
            r = subprocess.run([sys.executable, __file__, "--child", str(threads), str(sliders)], env=env,
                               capture_output=True, text=True, check=True)
            results[label].append(json.loads(r.stdout))
    print("| build | mesh | vertices | warm ms | cold ms | Newton steps warm | convex solves warm "
          "| warm / disk warm | per run: median (range) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---|")
    for label, runs in results.items():
        med = {m: {k: float(np.median([r[m][k] for r in runs])) for k in runs[0][m]} for m in runs[0]}
        for m, v in med.items():
            # Each child times both meshes back to back: the VM's speed phase is more likely shared.
            paired = [r[m]["warm_ms"] / r["disk"]["warm_ms"] for r in runs]
            print(f"| {label} | {m} | {int(v['vertices'])} | {v['warm_ms']:.3f} | {v['cold_ms']:.3f} | "
                  f"{v['warm_steps']:.2f} | {'-' if np.isnan(v['warm_solves']) else format(v['warm_solves'], '.2f')} | "
                  f"{v['warm_ms'] / med['disk']['warm_ms']:.2f} | "
                  f"{np.median(paired):.2f} ({min(paired):.2f}-{max(paired):.2f}) |")


if __name__ == "__main__":
    child(int(sys.argv[2]), int(sys.argv[3])) if sys.argv[1:2] == ["--child"] else main()
