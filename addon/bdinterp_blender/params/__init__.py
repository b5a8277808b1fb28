"""Pose parameters: poses on 1D to 3D grids of parameter values (angles that wrap, groups that
combine), blended live with bounded distortion and driven by sliders, keyframes, drivers or bones.

props (Object.bdi_grids) -> live (handlers: the blend follows the values) -> setup (pose_grid,
drive_by_bone, remove_pose_grid) -> ui (panel section, operators). The weights and the blend itself are bdinterp.pose_grid's.
"""


def register():
    from . import live, props, ui
    props.register()
    live.register()
    ui.register()


def unregister():
    from . import live, props, ui
    ui.unregister()
    live.unregister()
    props.unregister()
