"""Names and defaults shared by the add-on's modules (no bpy, no numpy): one place to change them."""

LIVE_KEY = "bdi.live"          # shape key written by live mode
SEP = ".bdi."                  # baked keys: <target>.bdi.<factor in percent>
SLIDER_SUFFIX = ".bdi"         # playback slider: <target>.bdi (custom property on the object)
BAKES_PROP = "_bdi_bakes"      # object custom property recording each bake (found after renames)
DEFAULT_TOLERANCE = 1e-4       # planarity, relative to the mesh size: bdinterp.PLANAR_TOLERANCE
# Frames per Interpolator.frames() call in a bake, per worker (one per usable core, or per `threads`):
# a call takes about this many frames' time on any number of cores (two cores: 0.06-0.08 s at 20k
# vertices, 0.3-0.5 s at 80k, where one frame alone takes ~0.1 s), so the progress bar moves and
# Esc is answered within 0.2 s up to ~40k vertices, and each worker warm-starts along its frames.
FRAMES_PER_WORKER = 4
DISTORTION_ATTR = "bdi_distortion"
DISTORTION_COLOR = "bdi_distortion_color"
LIVE_WARNING = ("needs the bdinterp add-on enabled to play or render its live mode; "
                "use 'Bake Live to Keys' for machines without it")
