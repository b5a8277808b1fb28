"""The onion-skin overlay's redraw cost in Blender (docs/BENCHMARKS.md): at each size, a bent grid
with three ghosts and a trail, drawn in a real window under Xvfb by examples/blender/onion_screenshot.py
(the add-on as Blender finds it: the one installed in BLENDER_USER_SCRIPTS, or this checkout's).

    /usr/bin/python3 scripts/bench_overlay.py [--sizes 5000,20000] [--redraws 30] [--blender blender]

Two runs a size: as it is, then with every GPU batch's draw() a no-op (this file, passed to
Blender before onion_screenshot.py with --stub-draws, swaps them in), so that the second run's
callback time is the Python side alone.  Prints a Markdown table: the draw callback's median CPU
time (time.perf_counter around it, cached redraws), the callback without GPU draws, the whole
viewport region's redraw (wm.redraw_timer) without and with the overlay, and the callback without
GPU draws in a redraw right after the object moved, a colour changed, a live frame (a third run,
in live mode).  Without a GPU (Xvfb)
Mesa's llvmpipe draws in software on the CPU: its batch.draw() calls carry that work.
"""

import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "examples", "blender", "onion_screenshot.py")


class _NoDraw:
    def draw(self, shader):
        pass


def stub_draws():
    """Inside Blender: every Plan the overlay makes draws nothing on the GPU (Python side only)."""
    import bpy

    def patch():
        from bdinterp_blender.view import overlay
        init = overlay.Plan.__init__

        def no_gpu(self, *args):
            init(self, *args)
            for name in ("ghosts", "lines", "points"):
                setattr(self, name, [(_NoDraw(), c) for _, c in getattr(self, name)])
        overlay.Plan.__init__ = no_gpu
    bpy.app.timers.register(patch, first_interval=0.1)  # after onion_screenshot.py enabled it


def run(blender, size, redraws, stub, live=False):
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", blender, "--factory-startup"]
    cmd += ["--python", os.path.abspath(__file__)] if stub else []
    cmd += ["--python", SCRIPT, "--", "--scene", "grid:%d" % size, "--redraws", str(redraws),
            "--out", "/tmp/bench_overlay.png", "--changes"] + (["--stub-draws"] if stub else [])
    cmd += ["--live"] if live else []
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("JSON:")]
    if not lines:
        sys.exit("no result from %s:\n%s" % (" ".join(cmd), proc.stderr[-3000:]))
    out = json.loads(lines[-1][5:])
    if out.get("error"):
        sys.exit(out["error"])
    return out


def _ms(seconds):
    return "%.3f" % (1e3 * seconds) if seconds is not None else "–"


def main(argv):
    def opt(name, default):
        return argv[argv.index(name) + 1] if name in argv else default
    blender, redraws = opt("--blender", "blender"), int(opt("--redraws", "30"))
    print("| vertices | callback (ms) | callback, no GPU draws (ms) | redraw without / with overlay (ms) "
          "| no GPU draws, after a move / a colour / a live frame (ms) |")
    print("|---:|---:|---:|---:|---:|")
    for size in map(int, opt("--sizes", "5000,20000").split(",")):
        full, python = run(blender, size, redraws, False), run(blender, size, redraws, True)
        live = run(blender, size, redraws, True, live=True)
        print("| %d | %.2f | %.3f | %.0f / %.0f | %s / %s / %s |" % (
            full["vertices"], 1e3 * full["draw_cached"], 1e3 * python["draw_cached"],
            1e3 * full["redraw_off"], 1e3 * full["redraw_on"], _ms(python.get("draw_moved")),
            _ms(python.get("draw_recoloured")), _ms(live.get("draw_live"))), flush=True)
    print("\nRenderer: %s" % full["renderer"])


if __name__ == "__main__":
    if "bpy" in sys.modules or "--stub-draws" in sys.argv:
        stub_draws()
    else:
        main(sys.argv[1:])
