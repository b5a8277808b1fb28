"""Frames written into the file: the playback slider and its drivers (playback), bake jobs
(baking), keyframes for export (export), characters of several objects (character) and live mode,
which recomputes the shape on every change (live)."""
