"""The sidebar panels' draw code, run against a recording layout (no UI in background mode)."""

import bpy
import pytest

from conftest import bent_strip


class Layout:
    """Stands in for bpy.types.UILayout: checks every property and operator it is asked to show."""

    def __init__(self, log):
        self.log = log

    def _sub(self, *args, **kw):
        return Layout(self.log)

    row = column = box = split = _sub

    def prop(self, data, name, **kw):
        if name.startswith('["'):
            assert name[2:-2] in data.keys(), name
        else:
            assert name in data.bl_rna.properties, name
        self.log.append(("prop", name))

    def prop_search(self, data, name, search_data, search_name, **kw):
        assert name in data.bl_rna.properties and search_name in search_data.bl_rna.properties
        self.log.append(("prop_search", name))

    def operator(self, idname, **kw):
        module, op = idname.split(".")
        assert hasattr(getattr(bpy.ops, module), op), idname
        self.log.append(("operator", idname))
        return type("Props", (), {})()

    def label(self, text="", **kw):
        self.log.append(("label", text))

    def template_curve_mapping(self, data, name, **kw):
        assert name in data.bl_rna.properties
        self.log.append(("curve", name))

    def __setattr__(self, name, value):  # scale_y, enabled, ...
        object.__setattr__(self, name, value)


PANELS = ["BDINTERP_PT_main", "BDINTERP_PT_inbetweens", "BDINTERP_PT_poses", "BDINTERP_PT_live",
          "BDINTERP_PT_distortion"]


def draw_all(context):
    log = []
    for name in PANELS:
        cls = getattr(bpy.types, name)
        panel = type("P", (), {"layout": Layout(log)})()
        if cls.poll(context):
            if hasattr(cls, "draw_header"):
                cls.draw_header(panel, context)
            cls.draw(panel, context)
    return log


@pytest.mark.parametrize("configure", ["plain", "everything"])
def test_panels_draw(addon, configure):
    obj = bent_strip()
    bpy.context.view_layer.objects.active = obj
    if configure == "everything":
        obj.bdi.target = "Bend"
        addon.bake(obj, target="Bend", count=2)
        bpy.ops.bdinterp.easing_curve_new()
        obj.bdi.anchor = 'VERTEX'
        bpy.ops.bdinterp.pose_add()
        obj.bdi.live_error = "bdinterp: live mode turned off for Strip: something went wrong"
    log = draw_all(bpy.context)
    names = {entry[1] for entry in log}
    assert {"source", "target", "count", "easing", "anchor", "bdinterp.bake"} <= names
    if configure == "everything":
        assert {'["Bend.bdi"]', "mapping", "anchor_vertex", "key", "weight"} <= names
        assert any(kind == "label" and "live mode turned off" in text for kind, text in log)


def test_panel_without_shape_keys_explains(addon):
    bpy.ops.mesh.primitive_plane_add()
    log = draw_all(bpy.context)
    assert ("label", "Add at least two shape keys") in log
