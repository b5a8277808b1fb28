"""The layers of a layered painting read from its file (no bpy): OpenRaster (.ora: a zip with
stack.xml and a PNG per layer, as Krita, GIMP and MyPaint write it) and COA Tools' JSON (a .json
listing `nodes`, each a sprite's PNG by `resource_path` relative to the file, its top-left corner
`position` in the canvas and its draw order `z`, larger in front, as COA Tools' Krita, GIMP and
Photoshop exporters write it). Every layer's image is found before anything is returned, so a
broken file is refused whole.

A painting may come from anyone, so reading one is bounded: the limits below are checked while
reading (stack.xml is parsed as a stream, a layer's PNG unpacked in chunks), so that a file made
to exhaust memory or time is refused as soon as it passes one, with a ValueError naming the file
(and the layer). Every layer must be a PNG whose header gives its size; COA images must lie in the
painting's folder.
"""
import collections
import json
import lzma
import math
import os
import struct
import xml.etree.ElementTree as ET
import zipfile
import zlib

MAX_LAYERS = 1000                 # visible layers (or COA nodes) in one painting
MAX_PIXELS = 1 << 26              # pixels of one layer's image (64 Mpx, e.g. 8192 x 8192)
MAX_BYTES = 128 << 20             # bytes unpacked from an .ora (stack.xml and PNGs) or COA JSON + images
MAX_JSON_BYTES = 2 << 20          # a COA JSON file (parsed whole: its objects cost ~30 times its bytes)
MAX_DEPTH = 64                    # nesting of stack.xml's elements (groups in groups)
MAX_ELEMENTS = 20 * MAX_LAYERS    # elements of stack.xml, hidden ones and unknown tags included
MAX_ENTRIES = 4 * MAX_LAYERS      # members of an .ora's zip (its PNGs, thumbnails, merged image)
MAX_OFFSET = 1_000_000            # |x|, |y| of a layer or group, pixels
MAX_TILES = 1024                  # columns or rows of a COA sprite sheet
CHUNK = 1 << 20                   # bytes unpacked at a time

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

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


def png_size(head):
    """(width, height) from the first 24 bytes of a PNG (its signature and IHDR chunk); ValueError
    if it is not a PNG or its size is beyond MAX_PIXELS."""
    if len(head) < 24 or not head.startswith(PNG_SIGNATURE) or head[12:16] != b"IHDR":
        raise ValueError("it is not a PNG image")
    w, h = struct.unpack(">II", head[16:24])
    if w == 0 or h == 0:
        raise ValueError("its PNG header gives an empty size %d x %d" % (w, h))
    if w * h > MAX_PIXELS:
        raise ValueError("its PNG header gives %d x %d pixels, more than the limit of %d"
                         % (w, h, MAX_PIXELS))
    return w, h


class Budget:
    """Bytes left to unpack from one painting (MAX_BYTES)."""

    def __init__(self):
        self.left = MAX_BYTES

    def take(self, count):
        self.left -= count
        if self.left < 0:
            raise ValueError("it unpacks to more than %d bytes (the limit)" % MAX_BYTES)


# ---------------------------------------------------------------------------------------- OpenRaster

def _zip_entries(f):
    """The member count of the zip open as f, from its end-of-central-directory record (read before
    zipfile parses a directory of any size); None if there is none (zipfile says why)."""
    size = f.seek(0, os.SEEK_END)
    f.seek(max(0, size - 22 - 0xFFFF))
    tail = f.read()
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) < at + 22:
        return None
    return struct.unpack("<H", tail[at + 10:at + 12])[0]  # 0xFFFF: a zip64 count, too many


def _member(z, name, budget):
    """The bytes of the PNG member `name`, unpacked in chunks against the budget, its header
    (PNG_SIGNATURE, size) checked before the rest is unpacked."""
    out = bytearray()
    with z.open(name) as f:
        head = f.read(24)
        png_size(head)
        budget.take(len(head))
        out += head
        while True:
            chunk = f.read(CHUNK)
            if not chunk:
                return bytes(out)
            budget.take(len(chunk))
            out += chunk


def _coordinate(node, key, default):
    """A finite number attribute of node within MAX_OFFSET (ValueError saying which)."""
    text = node.get(key)
    try:
        value = default if text is None else float(text)
    except ValueError:
        raise ValueError("%s %r of %r is not a number" % (key, text, node.get("name"))) from None
    if not math.isfinite(value) or abs(value) > MAX_OFFSET:
        raise ValueError("%s %r of %r is not a number within +-%d" % (key, text, node.get("name"),
                                                                        MAX_OFFSET))
    return value


