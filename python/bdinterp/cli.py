"""Command-line interface: ``bdinterp`` / ``python3 -m bdinterp``.

Subcommands: interpolate, compare, plot-distortion (see ``bdinterp --help``).
Input errors end with exit code 2 and one line ``bdinterp: error: ...`` on
stderr naming the file; solver failures with exit code 3.  The figures need
matplotlib (imported only by the commands that draw).  The convergence
experiment of Fig. 6 is a repository tool: tools/bdinterp_tools/convergence.py.
"""

import argparse
import sys

import numpy as np

from bdinterp.constants import METHODS

PROG = "bdinterp"
EXIT_INPUT = 2
EXIT_SOLVER = 3

DESCRIPTION = """\
Bounded-distortion in-betweens of planar triangle meshes (Chen, Weber,
Keren, Ben-Chen: "Planar shape interpolation with bounded distortion").
Inputs are a SOURCE and a TARGET OBJ with identical faces, or one JSON file
{"faces": [[i,j,k],...], "shapes": {"source": [[x,y],...],
"target": [[x,y],...]}} (0-based faces)."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump), exit code 2."""

    def error(self, message):
        raise _InputError(f"{message} (see '{self.prog} --help')")


class _InputError(Exception):
    pass


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


def _pair_args(p):
    p.add_argument("source", metavar="SOURCE",
                   help="source mesh (.obj), or a two-key .json with both")
    p.add_argument("target", metavar="TARGET", nargs="?",
                   help="target mesh (.obj) with the same faces as SOURCE")
    p.add_argument("--anchor", default=None, metavar="auto|VERTEX",
                   help="what stays put: 'auto' (default: area-weighted "
                        "centroid and mean rotation blended) or a vertex "
                        "index whose position and orientation are blended")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no progress bar (shown on stderr if a terminal)")


def _samples_arg(p, default, what=""):
    p.add_argument("--samples", type=int, default=default, metavar="K",
                   help=f"number of t samples in [0,1]{what} (default {default})")


def _output_arg(p, what):
    p.add_argument("-o", "--output", required=True, metavar="FILE.png",
                   help=f"where to write the {what} (format from the "
                        f"extension: .png, .pdf, .svg)")


def build_parser():
    parser = _Parser(prog=PROG, description=DESCRIPTION,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                parser_class=_Parser)
    sub.required = True

    p = sub.add_parser(
        "interpolate", help="write in-between frames as OBJ files",
        description="Interpolate SOURCE -> TARGET and write frames "
                    "DIR/frame_0000.obj ... (t evenly spaced from --range).")
    _pair_args(p)
    p.add_argument("--frames", type=int, default=11, metavar="N",
                   help="number of frames, including both ends (default 11)")
    p.add_argument("--range", type=float, nargs=2, default=(0.0, 1.0),
                   metavar=("T0", "T1"),
                   help="first and last t (default 0 1; values outside "
                        "[0,1] extrapolate while the blended metric stays "
                        "valid)")
    p.add_argument("--method", choices=METHODS,
                   default="bdi", help="bdi (default), or a baseline")
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="output directory (created if missing)")
    p.set_defaults(run=cmd_interpolate)

    p = sub.add_parser(
        "compare", help="BDI vs ARAP vs linear: frames and distortion graph",
        description="Picture of each method's frame at t, faces coloured by "
                    "conformal distortion K (flipped faces red), and the "
                    "normalised distortion (K-1)/(K+1) of the --top most "
                    "distorted faces vs t (Fig. 13 of the paper).")
    _pair_args(p)
    p.add_argument("-t", type=float, default=0.5, help="t of the pictured "
                   "frames (default 0.5)")
    _samples_arg(p, 21, " for the graph")
    p.add_argument("--top", type=int, default=100, metavar="N",
                   help="how many most distorted faces to follow "
                        "(default 100)")
    _output_arg(p, "figure")
    p.set_defaults(run=cmd_compare)

    p = sub.add_parser(
        "plot-distortion", help="K(t) per triangle for a sample (Fig. 3)",
        description="Plot the conformal distortion K of a sample of "
                    "triangles as a function of t, for the BDI frames.")
    _pair_args(p)
    p.add_argument("--triangles", type=int, default=12, metavar="N",
                   help="number of triangles, spread over the range of "
                        "target distortion (default 12)")
    _samples_arg(p, 41)
    _output_arg(p, "figure")
    p.set_defaults(run=cmd_plot_distortion)

    return parser


def _anchor(value):
    if value is None or value == "auto":
        return value
    try:
        return int(value)
    except ValueError:
        raise ValueError(f"--anchor must be 'auto' or a vertex index, "
                         f"got '{value}'") from None


