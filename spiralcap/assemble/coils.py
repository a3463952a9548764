"""Design keys ``coils.*`` -> :class:`coils.ThreeAxisHelmholtz` (SI), with cross-key checks."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from typing import Any

from spiralcap.core.errors import InputError

__all__ = ["build_coils", "pack_clearance_m"]


def pack_clearance_m(pair_a: Any, pair_b: Any) -> float:
    """Least distance between the winding packs of two pairs as solids, m (negative: they
    overlap); :func:`coils.clearance.pack_clearance_m`."""
    from coils.clearance import pack_clearance_m as exact

    return exact(pair_a, pair_b)


def _size_key(design: Mapping[str, Any], ax: str) -> str:
    """The key that sets the size of pair ``ax``: ``radius_m``, or ``side_m`` for a square.

    Raises
    ------
    InputError
        A square pair without ``side_m``, or ``side_m`` on a circular pair.
    """
    key = f"coils.{ax}."
    side = design.get(key + "side_m")
    if design.get(key + "shape", "circle") == "square":
        if side is None:
            raise InputError(
                key + "side_m",
                None,
                f"a side in [0.02, 4] m: {key}shape = 'square' needs {key}side_m "
                f"(a square pair does not use {key}radius_m)",
            )
        return key + "side_m"
    if side is not None:
        raise InputError(
            key + "side_m",
            side,
            f"no value for a circular pair ({key}shape = 'circle' is sized by {key}radius_m); "
            f"set {key}shape = 'square' to use a side",
        )
    return key + "radius_m"


def _pair(design: Mapping[str, Any], ax: str, packing: float) -> Any:
    """The pair on axis ``ax`` (circular or square) with the design's cross-key checks."""
    from coils import HelmholtzPair, SquarePair
    from coils.square_pair import SQUARE_HELMHOLTZ_RATIO

    key = f"coils.{ax}."
    size_key = _size_key(design, ax)
    size = design[size_key]
    square = size_key.endswith("side_m")
    turns = design[key + "turns"]
    wire_mm = design[key + "wire_diameter_mm"]
    separation = design.get(key + "separation_m") or (
        SQUARE_HELMHOLTZ_RATIO * size if square else size
    )
    aspect = design.get(key + "pack_aspect", 1.0)
    area = turns * math.pi * (wire_mm * 1e-3) ** 2 / 4.0 / packing
    depth, width = math.sqrt(area / aspect), math.sqrt(area * aspect)
    if depth >= size:
        raise InputError(
            key + "wire_diameter_mm",
            wire_mm,
            f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
            f"for {turns} turns at packing factor {packing:g}, aspect {aspect:g}) is "
            f"below {size_key} = {size:g} m",
        )
    if width >= separation:
        raise InputError(
            key + "separation_m",
            separation,
            f"more than the winding pack width {width:.4g} m, else the two "
            "coils of the pair overlap",
        )
    common = {
        "turns": turns,
        "axis": ax,
        "separation_m": separation,
        "wire_diameter_m": wire_mm * 1e-3,
        "packing_factor": packing,
        "pack_aspect": aspect,
    }
    if square:
        return SquarePair(side_m=size, **common)
    return HelmholtzPair(radius_m=size, **common)


def build_coils(design: Mapping[str, Any]) -> Any:
    """The three-axis Helmholtz system a design describes.

    Parameters
    ----------
    design : Mapping
        Validated design (``spiralcap.design.Design``): keys ``coils.{x,y,z}.shape`` (circle
        or square), ``radius_m`` (a circle) or ``side_m`` (a square), ``turns``,
        ``wire_diameter_mm`` (converted to m), optional ``separation_m`` (default: the radius,
        or 0.5445 x the side) and ``coils.packing_factor``.

    Returns
    -------
    coils.ThreeAxisHelmholtz
        A :class:`coils.calibration.CalibratedHelmholtz` when the design carries a
        ``[calibration]`` table (``spiralcap.assemble.calibration``).

    Raises
    ------
    InputError
        Naming the design key: a square pair without ``side_m`` or a circle with one
        (``coils.A.side_m``), a winding pack as large as the coil's radius or side
        (``coils.A.wire_diameter_mm``), coils of a pair that overlap (``coils.A.separation_m``),
        or packs of two pairs that intersect as solids (``coils.A.radius_m`` or ``side_m`` of
        the inner pair; closer than ``coils.min_clearance_mm`` but apart is a failed check, not
        an error).
    """
    from coils import ThreeAxisHelmholtz

    packing = design["coils.packing_factor"]
    pairs = {ax: _pair(design, ax, packing) for ax in ("x", "y", "z")}
    for a, b in itertools.combinations("xyz", 2):
        gap = pack_clearance_m(pairs[a], pairs[b])
        if gap < 0.0:
            inner = min((a, b), key=lambda k: pairs[k].radius_m)
            size_key = _size_key(design, inner)
            raise InputError(
                size_key,
                design[size_key],
                f"a {size_key.rpartition('.')[2][:-2]} at which the {a} and {b} winding packs "
                f"do not intersect (as solids they overlap by at least {-gap * 1e3:.3g} mm; "
                "nest the pairs with sizes further apart or thinner packs)",
            )
    from spiralcap.assemble.calibration import apply_calibration

    return apply_calibration(design, ThreeAxisHelmholtz(**pairs))
