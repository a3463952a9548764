"""The coil set as a CAD model: six named solid winding packs (and the workspace sphere) as STEP/STL.

Through build123d (OpenCASCADE), the optional ``cad`` extra (``pip install "spiralcap[cad]"``).
Each pack is the solid ring of :mod:`coils.clearance` (mean radius R, axial width w, radial depth
h, mid-plane at ±s/2 on its pair's axis; a square pair's the frame of side a ± h, sharp corners), built on its own so every solid keeps its own name in
the STEP file (``coil_x-``, ``coil_x+``, …, ``workspace``). Millimetres, the usual CAD unit
(STEP carries it); the coil centre is the origin and x, y, z are the coil axes.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping
from typing import Any

from spiralcap.core.errors import InputError

__all__ = ["INSTALL_HINT", "cad_bodies", "cad_kernel_available", "require_cad", "write_cad"]

INSTALL_HINT = 'the optional CAD kernel: pip install "spiralcap[cad]" (build123d)'
_MM = 1e3


def cad_kernel_available() -> bool:
    """Is build123d importable (without importing it)?"""
    import importlib.util

    return importlib.util.find_spec("build123d") is not None


def require_cad(flag: str, path: str) -> None:
    """Refuse a CAD output when the kernel is missing: an InputError naming the option."""
    if not cad_kernel_available():
        raise InputError(flag, path, INSTALL_HINT)


def cad_bodies(pairs: Any, workspace_radius_m: float | None = None) -> list[tuple[str, Any]]:
    """(name, body) of every solid: each pack a :class:`coils.clearance.Ring` (a square pair's a
    :class:`coils.clearance.Frame`), the workspace a radius in m (only when
    ``workspace_radius_m`` is given and positive)."""
    from coils.clearance import pair_packs

    out: list[tuple[str, Any]] = []
    for pair in pairs:
        for sign, ring in zip("-+", pair_packs(pair)):
            out.append((f"coil_{pair.axis}{sign}", ring))
    if workspace_radius_m:
        out.append(("workspace", float(workspace_radius_m)))
    return out


def _solid(ring: Any) -> Any:
    from build123d import Box, Cylinder, Pos, Rot

    from coils.clearance import Frame

    w, h = ring.width_m * _MM, ring.depth_m * _MM
    if isinstance(ring, Frame):  # a frame, sides along the other axes, sharp corners
        # its sides along the turned body's local x and y: the next two axes in cyclic order,
        # taken in the order the turn below puts them (local x -> z for x, x for y and z)
        a, b = (s * _MM for s in ring.sides_m)
        lx, ly = ((b, a), (b, a), (a, b))[ring.axis]
        body = Box(lx + h, ly + h, w) - Box(lx - h, ly - h, w)
    else:
        r = ring.radius_m * _MM
        body = Cylinder(r + 0.5 * h, w) - Cylinder(r - 0.5 * h, w)  # about z, centred
    turn = (Rot(0, 90, 0), Rot(-90, 0, 0), Rot(0, 0, 0))[ring.axis]  # z onto x, y, z
    offset = [0.0, 0.0, 0.0]
    offset[ring.axis] = ring.centre_m * _MM
    return Pos(*offset) * (turn * body)


def compound(bodies: list[tuple[str, Any]]) -> Any:
    """The build123d compound of :func:`cad_bodies`, each child labelled with its name."""
    from build123d import Compound, Sphere

    children = []
    for name, body in bodies:
        solid = Sphere(body * _MM) if name == "workspace" else _solid(body)
        solid.label = name
        children.append(solid)
    out = Compound(children=children)
    out.label = "spiralcap coil set"
    return out


def cad_files(bodies: list[tuple[str, Any]], step: str | None, stl: str | None) -> dict[str, bytes]:
    """The bytes of the STEP and/or STL files of ``bodies`` (written to a scratch folder)."""
    from build123d import export_step, export_stl

    shape = compound(bodies)
    out: dict[str, bytes] = {}
    with tempfile.TemporaryDirectory() as tmp:
        if step is not None:
            scratch = os.path.join(tmp, "coils.step")
            if not export_step(shape, scratch):
                raise RuntimeError("the CAD kernel could not write the STEP file")
            with open(scratch, "rb") as fh:
                out[step] = fh.read()
        if stl is not None:
            scratch = os.path.join(tmp, "coils.stl")
            if not export_stl(shape, scratch, tolerance=0.05, angular_tolerance=0.1):
                raise RuntimeError("the CAD kernel could not write the STL file")
            with open(scratch, "rb") as fh:
                out[stl] = fh.read()
    return out


def write_cad(
    pairs: Any, step: str | None, stl: str | None, workspace_radius_m: float | None = None
) -> list[str]:
    """Write the STEP and/or STL files of the coil set, both or neither (atomic); the paths."""
    from spiralcap.design import write_files_atomic

    files: Mapping[str, bytes] = cad_files(cad_bodies(pairs, workspace_radius_m), step, stl)
    return [str(p) for p in write_files_atomic(files)]
