"""One pair of scene handlers for every part of the add-on that follows the scene (live mode, pose
grids, the drawings bound to meshes, the onion-skin overlay).

Each depsgraph update and frame change is read once into a Changes record (did the frame move;
which shape-key datablocks, object transforms and shapes the depsgraph reports updated) and
passed to the subscribers in their order: live mode and pose grids write their keys first, then
the drawings follow the meshes, then the overlay decides what to rebuild.  The add-on's own writes of a
shape key (live mode's key, reported by the depsgraph at the next update) are told apart, so
that a subscriber need not read a key's data to find out that nobody else edited it.
"""

import bpy
from bpy.app.handlers import persistent


class Changes:
    """What one update changed: `frame` (a frame change), `keys` (names of the Key datablocks
    whose data or values changed), `own` (those of them the add-on wrote itself since the last
    update and nobody else is known to have touched), `moved` and `shaped` (names of objects
    whose transform, whose evaluated geometry changed)."""

    __slots__ = ("frame", "keys", "own", "moved", "shaped")

    def __init__(self, frame=False, keys=(), own=(), moved=(), shaped=()):
        self.frame, self.keys, self.own = frame, set(keys), set(own)
        self.moved, self.shaped = set(moved), set(shaped)

    def edited_keys(self):
        """The Key datablocks changed by someone other than the add-on's own writes."""
        return self.keys - self.own


_subscribers = []   # (order, function(scene, depsgraph, Changes)), in order
_written = set()    # Key names the add-on wrote since the last update was read


def wrote(key):
    """The add-on wrote the shape keys of `key` (a Key datablock): its next report is ours."""
    _written.add(key.name)


def read(depsgraph, frame):
    """The Changes of one update (depsgraph None: nothing reported but the frame)."""
    keys, moved, shaped = set(), set(), set()
    for update in depsgraph.updates if depsgraph is not None else ():
        data = update.id.original
        if isinstance(data, bpy.types.Key) and update.is_updated_geometry:
            keys.add(data.name)
        elif isinstance(data, bpy.types.Object):
            if update.is_updated_transform:
                moved.add(data.name)
            if update.is_updated_geometry:
                shaped.add(data.name)
    own = keys & _written
    _written.clear()  # writes made by the subscribers below are reported at the next update
    return Changes(frame, keys, own, moved, shaped)


def dispatch(scene, depsgraph, frame):
    changed = read(depsgraph, frame)
    for _, fn in list(_subscribers):
        fn(scene, depsgraph, changed)


@persistent
def on_depsgraph_update(scene, depsgraph):
    dispatch(scene, depsgraph, False)


@persistent
def on_frame_change(scene, depsgraph=None):
    dispatch(scene, depsgraph, True)


HANDLERS = ((bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
            (bpy.app.handlers.frame_change_post, on_frame_change))


def subscribe(order, fn):
    """Call fn(scene, depsgraph, Changes) on every update, after the subscribers of lower order;
    the handlers are installed with the first subscriber."""
    unsubscribe(fn)
    _subscribers.append((order, fn))
    _subscribers.sort(key=lambda s: s[0])
    for handlers, handler in HANDLERS:
        # Drop stale copies left by an earlier load of this module (add-on reload).
        for h in [h for h in handlers if getattr(h, "__name__", "") == handler.__name__
                  and getattr(h, "__module__", "") == handler.__module__]:
            handlers.remove(h)
        handlers.append(handler)


def _same(a, b):
    """a is b, or b reloaded (the same function of a module loaded again)."""
    return a is b or (a.__module__, a.__qualname__) == (b.__module__, b.__qualname__)


def unsubscribe(fn):
    """Stop calling fn; the handlers go with the last subscriber."""
    _subscribers[:] = [s for s in _subscribers if not _same(s[1], fn)]
    if not _subscribers:
        for handlers, handler in HANDLERS:
            if handler in handlers:
                handlers.remove(handler)
