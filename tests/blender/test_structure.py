"""The add-on's modules import one way: each only imports modules of lower layers."""

import ast
import glob
import os

from conftest import ROOT

FOLDER = os.path.join(ROOT, "addon", "bdinterp_blender")
# The subpackages' layers; the base modules (core, names, actions, timing) are layer 0 and api a
# layer of its own (strokes beside it: neither imports the other). Within one subpackage a module
# imports only those listed before it in MODULES.
LAYER = {"": 0, "shapes": 1, "files": 2, "keys": 2, "view": 3, "params": 3, "api": 4, "strokes": 4,
         "ui": 5, "__init__": 6}


def modules_in_order():
    """__init__.MODULES: the dotted module names, lowest first (the reload idiom's order)."""
    tree = ast.parse(open(os.path.join(FOLDER, "__init__.py"), encoding="utf-8").read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and node.targets[0].id == "MODULES":
            return list(ast.literal_eval(node.value))
    raise AssertionError("__init__.py has no MODULES")


def layer(name):
    package = name.rpartition(".")[0]
    return LAYER[name] if name in ("api", "__init__") else LAYER[package]


def imports(name):
    """Dotted names of the add-on's modules that module `name` imports (also inside functions)."""
    path = os.path.join(FOLDER, *name.split(".")) + ".py"
    package = name.split(".")[:-1]
    out = set()
    for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
        if isinstance(node, ast.ImportFrom) and node.level >= 1:
            base = package[:len(package) - (node.level - 1)]
            target = base + (node.module.split(".") if node.module else [])
            for alias in node.names:
                full = ".".join(target + [alias.name])
                out.add(full if os.path.exists(os.path.join(FOLDER, *full.split(".")) + ".py")
                        else ".".join(target))
    return {m for m in out if m}


def test_modules_import_downwards_only():
    order = modules_in_order() + ["__init__"]
    files = {os.path.relpath(p, FOLDER)[:-3].replace(os.sep, ".")
             for p in glob.glob(os.path.join(FOLDER, "**", "*.py"), recursive=True)}
    files = {f for f in files if not f.endswith("__init__") or f == "__init__"}
    assert files == set(order), "a new module needs a place in __init__.MODULES: %s" % (
        files ^ set(order))
    rank = {m: i for i, m in enumerate(order)}
    wrong = []
    for m in order:
        for dep in imports(m):
            if dep not in rank:
                continue  # a subpackage itself (its __init__ holds only a docstring)
            same = dep.rpartition(".")[0] == m.rpartition(".")[0]
            if layer(dep) > layer(m) or (same and rank[dep] >= rank[m]) or \
                    (not same and layer(dep) == layer(m)):
                wrong.append((m, dep))
    assert wrong == []
    # and nothing reaches into another module's private names
    short = {m.rpartition(".")[2] for m in order}
    private = [(m, n.attr) for m in order
               for n in ast.walk(ast.parse(open(os.path.join(FOLDER, *m.split(".")) + ".py",
                                                encoding="utf-8").read()))
               if isinstance(n, ast.Attribute) and n.attr.startswith("_") and not n.attr.startswith("__")
               and isinstance(n.value, ast.Name) and n.value.id in short]
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
    from bdinterp_blender.ui import properties
    assert [item[0] for item in properties.METHOD_ITEMS] == list(bd.METHODS)
