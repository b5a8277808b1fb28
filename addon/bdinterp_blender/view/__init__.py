"""What is drawn in the viewport: the distortion colours (distortion), onion skins (onion), motion
trails (motion_trails), their GPU batches (overlay) and Grease Pencil drawings bound to meshes
(drawing_bind)."""
