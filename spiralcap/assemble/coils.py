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


#: Each shape's pair class (in :mod:`coils`) and the design key of its size.
SHAPES: dict[str, tuple[str, str]] = {
    "circle": ("HelmholtzPair", "radius_m"),
    "square": ("SquarePair", "side_m"),
    "rectangle": ("RectanglePair", "sides_m"),
}
_SIZE_WORDS = {"side_m": "a side in [0.02, 4] m", "sides_m": "two sides [a, b] in [0.02, 4] m"}


def _size_key(design: Mapping[str, Any], ax: str) -> str:
    """The key that sets the size of pair ``ax``: ``radius_m`` of a circle, ``side_m`` of a
    square, ``sides_m`` of a rectangle.

    Raises
    ------
    InputError
        A square or rectangle without its size key, or another shape's size key set (a
        circle's ``radius_m`` has a default and is ignored by the other shapes).
    """
    key = f"coils.{ax}."
    shape = design.get(key + "shape", "circle")
    own = SHAPES[shape][1]
    for other_shape, (_, other) in SHAPES.items():
        if other != own and other != "radius_m" and design.get(key + other) is not None:
            raise InputError(
                key + other,
                design.get(key + other),
                f"no value for a {shape} pair ({key}shape = '{shape}' is sized by {key}{own}); "
                f"set {key}shape = '{other_shape}' to use it",
            )
    if own != "radius_m" and design.get(key + own) is None:
        raise InputError(
            key + own,
            None,
            f"{_SIZE_WORDS[own]}: {key}shape = '{shape}' needs {key}{own} "
            f"(a {shape} pair does not use {key}radius_m)",
        )
    return key + own


def _pair(design: Mapping[str, Any], ax: str, packing: float) -> Any:
    """The pair on axis ``ax`` (its shape's class) with the design's cross-key checks."""
    import coils

    key = f"coils.{ax}."
    size_key = _size_key(design, ax)
    cls = getattr(coils, SHAPES[design.get(key + "shape", "circle")][0])
    value = design[size_key]
    sizes = tuple(float(v) for v in value) if isinstance(value, list) else (float(value),)
    size = min(sizes)
    turns = design[key + "turns"]
    wire_mm = design[key + "wire_diameter_mm"]
    separation = design.get(key + "separation_m") or cls.default_spacing_m(sizes)
    aspect = design.get(key + "pack_aspect", 1.0)
    area = turns * math.pi * (wire_mm * 1e-3) ** 2 / 4.0 / packing
    depth, width = math.sqrt(area / aspect), math.sqrt(area * aspect)
    if depth >= size:
        raise InputError(
            key + "wire_diameter_mm",
            wire_mm,
            f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
            f"for {turns} turns at packing factor {packing:g}, aspect {aspect:g}) is "
            f"below {size_key} = {value} m",
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
    from spiralcap.assemble.measured import measured_of

    measured = measured_of(design, ax)  # a lab's measured R and L: the pair answers them
    return cls(**{cls._SIZE_KEY: value if len(sizes) == 1 else sizes}, **common, measured=measured)


def _noun(size_key: str) -> str:
    """'a radius', 'a side' or 'sides' for a size key."""
    noun = size_key.rpartition(".")[2][:-2]
    return noun if noun.endswith("s") else "a " + noun


def build_coils(design: Mapping[str, Any]) -> Any:
    """The three-axis Helmholtz system a design describes.

    Parameters
    ----------
    design : Mapping
        Validated design (``spiralcap.design.Design``): keys ``coils.{x,y,z}.shape`` (circle,
        square or rectangle), ``radius_m`` (a circle), ``side_m`` (a square) or ``sides_m`` (a
        rectangle), ``turns``, ``wire_diameter_mm`` (converted to m), optional
        ``separation_m`` (default: the radius, 0.5445 x the side, or a rectangle's spacing with
        zero centre curvature) and ``coils.packing_factor``.

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
                f"{_noun(size_key)} at which the {a} and {b} winding packs "
                f"do not intersect (as solids they overlap by at least {-gap * 1e3:.3g} mm; "
                "nest the pairs with sizes further apart or thinner packs)",
            )
    from spiralcap.assemble.calibration import apply_calibration

    return apply_calibration(design, ThreeAxisHelmholtz(**pairs))
