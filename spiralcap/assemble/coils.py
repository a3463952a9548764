"""Design keys ``coils.*`` -> :class:`coils.ThreeAxisHelmholtz` (SI), with cross-key checks."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from typing import Any

from spiralcap.errors import InputError

__all__ = ["build_coils", "pack_clearance_m"]


def pack_clearance_m(pair_a: Any, pair_b: Any) -> float:
    """Least distance between the winding packs of two pairs as solids, m (negative: they
    overlap); :func:`coils.clearance.pack_clearance_m`."""
    from coils.clearance import pack_clearance_m as exact

    return exact(pair_a, pair_b)


def build_coils(design: Mapping[str, Any]) -> Any:
    """The three-axis Helmholtz system a design describes.

    Parameters
    ----------
    design : Mapping
        Validated design (``spiralcap.design.Design``): keys ``coils.{x,y,z}.radius_m``,
        ``turns``, ``wire_diameter_mm`` (converted to m), optional ``separation_m`` (default:
        the radius) and ``coils.packing_factor``.

    Returns
    -------
    coils.ThreeAxisHelmholtz

    Raises
    ------
    InputError
        Naming the design key: a winding pack as large as the coil radius
        (``coils.A.wire_diameter_mm``), coils of a pair that overlap (``coils.A.separation_m``),
        or packs of two pairs that intersect as solids (``coils.A.radius_m`` of the inner pair;
        closer than ``coils.min_clearance_mm`` but apart is a failed check, not an error).
    """
    from coils import HelmholtzPair, ThreeAxisHelmholtz

    packing = design["coils.packing_factor"]
    pairs = {}
    for ax in ("x", "y", "z"):
        key = f"coils.{ax}."
        radius, turns = design[key + "radius_m"], design[key + "turns"]
        wire_mm = design[key + "wire_diameter_mm"]
        separation = design.get(key + "separation_m") or radius
        aspect = design.get(key + "pack_aspect", 1.0)
        area = turns * math.pi * (wire_mm * 1e-3) ** 2 / 4.0 / packing
        depth, width = math.sqrt(area / aspect), math.sqrt(area * aspect)
        if depth >= radius:
            raise InputError(
                key + "wire_diameter_mm",
                wire_mm,
                f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
                f"for {turns} turns at packing factor {packing:g}, aspect {aspect:g}) is "
                f"below {key}radius_m = {radius:g} m",
            )
        if width >= separation:
            raise InputError(
                key + "separation_m",
                separation,
                f"more than the winding pack width {width:.4g} m, else the two "
                "coils of the pair overlap",
            )
        pairs[ax] = HelmholtzPair(
            radius_m=radius,
            turns=turns,
            axis=ax,
            separation_m=separation,
            wire_diameter_m=wire_mm * 1e-3,
            packing_factor=packing,
            pack_aspect=aspect,
        )
    for a, b in itertools.combinations("xyz", 2):
        gap = pack_clearance_m(pairs[a], pairs[b])
        if gap < 0.0:
            inner = min((a, b), key=lambda k: pairs[k].radius_m)
            raise InputError(
                f"coils.{inner}.radius_m",
                pairs[inner].radius_m,
                f"a radius at which the {a} and {b} winding packs do not intersect "
                f"(as solids they overlap by at least {-gap * 1e3:.3g} mm; nest the pairs "
                "with radii further apart or thinner packs)",
            )
    return ThreeAxisHelmholtz(**pairs)
