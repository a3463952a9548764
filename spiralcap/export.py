"""The designed coils for other tools: a magpylib model, and the field per ampere on a grid.

:func:`to_magpylib` hands the six coils to magpylib, the library this field uses to compute
and check magnetic fields: each coil is its winding pack as the filaments spiralcap itself sums
(:attr:`coils.HelmholtzPair.filament_set`, Gauss-Legendre nodes over the pack), each filament a
``magpylib.current.Circle`` carrying its share of the ampere-turns. :func:`field_grid` samples
the field per ampere of each pair over the workspace (a regular grid over the cube around the
workspace sphere) and :func:`write_field_grid` writes it as CSV or NumPy ``.npz`` with units in
every column name (``spiralcap coils --field-grid``).

Application layer: this module imports magpylib and writes files; the domain packages do not.
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from spiralcap.core.errors import InputError

__all__ = ["FieldGrid", "field_grid", "grid_columns", "to_magpylib", "write_field_grid"]

#: Grid points along each axis with the default step (the workspace diameter over 20 steps).
DEFAULT_STEPS_PER_DIAMETER = 20
#: Most grid points a --field-grid file may hold (about 60 MB of CSV).
MAX_GRID_POINTS = 300_000
_AXES = ("x", "y", "z")


def _system(model: Any) -> Any:
    """The ThreeAxisHelmholtz of a DesignModel, a Design, or the system itself."""
    from coils.system import ThreeAxisHelmholtz

    if isinstance(model, ThreeAxisHelmholtz):
        return model
    coils = getattr(model, "coils", None)
    if isinstance(coils, ThreeAxisHelmholtz):
        return coils
    from spiralcap.design import Design

    if isinstance(model, Design):
        from spiralcap.assemble.coils import build_coils

        return build_coils(model)
    raise InputError(
        "model", type(model).__name__, "an optimize.DesignModel, a Design or a ThreeAxisHelmholtz"
    )


def _rotation(axis: str) -> Any:
    """The rotation taking magpylib's Circle axis (z) onto the pair's axis (None for z)."""
    from scipy.spatial.transform import Rotation

    if axis == "x":
        return Rotation.from_euler("y", 90, degrees=True)
    if axis == "y":
        return Rotation.from_euler("x", -90, degrees=True)
    return None


def _local_halves(axis: str, half_u: float, half_v: float) -> tuple[float, float]:
    """A filament's half sides along the next two axes in cyclic order (u, v), as half sides
    along magpylib's local x and y after :func:`_rotation` (local x is z for an x pair and x
    for a y pair: v there; u for a z pair)."""
    return (half_u, half_v) if axis == "z" else (half_v, half_u)


def _filament(
    magpylib: Any,
    halves: tuple[float, float] | None,
    size_m: float,
    position_m: Any,
    ampere_turns: float,
    rotation: Any,
) -> Any:
    """One filament: a ``Circle`` of radius ``size_m`` (``halves`` None), or a closed
    ``Polyline`` rectangle of half sides ``halves`` along its local x and y (sides along the
    other two axes), counter-clockwise about its local z so a positive current makes a field
    along the pair's axis, as spiralcap's sign."""
    if halves is None:
        return magpylib.current.Circle(
            current=ampere_turns, diameter=2.0 * size_m, position=position_m, orientation=rotation
        )
    h, k = halves
    corners = [(h, -k, 0.0), (h, k, 0.0), (-h, k, 0.0), (-h, -k, 0.0), (h, -k, 0.0)]
    return magpylib.current.Polyline(
        current=ampere_turns, vertices=corners, position=position_m, orientation=rotation
    )


def to_magpylib(model: Any, currents_A: Sequence[float] = (1.0, 1.0, 1.0)) -> Any:
    """The six coils as a ``magpylib.Collection``, each coil its winding pack's filaments.

    Parameters
    ----------
    model : optimize.DesignModel, spiralcap.design.Design or coils.ThreeAxisHelmholtz
        The design whose coils to hand over (a Design is assembled first).
    currents_A : sequence of 3 floats
        Current in the x, y and z pair, A (both coils of a pair in series carry it).

    Returns
    -------
    magpylib.Collection
        Six child collections named ``"x pair, coil at -0.215 m"`` and so on, each holding the
        coil's filaments as ``magpylib.current.Circle`` objects, or closed square
        ``magpylib.current.Polyline`` objects for a square pair (SI: m, A; a filament's current
        is its ampere-turns, its weight times N times the pair current). Its
        ``getB(points_m)`` is spiralcap's field of the three pairs (magpylib uses scipy's
        CODATA 2022 mu_0, spiralcap CODATA 2018: they differ by about 1e-9 relative).

    Raises
    ------
    spiralcap.core.errors.InputError
        ``currents_A`` is not three finite numbers, or ``model`` has no coils.

    Examples
    --------
    The built-in design's coils in magpylib, an independent field solver: its field at 5 cm
    against spiralcap's own with 10 A in the x pair:

    >>> import numpy as np
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> from spiralcap.export import to_magpylib
    >>> model = build_model(load_design(None, []))
    >>> p = np.array([[0.02, 0.03, 0.05]])
    >>> ours = model.coils.field(p, np.array([10.0, 0.0, 0.0]))
    >>> theirs = to_magpylib(model, (10.0, 0.0, 0.0)).getB(p)
    >>> print(np.round(ours * 1e3, 5), f"{np.max(np.abs(theirs - ours)) / np.max(np.abs(ours)):.0e}")
    [[ 8.36433e+00 -7.40000e-04 -1.23000e-03]] 7e-10
    """
    import magpylib

    currents = np.asarray(currents_A, dtype=float)
    if currents.shape != (3,) or not np.all(np.isfinite(currents)):
        raise InputError("currents_A", currents_A, "three finite currents (x, y, z pair), A")
    system = _system(model)
    coils = []
    for pair, current in zip(system.pairs, currents, strict=True):
        fs = pair.filament_set
        e = np.eye(3)[pair.axis_index]
        rotation = _rotation(pair.axis)
        n = len(fs.turns) // 2  # filaments of one coil: the first half at -s/2, then +s/2
        polygon = hasattr(fs, "half_sides_m")  # four straight sides (a square, a rectangle)
        sizes = fs.half_sides_m if polygon else fs.radii_m
        others = getattr(fs, "half_sides_v_m", sizes)  # a rectangle's second half sides
        for side in (slice(0, n), slice(n, 2 * n)):
            centre = float(np.mean(fs.centres_m[side]))
            loops = [
                _filament(
                    magpylib,
                    _local_halves(pair.axis, float(size), float(other)) if polygon else None,
                    float(size),
                    float(z) * e,
                    float(turns * current),
                    rotation,
                )
                for size, other, z, turns in zip(
                    sizes[side], others[side], fs.centres_m[side], fs.turns[side], strict=True
                )
            ]
            coil = magpylib.Collection(*loops)
            coil.style.label = f"{pair.axis} pair, coil at {centre:+.4g} m"
            coils.append(coil)
    out = magpylib.Collection(*coils)
    out.style.label = "spiralcap coils"
    return out


@dataclass(frozen=True)
class FieldGrid:
    """The field per ampere of each pair on a regular grid.

    ``points_m`` (n, 3) are the grid points, m; ``field_per_A_T_per_A`` (n, 3, 3) the field
    matrix G: ``[:, c, k]`` is field component c of pair k per ampere, T/A.
    """

    points_m: np.ndarray
    field_per_A_T_per_A: np.ndarray
    step_m: float


def grid_columns() -> list[str]:
    """Column names: ``x_m, y_m, z_m``, then ``B{c}_per_A_{k}_T_per_A`` for pair k, component c."""
    return ["x_m", "y_m", "z_m"] + [f"B{c}_per_A_{k}_T_per_A" for k in _AXES for c in _AXES]


def field_grid(
    model: Any,
    half_width_m: float,
    step_m: float | None = None,
    box_m: Sequence[float] | None = None,
) -> FieldGrid:
    """The field per ampere of the x, y and z pairs on a grid over ``[-h, h]^3`` or a box.

    Parameters
    ----------
    model : optimize.DesignModel, spiralcap.design.Design or coils.ThreeAxisHelmholtz
        The coils.
    half_width_m : float
        Half the side of the cube sampled, m (the workspace radius); 0 samples the centre.
    step_m : float, optional
        Grid spacing, m (default: the box's longest side over :data:`DEFAULT_STEPS_PER_DIAMETER`).
    box_m : sequence of 6 floats, optional
        ``(x0, x1, y0, y1, z0, z1)``, m, with each lower end <= its upper end: the box sampled
        in place of the cube (``--grid-box-mm``). Along each axis the points are ``step_m``
        apart, centred in the box's extent on that axis.

    Raises
    ------
    spiralcap.core.errors.InputError
        ``--grid-step-mm`` not positive, or so small the grid exceeds :data:`MAX_GRID_POINTS`.

    Examples
    --------
    The field per ampere of each pair at the 27 points of a 10 cm cube:

    >>> import numpy as np
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> from spiralcap.export import field_grid
    >>> grid = field_grid(build_model(load_design(None, [])), 0.05, 0.05)
    >>> centre = np.flatnonzero(np.all(grid.points_m == 0.0, axis=1))[0]
    >>> print(grid.points_m.shape, np.round(np.diag(grid.field_per_A_T_per_A[centre]) * 1e3, 5))  # mT/A
    (27, 3) [0.83644 0.89918 0.9634 ]
    """
    system = _system(model)
    h = float(half_width_m)
    box = np.array([-h, h] * 3 if box_m is None else box_m, dtype=float).reshape(3, 2)
    sides = box[:, 1] - box[:, 0]
    where = "workspace cube" if box_m is None else "--grid-box-mm box"
    longest = float(np.max(sides))
    if step_m is None:
        step_m = longest / DEFAULT_STEPS_PER_DIAMETER if longest > 0 else 1.0
    if not (math.isfinite(step_m) and step_m > 0):
        raise InputError("--grid-step-mm", step_m * 1e3, "a grid spacing > 0 mm")
    counts = []
    for side in sides:
        span = float(side) / step_m + 1e-9  # points along a side less one (inf: subnormal step)
        counts.append(math.floor(span) + 1 if span < MAX_GRID_POINTS else MAX_GRID_POINTS + 1)
    if math.prod(counts) > MAX_GRID_POINTS:
        volume = float(np.prod(np.maximum(sides, step_m)))
        least = (volume / MAX_GRID_POINTS) ** (1 / 3)
        raise InputError(
            "--grid-step-mm",
            step_m * 1e3,
            f"a spacing of at least about {least * 1e3:.3g} mm (at most {MAX_GRID_POINTS} "
            f"points over the {' x '.join(f'{s * 1e3:g}' for s in sides)} mm {where})",
        )
    axes = [
        0.5 * (lo + hi) - 0.5 * (n - 1) * step_m + step_m * np.arange(n)
        for (lo, hi), n in zip(box, counts, strict=True)
    ]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return FieldGrid(grid, np.asarray(system.field_matrix(grid)), float(step_m))


def _table(grid: FieldGrid) -> np.ndarray:
    g = grid.field_per_A_T_per_A
    per_pair = [g[:, c, k] for k in range(3) for c in range(3)]
    return np.column_stack([grid.points_m, *per_pair])


def write_field_grid(path: str | os.PathLike[str], grid: FieldGrid) -> None:
    """Write ``grid`` as CSV (a header of :func:`grid_columns`, 17 significant figures) or, for
    a ``.npz`` name, NumPy arrays named by the same columns; atomically (nothing half-written).
    """
    from spiralcap.design import write_text_atomic

    write_text_atomic(path, field_grid_bytes(path, grid))


def field_grid_bytes(path: str | os.PathLike[str], grid: FieldGrid) -> bytes:
    """What :func:`write_field_grid` writes to ``path`` (CSV, or NumPy arrays for ``.npz``)."""
    table = _table(grid)
    names = grid_columns()
    if str(path).lower().endswith(".npz"):
        buf = io.BytesIO()
        arrays: dict[str, Any] = {name: table[:, i] for i, name in enumerate(names)}
        np.savez(buf, **arrays)  # plain float arrays
        return buf.getvalue()
    buf_text = io.StringIO()
    np.savetxt(buf_text, table, delimiter=",", fmt="%.17g", header=",".join(names), comments="")
    return buf_text.getvalue().encode()
