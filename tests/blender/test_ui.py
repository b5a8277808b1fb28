"""The sidebar panels' draw code, run against a recording layout (no UI in background mode)."""

import bpy
import pytest

from conftest import bent_strip


ICONS = set(bpy.types.UILayout.bl_rna.functions["prop"].parameters["icon"].enum_items.keys())


def check_icon(kw):
    assert kw.get("icon", "NONE") in ICONS, kw["icon"]  # e.g. MOD_SHAPEKEY is not in 3.4


class Layout:
    """Stands in for bpy.types.UILayout: checks every property, operator and icon it is asked to
    show."""

    def __init__(self, log):
        self.log = log

    def _sub(self, *args, **kw):
        return Layout(self.log)

    row = column = box = split = _sub

    def prop(self, data, name, **kw):
        check_icon(kw)
        if name.startswith('["'):
            assert name[2:-2] in data.keys(), name
        else:
            assert name in data.bl_rna.properties, name
        self.log.append(("prop", name))
        self.log.append(("text", name, kw.get("text")))

    def prop_search(self, data, name, search_data, search_name, **kw):
        assert name in data.bl_rna.properties and search_name in search_data.bl_rna.properties
        self.log.append(("prop_search", name))
        self.log.append(("text", name, kw.get("text")))

    def operator(self, idname, **kw):
        check_icon(kw)
        module, op = idname.split(".")
        assert hasattr(getattr(bpy.ops, module), op), idname
        self.log.append(("operator", idname))
        return type("Props", (), {})()

    def label(self, text="", **kw):
        check_icon(kw)
        self.log.append(("label", text))

    def template_curve_mapping(self, data, name, **kw):
        assert name in data.bl_rna.properties
        self.log.append(("curve", name))

    def __setattr__(self, name, value):  # scale_y, enabled, ...
        object.__setattr__(self, name, value)


PANELS = ["BDINTERP_PT_main", "BDINTERP_PT_inbetweens", "BDINTERP_PT_expert", "BDINTERP_PT_poses",
          "BDINTERP_PT_live", "BDINTERP_PT_distortion"]


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
    assert {"method", "tolerance"} <= names  # in the Expert sub-panel
    # a label on every field: its own text or a label just before it (the Live header's checkbox
    # is labelled by the panel's title)
    unlabelled = [e[1] for i, e in enumerate(log) if e[0] == "text" and e[2] == "" and e[1] != "live"
                  and log[i - 2][0] != "label"]
    assert unlabelled == []
    labels = [e[1] for e in log if e[0] == "label"]
    if configure == "plain":
        assert "Empty: Basis (reference)" in labels
    if configure == "everything":
        assert {'["Bend.bdi"]', "mapping", "anchor_vertex", "key", "weight"} <= names
        assert any(e[0] == "label" and "live mode turned off" in e[1] for e in log)
        assert "Keys written: 2" in labels and any(t.startswith("Max K ") for t in labels)
        assert "Folded polygons: 0" in labels


def test_live_panel_warns_and_offers_bake(addon):
    obj = bent_strip()
    bpy.context.view_layer.objects.active = obj
    addon.set_live(obj, target="Bend", factor=0.5)
    log = draw_all(bpy.context)
    assert ("operator", "bdinterp.bake_live") in log
    text = " ".join(e[1] for e in log if e[0] == "label")
    assert "needs the bdinterp add-on" in text and "Bake Live to Keys" in text


def test_long_messages_wrap_to_region_width(addon):
    from bdinterp_blender.ui import panels as ui
    region = type("R", (), {"width": 600})()
    context = type("C", (), {"region": region, "preferences": bpy.context.preferences})()
    wide = ui.wrap_width(context)
    region.width = 300
    narrow = ui.wrap_width(context)
    assert narrow < wide and narrow * 7 * bpy.context.preferences.view.ui_scale <= 300
    log = []
    ui.draw_message(Layout(log), "word " * 60, width=narrow)
    lines = [e[1] for e in log if e[0] == "label"]
    assert len(lines) > 1 and all(len(line) <= narrow for line in lines)
    assert " ".join(lines).split() == ("word " * 60).split()  # nothing cut off


def test_panel_without_shape_keys_explains(addon):
    bpy.ops.mesh.primitive_plane_add()
    log = draw_all(bpy.context)
    assert ("label", "Add a pose: a key on every selected piece") in log
    assert ("operator", "bdinterp.add_pose") in log  # the way on, one click


def test_every_icon_in_the_source_exists_in_this_blender(addon):
    """Also icons on paths the draw tests do not reach (degraded mode, preferences, dialogs):
    every icon named anywhere in the add-on's source."""
    import glob
    import os
    import re
    from conftest import ROOT
    src = "".join(open(p, encoding="utf-8").read() for p in glob.glob(
        os.path.join(ROOT, "addon", "bdinterp_blender", "**", "*.py"), recursive=True))
    used = set(re.findall(r"icon='([A-Z0-9_]+)'", src)) | set(re.findall(r"icon=\"([A-Z0-9_]+)\"", src))
    assert len(used) >= 10 and used <= ICONS, used - ICONS
    assert "MOD_SHAPEKEY" not in used  # not in Blender 3.4
