"""Interpolator.keyframes: the fewest keys within an error bound, on every gallery example."""

import glob
import os

import numpy as np
import pytest

import bdinterp
from bdinterp import io
from bdinterp.keyframes import even_count

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = sorted(os.path.basename(os.path.dirname(p))
                  for p in glob.glob(os.path.join(ROOT, "examples", "*", "target.obj")))
DENSE = np.linspace(0.0, 1.0, 1201)  # the check: independent of the factors keyframes samples


def interpolator(name):
    V, F = io.read_obj(os.path.join(ROOT, "examples", name, "source.obj"))[:2]
    Y = io.read_obj(os.path.join(ROOT, "examples", name, "target.obj"))[0]
    return bdinterp.Interpolator([V, Y], F, threads=1), V, Y


def test_every_gallery_example_is_checked():
    assert len(EXAMPLES) >= 12, EXAMPLES


@pytest.mark.parametrize("name", EXAMPLES)
def test_keys_stay_within_the_bound_and_are_no_more_than_even_ones(name):
    interp, V, Y = interpolator(name)
    size = max(np.linalg.norm(np.ptp(X, axis=0)) for X in (V, Y))
    assert interp.size == pytest.approx(size, rel=1e-12)
    tol = 0.005
    keys = interp.keyframes(tol)
    assert keys[0] == 0.0 and keys[-1] == 1.0 and np.all(np.diff(keys) > 0), keys
    # the piecewise-linear blend of the key frames against the exact in-between, densely
    ts = np.union1d(DENSE, keys)
    K, T = interp.frames(keys), interp.frames(ts)
    worst = 0.0
    for i, t in enumerate(ts):
        j = min(np.searchsorted(keys, t, side="right") - 1, len(keys) - 2)
        s = (t - keys[j]) / (keys[j + 1] - keys[j])
        worst = max(worst, np.linalg.norm((1 - s) * K[j] + s * K[j + 1] - T[i], axis=1).max())
    assert worst <= tol * size, (worst / size, len(keys))
    assert len(keys) <= even_count(interp, tol, DENSE)


def test_a_sub_range_and_a_tighter_bound():
    interp = interpolator("letter_e")[0]
    keys = interp.keyframes(0.002, 0.25, 0.75)
    assert keys[0] == 0.25 and keys[-1] == 0.75
    assert len(keys) > len(interp.keyframes(0.01, 0.25, 0.75)) >= 2


def test_bad_arguments_are_named():
    interp = interpolator("letter_e")[0]
    with pytest.raises(ValueError, match="tolerance must be > 0"):
        interp.keyframes(0.0)
    with pytest.raises(ValueError, match="t0 must be less than t1"):
        interp.keyframes(0.01, 0.5, 0.5)
    with pytest.raises(ValueError, match="tolerance"):
        interp.keyframes(float("nan"))
