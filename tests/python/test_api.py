"""The Python surface: Plane, frames(method=...), argument validation and thread safety."""
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import bdinterp
from bdinterp_tools import meshes


def random_plane(rng):
    """(B (2, 3) orthonormal rows, origin (3,)) of a random plane."""
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return Q[:, :2].T, rng.normal(size=3)


# ------------------------------------------------------------------------------------- Plane

def test_plane_fit_is_right_handed_and_round_trips():
    rng = np.random.default_rng(1)
    V, F = meshes.disk(60, seed=1)
    for _ in range(20):
        B, origin = random_plane(rng)
        X = V @ B + origin
        plane = bdinterp.Plane.fit(X)
        np.testing.assert_allclose(plane.normal, np.cross(*plane.axes), atol=1e-15)
        uv = plane.to_plane(X, "X")
        np.testing.assert_allclose(plane.to_space(uv), X, atol=1e-12)
        # Plane coordinates are an isometry of the plane: lengths are kept.
        np.testing.assert_allclose(np.linalg.norm(uv[1:] - uv[0], axis=1),
                                   np.linalg.norm(V[1:] - V[0], axis=1), rtol=1e-12)
        # With faces, the frame faces the mesh: positive total signed area.
        oriented = bdinterp.Plane.fit(X, F).to_plane(X, "X")
        assert meshes.signed_areas(oriented, F).sum() > 0


def test_plane_tolerance_is_relative_to_the_size():
    V, _ = meshes.disk(40, seed=2)
    X = np.c_[V, np.zeros(len(V))] * 1e3
    plane = bdinterp.Plane.fit(X)
    size = np.ptp(X, axis=0).max()
    Y = X.copy()
    Y[5, 2] += 0.5 * bdinterp.PLANAR_TOLERANCE * size
    plane.to_plane(Y, "Y")  # within the default tolerance
    Y[5, 2] += 2 * bdinterp.PLANAR_TOLERANCE * size
    with pytest.raises(ValueError, match="Y, vertex 5: not planar"):
        plane.to_plane(Y, "Y")
    plane.to_plane(Y, "Y", tolerance=1e-3)


def test_distortion_on_3d_input_has_one_handedness(disk):
    # Before: each shape got its own SVD plane, whose handedness is arbitrary; a stretch could count
    # every face as flipped. Now both are measured in the source's plane.
    V, F = disk
    rng = np.random.default_rng(5)
    for _ in range(25):
        B, origin = random_plane(rng)
        stretched = (V * [2.0, 0.7]) @ B + origin
        ratio = bdinterp.area_ratio(V @ B + origin, stretched, F)
        np.testing.assert_allclose(ratio, 1.4, rtol=1e-9)
        assert bdinterp.flipped_faces(V @ B + origin, stretched, F) == 0
        assert bdinterp.flipped_faces(V @ B + origin, (V * [-1, 1]) @ B + origin, F) == len(F)
        K = bdinterp.conformal_distortion(V @ B + origin, stretched, F)
        np.testing.assert_allclose(K, 2.0 / 0.7, rtol=1e-9)
    # A result tilted by 20 degrees out of the source's plane gets its own plane, seen from the side
    # of the source's normal: not flipped; its mirror image is.
    c, s = np.cos(np.radians(20)), np.sin(np.radians(20))
    normal = np.cross(B[0], B[1])
    B2 = np.array([B[0], c * B[1] + s * normal])
    assert bdinterp.flipped_faces(V @ B + origin, V @ B2 + origin, F) == 0
    assert bdinterp.flipped_faces(V @ B + origin, (V * [-1, 1]) @ B2 + origin, F) == len(F)


def test_interpolation_of_3d_input_reports_no_flips(bar):
    V, F, T = bar
    rng = np.random.default_rng(9)
    B, origin = random_plane(rng)
    frames = bdinterp.frames(V @ B + origin, T @ B + origin, F, [0.25, 0.5, 0.75])
    for X in frames:
        assert bdinterp.flipped_faces(V @ B + origin, X, F) == 0


# ----------------------------------------------------------------------------- frames(method)

@pytest.mark.parametrize("method", bdinterp.METHODS)
def test_frames_equal_single_interpolations(bar, method):
    V, F, T = bar
    ts = [0.0, 0.3, 0.8, 1.0]
    frames = bdinterp.frames(V, T, F, ts, method=method)
    assert frames.shape == (len(ts), len(V), 2)
    for t, X in zip(ts, frames):
        np.testing.assert_allclose(X, bdinterp.interpolate(V, T, F, t, method=method), atol=1e-9)
    np.testing.assert_allclose(frames[0], V, atol=1e-9)
    np.testing.assert_allclose(frames[-1], T, atol=1e-9)


