"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/): inputs that pass
validation and reach the solver, so that fuzzing starts from the interesting paths. The byte layouts
are documented at the top of each target. Run: /usr/bin/python3 tests/fuzz/make_corpus.py"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def small(x, lo):
    """A 'reasonable' number: selector byte 0, then int16 of x / lo (see fuzz::Bytes::number)."""
    return bytes([0]) + struct.pack("<h", max(-32768, min(32767, round(x / lo * 32768))))


def raw(x):
    return bytes([1]) + struct.pack("<d", x)


def grid(nx, ny):
    V = [(i / nx, j / ny) for j in range(ny + 1) for i in range(nx + 1)]
    F = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            F += [(a, a + 1, a + nx + 2), (a, a + nx + 2, a + nx + 1)]
    return V, F


def raw_input(V, F, shapes, maps, t, tol=b"", anchor=b"\x00", threads=0):
    """tol: b"" for the default tolerance, else its encoded number."""
    out = bytes([len(V), len(F), shapes - 2])
    for f in F:
        for v in f:
            out += bytes([v, 0])
    for m in maps:
        for x, y in V:
            X, Y = m(x, y)
            out += b"".join(small(c, 4.0) if abs(c) <= 4 else raw(c) for c in (X, Y))
    out += bytes([1]) + tol if tol else bytes([0])
    out += bytes([0, 1, 1])  # default max_iterations, reuse factorisations, base 0
    return out + anchor + bytes([threads]) + small(t, 1.5)


def disk_targets(affine, scale, offsets, ts):
    out = b"".join(small(a, 1.0) for a in affine) + small(scale, 0.3)
    out += b"".join(small(dx, 1.0) + small(dy, 1.0) for dx, dy in offsets)
    return out + b"".join(small(t, 1.5) for t in ts)


def write(target, name, data, folder="corpus"):
    d = os.path.join(HERE, folder, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def main():
    V, F = grid(4, 3)
    ident = lambda x, y: (x, y)
    stretch = lambda x, y: (1.5 * x, 0.6 * y)
    bend = lambda x, y: ((1.2 - y) * math.sin(x), 1.2 - (1.2 - y) * math.cos(x))
    write("fuzz_raw_input", "stretch", raw_input(V, F, 2, [ident, stretch], 0.5))
    write("fuzz_raw_input", "bend", raw_input(V, F, 2, [ident, bend], 0.3, threads=2))
    write("fuzz_raw_input", "three", raw_input(V, F, 3, [ident, stretch, bend], 0.7))
    write("fuzz_raw_input", "vertex_anchor", raw_input(V, F, 2, [ident, bend], 0.5, anchor=b"\x01\x07"))
    path = b"\x02\x02" + small(0, 2) + small(0, 10) + small(0, 10) + small(0, 7)
    path += small(1, 2) + small(1, 10) + small(0, 10) + small(1, 7) + b"\x00\x00"
    write("fuzz_raw_input", "path_anchor", raw_input(V, F, 2, [ident, stretch], 0.5, anchor=path))
    write("fuzz_raw_input", "nan_t", raw_input(V, F, 2, [ident, stretch], 0.5)[:-3] + raw(math.nan))
    write("fuzz_raw_input", "huge", raw_input(V, F, 2, [ident, stretch], 0.5)[:-3] + raw(1e300))
    zero = [(0.0, 0.0)] * 35
    write("fuzz_disk_targets", "identity", disk_targets([0, 0, 0, 0], 0, zero, [0.5]))
    write("fuzz_disk_targets", "shear", disk_targets([0.5, 0.3, 0, -0.2], 0, zero, [0.1, 0.5, 0.9]))
    wobble = [(math.sin(3 * k), math.cos(5 * k)) for k in range(35)]
    write("fuzz_disk_targets", "wobble", disk_targets([0.2, 0, 0, 0.2], 0.1, wobble, [0.3, 0.31, 1.0, 0.0]))
    write("fuzz_disk_targets", "flip", disk_targets([-2, 0, 0, 0], 0.05, wobble, [0.5, 1.2, -0.3]))

    # Earlier findings, fixed in the core: seeds, so that every run replays them first. (A
    # finding not yet fixed goes to tests/fuzz/known/ with folder="known"; docs/FUZZING.md.)
    strip = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (0.0, 1.0), (1.0, 1.0), (2.0, 1.0)]
    strip_f = [(0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4)]
    write("fuzz_raw_input", "negative_tol_no_interior",
          raw_input(strip, strip_f, 2, [ident, stretch], 0.5, tol=small(-1e-7, 1e-6)))
    fold = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.1, -0.1)]
    write("fuzz_raw_input", "cancelling_orientations",
          raw_input(fold, [(0, 1, 2), (1, 3, 2)], 2, [ident, stretch], 0.5))


if __name__ == "__main__":
    main()
