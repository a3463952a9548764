"""The coil set's bill of materials: one row per pair, what a workshop and an amplifier vendor need.

:func:`bill_of_materials` is the one definition behind ``spiralcap coils`` (text and
``bill_of_materials`` in ``--json``), the report's coil section and
``examples/size_coils_least_power.py``. Per pair (both coils in series):

- wire: bare diameter, its standard (IEC 60317-0-1 R40 nominal size or AWG, ASTM B258) and
  enamel: grade 2 (IEC 60317-0-1, the usual grade for wound coils) of the lowest thermal class
  (IEC 60317 series: 155, 180, 200, 220, 240) at or above the hot-spot limit;
- wire length of both coils (N turns of 2π R each, of 4a for a square pair) plus
  :data:`LEAD_ALLOWANCE_PER_COIL_m` per coil for the two tails to the terminal block and the
  winding-machine start;
- copper mass of that length (density x length x bare section: the wire to order);
- resistance at 20 °C and series inductance 2L + 2M of the winding (leads not included);
- current, voltage amplitude and apparent power S = V I / 2 (sinusoid amplitudes) at the
  operating point (worst heading at the operating field) and at the design's limits (each pair
  at the largest field every limit allows it, the same numbers the limit checks use);
- the amplifier channel the pair needs as the limits state it: its own
  ``limits.<axis>.current_A`` / ``voltage_V`` / ``power_W`` where set, else the global ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["BomRow", "DrivePoint", "LEAD_ALLOWANCE_PER_COIL_m", "bill_of_materials", "bom_table"]

#: Wire length added per coil for its two leads (0.75 m each to a terminal block) and the
#: winding-machine start, m.
LEAD_ALLOWANCE_PER_COIL_m = 2.0
#: Thermal classes of enamelled round copper wire in the IEC 60317 series, °C.
THERMAL_CLASSES_C = (155, 180, 200, 220, 240)


@dataclass(frozen=True)
class DrivePoint:
    """What the pair's amplifier must deliver at one point (amplitudes of sinusoids)."""

    current_amplitude_A: float
    voltage_amplitude_V: float
    apparent_power_VA: float


@dataclass(frozen=True)
class BomRow:
    """One pair (two identical coils in series) of the bill of materials; SI except mm wire."""

    axis: str
    coils: int
    turns: int
    wire_diameter_mm: float
    wire_standard: str
    enamel: str
    wire_length_m: float
    lead_allowance_m: float
    copper_mass_kg: float
    resistance_20C_ohm: float
    inductance_H: float
    operating: DrivePoint
    at_limits: DrivePoint
    #: The amplifier channel this pair needs, as the design's limits state it: current and
    #: voltage amplitude (its own ``limits.<axis>.*`` where set, else the global limits) and
    #: its copper power (its own ``limits.<axis>.power_W``, else the total ``limits.power_W``).
    channel_current_A: float = math.nan
    channel_voltage_V: float = math.nan
    channel_power_W: float = math.nan
    channel_limits: str = "global"  # which: "own channel" (limits.<axis>.*) or "global"


def _wire_standard(d_mm: float) -> str:
    from optimize.hardware import IEC_R40_mm, awg_diameters_mm

    for nominal in IEC_R40_mm:
        if math.isclose(d_mm, nominal, rel_tol=1e-9):
            return f"IEC 60317-0-1 nominal {nominal:g} mm (R40)"
    for gauge, awg in zip(range(40, -1, -1), awg_diameters_mm()):
        if math.isclose(d_mm, awg, rel_tol=1e-6):
            return f"AWG {gauge} (ASTM B258)"
    return f"{d_mm:g} mm, not a standard size (IEC 60317 R40 or AWG)"


def _enamel(limit_C: float) -> str:
    cls = next((c for c in THERMAL_CLASSES_C if c >= limit_C), None)
    if cls is None:
        return f"no IEC 60317 thermal class reaches {limit_C:g} °C"
    return f"grade 2 (IEC 60317-0-1), thermal class {cls}"


def _drive(terms: dict[str, Any], ax: str) -> DrivePoint:
    def term(kind: str) -> float:  # the pair's own channel's row where it has one
        own = f"axis_{kind}_{ax}"
        return float(terms[own] if own in terms else terms[f"{kind}_{ax}"])

    i, v = term("current"), term("voltage")
    return DrivePoint(i, v, 0.5 * v * i)


