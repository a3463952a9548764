"""Design keys ``coils.*`` -> :class:`coils.ThreeAxisHelmholtz` (SI), with cross-key checks."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from spiralcap.errors import InputError

__all__ = ["build_coils", "pack_clearance_m"]

_RING_SAMPLES = 2048


def _ring_points(axis: int, radius_m: float, centre_m: float, n: int) -> np.ndarray:
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    pts = np.zeros((n, 3))
    u, v = [k for k in range(3) if k != axis]
    pts[:, u], pts[:, v], pts[:, axis] = radius_m * np.cos(phi), radius_m * np.sin(phi), centre_m
    return pts


def _distance_to_ring(
    points: np.ndarray, axis: int, radius_m: float, centre_m: float
) -> np.ndarray:
    radial = np.sqrt(np.sum(np.delete(points, axis, axis=1) ** 2, axis=1))
    return np.hypot(radial - radius_m, points[:, axis] - centre_m)


def pack_clearance_m(pair_a: Any, pair_b: Any) -> float:
    """Least distance between the mean-turn circles of two orthogonal pairs, less their packs.

    The mean turns are circles; the gap is their smallest distance (circle sampled at 2048
    points, exact distance to the other circle) minus half the two pack sides. Negative means
    the winding packs intersect.

    Parameters
    ----------
    pair_a, pair_b : coils.HelmholtzPair
        Two pairs on different axes.

    Returns
    -------
    float
        Clearance, m.
    """
    gaps = []
    for sa, sb in itertools.product((-0.5, 0.5), repeat=2):
        pts = _ring_points(
            pair_a.axis_index, pair_a.radius_m, sa * pair_a.separation_m, _RING_SAMPLES
        )
        dist = _distance_to_ring(pts, pair_b.axis_index, pair_b.radius_m, sb * pair_b.separation_m)
        gaps.append(dist.min())
    return float(min(gaps)) - 0.5 * (pair_a.winding_pack_side_m + pair_b.winding_pack_side_m)


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
        or packs of two pairs that intersect (``coils.A.radius_m`` of the inner pair).
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
                f"(they overlap by {-gap:.3g} m; nest the pairs with distinct "
                "radii)",
            )
    return ThreeAxisHelmholtz(**pairs)
