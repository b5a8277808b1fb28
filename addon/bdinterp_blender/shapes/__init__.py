"""Shapes from Blender data: shape keys and vertex groups read into arrays (mesh_io), joints from
an armature's bones (rig), one frozen BakeSettings (settings) and the solve from shapes to frames
(solve). Nothing here writes to Blender."""
