"""The fewest in-between keys within an error bound (Interpolator.keyframes).

Between two keys at factors a < b a runtime shows the linear blend of their frames; the exact
in-between at t differs from it by the largest vertex distance. Keys are placed greedily: from
each key the next is the furthest factor whose segment stays within the bound at `samples`
evenly spaced factors inside it (bisection on the factor); where the segment found fails a check
four times as dense, the bisection is repeated with that check.
"""

import numpy as np

from . import _validate

SAMPLES = 8          # factors checked inside a segment while placing keys
VERIFY = 4           # the final check is this many times denser
PRECISION = 1e-4     # bisection stops at this fraction of the range
MARGIN = 0.999       # keys aim this far under the bound: a smooth error peaks a little between samples


def size(shapes):
    """The diagonal of the larger shape's bounding box."""
    return max(float(np.linalg.norm(np.ptp(np.asarray(s, dtype=np.float64), axis=0)))
               for s in shapes)


def blend_error(X0, X1, ts, frames, a, b):
    """Largest vertex distance of the exact frames at factors ts from the linear blend of the
    frames X0 (at a) and X1 (at b)."""
    s = (np.asarray(ts) - a) / (b - a)
    lerp = X0[None] + s[:, None, None] * (X1 - X0)[None]
    return float(np.linalg.norm(lerp - frames, axis=2).max()) if len(ts) else 0.0


class _Segments:
    """Frames of an Interpolator, cached by factor, and the error of segments between them."""

    def __init__(self, interp, bound):
        self.interp, self.bound, self.cache = interp, bound, {}

    def frame(self, t):
        if t not in self.cache:
            self.cache[t] = self.interp.at(t)
        return self.cache[t]

    def worst(self, a, b, samples):
        """(error, factor) of the worst of `samples` evenly spaced factors inside (a, b)."""
        ts = a + (b - a) * np.arange(1, samples + 1) / (samples + 1)
        new = [t for t in ts.tolist() if t not in self.cache]
        if new:
            self.cache.update(zip(new, self.interp.frames(new)))
        X0, X1 = self.frame(a), self.frame(b)
        errs = [blend_error(X0, X1, [t], self.cache[t][None], a, b) for t in ts.tolist()]
        i = int(np.argmax(errs))
        return errs[i], float(ts[i])

    def fits(self, a, b, samples=SAMPLES):
        return self.worst(a, b, samples)[0] <= self.bound


def keyframes(interp, tolerance, t0=0.0, t1=1.0):
    """Sorted factors from t0 to t1 (both included) such that the linear blend of the frames at
    consecutive factors is within tolerance x size of the exact in-between (see module doc)."""
    tolerance = _validate.real(tolerance, "tolerance")
    t0, t1 = _validate.real(t0, "t0"), _validate.real(t1, "t1")
    if not tolerance > 0:
        raise ValueError("tolerance must be > 0 (a fraction of the size), got %r" % tolerance)
    if not t0 < t1:
        raise ValueError("t0 must be less than t1, got t0=%r, t1=%r" % (t0, t1))
    seg = _Segments(interp, MARGIN * tolerance * interp.size)
    keys = [t0]
    while keys[-1] < t1:
        a = keys[-1]
        b = _furthest(seg, a, t1, SAMPLES)
        if not seg.fits(a, b, SAMPLES * VERIFY):  # refined where the denser check fails
            b = _furthest(seg, a, b, SAMPLES * VERIFY)
        keys.append(b)
    return np.array(keys)


def _furthest(seg, a, t1, samples):
    """The furthest factor b in (a, t1] whose segment from a fits at `samples` factors (bisection)."""
    if seg.fits(a, t1, samples):
        return t1
    lo, hi = a, t1
    while hi - lo > PRECISION * (t1 - a) or lo == a:
        mid = 0.5 * (lo + hi)
        if seg.fits(a, mid, samples):
            lo = mid
        else:
            hi = mid
        if hi - a < 1e-12:
            raise ValueError("no key spacing reaches the tolerance near t=%r" % a)
    return lo


def dense_error(interp, keys, ts, frames=None):
    """Largest vertex distance, relative to interp.size, of the exact frames at factors ts (within
    the keys' range; `frames`: those frames if computed already) from the linear blend of the
    frames at the sorted factors `keys`."""
    keys, ts = np.asarray(keys, dtype=np.float64), np.asarray(ts, dtype=np.float64)
    K = interp.frames(keys)
    T = interp.frames(ts) if frames is None else frames
    seg = np.clip(np.searchsorted(keys, ts, side="right") - 1, 0, len(keys) - 2)
    errs = [blend_error(K[i], K[i + 1], ts[seg == i], T[seg == i], keys[i], keys[i + 1])
            for i in range(len(keys) - 1)]
    return max(errs) / interp.size


def even_count(interp, tolerance, ts, t0=0.0, t1=1.0):
    """The fewest evenly spaced keys from t0 to t1 whose dense_error on ts is within tolerance."""
    n, frames = 2, interp.frames(ts)
    while dense_error(interp, np.linspace(t0, t1, n), ts, frames) > tolerance:
        n += 1
    return n