def test_linear_frames_are_the_vertex_blend(bar):
    V, F, T = bar
    ts = np.array([-0.5, 0.25, 2.0])
    X = bdinterp.frames(V, T, F, ts, method="linear")
    np.testing.assert_allclose(X, (1 - ts)[:, None, None] * V + ts[:, None, None] * T, atol=1e-12)


def test_frames_options_and_methods_are_checked(bar):
    V, F, T = bar
    with pytest.raises(ValueError, match=r"method must be one of \('bdi', 'arap', 'linear'\)"):
        bdinterp.frames(V, T, F, [0.5], method="ARAP")
    with pytest.raises(ValueError, match="anchor not supported with method='arap'"):
        bdinterp.frames(V, T, F, [0.5], method="arap", anchor=3)
    with pytest.raises(ValueError, match="tol not supported with method='linear'"):
        bdinterp.frames(V, T, F, [0.5], method="linear", tol=1e-6)
    strict = bdinterp.frames(V, T, F, [0.5], tol=1e-12, threads=1)[0]
    np.testing.assert_allclose(strict, bdinterp.interpolate(V, T, F, 0.5), atol=1e-9)


# -------------------------------------------------------------------------------- validation

@pytest.mark.parametrize("kwargs, message", [
    ({"tol": -1.0}, "tol must be > 0, got -1"),
    ({"tol": 0.0}, "tol must be > 0"),
    ({"tol": np.nan}, "tol must be finite"),
    ({"tol": "1e-8"}, "tol must be a real number"),
    ({"tol": 1e-8 + 0j}, "tol must be a real number"),
    ({"max_iterations": 0}, r"max_iterations must be an integer in \[1, 2147483647\], got 0"),
    ({"max_iterations": 2.5}, "max_iterations must be an integer, got 2.5"),
    ({"max_iterations": 2 ** 40}, r"max_iterations must be an integer in \[1, "),
    ({"threads": 2 ** 40}, r"threads must be an integer in \[-2147483647, 2147483647\], got 1099511627776"),
    ({"threads": -1}, r"threads must be in \[0, 1024\] \(got -1\)"),  # the core's check (one layer)
    ({"threads": 1025}, r"threads must be in \[0, 1024\] \(got 1025\)"),
    ({"threads": 1.0}, "threads must be an integer, got 1.0"),
    ({"threads": True}, "threads must be an integer, got True"),
    ({"base": 2}, r"base must be an integer in \[0, 1\], got 2"),
    ({"strict": "yes"}, "strict must be True or False"),
    ({"refinement": 2.0}, r"refinement must be in \[0, 1\] \(got 2\)"),  # the core's check
    ({"refinement": "1"}, "refinement must be a real number"),
])
def test_options_are_validated_naming_the_argument(disk, kwargs, message):
    V, F = disk
    with pytest.raises(ValueError, match=message):
        bdinterp.Interpolator([V, 2 * V], F, **kwargs)


def test_refinement_one_stops_at_the_tolerance():
    # A bar bent by 150 degrees: refined (the default), a frame goes on below tol until its steps stop
    # halving the residual; with refinement=1 it stops at tol, in fewer steps, and the two frames
    # differ by about what tol allows.
    V, F = meshes.rectangle(4.0, 1.0, n_approx=800, seed=3)
    a = np.radians(150)
    r = 4.0 / a - V[:, 1]
    T = np.c_[r * np.sin(V[:, 0] * a / 4.0), 4.0 / a - r * np.cos(V[:, 0] * a / 4.0)]
    size = np.linalg.norm(np.ptp(V, axis=0))
    refined, plain = (bdinterp.Interpolator([V, T], F, tol=1e-4, threads=1, refinement=r) for r in (1e-3, 1.0))
    X, Y = refined.at(0.4), plain.at(0.4)
    assert refined.stats.residual <= 1e-7 < plain.stats.residual <= 1e-4
    assert plain.stats.iterations < refined.stats.iterations
    assert 1e-13 < np.abs(X - Y).max() / size < 1e-5


