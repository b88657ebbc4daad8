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


@_contextlib.contextmanager
def sklearn_deferred():
    """Import build123d inside this block to spare the process the import of scikit-learn
    (~1 s of CPU, 40 % of build123d's import): build123d imports ``sklearn.cluster.DBSCAN``
    at import time for one function springcad never calls (``detect_primitives`` of STL
    meshes).

    Inside the block ``sklearn.cluster`` is a stand-in module whose ``DBSCAN`` imports the
    real class when it is called (any other attribute imports the real module); after it,
    the stand-in is gone from ``sys.modules``, so a later ``import sklearn.cluster`` is the
    real one. Nothing changes when scikit-learn or build123d is already imported."""
    if "sklearn.cluster" in _sys.modules or "build123d" in _sys.modules:
        yield
        return

    def real():
        if _sys.modules.get("sklearn.cluster") is standin:
            del _sys.modules["sklearn.cluster"]
        import importlib

        return importlib.import_module("sklearn.cluster")

    class Standin(_types.ModuleType):
        def __getattr__(self, name):
            if name.startswith("__"):  # the import system's probes (__path__ ...)
                raise AttributeError(name)
            return getattr(real(), name)

    class DBSCAN:
        """scikit-learn's DBSCAN, imported when first made."""

        def __new__(cls, *args, **kwargs):
            return real().DBSCAN(*args, **kwargs)

    standin = Standin("sklearn.cluster", "stand-in while build123d is imported")
    standin.DBSCAN = DBSCAN
    _sys.modules["sklearn.cluster"] = standin
    try:
        yield
    finally:
        if _sys.modules.get("sklearn.cluster") is standin:
            del _sys.modules["sklearn.cluster"]
