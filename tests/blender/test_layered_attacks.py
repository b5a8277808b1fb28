"""Every hostile painting of tests/python/test_painting_attacks.py imported through File > Import >
Layered painting in Blender: the operator reports an error naming the file, within 2 s, and every
datablock of the file is as it was (none added, none renamed). Seconds are CPU seconds."""
import os
import sys
import time

import bpy
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import test_painting_attacks as attacks  # noqa: E402

COLLECTIONS = ("objects", "meshes", "images", "materials", "node_groups", "textures", "collections",
               "actions", "scenes")


def census():
    return {name: sorted(b.name for b in getattr(bpy.data, name)) for name in COLLECTIONS}


def refused_in_blender(path):
    bpy.ops.mesh.primitive_plane_add()  # a file with something in it
    before = census()
    start = time.process_time()  # CPU time: a loaded machine does not fail the bound
    with pytest.raises(RuntimeError) as error:
        bpy.ops.bdinterp.import_layered(filepath=str(path))
    assert time.process_time() - start < attacks.SECONDS
    assert repr(str(path)) in str(error.value)
    assert census() == before
    return str(error.value)


@pytest.mark.parametrize("case", sorted(attacks.ORA))
def test_hostile_ora_imports_nothing(addon, tmp_path, case):
    write, says = attacks.ORA[case]
    path = tmp_path / "painting.ora"
    write(path)
    assert says in refused_in_blender(path)


@pytest.mark.parametrize("case", sorted(attacks.COA))
def test_hostile_coa_imports_nothing(addon, tmp_path, case):
    write, says = attacks.COA[case]
    folder = tmp_path / "painting"
    folder.mkdir()
    assert says in refused_in_blender(write(folder))
