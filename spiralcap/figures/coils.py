"""Coil figures: field-uniformity maps on a plane through the centre, and axial profiles.

Functions take arrays computed by the ``coils`` package (``coils.uniformity``,
``coils.uniform_region_radius_m``) and draw them; they compute no fields themselves.
Positions are in metres (as the ``coils.*.radius_m`` design keys), deviations in per cent.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.axes import Axes

from spiralcap.figures.style import series_style

__all__ = ["DEVIATION_LEVELS_PERCENT", "plot_field_deviation_map", "plot_uniformity_profile"]

#: Filled-contour levels of |deviation| (%), roughly logarithmic so the ±1 % and ±5 % bands and
#: the edges of the workspace are all resolved.
DEVIATION_LEVELS_PERCENT = (0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0)
_TOLERANCE_STYLES = {0.01: ("-", 2.0), 0.05: ("--", 2.0)}


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
) -> dict[str, Any]:
    """Map of |B| deviation from the centre value on a plane through the coil centre.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    u_m, v_m : array_like, shapes (nu,) and (nv,)
        Coordinates along the plane's two axes, m.
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
        Add a colour bar of |deviation| (%) beside the axes (pass False and add one colour bar
        for several maps: they share :data:`DEVIATION_LEVELS_PERCENT`).
    legend : bool
        Add a legend of the circles inside the axes.
    label_contours : bool
        Write ``±1 %``, ``±5 %`` on the tolerance contours.

    Returns
    -------
    dict
        ``filled`` (QuadContourSet), ``contours`` (dict tolerance -> QuadContourSet),
        ``circles`` (list of Line2D), ``colorbar`` (Colorbar or None).
    """
    u = np.asarray(u_m, dtype=float)
    v = np.asarray(v_m, dtype=float)
    dev = 100.0 * np.abs(np.asarray(deviation, dtype=float))
    top = float(np.nanmax(dev))
    filled = ax.contourf(
        u, v, dev, levels=list(DEVIATION_LEVELS_PERCENT), cmap="Blues", extend="max"
    )
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
            r * np.cos(t),
            r * np.sin(t),
            color="#D55E00",
            linestyle=":",
            linewidth=1.8,
            label=f"±{100 * tol:g} % sphere, r = {r * 1e3:.4g} mm",
        )
        circles.append(c)
    if workspace_radius_m:
        r = workspace_radius_m
        (c,) = ax.plot(
            r * np.cos(t),
            r * np.sin(t),
            color="black",
            linestyle="-.",
            linewidth=1.6,
            label=f"workspace, r = {r * 1e3:.4g} mm",
        )
        circles.append(c)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{axis_labels[0]} (m)")
    ax.set_ylabel(f"{axis_labels[1]} (m)")
    ax.grid(False)
    if title:
        ax.set_title(title)
    if circles and legend:
        ax.legend(loc="lower left", fontsize=7)
    cbar = None
    if colorbar:
        cbar = ax.figure.colorbar(filled, ax=ax, label="|B| deviation from centre (%)", shrink=0.9)
    return {"filled": filled, "contours": contours, "circles": circles, "colorbar": cbar}


def plot_uniformity_profile(
    ax: Axes,
    distance_m: Any,
    deviations: Mapping[str, Any],
    *,
    tolerances: tuple[float, ...] = (0.01, 0.05),
) -> dict[str, Any]:
    """Deviation of |B| from the centre value along lines through the centre.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    distance_m : array_like, shape (n,)
        Signed distance from the centre along each line, m.
    deviations : mapping label -> array_like, shape (n,)
        Relative deviation along each line (``"x pair, along x"`` -> values), dimensionless.
    tolerances : tuple of float
        Horizontal reference lines at ± each tolerance.

    Returns
    -------
    dict
        ``lines`` (list of Line2D), ``bands`` (list of Line2D).
    """
    d = np.asarray(distance_m, dtype=float)
    lines = []
    for k, (label, dev) in enumerate(deviations.items()):
        (ln,) = ax.plot(
            d,
            100.0 * np.asarray(dev, dtype=float),
            label=label,
            **series_style(k, markevery=max(1, len(d) // 12)),
        )
        lines.append(ln)
    bands = []
    for tol, ls in zip(tolerances, ("--", ":", "-."), strict=False):
        for sign in (1, -1):
            bands.append(ax.axhline(sign * 100 * tol, color="black", linestyle=ls, linewidth=1.0))
    ax.set_xlabel("distance from the centre (m)")
    ax.set_ylabel("|B| deviation from centre (%)")
    ax.legend(loc="best")
    return {"lines": lines, "bands": bands}
