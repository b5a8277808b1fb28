"""Pose parameters: poses on 1D to 3D grids of parameter values (angles that wrap, groups that
combine), blended live with bounded distortion and driven by sliders, keyframes, drivers or bones.

live (handlers: the blend follows the values) -> setup (pose_grid, drive_by_bone,
remove_pose_grid) -> bake_grid (in-betweens on a finer grid for linear runtimes). The weights and
the blend itself are bdinterp.pose_grid's; the properties, operators and panel are ui.pose_grids.
"""
