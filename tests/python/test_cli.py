"""The ``bdinterp`` command line and file IO, end to end on tiny meshes."""

import io as stdio
import os
import subprocess
import sys

import numpy as np
import pytest

import bdinterp
from bdinterp import cli, io
from bdinterp.cli import Progress
from bdinterp_tools import meshes

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture
def pair(tmp_path):
    """A tiny bent bar written as source.obj / target.obj."""
    V, F = meshes.rectangle(4.0, 1.0, 60, seed=2)
    x, y = V[:, 0], V[:, 1] - 0.5
    a = 0.3 * x  # bend by up to 1.2 rad along the bar
    Y = np.c_[np.sin(a) / 0.3 - y * np.sin(a), (1 - np.cos(a)) / 0.3
              + y * np.cos(a)]
    src, tgt = tmp_path / "source.obj", tmp_path / "target.obj"
    io.write_obj(src, V, F)
    io.write_obj(tgt, Y, F)
    return str(src), str(tgt), V, Y, F


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, err, *words):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bdinterp: error: ")
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0]


def test_interpolate_writes_readable_frames(pair, tmp_path, capsys):
    src, tgt, V, Y, F = pair
    out = tmp_path / "frames"
    code, stdout, _ = run(["interpolate", src, tgt, "--frames", 5, "-o", out],
                          capsys)
    assert code == 0 and "wrote 5 frames" in stdout
    files = sorted(os.listdir(out))
    assert files == [f"frame_{i:04d}.obj" for i in range(5)]
    frames = [io.read_obj(out / f) for f in files]
    assert all(np.array_equal(G, F) for _, G in frames)
    np.testing.assert_allclose(frames[0][0], V, atol=1e-9)
    np.testing.assert_allclose(frames[-1][0], Y, atol=1e-9)
    mid = frames[2][0]
    assert np.all(bdinterp.area_ratio(V, mid, F) > 0)
    np.testing.assert_allclose(
        mid, bdinterp.Interpolator([V, Y], F).at(0.5), atol=1e-12)


@pytest.mark.parametrize("method", ["arap", "linear"])
def test_interpolate_baselines(pair, tmp_path, capsys, method):
    src, tgt, V, Y, F = pair
    code, _, _ = run(["interpolate", src, tgt, "--frames", 3, "--method",
                      method, "-o", tmp_path / method], capsys)
    assert code == 0
    X, _ = io.read_obj(tmp_path / method / "frame_0001.obj")
    np.testing.assert_allclose(
        X, bdinterp.interpolate(V, Y, F, 0.5, method=method), atol=1e-12)


def test_interpolate_json_input(pair, tmp_path, capsys):
    _, _, V, Y, F = pair
    path = tmp_path / "pair.json"
    io.write_json(path, F, {"source": V, "target": Y})
    code, _, _ = run(["interpolate", path, "--frames", 2, "-o",
                      tmp_path / "j"], capsys)
    assert code == 0
    np.testing.assert_allclose(io.read_obj(tmp_path / "j" /
                                           "frame_0001.obj")[0], Y, atol=1e-9)


def test_figures_are_written(pair, tmp_path, capsys):
    src, tgt, *_ = pair
    for argv in (["compare", src, tgt, "-t", 0.5, "--samples", 5],
                 ["plot-distortion", src, tgt, "--samples", 5,
                  "--triangles", 4]):
        png = tmp_path / f"{argv[0]}.png"
        code, _, _ = run(argv + ["-o", png], capsys)
        assert code == 0
        assert png.read_bytes()[:8] == PNG_MAGIC


def test_compare_reports_each_method(pair, tmp_path, capsys):
    src, tgt, *_ = pair
    code, stdout, _ = run(["compare", src, tgt, "--samples", 3, "-o",
                           tmp_path / "c.png"], capsys)
    assert code == 0
    for m in ("bdi", "arap", "linear"):
        assert f"{m}: at t=0.5 max K" in stdout


