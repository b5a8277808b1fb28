"""InvalidInputError: the ValueError of input that can never succeed, with where it is wrong.

Raised by the compiled core (its InvalidInput) and by this package's own checks alike, built by one
rule (the core's): str(e) is the location then the detail, "shape 1, vertex 7: not planar: ...".
Attributes: detail (what is wrong, without the location), shape, face, vertex (indices into the
caller's shapes, faces and positions; None where the error is not about one).
"""
from . import _core

InvalidInputError = _core.InvalidInputError


def invalid(detail, shape=None, face=None, vertex=None):
    """An InvalidInputError (to raise) with these fields; indices are ints >= 0 or None."""
    def index(i):
        return -1 if i is None else int(i)
    return _core._invalid_input(detail, index(shape), index(face), index(vertex))
