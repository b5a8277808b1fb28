"""Builders of painting files, honest and hostile, for the painting readers' tests: PNGs, zips
written by hand (so that sizes, counts and compressed streams can lie), OpenRaster and COA files,
and the reader module itself (addon/bdinterp_blender's painting_files, which needs no bpy)."""
import glob
import importlib.util
import json
import os
import struct
import zipfile
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def reader():
    """The add-on's painting_files module, loaded by path (the add-on package needs bpy)."""
    path, = glob.glob(os.path.join(ROOT, "addon", "bdinterp_blender", "**", "painting_files.py"),
                      recursive=True)
    spec = importlib.util.spec_from_file_location("painting_files", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(w, h, header=None):
    """An RGBA PNG of w x h (transparent); `header` (w, h) writes another size in its IHDR."""
    hw, hh = header or (w, h)
    ihdr = struct.pack(">IIBBBBB", hw, hh, 8, 6, 0, 0, 0)
    rows = b"".join(b"\0" + bytes(4 * w) for _ in range(h))
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", zlib.compress(rows))
            + _chunk(b"IEND", b""))


def raw_zip(members):
    """A zip of members [(name, method, crc, size, stored bytes)] written field by field (sizes,
    CRCs and streams as given, true or not)."""
    out, central = bytearray(), bytearray()
    for name, method, crc, size, data in members:
        name = name.encode() if isinstance(name, str) else name
        central += struct.pack("<4s6H3L5H2L", b"PK\1\2", 20, 20, 0, method, 0, 0x21, crc, len(data),
                               size, len(name), 0, 0, 0, 0, 0, len(out)) + name
        out += struct.pack("<4s5H3L2H", b"PK\3\4", 20, 0, method, 0, 0x21, crc, len(data), size,
                           len(name), 0) + name + data
    count = min(len(members), 0xFFFF)
    return bytes(out + central + struct.pack("<4s4H2LH", b"PK\5\6", 0, 0, count, count,
                                             len(central), len(out), 0))


def deflated_zeros(prefix, gib):
    """(crc, size, raw deflate stream) of `prefix` then `gib` GiB of zeros, built from one
    compressed 16 MiB block repeated (a full flush makes the blocks independent)."""
    block, zeros = 16 << 20, bytes(16 << 20)
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    first = c.compress(prefix + zeros) + c.flush(zlib.Z_FULL_FLUSH)
    again = c.compress(zeros) + c.flush(zlib.Z_FULL_FLUSH)
    count = int(gib * 1024 // 16)
    crc = zlib.crc32(prefix)
    for _ in range(count):
        crc = zlib.crc32(zeros, crc)
    return crc, len(prefix) + count * block, first + again * (count - 1) + c.flush()


def stored(name, data):
    return (name, 0, zlib.crc32(data), len(data), data)


def ora(path, stack, images):
    """An .ora at path with stack.xml `stack` (str or bytes) and members {name: bytes}."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("mimetype", "image/openraster", compress_type=zipfile.ZIP_STORED)
        z.writestr("stack.xml", stack)
        for name, data in images.items():
            z.writestr(name, data)
    return path


def coa(folder, nodes, images, name="painting.json"):
    """A COA Tools JSON file `name` in folder listing nodes, with the files {relative path: bytes}."""
    for rel, data in images.items():
        os.makedirs(os.path.dirname(os.path.join(folder, rel)), exist_ok=True)
        with open(os.path.join(folder, rel), "wb") as f:
            f.write(data)
    path = os.path.join(folder, name)
    with open(path, "w", encoding="utf-8") as f:
        json.dump({"name": "painting", "nodes": nodes}, f)
    return path
