"""Regenerate docs/gallery/ from examples/ and print its markdown tables.

Usage (from the repository root, with the core built)::

    /usr/bin/python3 scripts/make_gallery.py [--out docs/gallery] [NAME ...]

For every example (examples/<name>/{source,target}.obj) it interpolates at
21 values of t with BDI, ARAP and the linear blend and writes

- <name>_compare.png: the frames at t (0.75 for the spiral, as in the
  paper's Fig. 13, else 0.5) coloured by distortion, and the distortion of
  the 100 most distorted faces vs t;
- <name>_distortion.png: K(t) of 12 BDI faces (Fig. 3);

plus convergence.png (Fig. 6 left), and GALLERY.md with one table per
example: max K over t, faces flipped (or collapsed), the error at t = 1 and,
for BDI, the most Newton iterations in a frame, and at its end the pictures other
scripts draw (OTHER_PICTURES).  The same markdown is printed on
stdout.  A full run (no NAMEs, default --out) also writes the summary table,
one row per example, into README.md between the README_BEGIN and README_END
lines, so that the README's numbers are never typed by hand.  Given NAMEs,
only those are redone and GALLERY.md and README.md are left as they are.
"""

import argparse
import os
import sys

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tools"))

import bdinterp  # noqa: E402
from bdinterp import figures, io  # noqa: E402
from bdinterp.cli import Progress  # noqa: E402
from bdinterp_tools import convergence, meshes  # noqa: E402

TS = np.linspace(0.0, 1.0, 21)
PICTURED_T = {"spiral": 0.75}
DPI = 80
# README's gallery table: what each example is called there (default: its name).
LABELS = {"affine": "affine (Fig. 4)", "bar_half_bent": "bar_half_bent (Fig. 11)",
          "conformal": "conformal (Fig. 9)", "teichmuller": "teichmuller (Sec. 4.3)",
          "spiral": "spiral (1.5 turns)", "folded": "folded (Fig. 10, folded target)",
          "letter_8": "letter_8 (2 holes)", "letter_e": "letter_e (Blender text, a hole)",
          "skinned_swing": "skinned_swing (armature, folds)",
          "body_tail": "body_tail (tail bent 300°)",
          "cutout": "cutout (7 layered pieces, 6 pins)"}
# Pictures drawn by other scripts, listed at the end of a full GALLERY.md.
OTHER_PICTURES = [
    "### Meshes from sprites", "",
    "Each sprite of examples/sprites with its mesh from `bdinterp.mesh_from_image` "
    "(default parameters) over it; below, the mesh's right part turned 90° about the top "
    "middle of its bounding box (the turn ramps smoothly across the middle 80 % of its "
    "width: the target, green), the source (grey) and bdinterp's in-between at t = 0.5 "
    "coloured by K, never above the target's largest K. Drawn by `/usr/bin/python3 "
    "scripts/sprites_gallery.py`, which prints the figures (docs/SPRITES.md).", "",
    "![sprites, their meshes and a bend of each](sprites.png)", ""]
README_BEGIN = "<!-- gallery table: written by scripts/make_gallery.py -->"
README_END = "<!-- end of gallery table -->"


def examples(names):
    base = os.path.join(ROOT, "examples")
    found = sorted(d for d in os.listdir(base) if os.path.isfile(
        os.path.join(base, d, "source.obj")))
    unknown = set(names) - set(found)
    if unknown:
        raise SystemExit(f"make_gallery: no example {', '.join(unknown)} "
                         f"(have {', '.join(found)})")
    return [(n, os.path.join(base, n)) for n in (names or found)]


def away_from_folds(X0, X1, F, rings=2):
    """Boolean (m,) mask of the faces outside a `rings`-face neighbourhood of the target's folded
    faces, or None when none folds: where a folded pair is to behave like a valid one."""
    folded = bdinterp.area_ratio(X0, X1, F) <= 0
    return ~meshes.near_faces(F, folded, rings) if folded.any() else None


def joint_openings(name, X0, F, result):
    """{method: the largest joint opening over t (x size)} of an example made of pinned pieces
    (cutout: examples/cutout/cutout_character.py measures it), else None."""
    if name != "cutout":
        return None
    sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
    import cutout_character as cc
    pieces, joints = cc.character()
    tris_of = {piece: F[np.isin(F[:, 0], list(r))] for piece, r in cc.one_mesh(pieces)[3].items()}
    size = float(np.linalg.norm(np.ptp(X0, axis=0)))
    return {m: max(cc.joint_openings(X0, r["frames"], tris_of, joints, size).values())
            for m, r in result.items()}


