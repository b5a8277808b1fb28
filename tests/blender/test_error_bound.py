"""The bake's Error Bound mode: the fewest in-betweens whose linear blend (what the slider's
drivers show between two keys) stays within the bound of the exact in-between."""

import json

import bpy
import numpy as np

from conftest import bent_strip, read_key, triangles


def test_error_bound_bake_keeps_the_slider_within_the_bound(bd):
    from bdinterp_blender import error_bound_factors
    obj = bent_strip()
    props = obj.bdi
    props.target, props.use_error_bound, props.error_bound = "Bend", True, 0.002
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    factors = error_bound_factors(obj, "Bend", 0.002)
    names = [kb.name for kb in obj.data.shape_keys.key_blocks if kb.name.startswith("Bend.bdi.")]
    assert json.loads(props.result)["keys"] == len(names) == len(factors) >= 2
    # the keys as written (float32), from the source to the target, against exact in-betweens
    ts = np.array([0.0] + factors + [1.0])
    keys = [read_key(obj, "Basis")] + [read_key(obj, n) for n in names] + [read_key(obj, "Bend")]
    interp = bd.Interpolator([keys[0], keys[-1]], triangles(obj))
    size = max(np.linalg.norm(np.ptp(keys[i], axis=0)) for i in (0, -1))
    dense = np.linspace(0.0, 1.0, 401)
    worst = 0.0
    for t, X in zip(dense, interp.frames(dense)):
        j = min(np.searchsorted(ts, t, side="right") - 1, len(ts) - 2)
        s = (t - ts[j]) / (ts[j + 1] - ts[j])
        worst = max(worst, np.linalg.norm((1 - s) * keys[j] + s * keys[j + 1] - X, axis=1).max())
    assert worst <= 0.002 * size + 1e-6, worst / size
    # fewer keys for a looser bound; the method must be bdi
    assert len(error_bound_factors(obj, "Bend", 0.01)) < len(factors)
    props.method = 'linear'
    before = [kb.name for kb in obj.data.shape_keys.key_blocks]
    try:
        bpy.ops.bdinterp.bake()
        raise AssertionError("baked an error bound with the linear method")
    except RuntimeError as exc:
        assert "error bound measures bdi in-betweens" in str(exc)
    assert [kb.name for kb in obj.data.shape_keys.key_blocks] == before
