"""Hardware as optimisation variables: coil windings, coil radii, the capsule magnet, the spiral.

The numbers :class:`optimize.system.Constants` holds for a fixed design are written here as
backend-generic expressions of the hardware (numpy floats or CasADi symbols), so the same NLP
(:mod:`optimize.problem`) sizes hardware and operating point together:

- centre gain of a pair, two coaxial loops of N turns at ±s/2: g = μ0 N R² / (R² + s²/4)^{3/2}
  (Biot–Savart on the axis), times a pack correction (exact filament model / this formula);
- resistance ρ(T) · 2N·2πR / (π d²/4); copper mass density · 2N·2πR · π d²/4;
- self inductance by Stefan's formula (Rosa & Grover 1912, eq. 91) and the mutual inductance
  N² M(R, R, s) by Maxwell's formula (coils.coaxial_mutual_inductance_H), times a pack
  correction; the thermal winding pack (side c = sqrt(N π d²/4 / packing), mean radius R:
  coils.thermal.WindingPack) is an exact function of the turns, wire and radius, so the hot
  spot and the self-consistent resistance follow the freed hardware with no frozen factor;
- magnet moment B_r π/4 (D² − D_i²) L / μ0 (capsule.Magnet).

Frozen per outer iteration (recomputed exactly at each new hardware, then re-solved, until they
settle): the packs' radiation view factors (a ray trace, coils.viewfactors: settled within
1e-3), the two pack corrections, the workspace field factor (the weakest field over the
workspace and headings per tesla: exact differentiation through the 13 x 15 field-ellipse
minimum would cost more than it gains; it moves by < 1e-3 over the radius ranges here), the
gap between the mean turns of two orthogonal pairs (linearised in the two radii) and the
clearance correction below.

Clearance rows (docs/coils-clearance.md). The packs are solid rings of rectangular section; their
least distance (coils.clearance, exact) has no closed form for crossed axes. Each ring lies in
the torus of tube radius half its section's diagonal, so ``gap(mean turns) - (diag_a + diag_b)/2``
is a smooth lower bound, conservative by at most ``(diag - max(w, h))/2`` per pack (0.21 of a
square pack's side). The row holds that bound plus the frozen correction δ = exact - bound
at the outer iteration's hardware (δ >= 0), so at the settled hardware the row is the exact
clearance; every buildable neighbour is then checked with the exact distance.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from spiralcap.core import backend as bk
from spiralcap.core.constants import COPPER_DENSITY_kg_m3, MU0_T_m_per_A

AXES = ("x", "y", "z")
COIL_QUANTITIES = ("radius_m", "turns", "wire_diameter_m", "pack_aspect")
#: The sizes of the pairs of other shapes in place of ``radius_m`` (each pair class's
#: ``SIZE_NAMES``; ``coils.system.PAIR_CLASSES``).
OTHER_SIZES = ("side_m", "side_a_m")
#: Every size quantity a pair may have.
SIZES = ("radius_m", *OTHER_SIZES)
NAMES = (
    *(f"{ax}.{q}" for ax in AXES for q in COIL_QUANTITIES),
    "magnet.diameter_m",
    "magnet.length_m",
    "spiral.wire_diameter_m",
    *(f"{ax}.{q}" for q in OTHER_SIZES for ax in AXES),
)
#: Typical magnitudes: the NLP's variable scaling.
REFERENCE = {
    "radius_m": 0.1,
    "side_m": 0.2,
    "side_a_m": 0.2,
    "turns": 100.0,
    "wire_diameter_m": 1e-3,
    "pack_aspect": 1.0,
    "diameter_m": 1e-3,
    "length_m": 1e-3,
}

#: IEC 60317-0-1 / IEC 60228 nominal bare copper diameters, R40 preferred series, mm.
IEC_R40_mm = (
    0.10, 0.106, 0.112, 0.118, 0.125, 0.132, 0.14, 0.15, 0.16, 0.17, 0.18, 0.19, 0.20, 0.212,
    0.224, 0.236, 0.25, 0.265, 0.28, 0.30, 0.315, 0.335, 0.355, 0.375, 0.40, 0.425, 0.45, 0.475,
    0.50, 0.53, 0.56, 0.60, 0.63, 0.67, 0.71, 0.75, 0.80, 0.85, 0.90, 0.95, 1.00, 1.06, 1.12,
    1.18, 1.25, 1.32, 1.40, 1.50, 1.60, 1.70, 1.80, 1.90, 2.00, 2.12, 2.24, 2.36, 2.50, 2.65,
    2.80, 3.00, 3.15, 3.35, 3.55, 3.75, 4.00, 4.25, 4.50, 4.75, 5.00,
)  # fmt: skip


def awg_diameters_mm() -> tuple[float, ...]:
    """AWG 0 to 40 bare diameters, mm: d = 0.127 · 92^((36 − n)/39) (ASTM B258).

    Returns
    -------
    tuple of float
        AWG 40 to AWG 0 bare diameters, ascending, mm.
    """
    return tuple(0.127 * 92.0 ** ((36 - n) / 39.0) for n in range(40, -1, -1))


@dataclass(frozen=True)
class FreeVariable:
    """One freed hardware quantity (a name of :data:`NAMES`) and its box, SI.

    Attributes
    ----------
    name : str
        A name of :data:`NAMES` (``"x.turns"``, ``"magnet.length_m"``, ...).
    lo, hi : float
        Its box, in the unit its name carries (m; turns a count; pack aspect dimensionless).
    """

    name: str
    lo: float
    hi: float

    @property
    def kind(self) -> str:
        """'turns' (whole numbers), 'wire' (a standard coil-wire diameter) or 'continuous' (a
        category, no unit)."""
        q = self.name.split(".", 1)[1]
        if q == "turns":
            return "turns"
        return "wire" if self.name in {f"{ax}.wire_diameter_m" for ax in AXES} else "continuous"


@dataclass(frozen=True)
class Sizing:
    """Which hardware is free, the standard wire diameters (m) and the least coil bore (m).

    Attributes
    ----------
    free : tuple of FreeVariable
        The freed hardware and its boxes.
    wire_diameters_m : tuple of float
        Standard bare wire diameters a coil may use, m.
    min_bore_m : float or None
        Least clear diameter inside the smallest pair, m (None: no row).
    """

    free: tuple[FreeVariable, ...]
    wire_diameters_m: tuple[float, ...] = tuple(d * 1e-3 for d in IEC_R40_mm)
    min_bore_m: float | None = None


def size_name(ax: str, pair: Any) -> str:
    """The name of pair ``ax``'s size: ``"x.radius_m"`` of a circle, its own size otherwise
    (``"x.side_m"`` of a square; the pair class's first ``SIZE_NAMES``).

    Parameters
    ----------
    ax : {"x", "y", "z"}
        The pair's axis.
    pair : coils.winding.WoundPair or its class, or a shape key
        The pair (or its ``shape_key``).

    Returns
    -------
    str
        A name of :data:`NAMES`.
    """
    cls = pair[0] if isinstance(pair, tuple) else pair
    return f"{ax}.{cls.SIZE_NAMES[0]}"


def shape_keys(model: Any) -> tuple[Any, Any, Any]:
    """Per pair (x, y, z), its ``shape_key``: what a compiled sizing problem knows of it.

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    tuple of tuple
        Per pair, the pair class and any fixed number its sizes follow.
    """
    x, y, z = (p.shape_key for p in model.coils.pairs)
    return (x, y, z)


def hardware_of(model: Any) -> dict[str, float]:
    """The hardware values of a model, by name (each pair's size under its own name).

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    dict of str to float
        Value by :data:`NAMES` name, in the unit each name carries (m; turns a count; aspect
        dimensionless).
    """
    out: dict[str, float] = {}
    for ax, p in zip(AXES, model.coils.pairs):
        out[size_name(ax, p.shape_key)] = float(p.sizes_m[0])
        out[f"{ax}.turns"] = float(p.turns)
        out[f"{ax}.wire_diameter_m"] = float(p.wire_diameter_m)
        out[f"{ax}.pack_aspect"] = float(p.pack_aspect)
    mag, spiral = model.capsule.magnet, model.capsule.spiral
    out["magnet.diameter_m"] = float(mag.diameter_m)
    out["magnet.length_m"] = float(mag.length_m)
    out["spiral.wire_diameter_m"] = float(spiral.wire_diameter_m)
    return out


def derived_sizes(model: Any, values: Mapping[str, float]) -> dict[str, float]:
    """The sizes that follow a pair's free size in ``values`` (a rectangle's second side
    ``<ax>.side_b_m`` at its aspect), by name, m: what a sized design needs besides its free
    names.

    Parameters
    ----------
    model : DesignModel
        The design (its pairs' shapes).
    values : mapping of str to float
        Hardware by :data:`NAMES` name, each in the unit its name carries.

    Returns
    -------
    dict of str to float
        Each derived size by ``<ax>.<name>``, m (empty: none).
    """
    out: dict[str, float] = {}
    for ax, p in zip(AXES, model.coils.pairs):
        key = p.shape_key
        name = size_name(ax, key)
        if name in values and p.DERIVED_SIZE_NAMES:
            sizes = p.scaled_sizes(key, values[name])
            out.update({f"{ax}.{n}": float(v) for n, v in zip(p.DERIVED_SIZE_NAMES, sizes[1:])})
    return out


def helmholtz_flags(model: Any) -> tuple[bool, bool, bool]:
    """Per pair: does the separation follow the size (its default spacing: R, 0.5445 a, ...)?

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    tuple of bool
        Per pair (x, y, z), flag: the separation is the default spacing of its size.
    """
    x, y, z = (p.helmholtz for p in model.coils.pairs)
    return (x, y, z)


def with_hardware(model: Any, values: Mapping[str, float]) -> Any:
    """The model rebuilt with hardware ``values`` (turns rounded; exact domain objects).

    Raises ``spiralcap.core.errors.InputError`` when the coils or the magnet cannot be built.

    Parameters
    ----------
    model : DesignModel
        The design.
    values : mapping of str to float
        New hardware by :data:`NAMES` name, in the unit each name carries.

    Returns
    -------
    DesignModel
        The rebuilt design (constants cleared).
    """
    import coils

    hw = {**hardware_of(model), **values}
    pairs = []
    for ax, p in zip(AXES, model.coils.pairs):
        key = p.shape_key
        sizes = p.scaled_sizes(key, hw[size_name(ax, key)])
        pairs.append(
            replace(
                p,
                **p.size_fields(sizes),
                turns=max(1, round(hw[f"{ax}.turns"])),
                wire_diameter_m=hw[f"{ax}.wire_diameter_m"],
                pack_aspect=hw[f"{ax}.pack_aspect"],
                separation_m=None if p.helmholtz else p.separation_m,
            )
        )
    cap = model.capsule
    magnet = replace(cap.magnet, diameter_m=hw["magnet.diameter_m"], length_m=hw["magnet.length_m"])
    spiral = replace(cap.spiral, wire_diameter_m=hw["spiral.wire_diameter_m"])
    return replace(
        model,
        coils=coils.ThreeAxisHelmholtz(*pairs),
        capsule=replace(cap, magnet=magnet, spiral=spiral),
        constants=None,
    )


# --- frozen factors ---------------------------------------------------------------------------


def mean_turn_gap_m(pa: Any, pb: Any) -> float:
    """Least distance between the mean turns of two orthogonal pairs, m (sampled).

    GAP_SAMPLES points along the first pair's mean turns (its ``mean_turn_points``), the exact
    distance to the second's (its ``mean_turn_distance_m``).

    Parameters
    ----------
    pa, pb : coils.winding.WoundPair
        Two pairs on different axes.

    Returns
    -------
    float
        Least distance between their mean turns, m.
    """
    best = np.inf
    for sa, sb in itertools.product((-0.5, 0.5), repeat=2):
        sep_a, sep_b = sa * float(pa.separation_m), sb * float(pb.separation_m)
        pts = pa.mean_turn_points(pa.axis_index, pa.sizes_m, sep_a, GAP_SAMPLES)
        d = pb.mean_turn_distance_m(pts, pb.axis_index, pb.sizes_m, sep_b)
        best = min(best, float(d.min()))
    return best


#: Points on the first mean turn at which :func:`mean_turn_gap_m` takes the distance.
GAP_SAMPLES = 2048


@dataclass(frozen=True)
class Frozen:
    """Numbers held fixed during one inner solve (see the module notes).

    Attributes
    ----------
    gain_correction : ndarray, shape (3,)
        Exact filament-model centre gain / the two-loop formula, per pair, dimensionless.
    mutual_correction : ndarray, shape (3,)
        Exact pack mutual inductance / N² times the filament one, per pair, dimensionless.
    workspace_factor : float
        Weakest field over the workspace per tesla at the centre, dimensionless.
    gap0_m : ndarray, shape (3,)
        Mean-turn gaps of the pairs xy, xz, yz, m.
    dgap_dra, dgap_drb : ndarray, shape (3,)
        Their derivatives with the first and the second pair's radius, dimensionless (m/m).
    radii0_m : ndarray, shape (3,)
        The radii the gaps were linearised at, m.
    view_factors : ndarray, shape (3, 4)
        The packs' view factors ``[room, x, y, z]``, dimensionless.
    clearance_delta_m : ndarray, shape (3,)
        Exact clearance minus the torus bound, m (>= 0 for two rings).
    delta_slopes : ndarray, shape (3, 4)
        For two pairs with a square frame: the correction's derivatives with the first and
        second pair's pack width and depth ``(w_a, h_a, w_b, h_b)``, dimensionless (m/m); zero
        for two rings (not used).
    packs0_m : ndarray, shape (3, 2)
        Each pair's pack (width, depth) the slopes were taken at, m.
    """

    gain_correction: np.ndarray  # (3,)
    mutual_correction: np.ndarray  # (3,)
    workspace_factor: float
    gap0_m: np.ndarray  # (3,) for pairs xy, xz, yz
    dgap_dra: np.ndarray  # (3,)
    dgap_drb: np.ndarray  # (3,)
    radii0_m: np.ndarray  # (3,) radii the gaps were linearised at
    view_factors: np.ndarray  # (3, 4) packs' view factors [room, x, y, z] at this hardware
    clearance_delta_m: np.ndarray  # (3,) exact clearance - torus bound, >= 0
    delta_slopes: np.ndarray = field(default_factory=lambda: np.zeros((3, 4)))
    packs0_m: np.ndarray = field(default_factory=lambda: np.zeros((3, 2)))


PAIRS_OF_PAIRS = ((0, 1), (0, 2), (1, 2))
#: Scale of the clearance rows, m.
CLEARANCE_REF_m = 0.01
#: What the sizing's clearance rows keep beyond the least clearance, m: their gaps are
#: linearised and corrected at the relaxation's hardware, so a neighbour whose continuous
#: quantities re-balance around whole turns (pack aspects, radii) can fall short of the exact
#: clearance by a few micrometres (2.6 um measured); the exact check stays the asked value.
CLEARANCE_MARGIN_m = 5e-6


def frozen_factors(model: Any) -> Frozen:
    """The frozen numbers at ``model``'s (exact, built) hardware.

    Parameters
    ----------
    model : DesignModel
        The design at the outer iteration's hardware.

    Returns
    -------
    Frozen
        The frozen numbers (dimensionless factors, m).
    """
    from coils.clearance import pack_clearance_m
    from optimize.system import prepare

    m = prepare(model)
    pairs = m.coils.pairs
    gain_corr, mut_corr = zip(*(p.formula_corrections() for p in pairs))
    gaps, da, db, delta = [], [], [], []
    h = 1e-6
    for i, j in PAIRS_OF_PAIRS:
        a, b = pairs[i], pairs[j]
        g0 = mean_turn_gap_m(a, b)
        gaps.append(g0)
        delta.append(_clearance_delta_m(pack_clearance_m(a, b), g0, a, b))
        da.append((mean_turn_gap_m(_scaled(a, h), b) - g0) / (h * a.sizes_m[0]))
        db.append((mean_turn_gap_m(a, _scaled(b, h)) - g0) / (h * b.sizes_m[0]))
    return Frozen(
        np.array(gain_corr),
        np.array(mut_corr),
        float(m.constants.workspace_factor),
        np.array(gaps),
        np.array(da),
        np.array(db),
        np.array([p.sizes_m[0] for p in pairs]),
        np.asarray(m.constants.view_factors, dtype=float),
        np.array(delta),
        np.array([_delta_slopes(pairs[i], pairs[j]) for i, j in PAIRS_OF_PAIRS]),
        np.array([(p.winding_pack_width_m, p.winding_pack_depth_m) for p in pairs]),
    )


def _clearance_delta_m(exact_m: float, gap_m: float, a: Any, b: Any) -> float:
    """Exact pack clearance minus the tube bound at the mean-turn gap, m: clipped at 0 for two
    rings (as before squares); not clipped with a square frame, so the row is the exact
    clearance at the frozen hardware even where the sampled gap overstates the true one."""
    from coils.clearance import torus_clearance_bound_m

    if a.RING and b.RING:
        return max(exact_m - torus_clearance_bound_m(gap_m, a, b), 0.0)
    return exact_m - (gap_m - (a.tube_m + b.tube_m))


def _delta_slopes(a: Any, b: Any) -> np.ndarray:
    """d(clearance correction)/d(w_a, h_a, w_b, h_b) by central differences on the exact
    solid distance, for two pairs with a square frame (zeros for two rings, whose correction
    row is as before). The frame-to-frame distance is piecewise linear in the pack sides, so
    with these slopes the row tracks the exact clearance to first order as the packs grow and
    the outer iterations settle."""
    from coils.clearance import pack_distance_m

    if a.RING and b.RING:
        return np.zeros(4)
    packs = [a.pack_solids()[1], b.pack_solids()[1]]
    kinds = [type(a), type(b)]

    def delta(k: int, name: str, step: float) -> float:
        moved = list(packs)
        moved[k] = replace(packs[k], **{name: getattr(packs[k], name) + step})
        tubes = sum(c.tube_radius_m(q.width_m, q.depth_m) for q, c in zip(moved, kinds))
        return pack_distance_m(*moved) + tubes  # the gap term does not move with the packs

    out = []
    for k in range(2):
        for name in ("width_m", "depth_m"):
            step = 1e-4 * getattr(packs[k], name)
            out.append((delta(k, name, step) - delta(k, name, -step)) / (2.0 * step))
    return np.array(out)


def _scaled(p: Any, h: float) -> Any:
    """The pair with every size scaled by 1 + h (at its default spacing if it had it)."""
    return p.with_sizes(tuple(size * (1 + h) for size in p.sizes_m))


# --- expressions ------------------------------------------------------------------------------


def coil_quantities(
    shape: Any,
    sizes: tuple[Any, ...],
    turns: Any,
    wire: Any,
    separation: Any,
    *,
    packing: Any,
    resistivity: Any,
    h: Any,
    aspect: Any = 1.0,
) -> dict[str, Any]:
    """Pack side (of the equal-area square), width (axial) and depth (radial), uncorrected
    gain, resistance, self inductance, filament mutual inductance (times N²), convective
    conductance of the faces and copper mass of one pair (backend-generic): the pair's shape
    gives the gain, wire length and inductances (its ``terms``) and the mean turn.

    Parameters
    ----------
    shape : type
        The pair class (``coils.winding.WoundPair`` and its shapes).
    sizes : tuple of float or CasADi
        The pair's sizes (its ``SIZE_NAMES``; the mean radius R of a circle, the side a of a
        square, the sides a, b of a rectangle), m.
    turns : float or CasADi
        Turns N of each coil, count (continuous in the relaxation).
    wire : float or CasADi
        Bare wire diameter d, m.
    separation : float or CasADi
        Distance s between the coil planes, m.
    packing : float or CasADi
        Copper area / pack area, dimensionless.
    resistivity : float or CasADi
        Copper resistivity, Ω·m.
    h : float or CasADi
        Face heat transfer coefficient, W/(m²·K).
    aspect : float or CasADi
        Axial width / radial depth of the pack, dimensionless.

    Returns
    -------
    dict of str to float or CasADi
        Each quantity by name, the unit in each name (``side_m``, ``gain_T_per_A``,
        ``resistance_ohm``, ``self_inductance_H``, ``mutual_filament_H``,
        ``conductance_W_per_K``, ``copper_mass_kg``).
    """
    area = bk.pi * wire * wire / 4.0
    pack_area = turns * area / packing
    side = bk.sqrt(pack_area)
    width, depth = bk.sqrt(pack_area * aspect), bk.sqrt(pack_area / aspect)
    terms = shape.terms(sizes, turns, separation, width, depth)
    length = terms.pop("length_m")
    return {
        "side_m": side,
        "width_m": width,
        "depth_m": depth,
        **terms,
        "resistance_ohm": resistivity * length / area,
        "conductance_W_per_K": h * 2.0 * 2.0 * (width + depth) * shape.turn_length_m(sizes),
        "copper_mass_kg": COPPER_DENSITY_kg_m3 * length * area,
    }


def view_factor_rows(flat: Any) -> list[list[Any]]:
    """The (3, 4) view-factor rows ``[room, x, y, z]`` of a flat (12,) CasADi parameter.

    Parameters
    ----------
    flat : casadi.SX, shape (12,)
        The view factors row by row, dimensionless.

    Returns
    -------
    list of list of casadi.SX
        The (3, 4) rows, dimensionless.
    """
    return [[flat[4 * k + j] for j in range(4)] for k in range(3)]


@dataclass(frozen=True)
class HardwareStructure:
    """What a sizing problem compiles in: the free names, Helmholtz spacing per pair, headings.

    Attributes
    ----------
    free : tuple of str
        The freed :data:`NAMES`.
    helmholtz : tuple of bool
        Per pair, flag: Helmholtz spacing (the separation follows the radius).
    headings : int
        Number of headings.
    copper_mass_limit : bool
        Flag: the copper-mass row is part of the problem.
    shapes : tuple of tuple
        Per pair, its ``shape_key`` (:func:`shape_keys`): the pair class, which gives the
        shape's terms, and any fixed number its sizes follow (one per pair).
    """

    free: tuple[str, ...]
    helmholtz: tuple[bool, bool, bool]
    headings: int
    copper_mass_limit: bool = False
    shapes: tuple = ()

    def shape(self, k: int) -> Any:
        """Pair k's class (a ``coils.winding.WoundPair``).

        Parameters
        ----------
        k : int
            The pair (0, 1, 2 for x, y, z), an index.

        Returns
        -------
        type
            The pair's class (``coils.HelmholtzPair``, ``coils.SquarePair``, ...), which gives
            the shape's terms.
        """
        return self.shapes[k][0]

    def key(self, k: int) -> tuple[Any, ...]:
        """Pair k's shape key.

        Parameters
        ----------
        k : int
            The pair (0, 1, 2 for x, y, z), an index.

        Returns
        -------
        tuple
            Its ``shape_key``: the pair class and any fixed number its sizes follow (a
            rectangle's aspect b / a).
        """
        return self.shapes[k]

    @property
    def names(self) -> tuple[str, ...]:
        """The hardware names of this problem: :data:`NAMES` with each pair's own size."""
        own = {size_name(ax, self.key(k)) for k, ax in enumerate(AXES)}
        sizes = {f"{ax}.{q}" for ax in AXES for q in SIZES}
        return tuple(n for n in NAMES if n not in sizes or n in own)

    def sizes(self, hw: dict[str, Any], k: int) -> tuple[Any, ...]:
        """Pair k's sizes as expressions (its ``SIZE_NAMES`` order), m.

        Parameters
        ----------
        hw : dict of str to casadi.SX
            The hardware expressions by name, in the unit each name carries.
        k : int
            The pair (0, 1, 2 for x, y, z), an index.

        Returns
        -------
        tuple of casadi.SX
            The sizes (R; a; a and b of a rectangle), m: its free size and those that follow
            it (``scaled_sizes``).
        """
        return self.shape(k).scaled_sizes(self.key(k), self.size(hw, k))

    def size(self, hw: dict[str, Any], k: int) -> Any:
        """Pair k's (first) size expression: R, or the side a of a square or rectangle.

        Parameters
        ----------
        hw : dict of str to casadi.SX
            The hardware expressions by name, in the unit each name carries.
        k : int
            The pair (0, 1, 2 for x, y, z), an index.

        Returns
        -------
        casadi.SX
            The size, m.
        """
        return hw[size_name(AXES[k], self.key(k))]

    def reach(self, hw: dict[str, Any], k: int) -> Any:
        """Least distance from pair k's axis to its mean turn: R, or a/2 for a square.

        Parameters
        ----------
        hw : dict of str to casadi.SX
            The hardware expressions by name, in the unit each name carries.
        k : int
            The pair (0, 1, 2 for x, y, z), an index.

        Returns
        -------
        casadi.SX
            The distance, m.
        """
        return self.shape(k).reach_m(self.sizes(hw, k))

    def spacing(self, hw: dict[str, Any], k: int, separation: Any) -> Any:
        """Pair k's separation: its size's Helmholtz spacing (R; 0.5445 a) or ``separation``.

        Parameters
        ----------
        hw : dict of str to casadi.SX
            The hardware expressions by name, in the unit each name carries.
        k : int
            The pair (0, 1, 2 for x, y, z), an index.
        separation : casadi.SX
            The pair's fixed separation parameter, m (used without Helmholtz spacing).

        Returns
        -------
        casadi.SX
            The separation, m.
        """
        if not self.helmholtz[k]:
            return separation
        ratio = self.shape(k).spacing_per_size(self.key(k))
        size = self.size(hw, k)
        return size if ratio == 1.0 else ratio * size


def _hardware_symbols(b: Any, hs: HardwareStructure) -> dict[str, Any]:
    """Every hardware quantity by name: an NLP variable where free, else a parameter."""
    hw: dict[str, Any] = {}
    for name in hs.names:
        if name in hs.free:
            hw[name] = b.variable(name, REFERENCE[name.split(".", 1)[1]], 0.0, np.inf)
        else:
            hw[name] = b.parameter(f"hw.{name}")
    return hw


def _coil_symbols(b: Any, hs: HardwareStructure, hw: dict[str, Any]) -> tuple[list, Any, Any]:
    """:func:`coil_quantities` of the three pairs as expressions, with the packing factor and
    heat-transfer coefficient parameters they use."""
    packing, rho, hcoef = (
        b.parameter("hw.packing"),
        b.parameter("hw.resistivity"),
        b.parameter("hw.h"),
    )
    sep = b.parameter("hw.separation_m", (3,))
    q = []
    for k, ax in enumerate(AXES):
        q.append(
            coil_quantities(
                hs.shape(k),
                hs.sizes(hw, k),
                hw[f"{ax}.turns"],
                hw[f"{ax}.wire_diameter_m"],
                hs.spacing(hw, k, sep[k]),
                packing=packing,
                resistivity=rho,
                h=hcoef,
                aspect=hw[f"{ax}.pack_aspect"],
            )
        )
    return q, packing, hcoef


def _pack_symbols(
    b: Any,
    hs: HardwareStructure,
    hw: dict[str, Any],
    q: list,
    packing: Any,
    hcoef: Any,
    convection: str,
) -> tuple:
    """The three winding packs (:class:`coils.thermal.WindingPack`) as expressions: each the
    pair's thermal ring (a frame as the ring as long as its mean turn, with its vertical bars
    where its plane is vertical; coils.thermal)."""
    from coils.thermal import WindingPack

    conductivity, emissivity = b.parameter("hw.conductivity"), b.parameter("hw.emissivity")

    return tuple(
        WindingPack(
            pack_width_m=q[k]["width_m"],
            pack_depth_m=q[k]["depth_m"],
            packing_factor=packing,
            conductivity_W_mK=conductivity,
            heat_transfer_coefficient_W_m2K=hcoef,
            emissivity=emissivity,
            vertical_axis=AXES[k] == "z",
            air_speed_m_s=b.parameter("hw.air_speed_m_s"),
            convection=convection,
            **hs.shape(k).thermal_ring(AXES[k], hs.sizes(hw, k)),
        )
        for k in range(3)
    )


def symbolic_constants(
    b: Any,
    hs: HardwareStructure,
    spiral_starts: int,
    convection: str = "fixed",
) -> tuple[Any, Any, list]:
    """Constants as expressions of the hardware (free: variables, fixed: parameters).

    Returns (constants, hardware expressions by name, geometry terms builder args).

    Parameters
    ----------
    b : NLPBuilder
        The problem being built.
    hs : HardwareStructure
        Which hardware is free.
    spiral_starts : int
        Number of spiral starts.
    convection : str
        Cooling mode (one of :data:`coils.thermal.CONVECTION_MODES`).

    Returns
    -------
    constants : Constants
        The constants as CasADi expressions, SI.
    hardware : dict of str to casadi.SX
        Each hardware quantity by name, in the unit its name carries.
    quantities : list of dict
        Per pair :func:`coil_quantities` (units in the names), then ``{"power_W": ...}`` (W).
    """
    import casadi as ca

    import capsule as cap
    from optimize.system import Constants

    hw = _hardware_symbols(b, hs)
    q, packing, hcoef = _coil_symbols(b, hs, hw)
    gcorr, mcorr = (
        b.parameter("frozen.gain_correction", (3,)),
        b.parameter("frozen.mutual_correction", (3,)),
    )
    s_max = b.parameter("heading.s", (3,))
    s_all = ca.reshape(b.parameter("heading.s_all", (hs.headings, 3)), 3, hs.headings).T
    g = [gcorr[k] * q[k]["gain_T_per_A"] for k in range(3)]
    res = [q[k]["resistance_ohm"] for k in range(3)]  # at 20 °C ("hw.resistivity" is ρ20)
    # worst-heading copper loss, W: an epigraph variable above every heading's loss (a max of
    # tied headings is not smooth); its rows are added with the geometry terms
    power = b.variable("power_W_scaled", 1.0, 0.0, np.inf) * b.parameter("scale.power_W")
    per_tesla = ca.horzcat(*(s_all[:, k] / g[k] for k in range(3)))
    worst = ca.vertcat(*(s_max[k] / g[k] for k in range(3)))
    packs = _pack_symbols(b, hs, hw, q, packing, hcoef, convection)
    body_d, body_l = b.parameter("body.diameter_m"), b.parameter("body.length_m")
    wire_sp = hw["spiral.wire_diameter_m"]
    d_mag, l_mag = hw["magnet.diameter_m"], hw["magnet.length_m"]
    d_in, br = b.parameter("magnet.inner_diameter_m"), b.parameter("magnet.remanence_T")
    c = Constants(
        gains_T_per_A=ca.vertcat(*g),
        resistance_20C_ohm=ca.vertcat(*res),
        inductance_H=ca.vertcat(
            *(
                2.0 * q[k]["self_inductance_H"] + 2.0 * mcorr[k] * q[k]["mutual_filament_H"]
                for k in range(3)
            )
        ),
        packs=packs,
        current_per_tesla_A_per_T=worst,
        power_weights_per_T2=0.5 * per_tesla * per_tesla,
        heading_current_per_tesla_A_per_T=per_tesla,
        workspace_factor=b.parameter("frozen.workspace_factor"),
        moment_Am2=br * 0.25 * bk.pi * (d_mag * d_mag - d_in * d_in) * l_mag / MU0_T_m_per_A,
        body_diameter_m=body_d,
        body_length_m=body_l,
        wire_diameter_m=wire_sp,
        wound_length_m=b.parameter("spiral.wound_length_m"),
        helix_diameter_m=cap.helix_diameter_m(body_d, wire_sp),
        copper_mass_kg=ca.vertcat(*(q[k]["copper_mass_kg"] for k in range(3))),
        starts=spiral_starts,
        view_factors=view_factor_rows(b.parameter("frozen.view_factors", (12,))),
        mass_kg=b.parameter("capsule.mass_base_kg")
        + b.parameter("capsule.mass_per_magnet_volume_kg_m3")
        * 0.25
        * bk.pi
        * (d_mag * d_mag - d_in * d_in)
        * l_mag,
    )
    q.append({"power_W": power})
    return c, hw, q


def _envelope_terms(
    hs: HardwareStructure, hw: dict, q: list, ctx: Any, freed: list[bool], sep: Any
) -> list:
    """Rows ``envelope_<i>[<pair>]``: each freed pair's packs inside half the envelope along
    every axis (coils.clearance.pair_extent_m; a square frame reaches a/2 + h/2 across its
    axis, its sides' outer faces); none without ``limits.envelope_mm``."""
    from optimize.nlp import Row
    from optimize.problem import Term

    env = ctx.limits.envelope_m
    if env is None:
        return []
    out = []
    for k, ax in enumerate(AXES):
        if not freed[k]:
            continue
        s = hs.spacing(hw, k, sep[k])
        halves = hs.shape(k).half_extents_m(k, hs.sizes(hw, k), s, q[k]["width_m"], q[k]["depth_m"])
        for i, half in enumerate(halves):
            out.append(
                Term(
                    Row(f"envelope_{AXES[i]}[{ax}]", "limit", "m"),
                    2.0 * half,
                    env[i],
                    lambda v, a: v / a - 1.0,
                )
            )
    return out


def geometry_terms(b: Any, hs: HardwareStructure, hw: dict, q: list, ctx: Any) -> list:
    """Rows that keep a freed design buildable: packs inside their radius, clear of each other
    and of the bore by the least clearance (module notes), a clear bore, the copper mass within
    its limit, the magnet inside the shell, the spiral's turns apart.

    Parameters
    ----------
    b : NLPBuilder
        The problem being built.
    hs : HardwareStructure
        Which hardware is free.
    hw : dict of str to casadi.SX
        The hardware expressions by name, in the unit each name carries.
    q : list of dict
        :func:`symbolic_constants`'s per-pair quantities (units in the names).
    ctx : Context
        The expressions at the operating point.

    Returns
    -------
    list of Term
        The geometry, clearance, copper-mass and heading-loss rows.
    """
    from optimize.nlp import Row
    from optimize.problem import Term

    free = set(hs.free)
    out: list = []

    def upper(v: Any, a: Any) -> Any:
        return v / a - 1.0

    from optimize.physics import heading_losses_W

    losses = heading_losses_W(ctx.field_T, ctx.constants, ctx.ambient_temperature_C)
    for h, loss in enumerate(losses):
        out.append(Term(Row(f"heading_loss[{h}]", "epigraph", "W"), loss, q[3]["power_W"], upper))

    if free & {f"{ax}.{qq}" for ax in AXES for qq in (*COIL_QUANTITIES, *OTHER_SIZES)}:
        out += _coil_terms(b, hs, hw, q, ctx)
    out += _capsule_terms(b, free, hw, ctx)
    return out


def _coil_terms(b: Any, hs: HardwareStructure, hw: dict, q: list, ctx: Any) -> list:
    """The freed pairs' rows of :func:`geometry_terms`: pack inside its radius and spacing, a
    clear bore and room to it, clearances between pairs, the envelope, the copper mass."""
    from optimize.nlp import Row
    from optimize.problem import Term

    free = set(hs.free)
    out: list = []

    def upper(v: Any, a: Any) -> Any:
        return v / a - 1.0

    sep = b.parameter("hw.separation_m", (3,))
    bore = b.parameter("hw.min_bore_m")
    gap0, dga, dgb, delta = (
        b.parameter(f"frozen.{n}", (3,))
        for n in ("gap0_m", "dgap_dra", "dgap_drb", "clearance_delta_m")
    )
    need = b.parameter("requirement.min_clearance_m")
    bore_r = b.parameter("requirement.bore_radius_m")
    r0 = b.parameter("frozen.radii0_m", (3,))
    freed = [bool(free & {f"{ax}.{qq}" for qq in (*COIL_QUANTITIES, *OTHER_SIZES)}) for ax in AXES]
    for k, ax in enumerate(AXES):
        if not freed[k]:  # a fixed pair's rows would be constants
            continue
        r, width, depth = hs.reach(hw, k), q[k]["width_m"], q[k]["depth_m"]
        # the pack inside its turn: h <= R, or h <= the (shorter) side of a frame (coils.winding)
        inside = hs.shape(k).depth_limit_m(hs.sizes(hw, k))
        out.append(Term(Row(f"pack_side_{ax}", "geometry", "m"), depth, inside, upper))
        if not hs.helmholtz[k]:
            out.append(Term(Row(f"pack_separation_{ax}", "geometry", "m"), width, sep[k], upper))
        out.append(
            Term(
                Row(f"bore_{ax}", "geometry", "m", -1.0),
                2.0 * r - depth,
                bore,
                lambda v, a: (a - v) / bk.fmax(a, 1e-3),
            )
        )
        out.append(
            Term(
                Row(f"bore_clearance_{ax}", "geometry", "m", -1.0),
                r - 0.5 * depth - bore_r,
                need,
                lambda v, a: (a + CLEARANCE_MARGIN_m - v) / CLEARANCE_REF_m,
            )
        )
    for n, (i, j) in enumerate(PAIRS_OF_PAIRS):
        if not (freed[i] or freed[j]):
            continue
        ri, rj = hs.size(hw, i), hs.size(hw, j)
        gap = gap0[n] + dga[n] * (ri - r0[i]) + dgb[n] * (rj - r0[j])
        clearance = gap - _tubes(hs, q, i, j) + delta[n]
        if not (
            hs.shape(i).RING and hs.shape(j).RING
        ):  # the correction to first order in the packs
            clearance = clearance + _delta_moves(b, q, n, i, j)
        out.append(
            Term(
                Row(f"clearance_{AXES[i]}{AXES[j]}", "geometry", "m", -1.0),
                clearance,
                need,
                lambda v, a: (a + CLEARANCE_MARGIN_m - v) / CLEARANCE_REF_m,
            )
        )
    out += _envelope_terms(hs, hw, q, ctx, freed, sep)
    if hs.copper_mass_limit:
        mass = q[0]["copper_mass_kg"] + q[1]["copper_mass_kg"] + q[2]["copper_mass_kg"]
        limit = b.parameter("limit.copper_mass_kg")
        out.append(Term(Row("copper_mass", "limit", "kg"), mass, limit, upper))
    return out


def _delta_moves(b: Any, q: list, n: int, i: int, j: int) -> Any:
    """How the clearance correction of pairs (i, j) moves with their packs since the frozen
    hardware (:func:`_delta_slopes`), m."""
    slopes = b.parameter("frozen.delta_slopes", (12,))
    packs0 = b.parameter("frozen.packs0_m", (6,))
    now = [q[i]["width_m"], q[i]["depth_m"], q[j]["width_m"], q[j]["depth_m"]]
    then = [packs0[2 * i], packs0[2 * i + 1], packs0[2 * j], packs0[2 * j + 1]]
    return sum(slopes[4 * n + m] * (now[m] - then[m]) for m in range(4))


def _tubes(hs: HardwareStructure, q: list, i: int, j: int) -> Any:
    """The two packs' tube radii about their mean turns (each pair's ``tube_radius_m``), summed,
    m."""
    return sum(hs.shape(k).tube_radius_m(q[k]["width_m"], q[k]["depth_m"]) for k in (i, j))


def _capsule_terms(b: Any, free: set, hw: dict, ctx: Any) -> list:
    """The magnet and spiral rows of :func:`geometry_terms`: the magnet inside the shell, the
    spiral's turns apart."""
    import capsule as cap
    from optimize.nlp import Row
    from optimize.problem import ALPHA_REF_rad, Term

    out: list = []

    def upper(v: Any, a: Any) -> Any:
        return v / a - 1.0

    if free & {"magnet.diameter_m", "magnet.length_m"}:
        r_in, l_cyl = b.parameter("body.inner_radius_m"), b.parameter("body.cylinder_length_m")
        half_d = 0.5 * hw["magnet.diameter_m"]
        out.append(Term(Row("magnet_diameter", "geometry", "m"), half_d, r_in, upper))
        room = 0.5 * l_cyl + bk.sqrt(bk.fmax(r_in * r_in - half_d * half_d, 1e-12))
        out.append(
            Term(Row("magnet_length", "geometry", "m"), 0.5 * hw["magnet.length_m"], room, upper)
        )
    if "spiral.wire_diameter_m" in free:
        from optimize import physics as ph

        # at its worst corner of the tolerance box: the thickest wire, the flattest angle
        c = ph.wire_corner(ctx.constants, ctx.tolerances, +1)
        floor = cap.min_helical_angle_for_clearance_rad(
            c.helix_diameter_m, c.wire_diameter_m, c.starts
        )
        out.append(
            Term(
                Row("spiral_clearance", "geometry", "rad", -1.0),
                ph.angle_corner(ctx.helical_angle_rad, ctx.tolerances, -1),
                floor,
                lambda v, a: (a - v) / ALPHA_REF_rad,
            )
        )
    return out


def _mass_parameters(capsule: Any) -> dict[str, float]:
    """The capsule's mass as base + rate x magnet volume (kg, kg/m³): a measured mass is
    fixed; an estimated one follows a free magnet (capsule.mass_from_parts_kg)."""
    import capsule as cap

    if capsule.set_mass_kg is not None:
        return {
            "capsule.mass_base_kg": capsule.mass_kg,
            "capsule.mass_per_magnet_volume_kg_m3": 0.0,
        }
    body = capsule.body
    return {
        "capsule.mass_base_kg": float(cap.mass_from_parts_kg(body.diameter_m, body.length_m, 0.0)),
        "capsule.mass_per_magnet_volume_kg_m3": cap.NDFEB_DENSITY_kg_m3
        - cap.CONTENTS_DENSITY_kg_m3,
    }


def sizing_parameters(model: Any, frozen: Frozen, min_bore_m: float) -> dict[str, Any]:
    """Values of the hardware, body, heading and frozen parameters of a sizing problem.

    Parameters
    ----------
    model : DesignModel
        The design at the outer iteration's hardware.
    frozen : Frozen
        The frozen numbers.
    min_bore_m : float
        Least clear bore diameter, m.

    Returns
    -------
    dict of str to float or ndarray
        Value by parameter name, in the unit each name carries.
    """
    from spiralcap.core.constants import COPPER_RESISTIVITY_20C_ohm_m

    hw = hardware_of(model)
    pairs = model.coils.pairs
    n2 = np.asarray(model.headings, dtype=float) ** 2
    s2 = np.clip(1.0 - n2, 0.0, 1.0)
    body, mag, spiral = model.capsule.body, model.capsule.magnet, model.capsule.spiral
    values: dict[str, Any] = {f"hw.{k}": v for k, v in hw.items()}
    values.update(
        {
            "hw.packing": pairs[0].packing_factor,
            "hw.resistivity": COPPER_RESISTIVITY_20C_ohm_m,  # the resistance at 20 °C
            "hw.h": model.heat_transfer_coefficient_W_m2K or 0.0,
            "hw.air_speed_m_s": float(model.air_speed_m_s),
            "hw.conductivity": model.winding_conductivity_W_mK,
            "hw.emissivity": model.surface_emissivity,
            "hw.separation_m": np.array([p.separation_m for p in pairs]),
            "hw.min_bore_m": min_bore_m,
            "heading.s": np.max(np.sqrt(s2), axis=0),
            "heading.s_all": np.sqrt(s2),
            "body.diameter_m": body.diameter_m,
            "body.length_m": body.length_m,
            "body.inner_radius_m": body.inner_radius_m,
            "body.cylinder_length_m": body.cylinder_length_m,
            "magnet.inner_diameter_m": mag.inner_diameter_m,
            "magnet.remanence_T": mag.remanence_T,
            **_mass_parameters(model.capsule),
            "spiral.wound_length_m": spiral.wound_length_m,
            "frozen.gain_correction": frozen.gain_correction,
            "frozen.mutual_correction": frozen.mutual_correction,
            "frozen.workspace_factor": frozen.workspace_factor,
            "frozen.gap0_m": frozen.gap0_m,
            "frozen.dgap_dra": frozen.dgap_dra,
            "frozen.dgap_drb": frozen.dgap_drb,
            "frozen.radii0_m": frozen.radii0_m,
            "frozen.view_factors": frozen.view_factors.ravel(),
            "frozen.clearance_delta_m": frozen.clearance_delta_m,
            "frozen.delta_slopes": frozen.delta_slopes.ravel(),
            "frozen.packs0_m": frozen.packs0_m.ravel(),
        }
    )
    return values


def bore_m(model: Any) -> float:
    """Clear diameter inside the smallest pair: min over pairs of 2R − h (h radial depth), m.

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    float
        Clear bore diameter, m.
    """
    return float(min(2.0 * p.radius_m - p.winding_pack_depth_m for p in model.coils.pairs))
