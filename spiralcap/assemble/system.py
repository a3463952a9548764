"""Design -> :class:`optimize.DesignModel`: coils, capsule, tissues, workspace, limits, options."""

from __future__ import annotations

import math

import numpy as np

from spiralcap.design import Design
from spiralcap.errors import InputError
from spiralcap.schema import winding_temperature_C

#: Below this helical angle the D' conversion of torque_model.geometry no longer holds for the
#: paper's capsule (the bump wraps round the back; see its docstring).
MIN_MODEL_ANGLE_deg = 1.8


def _headings(design: Design) -> np.ndarray:
    from optimize.system import default_headings

    raw = design["workspace.headings"]
    if raw == "all":
        return default_headings()
    h = np.asarray(raw, dtype=float)
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def build_model(design: Design):
    """The :class:`optimize.DesignModel` of a validated design (SI inside).

    Raises
    ------
    InputError
        Cross-key problems: bounds in the wrong order, a coil limit below ambient temperature.
    """
    from optimize.system import Bounds, DesignModel, Limits, Requirements, workspace_points
    from spiralcap.assemble.capsule import build_capsule
    from spiralcap.assemble.coils import build_coils
    from spiralcap.assemble.tissue import build_tissues

    d = design
    for lo, hi in (
        ("optimize.helical_angle_min_deg", "optimize.helical_angle_max_deg"),
        ("optimize.frequency_min_hz", "optimize.frequency_max_hz"),
    ):
        if d[lo] > d[hi]:
            raise InputError(hi, d[hi], f"a value >= {lo} = {d[lo]:g}")
    import capsule as cap

    floor = max(
        MIN_MODEL_ANGLE_deg,
        math.degrees(
            cap.min_helical_angle_for_clearance_rad(
                cap.helix_diameter_m(
                    d["capsule.diameter_mm"], d["capsule.spiral.wire_diameter_mm"]
                ),
                d["capsule.spiral.wire_diameter_mm"],
                d["capsule.spiral.starts"],
            )
        ),
    )
    if d["optimize.helical_angle_min_deg"] < floor:
        raise InputError(
            "optimize.helical_angle_min_deg",
            d["optimize.helical_angle_min_deg"],
            f"an angle >= {floor:.3g} deg (below it the spiral's turns touch or the "
            "paper's profile conversion no longer holds)",
        )
    if d["limits.coil_temperature_C"] <= d["coils.ambient_temperature_C"]:
        raise InputError(
            "limits.coil_temperature_C",
            d["limits.coil_temperature_C"],
            f"a temperature above coils.ambient_temperature_C = "
            f"{d['coils.ambient_temperature_C']:g}",
        )
    limits = Limits(
        current_A=d["limits.current_A"],
        voltage_V=d["limits.voltage_V"],
        power_W=d["limits.power_W"],
        coil_temperature_C=d["limits.coil_temperature_C"],
        field_exposure=d["limits.field_exposure"],
    )
    req = Requirements(
        axial_load_N=d["requirements.axial_load_mN"] * 1e-3,
        slip_efficiency=d["requirements.slip_efficiency"],
        min_speed_m_s=d["requirements.min_speed_mm_s"] * 1e-3,
        min_spiral_turns=d["requirements.min_spiral_turns"],
    )
    bounds = Bounds(
        helical_angle_min_rad=math.radians(d["optimize.helical_angle_min_deg"]),
        helical_angle_max_rad=math.radians(d["optimize.helical_angle_max_deg"]),
        frequency_min_hz=d["optimize.frequency_min_hz"],
        frequency_max_hz=d["optimize.frequency_max_hz"],
        objective=d["optimize.objective"],
        starts=d["optimize.starts"],
    )
    return DesignModel(
        coils=build_coils(d),
        capsule=build_capsule(d),
        tissues=tuple(build_tissues(d)),
        frequency_hz=d["operation.frequency_hz"],
        headings=_headings(d),
        points_m=workspace_points(d["workspace.radius_m"]),
        limits=limits,
        requirements=req,
        bounds=bounds,
        winding_temperature_C=winding_temperature_C(d),
        ambient_temperature_C=d["coils.ambient_temperature_C"],
        heat_transfer_coefficient_W_m2K=d["coils.heat_transfer_coefficient_W_m2K"],
    )