class _Stack:
    """stack.xml read as a stream of its elements (no tree kept): the layers of the first stack of
    the image, groups flattened (their offsets added, opacities multiplied), hidden layers and
    groups skipped; a stack's first child is drawn on top."""

    def __init__(self):
        self.parser = ET.XMLPullParser(("start", "end"))
        self.open = []      # per open element: (dx, dy, opacity) of a visible stack, "image", or None
        self.elements, self.top_seen = 0, False
        self.layers = []    # (name, src, x, y, opacity), top first

    def feed(self, data):
        self.parser.feed(data)
        self._events()

    def close(self):
        self.parser.close()
        self._events()
        if self.open or not self.elements:
            raise ET.ParseError("stack.xml has no complete image element")

    def _events(self):
        for event, node in self.parser.read_events():
            if event == "end":
                self.open.pop()
                if len(node):  # its children are done with: keep memory to the open elements
                    del node[:]
                continue
            self.elements += 1
            if self.elements > MAX_ELEMENTS or len(self.open) >= MAX_DEPTH:
                raise ValueError("stack.xml has more than %d elements or a nesting deeper than %d"
                                 % (MAX_ELEMENTS, MAX_DEPTH))
            self.open.append(self._start(node))

    def _start(self, node):
        parent = self.open[-1] if self.open else "root"
        if parent == "root":
            return "image"
        if parent == "image":
            if node.tag != "stack" or self.top_seen:
                return None
            self.top_seen = True
            return (0.0, 0.0, 1.0)
        if parent is None or node.get("visibility", "visible") == "hidden":
            return None
        dx, dy, opacity = parent
        x, y = dx + int(_coordinate(node, "x", 0)), dy + int(_coordinate(node, "y", 0))
        alpha = opacity * min(1.0, max(0.0, _coordinate(node, "opacity", 1.0)))
        if node.tag == "stack":
            return (x, y, alpha)
        if node.tag == "layer":
            if len(self.layers) >= MAX_LAYERS:
                raise ValueError("it has more than %d visible layers" % MAX_LAYERS)
            src = node.get("src")
            self.layers.append((node.get("name", src), src, x, y, alpha))
        return None


