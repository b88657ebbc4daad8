"""Parametric parts for build123d users: a designed spring's flexure ring and camshaft.

``sc.FlexureRing(spring)`` and ``sc.Camshaft(spring)`` are the solids ``springcad build``
makes (:mod:`springcad.geometry.disk`), built from one spring of a :class:`Design`; each
is a build123d ``Part`` to place, fuse or export like any other. The whole stack, every
part placed, named and coloured, is :meth:`springcad.Build.compound`.

Part frame: the stack axis is z, flexure 0 / pocket 0 point along +y, the part starts
at z = 0. Units: mm.

Example:
    >>> import springcad as sc
    >>> s1 = sc.design_job("templates/paper_S1.toml").springs["S1"]
    >>> ring, cam = sc.FlexureRing(s1), sc.Camshaft(s1)
    >>> ring.volume                     # mm^3
"""

from __future__ import annotations

from springcad.api.results import Design, Spring, Verification
from springcad.options import api_door, check_number, refuse

__all__ = ["Camshaft", "FlexureRing"]


def _spring_design(spring):
    """The internal :class:`~springcad.design.spring.SpringDesign` of ``spring``: an API
    :class:`Spring`, or a SpringDesign itself (what the geometry builders take).

    Raises:
        OptionError: anything else (a whole design names the springs to choose from).
    """
    from springcad.design.spring import SpringDesign  # numpy: not on ``import springcad``

    if isinstance(spring, Spring):
        return spring.raw
    if isinstance(spring, SpringDesign):
        return spring
    if isinstance(spring, (Design, Verification)):
        names = list((spring if isinstance(spring, Design) else spring.design).springs)
        raise refuse("spring", f"a {type(spring).__name__}", "takes one designed spring",
                     f"choose one: design.springs[{names[0]!r}] (springs: {', '.join(names)})")
    raise refuse("spring", type(spring).__name__, "takes one designed spring "
                 "(sc.design_job(...).springs[name])")


@api_door
def FlexureRing(spring):  # noqa: N802 (a part constructor, named like build123d's)
    """The flexure ring of a designed spring: rim, N flexures with tip balls, root fillets
    and rim holes, a z-prism of the design's exact profile.

    Args:
        spring: a :class:`Spring` (``design.springs[name]``).

    Returns:
        A build123d ``Part`` (:class:`springcad.geometry.disk.FlexureRing`): z from 0 to
        the spring's thickness, outer radius ``spring.outer_radius_mm`` (mm); ``.info``
        carries its title, material and dimensions for drawings.

    Raises:
        OptionError: ``spring`` is not one designed spring.
        GeometryError: the CAD kernel could not make the solid.
    """
    from springcad.geometry.disk import FlexureRing as Ring

    return Ring(_spring_design(spring))


@api_door
def Camshaft(spring, toothed_length_mm: float | None = None):  # noqa: N802 (as build123d's)
    """A floating camshaft for a designed spring: its teeth cut to the spring's cam
    profile, its D bore taking a D shaft of ``hardware.shaft_diameter_mm``, no hub.

    The camshafts of a stack (end camshafts with turned hubs, camshafts shared by springs
    joined shaft-to-shaft) are in :meth:`springcad.Build.compound`.

    Args:
        spring: a :class:`Spring` (``design.springs[name]``).
        toothed_length_mm: length of the teeth (mm); default the spring's thickness.

    Returns:
        A build123d ``Part`` (:class:`springcad.geometry.disk.Camshaft`): z from 0 to
        ``toothed_length_mm``, tooth tips on the radius ``cam_tip_radius_mm`` of the
        design (mm).

    Raises:
        OptionError: ``spring`` is not one designed spring, or the length is not positive.
        GeometryError: the CAD kernel could not make the solid.
    """
    from springcad.design.hardware import FLAT_RATIO
    from springcad.geometry.disk import Camshaft as Cam

    s = _spring_design(spring)
    length = s.thickness_mm if toothed_length_mm is None else toothed_length_mm
    check_number("toothed_length_mm", length, 0.0, 1000.0, low_open=True, unit=" mm")
    return Cam(s, length, 0.0, "d_flat", "", s.hardware.shaft_diameter_mm, FLAT_RATIO)
