"""bdinterp: planar shape interpolation with bounded distortion (Chen et al., SIGGRAPH 2013).

Public API (numpy in, numpy out):
    interpolate(source, target, faces, t, *, anchor=None, method="bdi")
    frames(source, target, faces, ts, *, method="bdi", anchor=None, **options)
    blend(shapes, faces, weights, *, anchor=None, base=0)
    Interpolator(shapes, faces, *, anchor=None, base=0, tol=1e-10, max_iterations=50, threads=0)
        .at(t), .blend(weights), .frames(ts), .stats (FrameStats)
    conformal_distortion(source, result, faces), area_ratio(source, result, faces),
    flipped_faces(source, result, faces)
    mesh_from_image(image, **options) -> SpriteMesh (options: SpriteMeshOptions' fields)
        (a triangle mesh of a sprite's alpha)
    Stroke, StrokeInterpolator, interpolate_strokes (drawn strokes as thin bands, bdinterp.strokes)
    pose_grid: Parameter, PoseGrid (poses on a grid of parameter values: multilinear weights,
        wrapping angles, clamping), PoseBlender (groups of them combined, blended by one Interpolator)
    pose_bake: GridBake (a grid's in-betweens on a finer grid for linear runtimes, and their error)
    Plane (the plane of planar 3D input), Layers (pieces in parallel planes at their own depths),
    AnchorPath, FrameStats, METHODS, PLANAR_TOLERANCE
    threading_info() (usable cores, the busy verdict, the BLAS/OpenMP runtimes CHOLMOD calls)
    SolverError (a RuntimeError); invalid input raises ValueError, InvalidInputError (a ValueError
    with .detail, .shape, .face, .vertex) where it is about one shape, face or vertex.
"""
from ._core import FrameStats, SolverError, threading_info
from .constants import METHOD_LABELS, METHODS, PLANAR_TOLERANCE
from .errors import InvalidInputError
from .distortion import area_ratio, conformal_distortion, flipped_faces
from .interpolate import AnchorPath, Interpolator, blend, frames, interpolate
from . import pose_bake, pose_grid
from .pose_grid import Parameter, PoseBlender, PoseGrid
from .layers import Layers
from .plane import Plane
from .sprite import SpriteMesh, SpriteMeshOptions, mesh_from_image
from . import strokes
from .strokes import Stroke, StrokeInterpolator, interpolate_strokes

__version__ = "0.1.0"

__all__ = ["interpolate", "frames", "blend", "Interpolator", "AnchorPath", "FrameStats", "Plane", "Layers",
           "conformal_distortion", "area_ratio", "flipped_faces", "SolverError", "InvalidInputError", "METHODS",
           "METHOD_LABELS", "PLANAR_TOLERANCE", "threading_info", "mesh_from_image", "SpriteMesh",
           "SpriteMeshOptions", "strokes", "Stroke", "StrokeInterpolator", "interpolate_strokes", "__version__",
           "pose_grid", "pose_bake", "Parameter", "PoseGrid", "PoseBlender"]
