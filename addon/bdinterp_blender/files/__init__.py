"""Files in: painting readers (painting_files, bounded, no bpy), Mesh from Image (sprite_mesh) and
the layered import of a painting as cut-out pieces (layered_import)."""