def test_convergence_writes_figure_and_csv(tmp_path, capsys):
    # The Fig. 6 experiment, now the repository tool bdinterp_tools.convergence.
    from bdinterp_tools import convergence
    png, csv = tmp_path / "conv.png", tmp_path / "conv.csv"
    code = convergence.main([str(a) for a in [
        "--levels", 2, "--start", 40, "-t", 0.5, "--maps", "phi2", "-o", png,
        "--csv", csv]])
    capsys.readouterr()
    assert code == 0 and png.read_bytes()[:8] == PNG_MAGIC
    rows = csv.read_text().split()
    assert rows[0] == "map,t,vertices,E2,Einf" and len(rows) == 3
    e2 = [float(r.split(",")[3]) for r in rows[1:]]
    assert e2[1] < e2[0]


@pytest.mark.parametrize("argv, words", [
    (["interpolate", "missing.obj", "missing2.obj", "-o", "x"],
     ["missing.obj"]),
    (["interpolate", "{src}", "-o", "x"], [".json"]),
    (["interpolate", "{src}", "{tgt}", "--frames", 1, "-o", "x"],
     ["--frames"]),
    (["interpolate", "{src}", "{tgt}", "--anchor", "999", "-o", "x"],
     ["--anchor", "999"]),
    (["interpolate", "{src}", "{other}", "-o", "x"], ["different faces"]),
    (["interpolate", "{src}", "{bad}", "-o", "x"], ["bad.obj:3", "vertex"]),
    (["compare", "{src}", "{tgt}", "--top", "many", "-o", "x.png"],
     ["--top"]),
    (["frobnicate"], ["frobnicate"]),
    ([], ["COMMAND"]),
])
def test_bad_input_exits_2_with_one_line(pair, tmp_path, capsys, argv, words):
    src, tgt, V, Y, F = pair
    other = tmp_path / "other.obj"
    io.write_obj(other, V, F[:-1])
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 1 oops 0\nf 1 2 3\n")
    subst = {"{src}": src, "{tgt}": tgt, "{other}": other, "{bad}": bad}
    argv = [subst.get(a, a) if isinstance(a, str) else a for a in argv]
    code, _, err = run(argv, capsys)
    assert_one_line_error(code, err, *words)