def test_arrays_are_validated_naming_the_argument(disk):
    V, F = disk
    T = 2 * V
    ragged_faces = F.tolist()
    ragged_faces[2] = ragged_faces[2] + [0]
    cases = [
        (lambda: bdinterp.interpolate(V, T + 1j, F, 0.5), "shape 1: is complex"),
        (lambda: bdinterp.interpolate(V.astype(complex), T, F, 0.5), "shape 0: is complex"),
        (lambda: bdinterp.interpolate(V, T.astype(str), F, 0.5), "shape 1: must hold real numbers"),
        (lambda: bdinterp.interpolate(V, [[0, 0]] + [[1, 2, 3]] * (len(V) - 1), F, 0.5),
         "shape 1: is ragged"),
        (lambda: bdinterp.interpolate(V, T, ragged_faces, 0.5),
         "face 2: has 4 vertices: faces must be triangles"),
        (lambda: bdinterp.interpolate(V, T, F.astype(str), 0.5), "faces must be an integer array"),
        (lambda: bdinterp.interpolate(V, T, F + 0j, 0.5), "faces must be an integer array"),
        (lambda: bdinterp.conformal_distortion(V, T + 1j, F), "result is complex"),
        (lambda: bdinterp.Interpolator([V, T], F).blend([0.5, 0.5, 0]), "one entry per shape"),
        (lambda: bdinterp.Interpolator([V, T], F).blend([0.5 + 1j, 0.5]), "weights is complex"),
        (lambda: bdinterp.Interpolator([V, T], F).frames([0.2, np.nan]), r"ts\[1\] must be finite"),
        (lambda: bdinterp.Interpolator([V, T], F).at("0.5"), "t must be a real number"),
        (lambda: bdinterp.Interpolator([V, T], F).at(0.5j), "t must be a real number"),
        (lambda: bdinterp.Interpolator("shapes", F), "shapes must be a sequence"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()


@pytest.mark.parametrize("method", bdinterp.METHODS)
@pytest.mark.parametrize("t", [np.nan, np.inf])
def test_non_finite_t_is_refused_by_every_method(disk, method, t):
    V, F = disk
    with pytest.raises(ValueError, match="t must be finite"):
        bdinterp.interpolate(V, 2 * V, F, t, method=method)
    with pytest.raises(ValueError, match=r"ts\[0\] must be finite"):
        bdinterp.frames(V, 2 * V, F, [t], method=method)


@pytest.mark.parametrize("path, message", [
    (dict(ts=[0, 1], positions=[[0, 0], [1, 1]], angles=[0, np.nan]), r"angles\[1\] must be finite"),
    (dict(ts=[0, np.nan], positions=[[0, 0], [1, 1]], angles=[0, 0]), r"ts\[1\] must be finite"),
    (dict(ts=[1, 0], positions=[[0, 0], [1, 1]], angles=[0, 0]), "strictly increasing"),
    (dict(ts=[0, 1], positions=[[0, 0], [1, np.inf]], angles=[0, 0]), "positions: vertex 1"),
    (dict(ts=[0, 1], positions=[[0, 0]], angles=[0, 0]), "2 ts, 1 positions and 2 angles"),
    (dict(ts=[0, 1], positions=[[0, 0], [1, 1]], angles=[0, 0], vertex=-5),
     r"the anchor vertex -5 is out of range \[0, "),  # the core checks the range (one layer)
    (dict(ts=[0, 1], positions=[[0, 0], [1, 1]], angles=[0, 0], vertex=1.5),
     "anchor path vertex must be an integer"),
])
def test_anchor_path_fields_are_validated(bar, path, message):
    V, F, T = bar
    with pytest.raises(ValueError, match=message):
        bdinterp.interpolate(V, T, F, 0.5, anchor=bdinterp.AnchorPath(**path))


# ---------------------------------------------------------------------------- thread safety

def test_one_interpolator_shared_by_threads_gives_the_sequential_frames(disk):
    # One Interpolator used from several threads at once: the calls are serialised by a per-object
    # lock (taken with the GIL released), so nothing is corrupted and every frame is what a
    # sequential call gives (to the solver's tolerance: the warm starts differ).
    V, F = disk
    T = meshes.apply_map("phi2", V)
    shared = bdinterp.Interpolator([V, T], F)
    work = [np.linspace(0, 1, 9) + 0.01 * k for k in range(4)]
    expected = [bdinterp.Interpolator([V, T], F).frames(ts) for ts in work]
    results, errors = [None] * len(work), []

    def run(k):
        try:
            out = []
            for rep in range(3):
                if rep % 2:
                    out.append(shared.frames(work[k]))
                else:
                    out.append(np.stack([shared.at(t) for t in work[k]]))
            results[k] = out
        except Exception as e:  # reported below, a failing thread must fail the test
            errors.append(e)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(len(work))]
    for th in threads:
        th.start()
    for th in threads:
        th.join(120)
    assert not errors and not any(th.is_alive() for th in threads)
    scale = np.abs(T).max()
    for k in range(len(work)):
        for got in results[k]:
            assert np.abs(got - expected[k]).max() < 1e-8 * scale
    assert shared.stats.residual <= 1e-10


# ---------------------------------------------------------------------------- threads and runtimes

def test_frames_run_the_threads_asked_for_and_report_them(disk):
    # threads=8 on this machine of fewer cores: 8 factors are 8 workers, a thread each; the frames
    # are a single-threaded Interpolator's to the solver's tolerance.
    V, F = disk
    T = meshes.apply_map("phi2", V)
    ts = np.linspace(0.1, 0.8, 8)
    eight = bdinterp.Interpolator([V, T], F, threads=8)
    got = eight.frames(ts)
    assert eight.stats.threads == 8 and eight.stats.converged
    one = bdinterp.Interpolator([V, T], F, threads=1)
    assert np.abs(got - one.frames(ts)).max() < 1e-8 * np.abs(T).max()
    assert one.stats.threads == 1
    eight.frames(ts[:3])
    assert eight.stats.threads == 3  # never more workers than frames


def test_threading_info_names_the_runtimes_cholmod_calls():
    # Debian's CHOLMOD calls OpenBLAS and libgomp: bdinterp must find the very libraries it binds
    # to (their thread controls are what keeps frames off other programs' cores).
    info = bdinterp.threading_info()
    assert set(info) == {"usable_cores", "machine_busy", "blas", "blas_threads", "openmp"}
    assert 1 <= info["usable_cores"] <= len(os.sched_getaffinity(0))
    assert isinstance(info["machine_busy"], bool)
    assert info["openmp"] and "libgomp" in os.path.basename(info["openmp"])
    assert info["blas"] and os.path.exists(info["blas"])
    assert info["blas_threads"]  # Debian's libblas.so.3 is OpenBLAS here (scripts/setup-debian.sh)


def test_usable_cores_follow_the_affinity_mask():
    # A farm that pins a job to one CPU (taskset, a cpuset) gets one chunk per loop, not one per
    # CPU of the host; frames stay what they are.
    code = ("import bdinterp, numpy as np; print(bdinterp.threading_info()['usable_cores']); "
            "V = np.array([[0,0],[1,0],[1,1],[0,1],[.5,.5]], float); "
            "F = np.array([[0,1,4],[1,2,4],[2,3,4],[3,0,4]], np.int32); "
            "print(abs(bdinterp.interpolate(V, V * [2, 1], F, .5)).max())")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    out = subprocess.run(["taskset", "-c", "0", sys.executable, "-c", code], env=env, check=True,
                         capture_output=True, text=True).stdout.split()
    assert out[0] == "1"
    assert float(out[1]) > 0


def test_usable_cores_follow_a_cgroup_cpu_quota():
    # A container's --cpus or a systemd unit's CPUQuota: the process runs in a cgroup with a quota
    # of one core on a machine with more; its loops must not be split for cores it cannot have.
    # Made for real in a child cgroup (root, cgroup v1 or v2 with the cpu controller).
    if os.cpu_count() < 2:
        pytest.skip("one CPU: nothing to limit")
    name = "bdinterp-test-%d" % os.getpid()
    if os.path.isfile("/sys/fs/cgroup/cpu/cpu.cfs_quota_us"):
        group, limits = "/sys/fs/cgroup/cpu/" + name, {"cpu.cfs_period_us": "100000",
                                                         "cpu.cfs_quota_us": "100000"}
    elif "cpu" in open("/sys/fs/cgroup/cgroup.subtree_control").read().split() \
            if os.path.isfile("/sys/fs/cgroup/cgroup.subtree_control") else False:
        group, limits = "/sys/fs/cgroup/" + name, {"cpu.max": "100000 100000"}
    else:
        pytest.skip("no cgroup cpu controller to write to")
    try:
        os.mkdir(group)
    except OSError as e:
        pytest.skip("cannot make a cgroup here: %s" % e)
    try:
        for f, value in limits.items():
            with open(os.path.join(group, f), "w") as out:
                out.write(value)
        code = "import bdinterp; print(bdinterp.threading_info()['usable_cores'])"
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
        script = 'echo $$ > %s/cgroup.procs && exec "$0" -c "$1"' % group
        out = subprocess.run(["sh", "-c", script, sys.executable, code], env=env, check=True,
                             capture_output=True, text=True).stdout.split()
        assert out == ["1"]
    finally:
        os.rmdir(group)
