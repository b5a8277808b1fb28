"""The layers of a layered painting read from its file (no bpy): OpenRaster (.ora: a zip with
stack.xml and a PNG per layer, as Krita, GIMP and MyPaint write it) and COA Tools' JSON (a .json
listing `nodes`, each a sprite's PNG by `resource_path` relative to the file, its top-left corner
`position` in the canvas and its draw order `z`, larger in front, as COA Tools' Krita, GIMP and
Photoshop exporters write it). Every layer's image is found before anything is returned, so a
broken file is refused whole."""
import collections
import json
import math
import os
import xml.etree.ElementTree as ET
import zipfile

# name; x, y: the layer's top-left corner in canvas pixels (y downwards); opacity in [0, 1];
# tiles: (columns, rows, frame) of a sprite sheet, the frame counted row by row from the top left;
# data: the PNG's bytes (inside an .ora), or file: its path on disk (COA Tools' sprite folder).
Layer = collections.namedtuple("Layer", "name x y opacity tiles data file")


def read_painting(path):
    """The visible layers of the painting at path, bottom layer first: COA Tools' JSON for a .json,
    else OpenRaster. ValueError naming the file, and the layer, if it cannot be read."""
    if os.fspath(path).lower().endswith(".json"):
        return coa_layers(path)
    return ora_layers(path)


def _float(node, key, default):
    try:
        return float(node.get(key, default))
    except ValueError:
        raise ET.ParseError("%s %r of %r is not a number" % (key, node.get(key), node.get("name"))) from None


def ora_layers(path):
    """An OpenRaster file's visible layers: groups flattened (their offsets added and opacities
    multiplied), hidden layers and groups skipped."""
    try:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("stack.xml"))
            names = set(z.namelist())
            found = []

            def walk(stack, dx, dy, opacity):  # a stack's first child is drawn on top
                for node in stack:
                    if node.get("visibility", "visible") == "hidden":
                        continue
                    x, y = dx + int(_float(node, "x", 0)), dy + int(_float(node, "y", 0))
                    alpha = opacity * min(1.0, max(0.0, _float(node, "opacity", 1.0)))
                    if node.tag == "stack":
                        walk(node, x, y, alpha)
                    elif node.tag == "layer":
                        name, src = node.get("name", node.get("src")), node.get("src")
                        if src not in names:
                            raise ValueError("%r: the image %r of layer %r is missing from the "
                                             "file" % (os.fspath(path), src, name))
                        found.append(Layer(name, x, y, alpha, (1, 1, 0), z.read(src), None))
            top = root.find("stack")
            walk(top if top is not None else [], 0, 0, 1.0)
    except (OSError, zipfile.BadZipFile, KeyError, ET.ParseError) as e:
        raise ValueError(_unreadable(os.fspath(path), e)) from None
    return found[::-1]


def _unreadable(path, error):
    """Why the OpenRaster file at path could not be read, in plain words."""
    if isinstance(error, FileNotFoundError):
        return "%r not found: check the file's name and folder" % path
    if isinstance(error, zipfile.BadZipFile):
        try:
            with open(path, "rb") as f:
                zipped = f.read(4) == b"PK\x03\x04"
        except OSError:
            zipped = False
        if zipped:  # a zip's start without its end: cut short while it was saved or copied
            return ("%r is damaged (it ends too early: %s): save or copy it again from the "
                    "painting program" % (path, error))
    if isinstance(error, KeyError):
        return "%r is not an OpenRaster file: it has no stack.xml" % path
    return "%r is not an OpenRaster file (%s)" % (path, error)


def _number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _coa_field(node, key, check, default, wants):
    value = node.get(key, default)
    if not check(value):
        raise ValueError("%r must be %s, not %r" % (key, wants, value))
    return value


def _coa_layer(folder, node):
    """One of COA Tools' nodes as a Layer (ValueError saying which field is wrong)."""
    if not isinstance(node, dict):
        raise ValueError("a node must be an object, not %r" % (node,))
    name = _coa_field(node, "name", lambda v: isinstance(v, str) and v, None, "a name")
    src = _coa_field(node, "resource_path", lambda v: isinstance(v, str) and v, None, "a file name")
    x, y = _coa_field(node, "position", lambda v: isinstance(v, list) and len(v) == 2
                      and all(_number(c) for c in v), None, "two numbers (the top-left corner)")
    columns, rows = (_coa_field(node, key, lambda v: isinstance(v, int) and v >= 1, 1, "a count >= 1")
                     for key in ("tiles_x", "tiles_y"))
    frame = _coa_field(node, "frame_index", lambda v: isinstance(v, int) and 0 <= v < columns * rows,
                       0, "a frame of the %d x %d tiles" % (columns, rows))
    opacity = node.get("opacity", 1.0)
    if not _number(opacity):  # Krita's exporter writes a placeholder ([0, 0]): the layer is opaque
        opacity = 1.0
    elif not 0.0 <= opacity <= 1.0:
        raise ValueError("'opacity' must lie in [0, 1], not %r" % opacity)
    file = os.path.join(folder, src)
    if not os.path.isfile(file):
        raise ValueError("its image %r is missing" % file)
    return Layer(name, x, y, float(opacity), (columns, rows, frame), None, file)


def coa_layers(path):
    """COA Tools' JSON export's sprites, by z (ties in the file's order); each must name an
    existing image (its sprite sheet's frame for several tiles)."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ValueError("%r is not a COA Tools JSON file (%s)" % (os.fspath(path), e)) from None
    nodes = doc.get("nodes") if isinstance(doc, dict) else None
    if not isinstance(nodes, list):
        raise ValueError("%r is not a COA Tools JSON file: it has no list of 'nodes'" % os.fspath(path))
    folder = os.path.dirname(os.path.abspath(path))
    layers = []
    for i, node in enumerate(nodes):
        z = node.get("z") if isinstance(node, dict) else None
        label = node.get("name", "") if isinstance(node, dict) else ""
        try:
            if not _number(z):
                raise ValueError("'z' must be a number (the draw order), not %r" % (z,))
            layers.append((z, i, _coa_layer(folder, node)))
        except ValueError as e:
            raise ValueError("%r: node %d %r: %s" % (os.fspath(path), i, label, e)) from None
    return [layer for _, _, layer in sorted(layers, key=lambda item: item[:2])]
