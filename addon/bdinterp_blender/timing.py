"""Timing of in-betweens: easing, factors, key names and the playback driver expressions.

Two numbers per in-between: its *position* on the playback slider (0..1, evenly spaced for a
count) and its *factor* t = easing(position), the interpolation parameter it is baked at.
Pure Python (no bpy), so it is cheap to import and easy to test.
"""

from .names import SEP  # key names: <target>.bdi.<factor in percent>

EASINGS = {
    "LINEAR": lambda u: u,
    "EASE_IN": lambda u: u * u,                      # slow start
    "EASE_OUT": lambda u: 1.0 - (1.0 - u) ** 2,      # slow end
    "EASE_IN_OUT": lambda u: u * u * (3.0 - 2.0 * u),  # smoothstep
}


def parse_factors(text):
    """'0.25, 0.5 0.75' -> [0.25, 0.5, 0.75] (ValueError naming the bad entry)."""
    out = []
    for tok in text.replace(",", " ").replace(";", " ").split():
        try:
            out.append(float(tok))
        except ValueError:
            raise ValueError("factor %r is not a number" % tok) from None
    return out


def schedule(count=None, factors=None, easing="LINEAR"):
    """Return (positions, factors) of the in-betweens.

    factors given explicitly: each must lie strictly inside (0, 1); positions = factors (sorted).
    Otherwise `count` evenly spaced positions j/(count+1) mapped through `easing`, a name from
    EASINGS or a callable u -> t (a custom curve; it may overshoot [0, 1]).
    """
    if factors is not None:
        ts = sorted(float(f) for f in factors)
        if not ts:
            raise ValueError("no factors given")
        bad = [t for t in ts if not 0.0 < t < 1.0]
        if bad:
            raise ValueError("explicit factors must lie strictly between 0 and 1 (got %s)" % bad)
        if len(set(ts)) != len(ts):
            raise ValueError("factors must be distinct")
        return list(ts), list(ts)
    count = int(count if count is not None else 3)
    if count < 1:
        raise ValueError("number of in-betweens must be at least 1 (got %d)" % count)
    ease = easing if callable(easing) else EASINGS.get(easing)
    if ease is None:
        raise ValueError("unknown easing %r (use one of %s or a callable)" % (easing, ", ".join(EASINGS)))
    positions = [j / (count + 1.0) for j in range(1, count + 1)]
    return positions, [float(ease(u)) for u in positions]


def factor_label(t):
    """0.5 -> '050', 0.125 -> '012.5', 1 -> '100' (percent, three digits before the point)."""
    p = round(t * 100.0, 6)
    if abs(p - round(p)) < 1e-9:
        return "%03d" % round(p)
    return ("%07.3f" % p).rstrip("0")


def key_name(target, t):
    return "%s%s%s" % (target, SEP, factor_label(t))


def key_names(target, ts):
    names = [key_name(target, t) for t in ts]
    seen = {}
    for name, t in zip(names, ts):
        if name in seen:
            raise ValueError("factors %g and %g both give the key name %r" % (seen[name], t, name))
        seen[name] = t
    return names


def tent_expressions(positions):
    """Driver expressions (variable `s`, the slider) for keys at `positions` and for the target.

    Piecewise-linear 'tent' weights over the knots 0, positions..., 1, so that the slider plays
    source -> in-betweens -> target.  Only min/max/arithmetic: Blender evaluates these as
    'simple expressions', without Python, so playback works when scripts are not trusted and
    without the add-on.
    """
    knots = [0.0] + list(positions) + [1.0]
    exprs = []
    for a, b, c in zip(knots, knots[1:], knots[2:]):
        exprs.append("max(0.0, min((s - %r) / %r, (%r - s) / %r))" % (a, b - a, c, c - b))
    a = knots[-2]
    target = "max(0.0, min(1.0, (s - %r) / %r))" % (a, 1.0 - a)
    return exprs, target
