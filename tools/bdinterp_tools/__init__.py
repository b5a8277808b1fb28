"""Repository tools around bdinterp, not part of the installed package.

meshes (test and example meshes; Delaunay via scipy), bench (the Python benchmark) and convergence
(the Fig. 6 experiment). Use with ``PYTHONPATH=tools`` (the tests, scripts and examples add it).
"""
