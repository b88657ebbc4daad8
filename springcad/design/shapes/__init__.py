"""Flexure shapes, one module each, registered by name (:mod:`.registry`).

``straight`` (radial, stiffness width law) and ``serpentine`` (curved, constant-stress
width law); a new shape is a module like these plus its registration. The protocol and
the record are in :mod:`.base`. Light: the shape modules load on first use.
"""

from springcad.design.shapes.registry import (AUTO, BUILT_IN, SHAPES, get, names, register,
                                              size_flexure, tried, unregister)

__all__ = ["AUTO", "BUILT_IN", "SHAPES", "get", "names", "register", "size_flexure", "tried",
           "unregister"]
