"""The hardware to scale: three nested Helmholtz pairs, the workspace, and the capsule.

:func:`plot_geometry` draws a section through the coil centre in the x–z plane, in mm: the x
and z pairs cut through their winding packs (rectangles of axial width x radial depth at the
mean radius, the coil itself edge-on; a square pair's at half its side, where the section
cuts its frame), the y pair face-on (its two coils are parallel to the section plane, so they
show as the outline of their winding annulus, or of the square frame), the workspace sphere and,
when a least clearance is given, where the packs of two pairs come closest (the 3-D segment
between the solids, :func:`coils.clearance.pack_closest_points`, projected onto the section)
with its length. An inset shows
the capsule to its own scale: the shell, the spiral wire at its helical angle over the wound
length (front half solid, back half dashed, every start) and the diametrically magnetised
magnet with its moment. Everything is read off the domain objects (``coils.ThreeAxisHelmholtz``,
``capsule.Capsule``); nothing is computed here but the drawing.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes

from spiralcap.core.constants import to_unit
from spiralcap.figures.style import COLOURS

__all__ = ["CapsuleDrawn", "GeometryDrawn", "draw_geometry", "plot_capsule", "plot_geometry"]

_MM = 1e3
_PAIR_STYLE: dict[str, tuple[str, Any]] = {
    "x": (COLOURS[0], "-"),
    "y": (COLOURS[2], "--"),
    "z": (COLOURS[1], "-."),
}


class GeometryDrawn(NamedTuple):
    """What :func:`plot_geometry` drew: one list of artists per pair, the workspace, the inset."""

    pairs: dict[str, list[Any]]
    workspace: Any
    capsule_axes: Any


class CapsuleDrawn(NamedTuple):
    """What :func:`plot_capsule` drew."""

    shell: Any
    spiral: list[Any]
    magnet: Any
    moment: Any


def _pack(ax: Axes, cx: float, cy: float, wx: float, wy: float, colour: str, hatch: str) -> Any:
    from matplotlib.patches import Rectangle

    return ax.add_patch(
        Rectangle(
            (cx - wx / 2, cy - wy / 2),
            wx,
            wy,
            facecolor=colour,
            edgecolor="black",
            linewidth=0.6,
            hatch=hatch,
            alpha=0.9,
        )
    )


def plot_geometry(
    ax: Axes,
    coils: Any,
    capsule: Any = None,
    *,
    workspace_radius_m: float | None = None,
    capsule_ax: Any = None,
    legend_ax: Any = None,
    min_clearance_m: float | None = None,
) -> GeometryDrawn:
    """Section of the coil system through its centre (x–z plane), to scale, in mm.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    coils : coils.ThreeAxisHelmholtz
        The three pairs (``.x``, ``.y``, ``.z``: radius, separation, winding-pack side).
    capsule : capsule.Capsule, optional
        Drawn on ``capsule_ax`` to its own scale (:func:`plot_capsule`).
    workspace_radius_m : float, optional
        Radius of the workspace sphere, m (dash-dot circle).
    capsule_ax, legend_ax : matplotlib.axes.Axes, optional
        Where the capsule and the legend go (the legend goes under ``ax`` when not given).
    min_clearance_m : float, optional
        The least clearance allowed (coils.min_clearance_mm); given, the closest approach of
        each two pairs' packs is drawn and labelled with its length.

    Returns
    -------
    GeometryDrawn
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Annulus

    drawn: dict[str, list[Any]] = {}
    handles = []
    extent = 0.0
    for name, hatch in (("x", ""), ("z", "///"), ("y", "")):
        pair = getattr(coils, name)
        colour, ls = _PAIR_STYLE[name]
        # the mean turn's reach in the section plane (x-z): along z for x, along x for z
        reaches = pair.reaches_m(pair.sizes_m)
        r = float(reaches[1] if name == "x" else reaches[0]) * _MM
        h = 0.5 * pair.separation_m * _MM
        width, depth = pair.winding_pack_width_m * _MM, pair.winding_pack_depth_m * _MM
        extent = max(extent, r + depth, h + width)
        arts: list[Any] = []
        frame = not pair.RING
        if name == "y" and frame:
            # a frame face-on: the band between the rectangles of half sides reach ± depth/2
            # (a y pair's first side runs along z, its second along x)
            half_x, half_z = float(reaches[1]) * _MM, float(reaches[0]) * _MM
            arts.append(ax.add_patch(_square_band(half_x, half_z, depth, colour, ls)))
        elif name == "y":
            # parallel to the section plane: the winding annulus seen face-on
            arts.append(
                ax.add_patch(
                    Annulus(
                        (0.0, 0.0),
                        r + depth / 2,
                        depth,
                        facecolor=(0.0, 0.62, 0.45, 0.22),
                        edgecolor=colour,
                        linewidth=1.0,
                        linestyle=ls,
                    )
                )
            )
        else:
            for s_axial in (-h, h):
                for s_radial in (-r, r):
                    if name == "x":  # axis along the plot's x: width across, depth up
                        arts.append(_pack(ax, s_axial, s_radial, width, depth, colour, hatch))
                    else:
                        arts.append(_pack(ax, s_radial, s_axial, depth, width, colour, hatch))
                xs, ys = ([s_axial, s_axial], [-r, r]) if name == "x" else ([-r, r], [s_axial] * 2)
                arts += ax.plot(xs, ys, color=colour, linestyle=ls, linewidth=1.0)
        drawn[name] = arts
        handles.append(
            Line2D(
                [],
                [],
                color=colour,
                linestyle=ls,
                marker="s",
                markerfacecolor=colour if name != "y" else "none",
                label=f"{name} pair: "
                + (_frame_words(pair) if frame else f"R = {r:.0f} mm")
                + f", spacing {2 * h:.0f} mm, "
                f"pack {width:.0f} x {depth:.0f} mm" + (" (face-on)" if name == "y" else ""),
            )
        )
    ws = None
    if workspace_radius_m:
        t = np.linspace(0.0, 2 * math.pi, 181)
        rw = workspace_radius_m * _MM
        (ws,) = ax.plot(
            rw * np.cos(t),
            rw * np.sin(t),
            color="black",
            linestyle=(0, (6, 2, 1, 2)),
            linewidth=1.4,
            label=f"workspace sphere, r = {rw:.0f} mm",
        )
        handles.append(ws)
    if min_clearance_m is not None:
        handles += _clearances(ax, coils, min_clearance_m)
    ax.plot([0], [0], marker="+", color="black", markersize=10, linestyle="none")
    pad = 1.08 * extent
    ax.set_xlim(-pad, pad)
    ax.set_ylim(-pad, pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.grid(False)
    if legend_ax is None:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=7.5)
    else:
        legend_ax.axis("off")
        legend_ax.legend(handles=handles, loc="center", fontsize=7.5, frameon=False, ncols=2)
    cap_ax = None
    if capsule_ax is not None and capsule is not None:
        cap_ax = capsule_ax
        plot_capsule(cap_ax, capsule)
    return GeometryDrawn(drawn, ws, cap_ax)