def _stack_layers(z, budget):
    stack = _Stack()
    with z.open("stack.xml") as f:
        while True:
            chunk = f.read(CHUNK // 16)
            if not chunk:
                break
            budget.take(len(chunk))
            stack.feed(chunk)
    stack.close()
    return stack.layers


def ora_layers(path):
    """An OpenRaster file's visible layers: groups flattened (their offsets added and opacities
    multiplied), hidden layers and groups skipped."""
    where, name = os.fspath(path), None
    try:
        with open(path, "rb") as f:
            entries = _zip_entries(f)
            if entries is not None and entries > MAX_ENTRIES:
                raise ValueError("its zip has %d members, more than the limit of %d"
                                 % (entries, MAX_ENTRIES))
            with zipfile.ZipFile(f) as z:
                budget, names, images, found = Budget(), set(z.namelist()), {}, []
                for name, src, x, y, alpha in _stack_layers(z, budget):
                    if src not in names:
                        raise ValueError("its image %r is missing" % (src,))
                    if src not in images:  # several layers may show one image: unpacked once
                        images[src] = _member(z, src, budget)
                    found.append(Layer(name, x, y, alpha, (1, 1, 0), images[src], None))
    except ValueError as e:
        raise ValueError("%r%s: %s" % (where, "" if name is None else ": layer %.200r" % name, e)) from None
    except (OSError, EOFError, zipfile.BadZipFile, zipfile.LargeZipFile, KeyError, ET.ParseError,
            zlib.error, lzma.LZMAError, struct.error, NotImplementedError,
            RuntimeError) as e:  # NotImplementedError: an unknown compression; RuntimeError: encrypted
        raise ValueError(_unreadable(where, name, e)) from None
    return found[::-1]


def _unreadable(where, name, error):
    """Why the OpenRaster file `where` could not be read, in plain words: not found, damaged (a
    zip's start without its end: cut short while saved or copied), no stack.xml, or not one."""
    if isinstance(error, FileNotFoundError):
        return "%r not found: check the file's name and folder" % where
    if isinstance(error, zipfile.BadZipFile) and name is None:
        try:
            with open(where, "rb") as f:
                zipped = f.read(4) == b"PK\x03\x04"
        except OSError:
            zipped = False
        if zipped:
            return ("%r is damaged (it ends too early: %s): save or copy it again from the "
                    "painting program" % (where, error))
    if isinstance(error, KeyError) and name is None and "stack.xml" in str(error):
        return "%r is not an OpenRaster file: it has no stack.xml" % where
    return "%r is not an OpenRaster file%s (%s: %s)" % (
        where, "" if name is None else " (layer %.200r)" % name, type(error).__name__, error)


# ---------------------------------------------------------------------------------------- COA Tools

def _number(value, bound=math.inf):
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(value) and abs(value) <= bound
    except OverflowError:  # an int too large for a float
        return False


def _coa_field(node, key, check, default, wants):
    value = node.get(key, default)
    if not check(value):
        raise ValueError("%r must be %s, not %.200r" % (key, wants, value))
    return value


def _inside(folder, src):
    """The path of `src` in the painting's folder; ValueError if it is absolute or leaves it."""
    if "\0" in src or os.path.isabs(src) or src.startswith(("\\", "/")) or ":" in src \
            or ".." in src.replace("\\", "/").split("/"):
        raise ValueError("'resource_path' %r must be a path inside the painting's folder" % src)
    file = os.path.join(folder, src)
    real, root = os.path.realpath(file), os.path.realpath(folder)
    if os.path.commonpath([real, root]) != root:  # a link that leads out
        raise ValueError("'resource_path' %r leads out of the painting's folder" % src)
    return file


def _coa_image(file, budget):
    """Checks the PNG at file (header, size) against the limits."""
    if not os.path.isfile(file):
        raise ValueError("its image %r is missing" % file)
    budget.take(os.path.getsize(file))
    with open(file, "rb") as f:
        head = f.read(24)
    try:
        png_size(head)
    except ValueError as e:
        raise ValueError("its image %r: %s" % (file, e)) from None


def _coa_layer(folder, node, budget):
    """One of COA Tools' nodes as a Layer (ValueError saying which field is wrong)."""
    if not isinstance(node, dict):
        raise ValueError("a node must be an object, not %.200r" % (node,))
    name = _coa_field(node, "name", lambda v: isinstance(v, str) and v, None, "a name")
    src = _coa_field(node, "resource_path", lambda v: isinstance(v, str) and v, None, "a file name")
    x, y = _coa_field(node, "position", lambda v: isinstance(v, list) and len(v) == 2
                      and all(_number(c, MAX_OFFSET) for c in v), None,
                      "two numbers within +-%d (the top-left corner)" % MAX_OFFSET)
    columns, rows = (_coa_field(node, key, lambda v: isinstance(v, int) and 1 <= v <= MAX_TILES, 1,
                                "a count in [1, %d]" % MAX_TILES) for key in ("tiles_x", "tiles_y"))
    frame = _coa_field(node, "frame_index", lambda v: isinstance(v, int) and 0 <= v < columns * rows,
                       0, "a frame of the %d x %d tiles" % (columns, rows))
    opacity = node.get("opacity", 1.0)
    if not _number(opacity):  # Krita's exporter writes a placeholder ([0, 0]): the layer is opaque
        opacity = 1.0
    elif not 0.0 <= opacity <= 1.0:
        raise ValueError("'opacity' must lie in [0, 1], not %r" % opacity)
    file = _inside(folder, src)
    _coa_image(file, budget)
    return Layer(name, x, y, float(opacity), (columns, rows, frame), None, file)


def _coa_nodes(path, budget):
    """The `nodes` list of a COA JSON file (at most MAX_JSON_BYTES, MAX_LAYERS nodes)."""
    try:
        with open(path, "rb") as f:
            text = f.read(MAX_JSON_BYTES + 1)
    except OSError as e:
        raise ValueError("it is not a COA Tools JSON file (%s)" % e) from None
    if len(text) > MAX_JSON_BYTES:
        raise ValueError("it is larger than %d bytes (the limit for its JSON)" % MAX_JSON_BYTES)
    budget.take(len(text))
    try:
        doc = json.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, RecursionError) as e:
        raise ValueError("it is not a COA Tools JSON file (%s: %s)" % (type(e).__name__, e)) from None
    except ValueError as e:  # JSON syntax, an int of too many digits
        raise ValueError("it is not a COA Tools JSON file (%s)" % e) from None
    nodes = doc.get("nodes") if isinstance(doc, dict) else None
    if not isinstance(nodes, list):
        raise ValueError("it is not a COA Tools JSON file: it has no list of 'nodes'")
    if len(nodes) > MAX_LAYERS:
        raise ValueError("it has %d nodes, more than the limit of %d" % (len(nodes), MAX_LAYERS))
    return nodes


def coa_layers(path):
    """COA Tools' JSON export's sprites, by z (ties in the file's order); each must name an
    existing PNG inside the file's folder (its sprite sheet's frame for several tiles)."""
    where, budget = os.fspath(path), Budget()
    try:
        nodes = _coa_nodes(path, budget)
    except ValueError as e:
        raise ValueError("%r: %s" % (where, e)) from None
    folder = os.path.dirname(os.path.abspath(path))
    layers = []
    for i, node in enumerate(nodes):
        z = node.get("z") if isinstance(node, dict) else None
        label = node.get("name", "") if isinstance(node, dict) else ""
        try:
            if not _number(z):
                raise ValueError("'z' must be a number (the draw order), not %.200r" % (z,))
            layers.append((z, i, _coa_layer(folder, node, budget)))
        except ValueError as e:
            raise ValueError("%r: node %d %.200r: %s" % (where, i, label, e)) from None
    return [layer for _, _, layer in sorted(layers, key=lambda item: item[:2])]
