"""Names and defaults shared by the add-on's modules (no bpy, no numpy): one place to change them."""

LIVE_KEY = "bdi.live"          # shape key written by live mode
SEP = ".bdi."                  # baked keys: <target>.bdi.<factor in percent>
SLIDER_SUFFIX = ".bdi"         # playback slider: <target>.bdi (custom property on the object)
BAKES_PROP = "_bdi_bakes"      # object custom property recording each bake (found after renames)
DEFAULT_TOLERANCE = 1e-4       # planarity, relative to the mesh size: bdinterp.PLANAR_TOLERANCE
# Frames per Interpolator.frames() call in a bake: small enough that the progress bar moves and Esc
# is answered within ~0.1 s at 20k vertices (12.7 ms a frame), large enough that frames() warm-starts.
CHUNK = 8
DISTORTION_ATTR = "bdi_distortion"
DISTORTION_COLOR = "bdi_distortion_color"
LIVE_WARNING = ("needs the bdinterp add-on enabled to play or render its live mode; "
                "use 'Bake Live to Keys' for machines without it")