def _frame_words(pair: Any) -> str:
    """A frame's legend words: ``square, side 780 mm`` or ``rectangle, sides 620 x 800 mm``."""
    sizes = [f"{s * _MM:.0f}" for s in pair.sizes_m]
    return f"{pair.shape}, side{'s' if len(sizes) > 1 else ''} {' x '.join(sizes)} mm"


def _square_band(half_x_mm: float, half_z_mm: float, depth_mm: float, colour: Any, ls: Any) -> Any:
    """The face-on band of a frame (outer rectangle less the inner one), a PathPatch."""
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    def square(hx: float, hz: float, reverse: bool) -> list[tuple[float, float]]:
        corners = [(hx, -hz), (hx, hz), (-hx, hz), (-hx, -hz)]
        return (corners[::-1] if reverse else corners) + [corners[-1] if reverse else corners[0]]

    outer = square(half_x_mm + depth_mm / 2, half_z_mm + depth_mm / 2, False)
    inner = square(half_x_mm - depth_mm / 2, half_z_mm - depth_mm / 2, True)
    codes = [Path.MOVETO, *[Path.LINETO] * 3, Path.CLOSEPOLY] * 2
    return PathPatch(
        Path(outer + inner, codes),
        facecolor=(0.0, 0.62, 0.45, 0.22),
        edgecolor=colour,
        linewidth=1.0,
        linestyle=ls,
    )


def _clearances(ax: Axes, coils: Any, need_m: float) -> list[Any]:
    """The closest approach of each two pairs' packs, projected onto the x-z section, one marker
    shape per two pairs (greyscale-safe); their lengths go into the legend."""
    import itertools

    from matplotlib.lines import Line2D

    from coils.clearance import pack_closest_points

    handles = []
    for (a, b), marker in zip(itertools.combinations(coils.pairs, 2), ("o", "s", "^")):
        d, pa, pb = pack_closest_points(a, b)
        xs, zs = [pa[0] * _MM, pb[0] * _MM], [pa[2] * _MM, pb[2] * _MM]
        style: dict[str, Any] = {
            "color": "black",
            "linewidth": 1.2,
            "marker": marker,
            "markersize": 3.5,
        }
        ax.plot(xs, zs, **style)
        # short enough that the two-column legend stays inside the figure when it flags a gap
        tail = " (3-D, projected)" if d >= need_m * (1 - 1e-6) else f": under {need_m * _MM:g} mm"
        handles.append(
            Line2D([], [], **style, label=f"{a.axis}/{b.axis} packs {d * _MM:.1f} mm apart{tail}")
        )
    return handles


