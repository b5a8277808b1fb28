"""Reading and writing planar meshes and frame sequences.

Formats
-------
OBJ
    ``v x y [z]`` vertex lines and ``f i j k ...`` face lines with 1-based
    indices (``i/vt/vn`` forms and negative, relative indices are accepted;
    n-gons are split into a triangle fan).  Other lines are ignored.  If every
    vertex has z == 0 (or no z), positions are returned as (n,2), otherwise
    as (n,3) (the core accepts planar 3D shapes).  Written files use
    ``v x y 0`` lines for 2D positions.

Two-key JSON
    One file holding a source and a target with shared faces::

        {"faces": [[0, 1, 2], ...],            # 0-based triangles
         "shapes": {"source": [[x, y], ...],   # (n,2) or (n,3)
                    "target": [[x, y], ...]}}

    ``"shapes"`` may hold more named shapes (for blending); the pair is
    ``"source"`` and ``"target"``.
"""

import json
import os

import numpy as np

__all__ = ["read_obj", "write_obj", "read_json", "write_json", "read_pair",
           "write_frames"]


def read_obj(path):
    """Read an OBJ mesh.

    Returns
    -------
    V : (n,2) float64, or (n,3) if some z is nonzero.
    F : (m,3) int32, 0-based, n-gons triangulated by ear clipping.

    Raises
    ------
    ValueError naming the file and line for malformed lines, indices out of
    range, or a file with no faces; OSError if the file cannot be read.
    """
    # Imported here: examples/character/make_character.py loads this file by
    # path in Blender (no package, so no relative import) to write OBJs.
    from .polygon import triangulate
    verts, polygons = [], []
    with open(path, "rb") as f:
        for lineno, raw in enumerate(f, 1):
            where = f"{path}:{lineno}"
            try:
                words = raw.split(b"#", 1)[0].decode("utf-8").split()
            except UnicodeDecodeError:
                raise ValueError(f"{where}: bytes that are not UTF-8 outside a "
                                 f"comment") from None
            if not words:
                continue
            if words[0] == "v":
                verts.append(_parse_vertex(words[1:], where))
            elif words[0] == "f":
                polygons.append(_parse_face(words[1:], len(verts), where))
    if not polygons:
        raise ValueError(f"{path}: no faces ('f' lines) found")
    V = np.array(verts, dtype=np.float64).reshape(-1, 3)
    top = max(max(p) for p in polygons)
    if top >= len(V):
        # A face may refer forward to a vertex listed later; check at the end.
        raise ValueError(f"{path}: face refers to vertex {top + 1} "
                         f"but the file has only {len(V)} vertices")
    F = np.array([t for p in polygons for t in triangulate(p, V)],
                 dtype=np.int32)
    if np.all(V[:, 2] == 0.0):
        V = V[:, :2]
    return np.ascontiguousarray(V), F


def _parse_vertex(words, where):
    if len(words) < 2:
        raise ValueError(f"{where}: vertex needs at least x and y")
    try:
        xyz = [float(w) for w in words[:3]]
    except ValueError:
        raise ValueError(f"{where}: bad vertex coordinate in "
                         f"'v {' '.join(words)}'") from None
    if not np.all(np.isfinite(xyz)):
        raise ValueError(f"{where}: vertex coordinate is not finite")
    return xyz + [0.0] * (3 - len(xyz))


def _parse_face(words, n_seen, where):
    if len(words) < 3:
        raise ValueError(f"{where}: face needs at least 3 vertices")
    idx = []
    for w in words:
        try:
            i = int(w.split("/", 1)[0])
        except ValueError:
            raise ValueError(f"{where}: bad face index '{w}'") from None
        if i == 0:
            raise ValueError(f"{where}: face index 0 "
                             f"(OBJ indices are 1-based)")
        # Negative indices count back from the last vertex read so far.
        i = i - 1 if i > 0 else n_seen + i
        if i < 0:
            raise ValueError(f"{where}: relative face index '{w}' points "
                             f"before the first vertex")
        idx.append(i)
    return idx