def flat(X):
    """The examples lie in the XY plane; a layered one (cutout) has its pieces' depths in z, which
    the in-plane results do not depend on (tests/python/test_layers.py): dropped here."""
    return X[:, :2] if X.shape[1] == 3 else X


def numbers(X0, X1, F, result, joints=None):
    """Per method: max K over t and over 0 < t < 1, the most flipped faces in a frame and in an
    in-between, frames with flips, flipped faces and the largest vertex error at t = 1 (relative
    to the target's largest extent), Newton iterations (-1: not Newton), the largest joint
    opening (joints: joint_openings(), or None); for a folded target also max K and the most
    flipped faces of an in-between away from the folds."""
    inner = (TS > 0) & (TS < 1)
    size = float(np.ptp(X1, axis=0).max())
    away = away_from_folds(X0, X1, F)
    out = {}
    for m, r in result.items():
        out[m] = {"K": np.max(r["K"]), "K inner": np.max(r["K"][inner]),
                  "flipped": np.max(r["flipped"]), "flipped inner": np.max(r["flipped"][inner]),
                  "frames with flips": np.count_nonzero(r["flipped"]),
                  "flipped at 1": r["flipped"][-1],
                  "error at 1": np.linalg.norm(r["frames"][-1] - X1, axis=1).max() / size,
                  "iterations": r["iterations"], "joints": joints[m] if joints else None}
        if away is not None:
            frames = r["frames"][inner]
            out[m]["K away"] = np.max(r["K"][inner][:, away])
            out[m]["flipped away"] = max(np.count_nonzero(bdinterp.area_ratio(X0, X, F)[away] <= 0)
                                         for X in frames)
    return out


def table(name, X0, X1, F, nums):
    K_in = bdinterp.conformal_distortion(X0, X1, F)
    flips_in = np.count_nonzero(bdinterp.area_ratio(X0, X1, F) <= 0)
    lines = [f"### {name}", "",
             f"{len(X0)} vertices, {len(F)} faces; input (target) max K "
             f"{np.max(K_in):.4g}, {flips_in} flipped; {len(TS)} frames, "
             f"t = 0..1.", "",
             "| method | max K over t | max K, 0 < t < 1 "
             "| max flipped faces in a frame | frames with flips "
             "| error at t = 1 (x size) | Newton iterations (most in a frame) |",
             "|---|---|---|---|---|---|---|"]
    for m, n in nums.items():
        iters = str(n["iterations"]) if n["iterations"] >= 0 else "n/a"
        lines.append(f"| {m} | {n['K']:.4g} | {n['K inner']:.4g} | {n['flipped']} "
                     f"| {n['frames with flips']} | {n['error at 1']:.2g} | {iters} |")
    if "K away" in next(iter(nums.values())):
        lines += ["", "In-betweens outside two faces around the target's folds (where a folded pair "
                  "must behave like a valid one): " + "; ".join(
                      f"{m} max K {n['K away']:.4g}, at most {n['flipped away']} flipped"
                      for m, n in nums.items()) + "."]
    if next(iter(nums.values()))["joints"] is not None:
        lines += ["", "The joints' largest opening over t (the distance between where the parent's "
                  "and the child's triangles carry a pin, x the source's diagonal): " + "; ".join(
                      f"{m} {n['joints']:.2g}" for m, n in nums.items()) + "."]
    return "\n".join(lines) + "\n"


def summary(rows):
    """README's table: one row per example from (name, X0, X1, F, nums)."""
    methods = " / ".join(bdinterp.METHODS)
    lines = [f"| example | vertices | input max K | max K, 0 < t < 1: {methods} "
             f"| most faces flipped in an in-between: {methods} "
             f"| error at t = 1 (x size): {methods} | BDI Newton iterations (most) "
             f"| joints' largest opening (x size): {methods} |",
             "|---|---|---|---|---|---|---|---|"]
    for name, X0, X1, F, nums in rows:
        K_in = bdinterp.conformal_distortion(X0, X1, F)
        folded = np.count_nonzero(bdinterp.area_ratio(X0, X1, F) <= 0)
        away = away_from_folds(X0, X1, F)

        def each(key, away, fmt):  # "bdi / arap / linear"; folded: each (away from the folds)
            return " / ".join(format(n[key], fmt) + (f" ({n[away]:{fmt}})" if folded else "")
                              for n in nums.values())
        lines.append(f"| {LABELS.get(name, name)} | {len(X0)} | {np.max(K_in):.4g}"
                     + (f" ({np.max(K_in[away]):.4g}), {folded} folded" if folded else "")
                     + f" | {each('K inner', 'K away', '.4g')} "
                     f"| {each('flipped inner', 'flipped away', 'd')} "
                     f"| {' / '.join(format(n['error at 1'], '.1g') for n in nums.values())} "
                     f"| {nums['bdi']['iterations']} | {openings(nums)} |")
    return "\n".join(lines) + "\n"