def _load(args):
    from bdinterp import io
    X0, X1, F = io.read_pair(args.source, args.target)
    anchor = _anchor(args.anchor)
    if isinstance(anchor, int) and not 0 <= anchor < len(X0):
        raise ValueError(f"--anchor {anchor} is not a vertex index "
                         f"(mesh has {len(X0)} vertices)")
    return X0, X1, F, anchor


def _progress(args, total, label):
    return Progress(total, label, enabled=False if args.quiet else None)


def _positive(name, value, minimum=1):
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")


def cmd_interpolate(args):
    import bdinterp
    from bdinterp import io
    _positive("--frames", args.frames, 2)
    X0, X1, F, anchor = _load(args)
    ts = np.linspace(args.range[0], args.range[1], args.frames)
    bar = _progress(args, len(ts), "interpolate")
    frames = bdinterp.frames(X0, X1, F, ts, method=args.method, anchor=anchor)
    bar.step(len(ts))
    io.write_frames(args.output, frames, F, ts=ts)
    K = max(np.max(bdinterp.conformal_distortion(X0, X, F)) for X in frames)
    flipped = max(bdinterp.flipped_faces(X0, X, F) for X in frames)
    print(f"wrote {len(frames)} frames to {args.output} "
          f"(max K {K:.4g}, at most {flipped} flipped faces per frame)")


def _sweep(args, X0, X1, F, anchor, ts, methods):
    from bdinterp import figures
    figures.pyplot()  # a missing matplotlib is reported before the frames are computed
    bar = _progress(args, len(ts) * len(methods), args.command)
    return figures.sweep(X0, X1, F, ts, methods, anchor=anchor, progress=bar)


def cmd_compare(args):
    from bdinterp import figures
    _positive("--samples", args.samples, 2)
    _positive("--top", args.top)
    X0, X1, F, anchor = _load(args)
    # The pictured t joins the graph's samples so its frame is computed.
    ts = np.union1d(np.linspace(0.0, 1.0, args.samples), [args.t])
    result = _sweep(args, X0, X1, F, anchor, ts, METHODS)
    figures.save(figures.compare_figure(X0, X1, F, args.t, ts, result, args.top),
          args.output)
    i = int(np.argmin(np.abs(ts - args.t)))
    for m, r in result.items():
        print(f"{m:>6}: at t={args.t:g} max K {np.max(r['K'][i]):.4g}, "
              f"{r['flipped'][i]} flipped; over t: max K "
              f"{np.max(r['K']):.4g}, max flipped {np.max(r['flipped'])}")


def cmd_plot_distortion(args):
    import bdinterp
    from bdinterp import figures
    _positive("--samples", args.samples, 2)
    _positive("--triangles", args.triangles)
    X0, X1, F, anchor = _load(args)
    ts = np.linspace(0.0, 1.0, args.samples)
    r = _sweep(args, X0, X1, F, anchor, ts, ("bdi",))["bdi"]
    sample = figures.pick_faces(bdinterp.conformal_distortion(X0, X1, F),
                              args.triangles)
    figures.save(figures.distortion_curves_figure(X0, X1, F, ts, r["frames"], r["K"],
                                         sample), args.output)


def _inputs(args):
    """The input files of a parsed command line, as its errors name them."""
    files = [getattr(args, k, None) for k in ("source", "target")]
    return [str(f) for f in files if f is not None]


def _in_files(message, files):
    """message prefixed with the input files unless it already names one (the readers' do)."""
    if not files or any(f in message for f in files):
        return message
    return f"{' + '.join(files)}: {message}"


def main(argv=None):
    """Entry point; returns the exit code (0 ok, 2 bad input, 3 solver).

    Every error names the file it is about: reader errors name file and line, errors about the
    mesh as a whole (e.g. 'face 5 has zero area') are prefixed with the input files.
    """
    files = []
    try:
        args = build_parser().parse_args(argv)
        files = _inputs(args)
        args.run(args)
    except _InputError as e:
        return _fail(str(e), EXIT_INPUT)
    except OSError as e:
        what = e.strerror or str(e)
        where = f"{e.filename}: " if e.filename else ""
        return _fail(_in_files(f"{where}{what}", files), EXIT_INPUT)
    except (ValueError, ImportError) as e:
        return _fail(_in_files(str(e), files), EXIT_INPUT)
    except RuntimeError as e:  # bdinterp.SolverError and other core failures
        return _fail(_in_files(f"solver failed: {e}", files), EXIT_SOLVER)
    return 0


def _fail(message, code):
    # One line: the messages may quote file content with newlines.
    print(f"{PROG}: error: {' '.join(str(message).split())}", file=sys.stderr)
    return code


if __name__ == "__main__":
    sys.exit(main())
