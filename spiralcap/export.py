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


def _filament(
    magpylib: Any, square: bool, size_m: float, position_m: Any, ampere_turns: float, rotation: Any
) -> Any:
    """One filament: a ``Circle`` of radius ``size_m``, or a closed ``Polyline`` square of half
    side ``size_m`` (sides along the other two axes), counter-clockwise about its local z so a
    positive current makes a field along the pair's axis, as spiralcap's sign."""
    if not square:
        return magpylib.current.Circle(
            current=ampere_turns, diameter=2.0 * size_m, position=position_m, orientation=rotation
        )
    h = size_m
    corners = [(h, -h, 0.0), (h, h, 0.0), (-h, h, 0.0), (-h, -h, 0.0), (h, -h, 0.0)]
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
        square = hasattr(fs, "half_sides_m")  # coils.square_pair.SquarePair
        sizes = fs.half_sides_m if square else fs.radii_m
        for side in (slice(0, n), slice(n, 2 * n)):
            centre = float(np.mean(fs.centres_m[side]))
            loops = [
                _filament(
                    magpylib, square, float(size), float(z) * e, float(turns * current), rotation
                )
                for size, z, turns in zip(
                    sizes[side], fs.centres_m[side], fs.turns[side], strict=True
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


def field_grid(model: Any, half_width_m: float, step_m: float | None = None) -> FieldGrid:
    """The field per ampere of the x, y and z pairs on a grid over ``[-h, h]^3``.

    Parameters
    ----------
    model : optimize.DesignModel, spiralcap.design.Design or coils.ThreeAxisHelmholtz
        The coils.
    half_width_m : float
        Half the side of the cube sampled, m (the workspace radius); 0 samples the centre.
    step_m : float, optional
        Grid spacing, m (default: the cube's side over :data:`DEFAULT_STEPS_PER_DIAMETER`).

    Raises
    ------
    spiralcap.core.errors.InputError
        ``--grid-step-mm`` not positive, or so small the grid exceeds :data:`MAX_GRID_POINTS`.
    """
    system = _system(model)
    h = float(half_width_m)
    if step_m is None:
        step_m = 2.0 * h / DEFAULT_STEPS_PER_DIAMETER if h > 0 else 1.0
    if not (math.isfinite(step_m) and step_m > 0):
        raise InputError("--grid-step-mm", step_m * 1e3, "a grid spacing > 0 mm")
    span = 2.0 * h / step_m + 1e-9  # points per side less one (inf for a subnormal step)
    n = math.floor(span) + 1 if span < MAX_GRID_POINTS else MAX_GRID_POINTS + 1
    if n**3 > MAX_GRID_POINTS:
        raise InputError(
            "--grid-step-mm",
            step_m * 1e3,
            f"a spacing of at least {2e3 * h / (MAX_GRID_POINTS ** (1 / 3) - 1):.3g} mm "
            f"(at most {MAX_GRID_POINTS} points over the {2e3 * h:g} mm workspace cube)",
        )
    axis = -0.5 * (n - 1) * step_m + step_m * np.arange(n)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
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
