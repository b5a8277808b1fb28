"""The add-on's modules import one way: each only imports modules of lower layers."""

import ast
import glob
import os

from conftest import ROOT

LAYERS = [["core", "names", "actions", "overlay", "painting_files", "pivots"], ["timing", "mesh_io"], ["rig"], ["settings"], ["solve"],
          ["playback", "distortion", "sprite_mesh"], ["baking", "export", "layered_import"], ["character"], ["posing"],
          ["live"], ["api", "motion_trails", "drawing_bind"], ["properties", "operators", "pose_operators", "onion"],
          ["ui"], ["__init__"]]
RANK = {m: i for i, layer in enumerate(LAYERS) for m in layer}


def imports(path):
    """Sibling modules imported anywhere in the file (also inside functions)."""
    out = set()
    for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                out.add(node.module.split(".")[0])
            else:
                out |= {a.name for a in node.names}
    return out


def test_modules_import_downwards_only():
    folder = os.path.join(ROOT, "addon", "bdinterp_blender")
    modules = {os.path.basename(p)[:-3]: p for p in glob.glob(os.path.join(folder, "*.py"))}
    assert set(modules) == set(RANK), "a new module needs a layer: %s" % (set(modules) ^ set(RANK))
    wrong = [(m, dep) for m, p in modules.items() for dep in imports(p)
             if dep in RANK and RANK[dep] >= RANK[m] and dep != m]
    assert wrong == []
    # and nothing reaches into another module's private names
    private = [(m, n.attr) for m, p in modules.items()
               for n in ast.walk(ast.parse(open(p, encoding="utf-8").read()))
               if isinstance(n, ast.Attribute) and n.attr.startswith("_") and not n.attr.startswith("__")
               and isinstance(n.value, ast.Name) and n.value.id in RANK]
    assert private == []


def test_enabling_imports_neither_numpy_nor_the_core(addon):
    """Heavy imports wait for the first bake/live frame (Blender itself starts without numpy)."""
    from conftest import json_lines, run_blender
    expr = ("import sys, json; sys.path.insert(0, %r); import addon_loader; a = addon_loader.enable(); "
            "print('JSON:' + json.dumps({'numpy': 'numpy' in sys.modules, "
            "'core': any(m.startswith('bdinterp.') or m == 'bdinterp' for m in sys.modules), "
            "'enabled': hasattr(a, 'bake') and hasattr(__import__('bpy').types.Object, 'bdi')}))"
            % os.path.join(ROOT, "examples", "blender"))
    out = json_lines(run_blender(["--python-expr", expr], env_drop=()))[0]
    assert out == {"numpy": False, "core": False, "enabled": True}


def test_the_method_menu_is_the_packages_list_of_methods(addon, bd):
    from bdinterp_blender import properties
    assert [item[0] for item in properties.METHOD_ITEMS] == list(bd.METHODS)
