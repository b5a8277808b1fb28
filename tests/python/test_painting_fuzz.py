"""Property-based fuzzing of the painting readers (hypothesis, derandomized so that CI runs the same
cases every time): OpenRaster files built from random stacks (random tags, nesting, attributes of
numbers, garbage and huge values, images that are PNGs, lying PNGs or junk), then possibly
corrupted byte by byte; COA JSON files of random nodes and paths (inside, absolute, climbing out).
Whatever the file, a reader returns layers that obey its limits or raises ValueError naming the
file, within 2 s of CPU time a file; any other exception is a failure. Each drawn file is read as drawn and
with VARIANTS - 1 random corruptions of its bytes (the .ora) or of its JSON's tail (COA), so that
EXAMPLES drawn make EXAMPLES * VARIANTS files read per reader (>= 10^4 in all) at a quarter of
hypothesis's cost of drawing."""
import json
import os
import shutil
import tempfile
import time

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import painting_attacks as pa

pf = pa.reader()
EXAMPLES, VARIANTS = 1250, 4
SECONDS = 2.0  # of CPU time per file read
FUZZ = settings(max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
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
    if draw(st.booleans()):  # as a painting program writes them
        return {"src": "a.png", "x": str(draw(st.integers(-99, 99))), "y": str(draw(st.integers(-99, 99))),
                "opacity": repr(draw(st.floats(0, 1)))}
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
    """The bytes of an .ora (a random stack and images) and VARIANTS - 1 corruptions of it."""
    import io
    import zipfile
    stack = "<image><stack>%s</stack></image>" % draw(stacks())
    if draw(st.booleans()):
        stack = stack.encode("utf-8", "surrogatepass")[:draw(st.integers(0, 400))]
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", draw(st.sampled_from([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED]))) as z:
        z.writestr("stack.xml", stack)
        if draw(st.booleans()):
            z.writestr("a.png", pa.png(2, 2))
        for name in draw(st.lists(st.sampled_from(["b.png", "data/c.png"]), unique=True)):
            z.writestr(name, draw(IMAGES))
    data, out = out.getvalue(), [out.getvalue()]
    for _ in range(VARIANTS - 1):
        bad = bytearray(data)
        for at, byte in draw(st.lists(st.tuples(st.integers(0, len(data) - 1), st.integers(0, 255)),
                                      min_size=1, max_size=3)):
            bad[at] = byte
        out.append(bytes(bad))
    return out


READ = {"files": 0, "refused": 0, "layers": 0}  # how the cases went (printed with pytest -s)


def _check(path, read):
    """read(path)'s layers, checked against the limits; [] where it was refused as it should be."""
    READ["files"] += 1
    start = time.process_time()  # the reader's own time: a busy machine does not fail the test
    try:
        layers = read(path)
    except ValueError as e:
        assert repr(os.fspath(path)) in str(e), str(e)
        READ["refused"] += 1
        return []
    finally:
        assert time.process_time() - start < SECONDS
    READ["layers"] += len(layers)
    assert len(layers) <= pf.MAX_LAYERS
    for layer in layers:
        assert 0.0 <= layer.opacity <= 1.0
        assert abs(layer.x) <= pf.MAX_DEPTH * pf.MAX_OFFSET and abs(layer.y) <= pf.MAX_DEPTH * pf.MAX_OFFSET
    return layers


@pytest.fixture(scope="module")
def folder():
    """A folder for the files read, and beside the COA painting's folder an image outside it."""
    top = tempfile.mkdtemp()
    pa.coa(os.path.join(top, "p"), [], {"s/a.png": pa.png(2, 2), "s/junk.png": b"GIF89a",
                                        "s/b.png": pa.png(1, 1, header=(1 << 20, 1 << 20))})
    with open(os.path.join(top, "out.png"), "wb") as f:
        f.write(pa.png(2, 2))
    yield top
    shutil.rmtree(top)
    print("painting fuzz:", READ)


@FUZZ
@given(files=ora_files())
def test_fuzz_ora(folder, files):
    path = os.path.join(folder, "painting.ora")
    for data in files:
        with open(path, "wb") as f:
            f.write(data)
        for layer in _check(path, pf.ora_layers):
            w, h = pf.png_size(layer.data[:24])  # what Blender will decode was checked
            assert w * h <= pf.MAX_PIXELS


JSON = st.recursive(st.one_of(st.none(), st.booleans(), st.integers(), st.floats(), st.text(max_size=6)),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner,
                                                                                max_size=3), max_leaves=8)
PATHS = st.one_of(st.sampled_from(["s/a.png", "s/b.png", "s/../s/a.png", "../out.png", "/etc/passwd",
                                   "s/junk.png", "s", "C:\\x.png", "s\\..\\..\\out.png", ""]),
                  st.text(max_size=12))
GOOD = st.fixed_dictionaries({"name": st.text(min_size=1, max_size=5),
                              "resource_path": st.sampled_from(["s/a.png", "s/../s/a.png"]),
                              "position": st.lists(st.integers(-9, 9), min_size=2, max_size=2),
                              "z": st.integers(-3, 3)})
NODES = GOOD | st.fixed_dictionaries({}, optional={
    "name": st.one_of(st.text(max_size=5), JSON), "resource_path": st.one_of(PATHS, JSON),
    "position": st.one_of(st.lists(st.one_of(st.integers(), st.floats()), max_size=3), JSON),
    "z": st.one_of(st.integers(), st.floats(), JSON), "opacity": st.one_of(st.floats(), JSON),
    "tiles_x": st.one_of(st.integers(-2, 2000), JSON), "tiles_y": st.integers(-2, 2000),
    "frame_index": st.integers(-2, 10)})


MIXED = st.tuples(GOOD, NODES).map(lambda pair: {**pair[0], **pair[1]})  # a good node, a field spoilt
DOCS = st.one_of(st.lists(NODES | MIXED, max_size=4).map(lambda nodes: {"nodes": nodes}), JSON)


@FUZZ
@given(doc=DOCS,
       junk=st.lists(st.tuples(st.integers(0, 64), st.binary(max_size=4)), min_size=VARIANTS - 1,
                     max_size=VARIANTS - 1))
def test_fuzz_coa(folder, doc, junk):
    inside = os.path.join(folder, "p")
    path, text = os.path.join(inside, "painting.json"), json.dumps(doc).encode()
    for cut, tail in [(0, b"")] + junk:  # as drawn, then cut short and followed by junk
        with open(path, "wb") as f:
            f.write(text[:len(text) - cut] + tail)
        for layer in _check(path, pf.coa_layers):
            real = os.path.realpath(layer.file)
            assert real.startswith(os.path.realpath(inside) + os.sep), layer.file
