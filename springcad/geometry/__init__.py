"""Geometry layer: build123d solids from the design's exact 2D profiles.

``profile`` (faces and prisms from exact curves, contour checks), ``base`` (the
z-prism part base class and measurements), ``disk`` (flexure ring, camshaft),
``spacers``, ``adapters``, ``fasteners``, ``families`` (the registry that builds
each part kind from its plan), ``placement``, ``stack`` (placing the parts of a
stack), ``checks`` with ``edm`` (wire-EDM rules) and ``interference``.
"""

import contextlib as _contextlib
import sys as _sys
import types as _types


#: modules build123d imports at import time for functions springcad never calls, with the
#: names it takes from them: scikit-learn's DBSCAN (``detect_primitives`` of STL meshes;
#: ~1 s of CPU, 40 % of build123d's import) and IPython's pretty printer (``ShapeList``'s
#: ``__str__`` in a notebook; IPython's package import, ~0.6 s of CPU per process)
DEFERRED = {"sklearn.cluster": ("DBSCAN",),
            "IPython.lib.pretty": ("pretty", "RepresentationPrinter")}


def _standin(module: str, names: tuple):
    """A stand-in for ``module`` whose ``names`` import the real module when first used
    (called, or made); any other attribute imports the real module at once."""
    def real():
        if _sys.modules.get(module) is standin:
            del _sys.modules[module]
        import importlib

        return importlib.import_module(module)

    class Standin(_types.ModuleType):
        def __getattr__(self, name):
            if name.startswith("__"):  # the import system's probes (__path__ ...)
                raise AttributeError(name)
            return getattr(real(), name)

    def deferred(name):
        class Deferred:
            __doc__ = f"{module}.{name}, imported when first used."

            def __new__(cls, *args, **kwargs):
                return getattr(real(), name)(*args, **kwargs)

        Deferred.__name__ = Deferred.__qualname__ = name
        return Deferred

    standin = Standin(module, "stand-in while build123d is imported")
    for name in names:
        setattr(standin, name, deferred(name))
    return standin


@_contextlib.contextmanager
def sklearn_deferred():
    """Import build123d inside this block to spare the process the imports of scikit-learn
    and IPython (:data:`DEFERRED`): build123d imports ``sklearn.cluster.DBSCAN`` and
    ``IPython.lib.pretty`` at import time for functions springcad never calls.

    Inside the block each of these modules is a stand-in whose names import the real
    module when first used (a class made, a function called; any other attribute imports
    the real module); after it, the stand-ins are gone from ``sys.modules``, so a later
    import is the real one. Nothing changes for a module already imported, nor when
    build123d is."""
    if "build123d" in _sys.modules:
        yield
        return
    standins = {m: _standin(m, names) for m, names in DEFERRED.items()
                if m not in _sys.modules}
    _sys.modules.update(standins)
    try:
        yield
    finally:
        for module, standin in standins.items():
            if _sys.modules.get(module) is standin:
                del _sys.modules[module]
