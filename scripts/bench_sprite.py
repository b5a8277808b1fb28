"""mesh_from_image on 2048 x 2048 sprites held in memory, on one core (the process pinned to it).

    PYTHONPATH=python /usr/bin/python3 scripts/bench_sprite.py [--rounds 5] [--size 2048]

Sprites: the soft blob, the ring and the letter B of tools/bdinterp_tools/sprites.py drawn at the
size asked, and a noisy alpha (a blob whose edge is scattered over a few pixels). Prints a Markdown
table: the best and median seconds of `rounds` runs with the default parameters, as the process's
CPU time (what one free core takes; on a shared machine the wall time also counts the other
processes' turns on that core) and as wall time, vertices, faces and the outline's vertices.
"""
import argparse
import os
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tools")]

import bdinterp  # noqa: E402
from bdinterp_tools import sprites  # noqa: E402


def noisy_blob(size):
    alpha = sprites.soft_blob(size)[..., 3].astype(np.float32) / 255
    rng = np.random.default_rng(1)
    return np.clip(alpha + rng.normal(0, 0.15, alpha.shape).astype(np.float32), 0, 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--size", type=int, default=2048)
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    cases = {"soft_blob": sprites.soft_blob, "ring": sprites.ring, "letter_b": sprites.letter_b,
             "noisy_blob": noisy_blob}
    print(f"| sprite ({args.size}²) | CPU best s | CPU median s | wall best s | wall median s | vertices | "
          "faces | outline vertices |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, draw in cases.items():
        image = draw(args.size)
        cpu, wall = [], []
        for _ in range(args.rounds):
            start, start_cpu = time.perf_counter(), time.process_time()
            mesh = bdinterp.mesh_from_image(image)
            cpu.append(time.process_time() - start_cpu)
            wall.append(time.perf_counter() - start)
        print(f"| {name} | {min(cpu):.3f} | {np.median(cpu):.3f} | {min(wall):.3f} | {np.median(wall):.3f} | "
              f"{len(mesh.vertices)} | {len(mesh.faces)} | {mesh.outline_vertices} |")


if __name__ == "__main__":
    main()
