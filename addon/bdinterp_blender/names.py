"""Names and defaults shared by the add-on's modules (no bpy, no numpy): one place to change them."""

LIVE_KEY = "bdi.live"          # shape key written by live mode
POSE_KEY = "bdi.pose"          # shape key written by pose grids (pose parameters)
GRID_BAKE_SEP = ".bake."       # Bake Grid's keys: <grid>.bake.<i>_<j>
SEP = ".bdi."                  # baked keys: <target>.bdi.<factor in percent>
SLIDER_SUFFIX = ".bdi"         # playback slider: <target>.bdi (custom property on the object)
BAKES_PROP = "_bdi_bakes"      # object custom property recording each bake (found after renames)
DEFAULT_TOLERANCE = 1e-4       # planarity, relative to the mesh size: bdinterp.PLANAR_TOLERANCE
# A bake's step (one Interpolator.frames() call) aims at STEP_SECONDS, so that the progress bar moves
# and Esc is answered within 0.2 s while one frame on each worker takes less, and computes at most
# FRAMES_PER_WORKER frames on each worker (each warm-starts along its frames).
STEP_SECONDS = 0.15
FRAMES_PER_WORKER = 4
DISTORTION_ATTR = "bdi_distortion"
DISTORTION_COLOR = "bdi_distortion_color"
LIVE_WARNING = ("needs the bdinterp add-on enabled to play or render its live mode; "
                "use 'Bake Live to Keys' for machines without it")
