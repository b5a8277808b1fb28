"""Property-based fuzzing of the painting readers (hypothesis, derandomized so that CI runs the same
cases every time): OpenRaster files built from random stacks (random tags, nesting, attributes of
numbers, garbage and huge values, images that are PNGs, lying PNGs or junk), then possibly
corrupted byte by byte; COA JSON files of random nodes and paths (inside, absolute, climbing out).
Whatever the file, a reader returns layers that obey its limits or raises ValueError naming the
file, within 2 s a case; any other exception is a failure. CASES of each (>= 10^4 in all)."""
import os
import shutil
import tempfile

from hypothesis import HealthCheck, given, settings, strategies as st

import painting_attacks as pa

pf = pa.reader()
CASES = 5000
FUZZ = settings(max_examples=CASES, derandomize=True, database=None, deadline=2000,
                suppress_health_check=list(HealthCheck))

NUMBERS = st.one_of(st.integers(-10 ** 7, 10 ** 7).map(str), st.floats().map(repr),
                    st.sampled_from(["", "1e400", "-inf", "nan", "0x10", "9" * 400, "1,5"]),
                    st.text(max_size=8))
IMAGES = st.one_of(st.builds(pa.png, st.integers(1, 4), st.integers(1, 4)),
                   st.builds(lambda w, h: pa.png(1, 1, header=(w, h)),
                             st.integers(0, 2 ** 32 - 1), st.integers(0, 2 ** 32 - 1)),
                   st.binary(max_size=64))
SRCS = st.sampled_from(["a.png", "b.png", "data/c.png", "missing.png", "", "../a.png"])


def _attrs(draw):
    keys = draw(st.lists(st.sampled_from(["x", "y", "opacity", "visibility", "name", "src"]),
                         unique=True, max_size=6))
    values = {"visibility": st.sampled_from(["visible", "hidden", "x"]), "name": st.text(max_size=6),
              "src": SRCS}
    return {k: draw(values.get(k, NUMBERS)) for k in keys}


def _quote(value):
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


@st.composite
def stacks(draw, depth=0):
    """stack.xml's body: random elements, stacks nested a few levels deep."""
    parts = []
    for _ in range(draw(st.integers(0, 4 if depth < 3 else 0))):
        tag = draw(st.sampled_from(["layer", "stack", "text", "layer"]))
        attrs = "".join(' %s="%s"' % (k, _quote(v)) for k, v in _attrs(draw).items())
        inner = draw(stacks(depth + 1)) if tag == "stack" else ""
        parts.append("<%s%s>%s</%s>" % (tag, attrs, inner, tag))
    return "".join(parts)


@st.composite
def ora_files(draw):
    """The bytes of an .ora: a random stack and images, possibly corrupted."""
    import io
    import zipfile
    stack = "<image><stack>%s</stack></image>" % draw(stacks())
    if draw(st.booleans()):
        stack = stack.encode("utf-8", "surrogatepass")[:draw(st.integers(0, 400))]
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", draw(st.sampled_from([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED]))) as z:
        z.writestr("stack.xml", stack)
        for name in draw(st.lists(st.sampled_from(["a.png", "b.png", "data/c.png"]), unique=True)):
            z.writestr(name, draw(IMAGES))
    data = bytearray(out.getvalue())
    for at, byte in draw(st.lists(st.tuples(st.integers(0, len(data) - 1), st.integers(0, 255)),
                                  max_size=3)):
        data[at] = byte
    return bytes(data)


def _check(path, read):
    try:
        layers = read(path)
    except ValueError as e:
        assert repr(os.fspath(path)) in str(e), str(e)
        return []
    assert len(layers) <= pf.MAX_LAYERS
    for layer in layers:
        assert 0.0 <= layer.opacity <= 1.0
        assert abs(layer.x) <= pf.MAX_DEPTH * pf.MAX_OFFSET and abs(layer.y) <= pf.MAX_DEPTH * pf.MAX_OFFSET
    return layers


@FUZZ
@given(ora_files())
def test_fuzz_ora(data):
    folder = tempfile.mkdtemp()
    try:
        path = os.path.join(folder, "painting.ora")
        with open(path, "wb") as f:
            f.write(data)
        for layer in _check(path, pf.ora_layers):
            w, h = pf.png_size(layer.data[:24])  # what Blender will decode was checked
            assert w * h <= pf.MAX_PIXELS
    finally:
        shutil.rmtree(folder)


JSON = st.recursive(st.one_of(st.none(), st.booleans(), st.integers(), st.floats(), st.text(max_size=6)),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                                max_size=3), max_leaves=8)
PATHS = st.one_of(st.sampled_from(["s/a.png", "s/b.png", "s/../s/a.png", "../out.png", "/etc/passwd",
                                   "s/junk.png", "s", "C:\\x.png", "s\\..\\..\\out.png", ""]),
                  st.text(max_size=12))
NODES = st.fixed_dictionaries({}, optional={
    "name": st.one_of(st.text(max_size=5), JSON), "resource_path": st.one_of(PATHS, JSON),
    "position": st.one_of(st.lists(st.one_of(st.integers(), st.floats()), max_size=3), JSON),
    "z": st.one_of(st.integers(), st.floats(), JSON), "opacity": st.one_of(st.floats(), JSON),
    "tiles_x": st.one_of(st.integers(-2, 2000), JSON), "tiles_y": st.integers(-2, 2000),
    "frame_index": st.integers(-2, 10)})


@FUZZ
@given(st.one_of(st.lists(NODES, max_size=4).map(lambda n: {"nodes": n}), JSON), st.binary(max_size=8))
def test_fuzz_coa(doc, junk):
    import json
    folder = tempfile.mkdtemp()
    try:
        inside = os.path.join(folder, "p")
        pa.coa(inside, [], {"s/a.png": pa.png(2, 2), "s/b.png": pa.png(1, 1, header=(1 << 20, 1 << 20)),
                            "s/junk.png": b"GIF89a"})
        with open(os.path.join(folder, "out.png"), "wb") as f:
            f.write(pa.png(2, 2))
        path = os.path.join(inside, "painting.json")
        with open(path, "wb") as f:
            f.write(json.dumps(doc).encode() + junk)
        for layer in _check(path, pf.coa_layers):
            real = os.path.realpath(layer.file)
            assert real.startswith(os.path.realpath(inside) + os.sep), layer.file
    finally:
        shutil.rmtree(folder)