def _channel(limits: Any, k: int) -> dict[str, Any]:
    """The amplifier channel pair ``k`` needs, from the limits (BomRow.channel_*)."""
    ax = "xyz"[k]
    own = any(f"{kind}_{ax}" in limits.own for kind in ("current", "voltage", "power"))
    power = float(limits.axis_power_W[k]) if f"power_{ax}" in limits.own else float(limits.power_W)
    return {
        "channel_current_A": float(limits.channel("current", k)[1]),
        "channel_voltage_V": float(limits.channel("voltage", k)[1]),
        "channel_power_W": power,
        "channel_limits": "own channel" if own else "global",
    }


def bill_of_materials(model: Any, analysis: Any) -> tuple[BomRow, ...]:
    """The rows of the coil set's bill of materials (module notes).

    Parameters
    ----------
    model : optimize.DesignModel
        The design's model (prepared or not).
    analysis : spiralcap.analysis.coils.CoilAnalysis
        Its coil analysis (operating field, each pair's largest field inside the limits).
    """
    from optimize import physics, prepare
    from spiralcap.core.constants import COPPER_DENSITY_kg_m3

    model = prepare(model)
    c, f, amb = model.constants, model.frequency_hz, model.ambient_temperature_C

    def terms(field_T: float) -> dict[str, Any]:
        return {t.name: t.value for t in physics.limit_terms(f, field_T, c, model.limits, amb)}

    op = terms(analysis.operating_field_T)
    rows = []
    for k, (pair, lim) in enumerate(zip(model.coils.pairs, analysis.axis_limits)):
        ax = pair.axis
        coils_n = 2
        leads = coils_n * LEAD_ALLOWANCE_PER_COIL_m
        length = pair.wire_length_m + leads
        rows.append(
            BomRow(
                axis=ax,
                coils=coils_n,
                turns=int(pair.turns),
                # the catalogue size in mm, not its binary neighbour (2.36, not 2.3600000000000003)
                wire_diameter_mm=round(pair.wire_diameter_m * 1e3, 9),
                wire_standard=_wire_standard(pair.wire_diameter_m * 1e3),
                enamel=_enamel(float(model.limits.coil_temperature_C)),
                wire_length_m=length,
                lead_allowance_m=leads,
                copper_mass_kg=COPPER_DENSITY_kg_m3 * length * pair.wire_area_m2,
                resistance_20C_ohm=float(c.resistance_20C_ohm[k]),
                inductance_H=float(c.inductance_H[k]),
                operating=_drive(op, ax),
                at_limits=_drive(terms(lim.max_rotating_field_T), ax),
                **_channel(model.limits, k),
            )
        )
    return tuple(rows)


def bom_table(rows: tuple[BomRow, ...]) -> str:
    """The bill of materials as a plain-text table (the CLI, the example)."""
    from spiralcap.commands._common import format_table

    table = format_table(
        [
            "axis",
            "turns",
            "wire_mm",
            "wire_m",
            "Cu_kg",
            "R20_ohm",
            "L_mH",
            "I_op_A",
            "V_op_V",
            "S_op_VA",
            "I_lim_A",
            "V_lim_V",
            "S_lim_VA",
        ],
        [
            [
                r.axis,
                r.turns,
                r.wire_diameter_mm,
                r.wire_length_m,
                r.copper_mass_kg,
                r.resistance_20C_ohm,
                r.inductance_H * 1e3,
                r.operating.current_amplitude_A,
                r.operating.voltage_amplitude_V,
                r.operating.apparent_power_VA,
                r.at_limits.current_amplitude_A,
                r.at_limits.voltage_amplitude_V,
                r.at_limits.apparent_power_VA,
            ]
            for r in rows
        ],
    )
    notes = [
        f"  {r.axis}: {r.coils} coils x {r.turns} turns, {r.wire_standard}, enamel {r.enamel}; "
        f"amplifier channel ({r.channel_limits} limits): {r.channel_current_A:.4g} A, "
        f"{r.channel_voltage_V:.4g} V, {r.channel_power_W:.4g} W"
        for r in rows
    ]
    lead = rows[0].lead_allowance_m / rows[0].coils if rows else LEAD_ALLOWANCE_PER_COIL_m
    return "\n".join(
        [
            table,
            *notes,
            f"  wire length: both coils plus {lead:g} m of leads per coil; copper mass of that "
            "length; R20 and L of the winding; I, V amplitudes, S = V I / 2",
        ]
    )
