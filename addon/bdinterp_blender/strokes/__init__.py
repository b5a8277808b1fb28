"""Grease Pencil drawings interpolated by bdinterp: drawing (read keys, plan and write in-betweens,
interpolate_drawing) < ops (the operator, its menu entries and panel)."""