def openings(nums):
    """'bdi / arap / linear' joint openings of an example with joints, else '-'."""
    if next(iter(nums.values()))["joints"] is None:
        return "-"
    return " / ".join(format(n["joints"], ".2g") for n in nums.values())


def write_readme(text, path=os.path.join(ROOT, "README.md")):
    """Replace the lines between README_BEGIN and README_END of README.md by text."""
    with open(path, encoding="utf-8") as f:
        readme = f.read()
    if README_BEGIN not in readme or README_END not in readme:
        raise SystemExit(f"make_gallery: README.md has no '{README_BEGIN}' ... "
                         f"'{README_END}' block")
    head, rest = readme.split(README_BEGIN, 1)
    tail = rest.split(README_END, 1)[1]
    with open(path, "w", encoding="utf-8") as f:
        f.write(head + README_BEGIN + "\n" + text + README_END + tail)
    print(f"wrote {os.path.relpath(path, ROOT)}", file=sys.stderr)


def save(fig, path):
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    figures.pyplot().close(fig)
    print(f"wrote {os.path.relpath(path, ROOT)}", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("names", nargs="*", help="examples (default: all)")
    default_out = os.path.join(ROOT, "docs", "gallery")
    ap.add_argument("--out", default=default_out)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    md = ["# Gallery", "",
          "Generated by `scripts/make_gallery.py` from `examples/`. K is the "
          "per-face conformal distortion w.r.t. the source (1 = angle "
          "preserving); 'flipped' counts faces with area ratio <= 0.", ""]
    rows = []
    for name, folder in examples(args.names):
        X0, X1, F = io.read_pair(os.path.join(folder, "source.obj"),
                                 os.path.join(folder, "target.obj"))
        X0, X1 = flat(X0), flat(X1)
        t = PICTURED_T.get(name, 0.5)
        bar = Progress(len(TS) * len(bdinterp.METHODS), name)
        result = figures.sweep(X0, X1, F, TS, progress=bar)
        save(figures.compare_figure(X0, X1, F, t, TS, result),
             os.path.join(args.out, f"{name}_compare.png"))
        sample = figures.pick_faces(bdinterp.conformal_distortion(X0, X1, F),
                                  12)
        save(figures.distortion_curves_figure(
            X0, X1, F, TS, result["bdi"]["frames"], result["bdi"]["K"],
            sample), os.path.join(args.out, f"{name}_distortion.png"))
        nums = numbers(X0, X1, F, result, joint_openings(name, X0, F, result))
        rows.append((name, X0, X1, F, nums))
        md += [table(name, X0, X1, F, nums),
               f"![{name}: frames at t={t:g}]({name}_compare.png)", "",
               f"![{name}: K(t) per face]({name}_distortion.png)", ""]
    if not args.names:
        # Defaults of convergence.convergence: 3 maps x 3 t x 4 levels.
        data = convergence.convergence(progress=Progress(36, "convergence"))
        save(convergence.convergence_figure(data),
             os.path.join(args.out, "convergence.png"))
        md += ["### Convergence (Fig. 6 left)", "",
               "| map | t | " + " | ".join(
                   f"E2 / Einf at {n} vertices" for n in data["vertices"])
               + " |", "|---|---|" + "---|" * len(data["vertices"])]
        for i, name in enumerate(data["maps"]):
            for k, t in enumerate(data["ts"]):
                md.append(f"| {name} | {t:g} | " + " | ".join(
                    f"{e2:.2e} / {ei:.2e}" for e2, ei in
                    zip(data["E2"][i, k], data["Einf"][i, k])) + " |")
        md += ["", "![convergence](convergence.png)", ""] + OTHER_PICTURES
    md[4:4] = [summary(rows)]
    text = "\n".join(md)
    if not args.names:  # a partial run must not clobber the full page
        with open(os.path.join(args.out, "GALLERY.md"), "w",
                  encoding="utf-8") as f:
            f.write(text)
        if os.path.abspath(args.out) == os.path.abspath(default_out):
            write_readme(summary(rows))
    print(text)


if __name__ == "__main__":
    main()
