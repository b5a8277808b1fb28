"""Hostile paintings: each crafted file is refused with a ValueError naming the file (and what is
wrong), within 2 s and 200 MB. Each is read in a child process whose address space is capped at
200 MB above what it uses before reading (RLIMIT_AS) and whose Python allocations are traced
(tracemalloc), so that a reader that buffers too much fails there instead of slowing the suite;
its seconds are CPU seconds (a loaded machine does not fail the bound)."""
import json
import os
import subprocess
import sys

import pytest

import painting_attacks as pa

SECONDS, MEGABYTES = 2.0, 200
pf = pa.reader()

CHILD = r"""
import json, resource, sys, time, tracemalloc
sys.path.insert(0, sys.argv[1])
import painting_attacks
reader = painting_attacks.reader()
with open("/proc/self/status") as f:
    used = next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmSize:"))
cap = used + %d * 2**20
resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
tracemalloc.start()
start = time.process_time()
try:
    reader.read_painting(sys.argv[2])
    out = {"error": None}
except BaseException as e:
    out = {"error": type(e).__name__, "message": str(e)}
out["seconds"] = time.process_time() - start
out["peak"] = tracemalloc.get_traced_memory()[1]
print(json.dumps(out))
""" % MEGABYTES


def refused(path):
    """(message, seconds, peak bytes) of reading path in a capped child; fails unless ValueError."""
    run = subprocess.run([sys.executable, "-c", CHILD, os.path.dirname(os.path.abspath(pa.__file__)),
                          str(path)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["error"] == "ValueError", out
    assert repr(str(path)) in out["message"], out["message"]
    assert out["seconds"] < SECONDS, out
    assert out["peak"] < MEGABYTES * 2**20, out
    return out["message"]


PNG = pa.png(4, 3)


def _ora_stack(path, stack):
    return pa.ora(path, stack, {"a.png": PNG})


def _layers(count):
    return "<image><stack>%s</stack></image>" % ('<layer src="a.png"/>' * count)


ORA = {  # name: (writer of the file at path, what the message says)
    "zip bomb (PNG header, 1 GiB of zeros)": (lambda p: p.write_bytes(pa.raw_zip([
        pa.stored("stack.xml", b'<image><stack><layer name="bomb" src="a.png"/></stack></image>'),
        ("a.png", 8) + pa.deflated_zeros(PNG[:33], 1)])),
        "layer 'bomb': it unpacks to more than"),
    "zip bomb (1 GiB of zeros)": (lambda p: p.write_bytes(pa.raw_zip([
        pa.stored("stack.xml", b'<image><stack><layer src="a.png"/></stack></image>'),
        ("a.png", 8) + pa.deflated_zeros(b"", 1)])), "it is not a PNG image"),
    "PNG header claiming 100000 x 100000": (lambda p: pa.ora(p, _layers(1), {
        "a.png": pa.png(2, 2, header=(100000, 100000))}), "100000 x 100000 pixels, more than"),
    "GIF stored as .png": (lambda p: pa.ora(p, _layers(1), {"a.png": b"GIF89a\x01\0\x01\0" + bytes(30)}),
                           "it is not a PNG image"),
    "10^6 layers naming one PNG": (lambda p: _ora_stack(p, _layers(10 ** 6)), "more than 1000 visible"),
    "200000 nested stacks": (lambda p: _ora_stack(p, "<image>" + "<stack>" * 200000 + "</stack>"
                                                  * 200000 + "</image>"), "nesting deeper than 64"),
    "10^6 hidden elements": (lambda p: _ora_stack(p, "<image><stack>%s</stack></image>"
                                                  % ("<x/>" * 10 ** 6)), "more than 20000 elements"),
    "entity expansion": (lambda p: _ora_stack(p, '<?xml version="1.0"?><!DOCTYPE l [<!ENTITY a "aaaaaaaaaa">'
                         + "".join('<!ENTITY %s "%s">' % (chr(98 + i), ("&%s;" % chr(97 + i)) * 10)
                                   for i in range(8))
                         + ']><image><stack><layer name="&i;" src="a.png"/></stack></image>'),
                         "is not an OpenRaster file"),
    "non-UTF-8 stack.xml": (lambda p: _ora_stack(p, b'<image><stack><layer name="\xff\xfe" src="a.png"/>'
                                                 b"</stack></image>"), "is not an OpenRaster file"),
    "huge offset": (lambda p: _ora_stack(p, '<image><stack><layer src="a.png" x="1e400"/></stack></image>'),
                    "x '1e400' of None is not a number within"),
    "NaN opacity": (lambda p: _ora_stack(p, '<image><stack><layer src="a.png" opacity="nan"/></stack>'
                                            "</image>"), "opacity 'nan'"),
    "70000 zip members": (lambda p: p.write_bytes(pa.raw_zip([pa.stored(str(i), b"") for i in range(70000)])),
                          "members, more than the limit of 4000"),
    "member longer than its recorded size": (lambda p: p.write_bytes(pa.raw_zip([
        pa.stored("stack.xml", _layers(1).encode()), ("a.png", 0, 0, 40, PNG)])), "not an OpenRaster file"),
    "not a zip": (lambda p: p.write_bytes(b"PK\3\4" + os.urandom(200)), "is damaged"),  # a zip's start only
    "missing image": (lambda p: pa.ora(p, _layers(1), {}), "its image 'a.png' is missing"),
}


@pytest.mark.parametrize("case", sorted(ORA))
def test_hostile_ora(tmp_path, case):
    write, says = ORA[case]
    path = tmp_path / "painting.ora"
    write(path)
    assert says in refused(path)


def _node(**fields):
    node = {"name": "arm", "resource_path": "sprites/arm.png", "position": [0, 0], "z": 0}
    node.update(fields)
    return node


def _coa(folder, nodes, images=None):
    return pa.coa(str(folder), nodes, {"sprites/arm.png": PNG} if images is None else images)


def _outside(folder):
    """A real PNG beside the painting's folder, and a link to it from inside."""
    (folder.parent / "secret.png").write_bytes(PNG)
    os.makedirs(folder / "sprites", exist_ok=True)
    os.symlink(folder.parent / "secret.png", folder / "sprites" / "link.png")
    return _coa(folder, [_node(resource_path="sprites/link.png")])


def _raw(folder, data):
    (folder / "painting.json").write_bytes(data)
    return folder / "painting.json"


COA = {
    "absolute resource_path": (lambda d: _coa(d, [_node(resource_path=str(d.parent / "secret.png"))]),
                               "must be a path inside the painting's folder"),
    "resource_path climbing out": (lambda d: _coa(d, [_node(resource_path="sprites/../../secret.png")]),
                                   "must be a path inside the painting's folder"),
    "link leading out": (_outside, "leads out of the painting's folder"),
    "NUL in resource_path": (lambda d: _coa(d, [_node(resource_path="sprites/arm.png\0.txt")]),
                             "must be a path inside"),
    "position 1e400": (lambda d: _raw(d, b'{"nodes": [{"name": "arm", "resource_path": "a.png", '
                                         b'"position": [1e400, 0], "z": 0}]}'), "'position' must be"),
    "position 10^4000": (lambda d: _coa(d, [_node(position=[10 ** 4000, 0])]), "'position' must be"),
    "z of 5000 digits": (lambda d: _raw(d, b'{"nodes": [{"z": %s}]}' % (b"9" * 5000)),
                         "is not a COA Tools JSON file"),
    "10^6 nodes": (lambda d: _raw(d, b'{"nodes": [%s{}]}' % (b"{}," * 10 ** 6)), "larger than 2097152"),
    "1001 nodes": (lambda d: _coa(d, [_node()] * 1001), "1001 nodes, more than the limit of 1000"),
    "deep nesting": (lambda d: _raw(d, b"[" * 500000 + b"]" * 500000), "RecursionError"),
    "non-UTF-8": (lambda d: _raw(d, b'{"nodes": [{"name": "\xff\xfe"}]}'), "UnicodeDecodeError"),
    "GIF stored as .png": (lambda d: _coa(d, [_node()], {"sprites/arm.png": b"GIF89a" + bytes(40)}),
                           "it is not a PNG image"),
    "PNG header claiming 100000 x 100000": (lambda d: _coa(d, [_node()], {
        "sprites/arm.png": pa.png(2, 2, header=(100000, 100000))}), "100000 x 100000 pixels"),
    "10^6 tiles": (lambda d: _coa(d, [_node(tiles_x=10 ** 6)]), "'tiles_x' must be a count in [1, 1024]"),
}


@pytest.mark.parametrize("case", sorted(COA))
def test_hostile_coa(tmp_path, case):
    write, says = COA[case]
    folder = tmp_path / "painting"
    folder.mkdir()
    assert says in refused(write(folder))


def test_honest_files_still_read(tmp_path):
    """The limits leave ordinary paintings alone: an .ora with a group and a hidden layer, a COA
    file with two sprites, read with their places and opacities."""
    stack = ('<image w="50" h="40"><stack><layer name="top" src="a.png" x="3" y="4" opacity="0.5"/>'
             '<layer name="gone" src="a.png" visibility="hidden"/>'
             '<stack x="10" y="20" opacity="0.5"><layer name="inner" src="b.png" x="1" y="2"/></stack>'
             '</stack></image>')
    layers = pf.read_painting(pa.ora(tmp_path / "p.ora", stack, {"a.png": PNG, "b.png": pa.png(2, 2)}))
    assert [(l.name, l.x, l.y, l.opacity) for l in layers] == [("inner", 11, 22, 0.5), ("top", 3, 4, 0.5)]
    assert layers[0].data == pa.png(2, 2) and layers[1].data == PNG
    folder = tmp_path / "coa"
    folder.mkdir()
    path = _coa(folder, [_node(z=2, opacity=0.25), _node(name="leg", position=[5, 6], z=1)])
    assert [(l.name, l.x, l.y, l.opacity, l.file) for l in pf.read_painting(path)] == [
        ("leg", 5, 6, 1.0, str(folder / "sprites" / "arm.png")),
        ("arm", 0, 0, 0.25, str(folder / "sprites" / "arm.png"))]