def draw_geometry(
    fig: Any,
    coils: Any,
    capsule: Any = None,
    *,
    workspace_radius_m: float | None = None,
    min_clearance_m: float | None = None,
) -> GeometryDrawn:
    """The geometry view on a whole Figure (or SubFigure): the coil section on the left, the
    capsule to its own scale on the right, the legend under both. Returns what was drawn.
    """
    mosaic = [["coils", "capsule"], ["legend", "legend"]]
    axs = fig.subplot_mosaic(mosaic, width_ratios=[1.0, 1.1], height_ratios=[1.0, 0.42])
    return plot_geometry(
        axs["coils"],
        coils,
        capsule,
        workspace_radius_m=workspace_radius_m,
        capsule_ax=axs["capsule"],
        legend_ax=axs["legend"],
        min_clearance_m=min_clearance_m,
    )


def plot_capsule(ax: Axes, capsule: Any) -> CapsuleDrawn:
    """Side view of the capsule to scale, in mm: shell, spiral at its helical angle, magnet.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    capsule : capsule.Capsule
        Body (diameter, length), spiral (helical angle, wire diameter, wound length, starts)
        and magnet (diameter, length; magnetised across its axis).

    Returns
    -------
    CapsuleDrawn
    """
    from matplotlib.patches import Polygon, Rectangle

    body, spiral, magnet = capsule.body, capsule.spiral, capsule.magnet
    d, length = body.diameter_m * _MM, body.length_m * _MM
    # a cylinder with hemispherical ends: two half circles joined by straight sides
    cap = np.linspace(-math.pi / 2, math.pi / 2, 60)
    c = length / 2 - d / 2
    right = np.column_stack([c + d / 2 * np.cos(cap), d / 2 * np.sin(cap)])
    left = np.column_stack([-c - d / 2 * np.cos(cap), -d / 2 * np.sin(cap)])
    shell = ax.add_patch(
        Polygon(np.vstack([right, left]), closed=True, facecolor="0.93", edgecolor="black")
    )
    dm, lm = magnet.diameter_m * _MM, magnet.length_m * _MM
    mag = ax.add_patch(
        Rectangle(
            (-lm / 2, -dm / 2),
            lm,
            dm,
            facecolor="0.55",
            edgecolor="black",
            hatch="xx",
            linewidth=0.8,
        )
    )
    moment = ax.annotate(
        "",
        xy=(0.0, 0.42 * dm),
        xytext=(0.0, -0.42 * dm),
        arrowprops={"arrowstyle": "-|>", "color": "white", "linewidth": 1.6},
    )
    ax.text(0.0, 0.55 * dm, "m", ha="center", va="bottom", fontsize=8, style="italic")
    # the wire's centre line: helix of diameter D + d_w, lead pi D_h tan(alpha) per start
    dw = spiral.wire_diameter_m * _MM
    dh = d + dw
    lead = math.pi * dh * math.tan(spiral.helical_angle_rad)
    lw = spiral.wound_length_m * _MM
    theta = np.linspace(0.0, 2 * math.pi * lw / lead, 1200)
    z = -lw / 2 + lead * theta / (2 * math.pi)
    lines = []
    for k in range(int(spiral.starts)):
        phase = theta + 2 * math.pi * k / int(spiral.starts)
        y = 0.5 * dh * np.sin(phase)
        front = np.cos(phase) >= 0
        lines += ax.plot(
            z, np.where(front, y, np.nan), color=COLOURS[1], linewidth=2.2, solid_capstyle="butt"
        )
        lines += ax.plot(
            z,
            np.where(~front, y, np.nan),
            color=COLOURS[1],
            linewidth=0.8,
            linestyle=(0, (2, 1.5)),
        )
    alpha_deg = to_unit(spiral.helical_angle_rad, "deg")
    ax.set_title(
        f"capsule {d:.3g} × {length:.3g} mm, magnet {dm:.3g} × {lm:.3g} mm\n"
        f"spiral α = {alpha_deg:.3g}°, {int(spiral.starts)} start{'' if int(spiral.starts) == 1 else 's'}, wire {dw:.2g} mm, "
        f"wound over {lw:.3g} mm",
        fontsize=7.5,
    )
    pad = 0.12 * length
    ax.set_xlim(-length / 2 - pad, length / 2 + pad)
    ax.set_ylim(-0.5 * dh - 0.35 * d, 0.5 * dh + 0.35 * d)
    ax.set_aspect("equal")
    ax.set_xlabel("along the capsule axis (mm)", fontsize=8)
    ax.set_ylabel("mm", fontsize=8)
    ax.tick_params(labelsize=7.5)
    ax.grid(False)
    return CapsuleDrawn(shell, lines, mag, moment)
