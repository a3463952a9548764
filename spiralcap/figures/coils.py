"""Coil figures: field-uniformity maps on a plane through the centre, and axial profiles.

Functions take arrays computed by the ``coils`` package (``coils.uniformity``,
``coils.uniform_region_radius_m``) and draw them; they compute no fields themselves.
Positions are in metres (as the ``coils.*.radius_m`` design keys), deviations in per cent.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes

from spiralcap.figures.style import series_style

__all__ = [
    "DEVIATION_LEVELS_PERCENT",
    "MapDrawn",
    "ProfileDrawn",
    "plot_field_deviation_map",
    "plot_uniformity_profile",
]

#: Filled-contour levels of the signed deviation (%), symmetric and roughly logarithmic so the
#: ±1 % and ±5 % bands and the edges of the workspace are all resolved; a diverging colour
#: map centred on zero (blue weaker than the centre, red stronger).
_POS = (0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0)
DEVIATION_LEVELS_PERCENT = (*(-v for v in reversed(_POS)), 0.0, *_POS)
_TOLERANCE_STYLES = {0.01: ("-", 2.0), 0.05: ("--", 2.0)}
_TO_MM = 1e3


class MapDrawn(NamedTuple):
    """What :func:`plot_field_deviation_map` drew (contours keyed by tolerance)."""

    filled: Any
    contours: dict[float, Any]
    circles: list[Any]
    colorbar: Any


class ProfileDrawn(NamedTuple):
    """What :func:`plot_uniformity_profile` drew: curves and the ± tolerance lines."""

    lines: list[Any]
    bands: list[Any]


def plot_field_deviation_map(
    ax: Axes,
    u_m: Any,
    v_m: Any,
    deviation: Any,
    *,
    axis_labels: tuple[str, str] = ("x", "z"),
    tolerances: tuple[float, ...] = (0.01, 0.05),
    uniform_radii_m: Mapping[float, float] | None = None,
    workspace_radius_m: float | None = None,
    title: str | None = None,
    colorbar: bool = True,
    legend: bool = True,
    label_contours: bool = True,
) -> MapDrawn:
    """Map of the signed |B| deviation from the centre value on a plane through the centre.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    u_m, v_m : array_like, shapes (nu,) and (nv,)
        Coordinates along the plane's two axes, m (drawn in mm).
    deviation : array_like, shape (nv, nu)
        Relative deviation |B(p)| / |B(0)| - 1 (dimensionless), e.g.
        ``coils.uniformity(system, points, currents)`` reshaped to the grid.
    axis_labels : (str, str)
        Names of the plane's axes (``("x", "z")``).
    tolerances : tuple of float
        Deviations whose contours are drawn and labelled (0.01 for ±1 %); the ±1 % contour is
        solid, the ±5 % contour dashed.
    uniform_radii_m : mapping float -> float, optional
        Radius of the uniform sphere for each tolerance (``coils.uniform_region_radius_m``), m;
        drawn as dotted circles.
    workspace_radius_m : float, optional
        The design's workspace radius, m; drawn as a dash-dot circle.
    title : str, optional
        Axes title.
    colorbar : bool
        Add a colour bar of the signed deviation (%) beside the axes (pass False and add one
        colour bar for several maps: they share :data:`DEVIATION_LEVELS_PERCENT`).
    legend : bool
        Add a legend of the circles inside the axes.
    label_contours : bool
        Write ``±1 %``, ``±5 %`` on the tolerance contours.

    Returns
    -------
    MapDrawn
        ``contours`` holds each tolerance's contour of |deviation| (both signs).
    """
    from matplotlib.colors import BoundaryNorm

    u = np.asarray(u_m, dtype=float) * _TO_MM
    v = np.asarray(v_m, dtype=float) * _TO_MM
    signed = 100.0 * np.asarray(deviation, dtype=float)
    dev = np.abs(signed)
    top = float(np.nanmax(dev))
    levels = list(DEVIATION_LEVELS_PERCENT)
    norm = BoundaryNorm(levels, ncolors=256, extend="both")
    filled = ax.contourf(u, v, signed, levels=levels, cmap="RdBu_r", norm=norm, extend="both")
    # the sign in greyscale print: where the field is weaker than the centre by more than the
    # narrowest tolerance, a light dot hatch (a diverging map alone reads the same both ways)
    weak = -100.0 * min(tolerances, default=0.01)
    if np.nanmin(signed) < weak:
        hatched = ax.contourf(
            u,
            v,
            signed,
            levels=[float(np.nanmin(signed)) - 1.0, weak],
            colors="none",
            hatches=[".."],
        )
        for coll in getattr(hatched, "collections", [hatched]):
            coll.set_edgecolor("0.35")
            coll.set_linewidth(0.0)
    contours = {}
    for tol in tolerances:
        ls, lw = _TOLERANCE_STYLES.get(tol, (":", 1.6))
        if np.nanmin(dev) < 100 * tol < top:
            cs = ax.contour(
                u, v, dev, levels=[100 * tol], colors="black", linestyles=ls, linewidths=lw
            )
            if label_contours:
                ax.clabel(cs, fmt={100 * tol: f"±{100 * tol:g} %"}, fontsize=8)
            contours[tol] = cs
    circles = []
    t = np.linspace(0, 2 * np.pi, 241)
    for tol, r in (uniform_radii_m or {}).items():
        (c,) = ax.plot(
            r * _TO_MM * np.cos(t),
            r * _TO_MM * np.sin(t),
            color="#E69F00",
            linestyle=":",
            linewidth=2.0,
            label=f"±{100 * tol:g} % sphere, r = {r * 1e3:.3g} mm",
        )
        circles.append(c)
    if workspace_radius_m:
        r = workspace_radius_m * _TO_MM
        (c,) = ax.plot(
            r * np.cos(t),
            r * np.sin(t),
            color="black",
            linestyle="-.",
            linewidth=1.6,
            label=f"workspace, r = {r:.3g} mm",
        )
        circles.append(c)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{axis_labels[0]} (mm)")
    ax.set_ylabel(f"{axis_labels[1]} (mm)")
    ax.grid(False)
    if title:
        ax.set_title(title)
    if circles and legend:
        ax.legend(loc="lower left", fontsize=7)
    cbar = None
    if colorbar:
        cbar = ax.figure.colorbar(
            filled,
            ax=ax,
            label="|B| / |B(0)| − 1 (%)",
            shrink=0.9,
            ticks=_CBAR_TICKS,
            spacing="uniform",
        )
    return MapDrawn(filled, contours, circles, cbar)


#: Colour-bar ticks of the signed deviation maps (%).
_CBAR_TICKS = (-20.0, -5.0, -1.0, 0.0, 1.0, 5.0, 20.0)


def plot_uniformity_profile(
    ax: Axes,
    distance_m: Any,
    deviations: Mapping[str, Any],
    *,
    tolerances: tuple[float, ...] = (0.01, 0.05),
) -> ProfileDrawn:
    """Signed deviation of |B| from the centre value along lines through the centre.

    The ranges come from the data: the distance axis runs to where the largest deviation
    reaches about twice the widest tolerance, the deviation axis covers every curve there.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    distance_m : array_like, shape (n,)
        Signed distance from the centre along each line, m (drawn in mm).
    deviations : mapping label -> array_like, shape (n,)
        Relative deviation along each line (``"x pair, along x"`` -> values), dimensionless.
    tolerances : tuple of float
        Horizontal reference lines at ± each tolerance, named in the legend.

    Returns
    -------
    ProfileDrawn
    """
    d = np.asarray(distance_m, dtype=float) * _TO_MM
    devs = {k: 100.0 * np.asarray(v, dtype=float) for k, v in deviations.items()}
    lines = []
    for k, (label, dev) in enumerate(devs.items()):
        (ln,) = ax.plot(d, dev, label=label, **series_style(k, markevery=max(1, len(d) // 12)))
        lines.append(ln)
    bands = []
    for tol, ls in zip(tolerances, ("--", ":", "-."), strict=False):
        for sign in (1, -1):
            bands.append(
                ax.axhline(
                    sign * 100 * tol,
                    color="black",
                    linestyle=ls,
                    linewidth=1.1,
                    label=f"±{100 * tol:g} %" if sign > 0 else None,
                )
            )
    if devs:
        worst = np.max(np.abs(np.vstack(list(devs.values()))), axis=0)
        limit = 2.0 * 100 * max(tolerances, default=0.05)
        inside = np.abs(d)[worst <= limit]
        reach = float(inside.max()) if inside.size else float(np.abs(d).max())
        reach = min(float(np.abs(d).max()), 1.08 * reach)
        sel = np.abs(d) <= reach
        values = np.vstack([v[sel] for v in devs.values()])
        # the narrowest tolerance band is always shown; wider ones where the data reach them
        lo = min(float(values.min()), -100 * min(tolerances, default=0.0))
        hi = max(float(values.max()), 100 * min(tolerances, default=0.0))
        pad = 0.08 * (hi - lo)
        ax.set_xlim(-reach, reach)
        ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("distance from the centre (mm)")
    ax.set_ylabel("|B| / |B(0)| − 1 (%)")
    ax.legend(loc="best", fontsize=7.5, ncols=2)
    return ProfileDrawn(lines, bands)


#: Filled levels of the stray-field map, mT (log-spaced round numbers).
STRAY_LEVELS_mT = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0)


def plot_stray_plane(ax: Any, plane: Any, coils: Any, level_T: float) -> Any:
    """One plane of the stray-field map: filled log levels (mT), the ``level_T`` contour thick,
    the packs of the pairs whose axes lie in the plane as rectangles, the third pair's outline
    dashed. Returns the filled contour set (for a colour bar)."""
    from matplotlib.colors import BoundaryNorm
    from matplotlib.patches import Polygon, Rectangle

    u, v = np.asarray(plane.u_m) * 1e3, np.asarray(plane.v_m) * 1e3
    peak = np.asarray(plane.peak_T) * 1e3
    levels = list(STRAY_LEVELS_mT)
    norm = BoundaryNorm(levels, 256, extend="both")
    filled = ax.contourf(u, v, peak, levels=levels, cmap="Greys", norm=norm, extend="both")
    line = ax.contour(u, v, peak, levels=[level_T * 1e3], colors="#D55E00", linewidths=2.0)
    ax.clabel(line, fmt=lambda x: f"{x:g} mT", fontsize=8)
    second = {"xz": 2, "xy": 1}[plane.plane]
    for k, pair in enumerate(coils.pairs):
        size_mm = float(pair.radius_m) * 1e3
        if k in (0, second):  # the pair's axis lies in the plane: its packs cut it
            w, h = pair.winding_pack_width_m * 1e3, pair.winding_pack_depth_m * 1e3
            for a in (-0.5, 0.5):
                for r in (-1.0, 1.0):
                    c_ax, c_r = a * pair.separation_m * 1e3, r * size_mm
                    x0, y0 = (c_ax - w / 2, c_r - h / 2) if k == 0 else (c_r - h / 2, c_ax - w / 2)
                    dx, dy = (w, h) if k == 0 else (h, w)
                    ax.add_patch(Rectangle((x0, y0), dx, dy, facecolor="#0072B2", edgecolor="none"))
        else:  # the pair's mean turn, as the pair itself draws it (any shape)
            pts = pair.mean_turn_points(k, pair.sizes_m, 0.0, 200) * 1e3
            uv = [i for i in range(3) if i != k]
            ax.add_patch(Polygon(pts[:, uv], closed=True, fill=False, linestyle="--", lw=1.0))
    names = {"xz": ("x (mm)", "z (mm)"), "xy": ("x (mm)", "y (mm)")}[plane.plane]
    ax.set_xlabel(names[0])
    ax.set_ylabel(names[1])
    ax.set_aspect("equal")
    ax.set_title(f"{plane.plane[0]}–{plane.plane[1]} plane through the centre", fontsize=9)
    return filled