def write_obj(path, V, F, comment=None):
    """Write vertices V (n,2)/(n,3) and faces F (m,3) (0-based) as OBJ."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise ValueError(f"vertices must be (n,2) or (n,3), got {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"faces must be (m,3), got {F.shape}")
    if V.shape[1] == 2:
        V = np.c_[V, np.zeros(len(V))]
    with open(path, "w", encoding="utf-8") as f:
        if comment:
            for line in str(comment).splitlines():
                f.write(f"# {line}\n")
        # repr-exact floats so a written frame reads back bit-identical.
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
        f.writelines(f"f {i + 1} {j + 1} {k + 1}\n" for i, j, k in F.tolist())


def read_json(path):
    """Read the two-key JSON form.

    Returns
    -------
    faces : (m,3) int32.
    shapes : dict name -> (n,d) float64, all with the same shape.
    """
    with open(path, encoding="utf-8") as f:
        try:
            data = json.load(f)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}:{e.lineno}: invalid JSON: "
                             f"{e.msg}") from None
        except UnicodeDecodeError as e:
            raise ValueError(f"{path}: not UTF-8 (byte {e.start})") from None
    if not (isinstance(data, dict) and "faces" in data
            and "shapes" in data):
        raise ValueError(f"{path}: expected an object with keys 'faces' "
                         f"and 'shapes'")
    try:
        F = np.array(data["faces"], dtype=np.int32)
        shapes = {str(k): np.array(v, dtype=np.float64)
                  for k, v in dict(data["shapes"]).items()}
    except (TypeError, ValueError) as e:
        raise ValueError(f"{path}: non-numeric or ragged data ({e})") from None
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"{path}: 'faces' must be a list of index triples")
    for name, V in shapes.items():
        if V.ndim != 2 or V.shape[1] not in (2, 3):
            raise ValueError(f"{path}: shape '{name}' must be a list of "
                             f"[x, y] or [x, y, z] points")
        if F.size and (F.min() < 0 or F.max() >= len(V)):
            raise ValueError(f"{path}: face index out of range for shape "
                             f"'{name}' with {len(V)} vertices")
    return F, shapes


def write_json(path, faces, shapes):
    """Write faces (m,3) and a dict of named shapes in the two-key form."""
    data = {"faces": np.asarray(faces).tolist(),
            "shapes": {k: np.asarray(v, dtype=np.float64).tolist()
                       for k, v in shapes.items()}}
    with open(path, "w", encoding="utf-8") as f:
        json.dump(data, f)


def read_pair(source, target=None):
    """Load a source/target pair with shared faces.

    ``read_pair("a.obj", "b.obj")`` reads two OBJ files, which must have the
    same faces; ``read_pair("pair.json")`` reads the two-key JSON form.

    Returns (source (n,d), target (n,d), faces (m,3) int32).
    """
    if target is None:
        if not str(source).lower().endswith(".json"):
            raise ValueError(f"{source}: a single input must be a two-key "
                             f".json file; give SOURCE and TARGET for OBJ")
        F, shapes = read_json(source)
        missing = {"source", "target"} - shapes.keys()
        if missing:
            raise ValueError(f"{source}: 'shapes' lacks "
                             f"{', '.join(sorted(missing))}")
        X0, X1 = shapes["source"], shapes["target"]
    else:
        X0, F = read_obj(source)
        X1, F1 = read_obj(target)
        if not np.array_equal(F, F1):
            detail = (f"{len(F)} vs {len(F1)} triangles" if len(F) != len(F1)
                      else "same count, different indices")
            raise ValueError(f"{source} and {target} have different faces "
                             f"({detail})")
    if X0.shape[0] != X1.shape[0]:
        raise ValueError(f"source has {len(X0)} vertices but target has "
                         f"{len(X1)}")
    if X0.shape[1] != X1.shape[1]:
        # One file may be flat (z dropped) and the other planar 3D.
        X0, X1 = (np.c_[X, np.zeros(len(X))] if X.shape[1] == 2 else X
                  for X in (X0, X1))
    return X0, X1, F


def write_frames(directory, frames, faces, *, prefix="frame", ts=None):
    """Write frames (k,n,d) as ``directory/prefix_0000.obj`` etc.

    ts, if given, (k,) times written as a comment in each file.
    Returns the list of written paths.
    """
    os.makedirs(directory, exist_ok=True)
    frames = np.asarray(frames)
    width = max(4, len(str(len(frames) - 1)))
    paths = []
    for i, X in enumerate(frames):
        p = os.path.join(directory, f"{prefix}_{i:0{width}d}.obj")
        write_obj(p, X, faces,
                  comment=None if ts is None else f"t = {float(ts[i])!r}")
        paths.append(p)
    return paths
