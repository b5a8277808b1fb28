"""Frames of the gallery's examples and the test meshes, saved or compared (a refactoring
keeps every frame within 1e-9 of the size of the frames before it).

    /usr/bin/python3 scripts/frames_snapshot.py save FILE.npz
    /usr/bin/python3 scripts/frames_snapshot.py compare FILE.npz [--limit 1e-9]

Each case is solved by a fresh Interpolator: at(t) for t in 0, 0.1, ..., 1 (cold, one frame
at a time after forget()), and frames() over the same ts (warm). The comparison prints, per case, the
largest vertex distance relative to the case's size, and exits 1 if any exceeds the limit.
"""
import argparse
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "python")]

import bdinterp  # noqa: E402
import bdinterp.io  # noqa: E402
import cutout_meshes  # noqa: E402
import pose_meshes  # noqa: E402

TS = np.linspace(0, 1, 11)


def _examples():
    for d in sorted((ROOT / "examples").iterdir()):
        if (d / "source.obj").exists() and (d / "target.obj").exists():
            X0, X1, F = bdinterp.io.read_pair(d / "source.obj", d / "target.obj")
            yield f"example/{d.name}", [X0, X1], F


def _turned(V, angle, centre=(0.0, 0.0)):
    return cutout_meshes.turn(V, angle, np.asarray(centre))


def _test_meshes():
    V, F = pose_meshes.annulus(6)
    T = V * [1.3, 0.8]
    yield "holes/annulus_stretch", [V, T], F
    yield "holes/annulus_turn", [V, _turned(T, 200)], F
    V, F = pose_meshes.two_holes(8)
    T = V.copy()
    T[:, 1] += 0.3 * np.sin(np.pi * V[:, 0])
    yield "holes/two_holes_wave", [V, T], F
    V, F, shoulder = pose_meshes.body_with_limb()
    yield "pose/skinned_swing_120", [V, pose_meshes.skinned_swing(V, shoulder, np.radians(120))], F
    yield "pose/curled_270", [V, pose_meshes.curled(V, shoulder, np.radians(270))], F
    for name in ("shoulder", "chain", "head_with_eyes"):
        ch, T = getattr(cutout_meshes, name)()
        yield f"cutout/{name}", [ch.V, T], ch.F
    V, F, T, _, _ = cutout_meshes.pendulum()
    yield "cutout/pendulum", [V, T], F


def cases():
    yield from _examples()
    yield from _test_meshes()


def solve(shapes, F):
    it = bdinterp.Interpolator(shapes, F)
    cold = []
    for t in TS:
        it._core.forget()
        cold.append(it.at(t))
    it._core.forget()
    return np.stack(cold), it.frames(TS)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("mode", choices=["save", "compare"])
    p.add_argument("file")
    p.add_argument("--limit", type=float, default=1e-9)
    a = p.parse_args(argv)
    if a.mode == "save":
        out = {}
        for name, shapes, F in cases():
            out[name + "/cold"], out[name + "/warm"] = solve(shapes, F)
            print(name, flush=True)
        np.savez_compressed(a.file, **out)
        return 0
    ref, worst = np.load(a.file), 0.0
    for name, shapes, F in cases():
        size = float(np.linalg.norm(np.ptp(np.asarray(shapes[0]), axis=0)))
        for kind, X in zip(("cold", "warm"), solve(shapes, F)):
            d = float(np.linalg.norm(X - ref[f"{name}/{kind}"], axis=-1).max()) / size
            worst = max(worst, d)
            print(f"{name:34s} {kind}: {d:.2e}{'  OVER' if d > a.limit else ''}", flush=True)
    print(f"largest: {worst:.2e} of the size (limit {a.limit:g})")
    return 0 if worst <= a.limit else 1


if __name__ == "__main__":
    sys.exit(main())