def test_module_entry_point_subprocess(pair, tmp_path):
    # The real process: exit codes and stderr exactly as a shell sees them.
    src, tgt, *_ = pair
    env = dict(os.environ)
    pkg_root = os.path.dirname(os.path.dirname(bdinterp.__file__))
    env["PYTHONPATH"] = os.pathsep.join(
        [pkg_root] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    ok = subprocess.run([sys.executable, "-m", "bdinterp", "interpolate", src,
                         tgt, "--frames", "2", "-o", str(tmp_path / "s")],
                        env=env, capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr
    assert ok.stderr == ""  # no progress bar when stderr is not a terminal
    bad = subprocess.run([sys.executable, "-m", "bdinterp", "interpolate",
                          src, str(tmp_path / "nope.obj"), "-o", "x"],
                         env=env, capture_output=True, text=True)
    assert_one_line_error(bad.returncode, bad.stderr, "nope.obj")
    helped = subprocess.run([sys.executable, "-m", "bdinterp", "compare",
                             "--help"], env=env, capture_output=True,
                            text=True)
    assert helped.returncode == 0
    for option in ("--samples", "--top", "-t", "--anchor", "--output"):
        assert option in helped.stdout


def test_progress_bar_text():
    out = stdio.StringIO()
    bar = Progress(4, "work", stream=out, enabled=True)
    for _ in range(4):
        bar.step()
    assert out.getvalue().endswith("work [" + "#" * 30 + "] 4/4\n")
    quiet = stdio.StringIO()
    Progress(4, "work", stream=quiet).step()  # StringIO is not a terminal
    assert quiet.getvalue() == ""


# --------------------------------------------------------------- file IO

def test_obj_reader_handles_ngons_slashes_negative_and_3d(tmp_path):
    p = tmp_path / "m.obj"
    p.write_text("# square as a quad, then a triangle with relative indices\n"
                 "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                 "vt 0 0\n"
                 "f 1/1 2/1 3/1 4/1\n"
                 "f -4 -3 -1\n")
    V, F = io.read_obj(p)
    assert V.shape == (4, 3)  # z = 1: kept as planar 3D
    assert F.dtype == np.int32
    np.testing.assert_array_equal(F, [[0, 1, 2], [0, 2, 3], [0, 1, 3]])


def test_obj_roundtrip_is_exact(tmp_path):
    V, F = meshes.disk(50, 3)
    io.write_obj(tmp_path / "d.obj", V, F, comment="two\nlines")
    V2, F2 = io.read_obj(tmp_path / "d.obj")
    assert V2.shape == V.shape  # z = 0 everywhere: read back as 2D
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)


@pytest.mark.parametrize("text, where", [
    ("v 0 0\nv 1 0\nf 1 2 3\n", "face refers to vertex 3"),
    ("v 0 0\nv 1 0\nv 0 1\nf 1 2\n", ":4: face needs at least 3"),
    ("v 0 0\nv 1 0\nv 0 1\nf 0 1 2\n", ":4: face index 0"),
    ("v 0 0\nv 1 0\nv 0 1\nf 1 2 x\n", ":4: bad face index 'x'"),
    ("v 0\n", ":1: vertex needs at least x and y"),
    ("v 0 0\nv 1 0\nv 0 1\nf -5 1 2\n", ":4: relative face index"),
    ("v 0 0\n", "no faces"),
])
def test_obj_reader_errors_name_file_and_line(tmp_path, text, where):
    p = tmp_path / "bad.obj"
    p.write_text(text)
    with pytest.raises(ValueError, match="bad.obj") as e:
        io.read_obj(p)
    assert where in str(e.value)


def test_json_roundtrip_and_errors(tmp_path):
    V, F = meshes.disk(30, 1)
    p = tmp_path / "p.json"
    io.write_json(p, F, {"source": V, "target": 2 * V})
    X0, X1, G = io.read_pair(p)
    np.testing.assert_array_equal(X0, V)
    np.testing.assert_array_equal(X1, 2 * V)
    np.testing.assert_array_equal(G, F)
    io.write_json(p, F, {"source": V})
    with pytest.raises(ValueError, match="lacks target"):
        io.read_pair(p)
    p.write_text('{"faces": [[0, 1, 7]], "shapes": {"source": [[0, 0]]}}')
    with pytest.raises(ValueError, match="out of range"):
        io.read_json(p)
    p.write_text('{"faces": ')
    with pytest.raises(ValueError, match="p.json:1: invalid JSON"):
        io.read_json(p)


# ------------------------------------------- n-gons, bytes and file names

def _star_obj(path, k=7, inner=0.35, z=None, comment=b""):
    """A concave star polygon with k points as one OBJ face (2k corners)."""
    a = np.pi * np.arange(2 * k) / k
    r = np.where(np.arange(2 * k) % 2 == 0, 1.0, inner)
    P = np.c_[r * np.cos(a), r * np.sin(a)]
    lines = [comment] + [f"v {float(x)!r} {float(y)!r} {0.0 if z is None else z}".encode()
                         for x, y in P]  # float(): numpy 2 writes np.float64(...) as repr
    lines.append(("f " + " ".join(str(i + 1) for i in range(2 * k))).encode())
    path.write_bytes(b"\n".join(lines) + b"\n")
    return P


@pytest.mark.parametrize("k, inner", [(5, 0.4), (7, 0.2), (12, 0.8)])
def test_concave_ngons_are_triangulated_without_flips(tmp_path, k, inner):
    # A fan from corner 0 of a star covers parts outside it with flipped triangles; ear clipping
    # gives 2k - 2 triangles, all counter-clockwise, covering exactly the star's area.
    P = _star_obj(tmp_path / "star.obj", k, inner)
    V, F = io.read_obj(tmp_path / "star.obj")
    areas = meshes.signed_areas(V, F)
    assert len(F) == 2 * k - 2 and np.all(areas > 0)
    x, y = P[:, 0], P[:, 1]
    polygon_area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    np.testing.assert_allclose(areas.sum(), polygon_area, rtol=1e-12)
    fan = np.array([[0, j, j + 1] for j in range(1, 2 * k - 1)])
    assert np.any(meshes.signed_areas(V, fan) <= 0)  # what the fan did


def test_concave_ngon_in_a_tilted_plane_keeps_its_winding(tmp_path):
    p = tmp_path / "star.obj"
    _star_obj(p, 6, 0.3, z=2.0)
    V, F = io.read_obj(p)
    assert V.shape[1] == 3  # z = 2: planar 3D
    assert np.all(meshes.signed_areas(V[:, :2], F) > 0)


def test_obj_comments_may_hold_any_bytes(tmp_path):
    p = tmp_path / "latin1.obj"
    _star_obj(p, 5, 0.4, comment="# Gr\xfc\xdfe aus M\xfcnchen \xa9".encode("latin-1"))
    V, F = io.read_obj(p)
    assert len(V) == 10 and len(F) == 8
    bad = tmp_path / "bad.obj"
    bad.write_bytes(b"v 0 0\nv 1 0\nv 0 1\xe9\nf 1 2 3\n")
    with pytest.raises(ValueError, match="bad.obj:3: bytes that are not UTF-8"):
        io.read_obj(bad)


def test_every_cli_error_names_the_file(pair, tmp_path, capsys):
    src, tgt, V, Y, F = pair
    collapsed = np.array(V)
    collapsed[F[3, 1]] = collapsed[F[3, 0]]
    flat = tmp_path / "collapsed.obj"
    io.write_obj(flat, collapsed, F)
    code, _, err = run(["interpolate", flat, tgt, "-o", tmp_path / "o"], capsys)
    assert_one_line_error(code, err, "collapsed.obj", "target.obj", "zero area")
    latin = tmp_path / "latin.json"
    latin.write_bytes('{"faces": [], "shapes": {"s\xe9": []}}'.encode("latin-1"))
    code, _, err = run(["interpolate", latin, "-o", tmp_path / "o"], capsys)
    assert_one_line_error(code, err, "latin.json", "not UTF-8")


def test_figures_without_matplotlib_say_so(pair, tmp_path, capsys, monkeypatch):
    import sys as _sys
    src, tgt, *_ = pair
    monkeypatch.setitem(_sys.modules, "matplotlib", None)  # import matplotlib now fails
    code, _, err = run(["compare", src, tgt, "--samples", 2, "-o", tmp_path / "c.png"], capsys)
    assert_one_line_error(code, err, "needs matplotlib", "python3-matplotlib")


def test_ear_clipping_handles_collinear_corners_and_large_polygons():
    from bdinterp.polygon import triangulate
    # A square with a corner half way along its bottom edge: 3 triangles, none degenerate.
    square = np.array([[0, 0], [0.5, 0], [1, 0], [1, 1], [0, 1.0]])
    tris = np.array(triangulate(list(range(5)), square))
    areas = meshes.signed_areas(square, tris)
    assert len(tris) == 3 and np.all(areas > 0)
    np.testing.assert_allclose(areas.sum(), 1.0)
    # A star with 1000 points (2000 corners): still k - 2 positive triangles.
    a = np.pi * np.arange(2000) / 1000
    r = np.where(np.arange(2000) % 2 == 0, 1.0, 0.9)
    star = np.c_[r * np.cos(a), r * np.sin(a)]
    tris = np.array(triangulate(list(range(2000)), star))
    assert len(tris) == 1998 and np.all(meshes.signed_areas(star, tris) > 0)


def test_figures_show_3d_shapes_in_the_sources_frame(pair):
    # Every panel of a figure of 3D input is drawn in the source's plane: the 2D pictures of the
    # source and the target differ from the 2D originals by one and the same rigid motion.
    from bdinterp import figures
    _, _, V, Y, F = pair
    Q, _ = np.linalg.qr(np.random.default_rng(4).normal(size=(3, 3)))
    B = Q[:, :2].T
    plane = figures.view_plane(V @ B + 1.0, F)
    S, T = (figures.to_plane(X @ B + 1.0, F, plane) for X in (V, Y))
    M, *_ = np.linalg.lstsq(np.c_[V, np.ones(len(V))], S, rcond=None)
    np.testing.assert_allclose(np.c_[Y, np.ones(len(Y))] @ M, T, atol=1e-12)
    np.testing.assert_allclose(M[:2] @ M[:2].T, np.eye(2), atol=1e-12)
    assert np.linalg.det(M[:2]) > 0  # seen from the side the faces point to
