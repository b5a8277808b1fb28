"""Names and defaults shared by the library, the CLI and the Blender add-on (one place for each)."""

# Interpolation methods, in the order the CLI and the figures list them: the bounded-distortion
# in-betweens of the paper, ARAP (Alexa et al. 2000, rotations unwrapped) and the vertex blend.
METHODS = ("bdi", "arap", "linear")
METHOD_LABELS = {"bdi": "BDI (bounded distortion)", "arap": "ARAP (Alexa 2000)",
                 "linear": "linear blend"}

# Planarity: how far a vertex of 3D input may lie off its piece's plane, as a fraction of the shape's
# largest extent; the package's and the Blender add-on's default (addon names.DEFAULT_TOLERANCE).
# Blender's float32 rounding moves a rotated planar mesh off its plane by ~1e-7 of its size; an
# animator's hand-placed pieces by more.
PLANAR_TOLERANCE = 1e-4

# Interpolator defaults: the angle-sum tolerance max |2 pi - angle sum| (radians), the Newton
# iteration cap, and the thread count (0 = one per core).
TOLERANCE = 1e-10
MAX_ITERATIONS = 50
# Below the tolerance, steps go on towards TOLERANCE * REFINEMENT while they halve the residual, so
# that a frame does not depend on the frames solved before it (to about 1e-13 of the size).
REFINEMENT = 1e-3
THREADS = 0

# The largest value the core's C int options accept (max_iterations, threads, the anchor vertex).
INT_MAX = 2 ** 31 - 1
