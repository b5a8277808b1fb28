"""bdinterp: planar shape interpolation with bounded distortion (Chen et al., SIGGRAPH 2013).

Public API (numpy in, numpy out):
    interpolate(source, target, faces, t, *, anchor=None, method="bdi")
    blend(shapes, faces, weights, *, anchor=None, base=0)
    Interpolator(shapes, faces, *, anchor=None, base=0, tol=1e-10, max_iterations=50)
    conformal_distortion(source, result, faces), area_ratio(source, result, faces),
    flipped_faces(source, result, faces)
    AnchorPath, SolverError (a RuntimeError); invalid input raises ValueError.
"""
from ._core import SolverError
from .distortion import area_ratio, conformal_distortion, flipped_faces
from .interpolate import METHODS, AnchorPath, Interpolator, blend, interpolate

__version__ = "0.1.0"

__all__ = ["interpolate", "blend", "Interpolator", "AnchorPath", "conformal_distortion",
           "area_ratio", "flipped_faces", "SolverError", "METHODS", "__version__"]
