"""Every design-file key: its type, default, the values it allows, and a one-line meaning.

Keys carry their unit in the name (``radius_m``, ``helical_angle_deg``). A key with default
``None`` is optional: absent means "take it from elsewhere" (the tissue preset, the coil radius).
This table is the single source for validation, for ``spiralcap init`` comments and for the
report's input table. Every number has the range a real design can have, with the reason in its
help text; every key knows its SI conversion from the unit suffix of its name
(``Key.si_name``, ``Key.si_factor``, :func:`to_si`; table in ``spiralcap.core.constants``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from spiralcap.core.errors import InputError


@dataclass(frozen=True)
class Key:
    """One design key: type, default, allowed values (a predicate and its words), and meaning.

    ``lo``/``hi`` are the numeric bounds of a number or count (``None``: unbounded on that
    side; ``open_`` says whether the bounds themselves are excluded). ``name``, ``unit``,
    ``si_unit`` and ``si_factor`` are filled in from the key's name by the unit table
    (:data:`spiralcap.core.constants.UNIT_SUFFIXES`) once every key is declared: ``value_in_design
    * si_factor`` is the value in SI, under the leaf name :attr:`si_name`.
    """

    kind: type
    default: Any
    allowed: str
    check: Callable[[Any], bool]
    help: str
    lo: float | None = None
    hi: float | None = None
    open_: bool = False
    name: str = ""
    unit: str = ""
    si_unit: str = ""
    si_factor: float = 1.0

    @property
    def si_name(self) -> str:
        """The leaf of the key with its unit in SI: ``axial_load_mN`` -> ``axial_load_N``."""
        leaf = self.name.rpartition(".")[2]
        return leaf[: len(leaf) - len(self.unit)] + self.si_unit if self.unit else leaf


def _num(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _pos(help_: str, default: Any) -> Key:
    return Key(
        float, default, "a finite number > 0", lambda v: _num(v) and v > 0, help_, 0.0, None, True
    )


def _nonneg(help_: str, default: Any) -> Key:
    return Key(float, default, "a finite number >= 0", lambda v: _num(v) and v >= 0, help_, 0.0)


def _between(help_: str, default: Any, lo: float, hi: float, *, open_: bool = True) -> Key:
    if open_:
        return Key(
            float,
            default,
            f"a number in ({lo:g}, {hi:g})",
            lambda v: _num(v) and lo < v < hi,
            help_,
            lo,
            hi,
            True,
        )
    return Key(
        float,
        default,
        f"a number in [{lo:g}, {hi:g}]",
        lambda v: _num(v) and lo <= v <= hi,
        help_,
        lo,
        hi,
        False,
    )


def _count(help_: str, default: Any, lo: int = 1, hi: int | None = None) -> Key:
    def ok(v: Any) -> bool:
        return (
            isinstance(v, int) and not isinstance(v, bool) and v >= lo and (hi is None or v <= hi)
        )

    allowed = f"a whole number >= {lo}" if hi is None else f"a whole number in [{lo}, {hi}]"
    return Key(int, default, allowed, ok, help_, lo, hi, False)


def _choice(help_: str, default: str, options: tuple[str, ...]) -> Key:
    return Key(
        str, default, "one of " + ", ".join(repr(o) for o in options), lambda v: v in options, help_
    )


#: Most headings a design may list (each is a column of the current allocation).
MAX_HEADINGS = 64


def _is_heading_list(v: Any) -> bool:
    if v == "all":
        return True
    return (
        isinstance(v, list)
        and 0 < len(v) <= MAX_HEADINGS
        and all(
            isinstance(h, list)
            and len(h) == 3
            and all(_num(c) for c in h)
            and max(abs(c) for c in h) > 0
            for h in v
        )
    )


def _is_str_list(v: Any) -> bool:
    return isinstance(v, list) and len(v) <= 16 and all(isinstance(s, str) for s in v)


TISSUE_PRESETS = ("zhou2013-sample2", "zhou2013-sample3")
MAGNET_GRADES = ("N35", "N42", "N45", "N48", "N52")

KEYS: dict[str, Key] = {
    # --- coils ---------------------------------------------------------------------------------
    "coils.winding_temperature_C": _between(
        "fixed copper temperature for the resistance in the voltage and power limits (default: "
        "the mean winding temperature solved with the heating, coils.thermal); range: "
        "cold-room ambient to the 250 °C of the hottest enamel class",
        None,
        -50.0,
        250.0,
        open_=False,
    ),
    "coils.ambient_temperature_C": _between(
        "air temperature around the coils; range: any room a coil system is run in",
        25.0,
        -50.0,
        100.0,
        open_=False,
    ),
    "coils.heat_transfer_coefficient_W_m2K": _between(
        "convective heat-transfer coefficient from the winding surface, used exactly when set "
        "(default: each face's natural-convection correlation at the solved film temperature, "
        "coils.cooling; docs/coils-thermal.md); range: still air (0.5) to forced water "
        "cooling (1e4)",
        None,
        0.5,
        1e4,
        open_=False,
    ),
    "coils.cooling": _choice(
        "how the packs are cooled when coils.heat_transfer_coefficient_W_m2K is not set: "
        "'natural' (natural-convection correlations, Churchill & Chu 1975) or 'forced' (fan "
        "air at coils.air_speed_m_s across the packs, Churchill & Bernstein 1977, added to "
        "the natural value)",
        "natural",
        ("natural", "forced"),
    ),
    "coils.air_speed_m_s": _between(
        "air speed across the winding packs with coils.cooling = 'forced'; range: still air "
        "to a strong fan (20 m/s)",
        None,
        0.0,
        20.0,
        open_=False,
    ),
    "coils.min_clearance_mm": _between(
        "least distance between the winding packs of two different pairs, and between the "
        "inner faces of the packs and the workspace sphere: room for a coil former's wall "
        "(3-5 mm glass-fibre epoxy) and an air gap that cools the faces; range: 0 (packs may "
        "touch) to 200 mm",
        10.0,
        0.0,
        200.0,
        open_=False,
    ),
    "coils.packing_factor": _between(
        "copper cross-section / winding-pack cross-section (round wire, layer wound ~0.6-0.8); "
        "range: up to hexagonal close packing of round wire, 0.9069",
        0.7,
        0.0,
        0.9069,
        open_=True,
    ),
}
# the built-in pairs nest 13.7 mm apart as solids (coils.min_clearance_mm = 10; issue 18)
for _ax, _r, _n, _d in (("x", 0.43, 400, 3.0), ("y", 0.35, 350, 2.5), ("z", 0.28, 300, 2.36)):
    KEYS[f"limits.{_ax}.current_A"] = _between(
        f"current amplitude the {_ax} pair's own amplifier channel allows (optional: "
        "limits.current_A applies where absent); range as limits.current_A",
        None,
        1e-3,
        1e3,
        open_=False,
    )
    KEYS[f"limits.{_ax}.voltage_V"] = _between(
        f"drive-voltage amplitude the {_ax} pair's own amplifier channel allows (optional: "
        "limits.voltage_V applies where absent); range as limits.voltage_V",
        None,
        1e-3,
        1e4,
        open_=False,
    )
    KEYS[f"limits.{_ax}.power_W"] = _between(
        f"copper loss the {_ax} pair's own amplifier channel may drive, R I² / 2 at its "
        "worst-heading current (optional, besides the total limits.power_W); range: 1 mW to "
        "1 MW",
        None,
        1e-3,
        1e6,
        open_=False,
    )
    KEYS[f"coils.{_ax}.radius_m"] = _between(
        f"mean radius of each coil of the {_ax} pair (a circular pair; a square pair, "
        f"coils.{_ax}.shape = 'square', does not use it: its size is coils.{_ax}.side_m); "
        "range: a 1 cm bench coil to a 2 m whole-body system",
        _r,
        0.01,
        2.0,
        open_=False,
    )
    KEYS[f"coils.{_ax}.turns"] = _count(
        f"turns of each coil of the {_ax} pair; range: at most 10^5 turns (a winding of more "
        "is not made by hand or machine for a coil of this size)",
        _n,
        1,
        100_000,
    )
    KEYS[f"coils.{_ax}.wire_diameter_mm"] = _between(
        f"bare copper diameter of the {_ax} winding; range: AWG 44 (0.05 mm) to a 10 mm "
        "solid conductor",
        _d,
        0.05,
        10.0,
        open_=False,
    )
    KEYS[f"coils.{_ax}.pack_aspect"] = _between(
        f"axial width / radial depth of each {_ax} winding pack (1 = square section); range: "
        "0.25 to 4, beyond which the pack is a thin sheet the Stefan inductance fit, the "
        "filament field model and the one-temperature face cooling are not made for",
        1.0,
        0.25,
        4.0,
        open_=False,
    )
    KEYS[f"coils.{_ax}.separation_m"] = _between(
        f"distance between the two {_ax} coils (default: the radius, Helmholtz spacing; for "
        "a square pair 0.5445 x the side, square Helmholtz spacing); range: 5 mm to 4 m "
        "(twice the largest radius)",
        None,
        0.005,
        4.0,
        open_=False,
    )
# a lab's coils as measured (issue 37): series R and L of each pair at its channel's terminals
for _ax in "xyz":
    KEYS[f"coils.{_ax}.measured.resistance_ohm"] = _between(
        f"measured resistance of the {_ax} pair as wired to its channel (both coils in series, "
        f"leads included) at coils.{_ax}.measured.temperature_C: replaces the computed value in "
        "every voltage, power, heating and waveform figure, scaled with copper's temperature "
        "coefficient (optional); range: 0.1 mOhm to 10 kOhm",
        None,
        1e-4,
        1e4,
        open_=False,
    )
    KEYS[f"coils.{_ax}.measured.temperature_C"] = _between(
        f"copper temperature at which coils.{_ax}.measured.resistance_ohm was measured (absent: "
        "20 °C); range: -50 to 250 °C, the copper's range in the model",
        None,
        -50.0,
        250.0,
        open_=False,
    )
    KEYS[f"coils.{_ax}.measured.inductance_H"] = _between(
        f"measured inductance of the {_ax} pair at its terminals (both coils in series, their "
        "mutual inductance included): replaces the computed value in every voltage and "
        "waveform figure (optional); range: 0.1 uH to 1 kH",
        None,
        1e-7,
        1e3,
        open_=False,
    )
# amplifier apparent power per channel (issue 37)
for _ax in "xyz":
    KEYS[f"limits.{_ax}.apparent_power_VA"] = _between(
        f"apparent power the {_ax} pair's amplifier channel may deliver, V I / 2 with V and I "
        "the drive-voltage and current amplitudes at the worst heading (optional); range: "
        "1 mVA to 10 MVA",
        None,
        1e-3,
        1e7,
        open_=False,
    )
# square coil pairs (issue 30): the shape of each pair and the side of a square one
for _ax in "xyz":
    KEYS[f"coils.{_ax}.shape"] = _choice(
        f"shape of the {_ax} pair's coils: 'circle' (size coils.{_ax}.radius_m), 'square' "
        f"(size coils.{_ax}.side_m, sides parallel to the other two axes, sharp corners, so "
        f"square pairs nest into a cube) or 'rectangle' (sides coils.{_ax}.sides_m; "
        "docs/coils-square.md)",
        "circle",
        ("circle", "square", "rectangle"),
    )
    KEYS[f"coils.{_ax}.side_m"] = _between(
        f"side of each coil of a square {_ax} pair, on the winding's centre line (needed with "
        f"coils.{_ax}.shape = 'square', not allowed with a circle); range: a 2 cm bench coil "
        "to a 4 m room-size frame (the circles' radius range, doubled)",
        None,
        0.02,
        4.0,
        open_=False,
    )
    KEYS[f"coils.{_ax}.sides_m"] = Key(
        list,
        None,
        "two sides [a, b] in m, each from 0.02 to 4, with b/a from 0.25 to 4",
        lambda v: (
            isinstance(v, list)
            and len(v) == 2
            and all(_num(c) and 0.02 <= c <= 4.0 for c in v)
            and 0.25 <= v[1] / v[0] <= 4.0
        ),
        f"sides of each coil of a rectangular {_ax} pair on the winding's centre line, along "
        f"the next two axes in cyclic order (x: y, z; y: z, x; z: x, y); needed with "
        f"coils.{_ax}.shape = 'rectangle'. Range: the square's sides; an aspect b/a from 0.25 "
        "to 4, beyond which the zero-curvature spacing is no longer a Helmholtz-like pair",
    )

KEYS.update(
    {
        # --- capsule ---
        "capsule.diameter_mm": _between(
            "outer diameter of the capsule shell (PillCam SB2: 11); range: swallowable "
            "capsules and bench models, 3-40 mm",
            11.0,
            3.0,
            40.0,
            open_=False,
        ),
        "capsule.length_mm": _between(
            "overall length including the hemispherical ends (PillCam SB2: 26); range: 3-150 mm",
            26.0,
            3.0,
            150.0,
            open_=False,
        ),
        "capsule.shell_thickness_mm": _between(
            "wall thickness of the capsule shell; range: 0.05-10 mm (a printed or moulded wall)",
            0.5,
            0.05,
            10.0,
            open_=False,
        ),
        "capsule.spiral.helical_angle_deg": _between(
            "angle between the spiral wire and the capsule's cross-section plane (paper: 5-20); "
            "range: a screw thread lies strictly between flat (0) and axial (90)",
            10.0,
            0.0,
            90.0,
        ),
        "capsule.spiral.wire_diameter_mm": _between(
            "diameter of the spiral wire (paper: 1); range: 0.05-10 mm",
            1.0,
            0.05,
            10.0,
            open_=False,
        ),
        "capsule.spiral.wound_length_mm": _between(
            "axial length over which the spiral is wound; range: 0.1-150 mm (at most a capsule)",
            15.0,
            0.1,
            150.0,
            open_=False,
        ),
        "capsule.spiral.starts": _count(
            "number of independent spiral wires (starts); range: 1-12 (more wires than that "
            "do not fit round a capsule)",
            1,
            1,
            12,
        ),
        "capsule.mass_g": _between(
            "capsule mass, for the friction of its weight lying on the wall (default: from its "
            "parts, the magnet at 7500 kg/m³ and the rest of the capsule at 1300 kg/m³, a "
            "PillCam SB3's mean density); range: 0.1-500 g",
            None,
            0.1,
            500.0,
            open_=False,
        ),
        "capsule.magnet.shape": _choice(
            "magnet shape, diametrically magnetised", "cylinder", ("cylinder", "ring")
        ),
        "capsule.magnet.diameter_mm": _between(
            "outer diameter of the magnet; range: 0.1-40 mm (it must fit a capsule)",
            6.0,
            0.1,
            40.0,
            open_=False,
        ),
        "capsule.magnet.length_mm": _between(
            "axial length of the magnet; range: 0.1-150 mm (it must fit a capsule)",
            10.0,
            0.1,
            150.0,
            open_=False,
        ),
        "capsule.magnet.inner_diameter_mm": _between(
            "bore of a ring magnet (0 for a cylinder); range: 0-40 mm",
            0.0,
            0.0,
            40.0,
            open_=False,
        ),
        "capsule.magnet.grade": _choice(
            "sintered NdFeB grade (sets remanence_T if that is absent)", "N45", MAGNET_GRADES
        ),
        "capsule.magnet.remanence_T": _between(
            "remanence B_r (overrides the grade); range: no permanent magnet exceeds 1.6 T "
            "(N55 NdFeB ~1.5 T)",
            None,
            0.01,
            1.6,
            open_=False,
        ),
        # --- tissue ---
        "tissue.preset": _choice(
            "calibrated tissue parameter set (see docs/torque-model.md)",
            "zhou2013-sample2",
            TISSUE_PRESETS,
        ),
        "tissue.E1_kPa": _between(
            "spring modulus E1 of the five-element model (overrides tissue.preset only; each "
            "worst-case preset keeps its own material); range: 0 to 1 GPa, "
            "beyond any soft tissue (the presets hold 10-7000 kPa)",
            None,
            0.0,
            1e6,
            open_=False,
        ),
        "tissue.E2_kPa": _between(
            "spring modulus E2 (overrides tissue.preset only); range as tissue.E1_kPa",
            None,
            0.0,
            1e6,
            open_=False,
        ),
        "tissue.E3_kPa": _between(
            "spring modulus E3 (overrides tissue.preset only); range as tissue.E1_kPa",
            None,
            0.0,
            1e6,
            open_=False,
        ),
        "tissue.eta1_kPa_s": _between(
            "dashpot viscosity eta1 (overrides tissue.preset only); range: 1e-3 to 1e8 kPa·s, "
            "the presets "
            "hold 80-16000",
            None,
            1e-3,
            1e8,
            open_=False,
        ),
        "tissue.eta2_kPa_s": _between(
            "dashpot viscosity eta2 (overrides tissue.preset only); range as tissue.eta1_kPa_s",
            None,
            1e-3,
            1e8,
            open_=False,
        ),
        "tissue.lumen_diameter_mm": _between(
            "inner diameter of the patient's undeformed intestine: applies to every tissue set "
            "(tissue.preset, each worst-case preset, the uncertainty samples centre on it); "
            "default: each set's own bench lumen; range: 1-100 mm (small bowel ~10-30, colon up "
            "to ~80)",
            None,
            1.0,
            100.0,
            open_=False,
        ),
        "tissue.wall_thickness_mm": _between(
            "the patient's intestinal wall thickness: applies to every tissue set, as "
            "tissue.lumen_diameter_mm; range: 0.05-20 mm",
            None,
            0.05,
            20.0,
            open_=False,
        ),
        "tissue.friction_coefficient": _between(
            "capsule-mucosa Coulomb friction (overrides tissue.preset only: each worst-case "
            "preset keeps its own); range: 1e-3-5 (mucosa ~0.01-0.6)",
            None,
            1e-3,
            5.0,
            open_=False,
        ),
        "tissue.scale": _between(
            "deterministic multiplier on the resistive torque of every tissue set the design is "
            "checked against, the preset (with its overrides) and every worst-case preset alike: "
            "all five moduli and viscosities times this factor (the torque is linear in it); "
            "'what if the tissue is 50 % stiffer' is 1.5; range: 0.1-10 (the paper's two samples "
            "differ by ~2x, and tissue.uncertainty.scale_sigma_log allows e^2 ~ 7 per standard "
            "deviation)",
            1.0,
            0.1,
            10.0,
            open_=False,
        ),
        "tissue.worst_case_presets": Key(
            list,
            ["zhou2013-sample3"],
            "a list of preset names from " + ", ".join(TISSUE_PRESETS),
            lambda v: _is_str_list(v) and all(s in TISSUE_PRESETS for s in v),
            "further tissue sets the margin must also hold for (worst case over all; by default "
            "the paper's other intestine sample)",
        ),
        # --- operation and workspace ---
        "operation.frequency_hz": _between(
            "rotation frequency of the field at the operating point; range: 1 mHz to 100 Hz "
            "(a capsule in tissue steps out long before 100 Hz)",
            2.0,
            1e-3,
            100.0,
            open_=False,
        ),
        "workspace.radius_m": _between(
            "radius of the region around the coil centre the capsule must work in (0: centre "
            "only); range: 0-1 m (inside the largest coils)",
            0.05,
            0.0,
            1.0,
            open_=False,
        ),
        "workspace.headings": Key(
            list,
            "all",
            f'"all" or a list of 1-{MAX_HEADINGS} [x, y, z] direction vectors (finite, not all 0)',
            _is_heading_list,
            "capsule headings (rotation axes) to design for",
        ),
        # --- requirements ---
        "requirements.axial_load_mN": _between(
            "axial resistance the spiral must push against (20-100 in porcine small bowel); "
            "range: 0-10 N",
            50.0,
            0.0,
            1e4,
            open_=False,
        ),
        "requirements.slip_efficiency": _between(
            "forward speed / (frequency x spiral lead); 1 is a nut on a screw",
            0.5,
            0.0,
            1.0,
            open_=False,
        ),
        "requirements.min_speed_mm_s": _between(
            "least forward speed the capsule must reach (5 mm/s: about 17 min per metre); "
            "range: 0-1000 mm/s",
            5.0,
            0.0,
            1000.0,
            open_=False,
        ),
        "requirements.min_wall_strain": _between(
            "least strain the spiral must stretch the intestinal wall by, (D' - lumen) / "
            "(lumen + wall), for every tissue set: a spiral that does not stretch the wall does "
            "not grip it, so it neither screws the capsule forward nor meets the model's "
            "resistance (default 0.0168: includes the least strain at which the paper measured a "
            "spiral capsule's torque, capsule No. 4 at 20 deg in sample 3, 1.685 %, to three "
            "figures); range: 1e-4-0.5 (it cannot be switched off)",
            0.0168,
            1e-4,
            0.5,
            open_=False,
        ),
        "requirements.min_spiral_turns": _between(
            "fewest spiral turns over the wound length that can be made (0 switches the rule "
            "off); range: 0-1000",
            1.0,
            0.0,
            1000.0,
            open_=False,
        ),
        # --- limits ---
        "limits.current_A": _between(
            "largest current amplitude of any coil pair; range: up to 1 kA (beyond any "
            "amplifier for air coils)",
            15.0,
            1e-3,
            1e3,
            open_=False,
        ),
        "limits.voltage_V": _between(
            "largest drive-voltage amplitude across any coil pair; range: up to 10 kV",
            150.0,
            1e-3,
            1e4,
            open_=False,
        ),
        "limits.power_W": _between(
            "largest total copper loss of the three pairs; range: up to 1 MW",
            2000.0,
            1e-3,
            1e6,
            open_=False,
        ),
        "limits.copper_mass_kg": _between(
            "largest total copper mass of the three pairs, what the frame, the floor and the "
            "budget carry (unset: no limit; least-power sizing otherwise grows copper to its "
            "bounds, hundreds of kg); range: up to 100 t",
            None,
            0.0,
            1e5,
        ),
        "limits.coil_temperature_C": _between(
            "hottest winding temperature allowed (the hot spot at the pack centre); range: -50 to 250 °C, the hottest enamel "
            "insulation class (IEC 60317)",
            90.0,
            -50.0,
            250.0,
            open_=False,
        ),
        "limits.surface_temperature_C": _between(
            "hottest coil-pack surface a patient or operator may touch (optional; IEC 60601-1 "
            "3rd ed. Table 24, metal: 43 °C for contact of 10 min or more, 48 °C for 1-10 min, "
            "51 °C under 1 min; unset, the warning picks one by operation.session_min); range: "
            "-50 to 250 °C",
            None,
            -50.0,
            250.0,
            open_=False,
        ),
        "limits.field_exposure": _choice(
            "ICNIRP 2010 reference level applied to the rotating field",
            "occupational",
            ("occupational", "public", "off"),
        ),
        "limits.envelope_mm": Key(
            list,
            None,
            "a list of three lengths [X, Y, Z] in mm, each from 10 to 20000",
            lambda v: (
                isinstance(v, list)
                and len(v) == 3
                and all(_num(c) and 10.0 <= c <= 20000.0 for c in v)
            ),
            "the room the coil set must fit: edge lengths of an axis-aligned box round the packs "
            "as solids (outer faces and outer radii), a check and a row of the sizing NLP; "
            "optional",
        ),
        # --- optimisation ---
        "optimize.helical_angle_min_deg": _between(
            "lower bound on the helical angle; range: strictly between 0 and 90 deg", 2.0, 0, 90
        ),
        "optimize.helical_angle_max_deg": _between(
            "upper bound on the helical angle; range: strictly between 0 and 90 deg", 45.0, 0, 90
        ),
        "optimize.frequency_min_hz": _between(
            "lower bound on the rotation frequency; range as operation.frequency_hz",
            0.5,
            1e-3,
            100.0,
            open_=False,
        ),
        "optimize.frequency_max_hz": _between(
            "upper bound on the rotation frequency; range as operation.frequency_hz",
            5.0,
            1e-3,
            100.0,
            open_=False,
        ),
        "optimize.objective": _choice(
            "maximise the torque margin or the safety factor, or minimise the copper power or "
            "the copper mass (the last two subject to requirements.min_safety_factor); "
            "margin_p05: maximise the CVaR at 5 % of the worst-case margin over "
            "optimize.scenarios tissue scenarios (the mean of the worst 5 %, a lower bound on "
            "the 5th percentile, which is reported beside it)",
            "margin",
            ("margin", "ratio", "power", "copper_mass", "margin_p05"),
        ),
        "optimize.starts": _count(
            "initial helical angles IPOPT is started from; range: 1-64 (each start is one "
            "solve; more than 64 adds time, not answers)",
            4,
            1,
            64,
        ),
    }
)


# Keys added by later work are declared in one block per capability below, so each stays in one
# place (numeric keys with physical bounds: _between(..., lo, hi, open_=False)).

# --- hardware sizing (issue 9) ---
KEYS.update(
    {
        "requirements.min_safety_factor": _between(
            "least available / required torque for every tissue set (1: margin >= 0); range: 1 to "
            "100, beyond any design margin a 1-2 mN·m magnet torque can give",
            1.0,
            1.0,
            100.0,
            open_=False,
        ),
        "operation.field_amplitude_mT": _between(
            "rotating-field amplitude at the coil centre (default: the largest every limit "
            "allows at the operating frequency); range: up to 1 T, far above what air-cored "
            "Helmholtz coils make",
            None,
            0.0,
            1000.0,
        ),
        "coils.wire_standard": _choice(
            "standard wire diameters a freed wire diameter is rounded to (IEC 60317 R40 or AWG)",
            "iec-r40",
            ("iec-r40", "awg"),
        ),
        "requirements.min_bore_m": _between(
            "least clear diameter inside every coil pair when coil hardware is freed, between "
            "the inner faces of its winding packs (2R - h; a former's wall inside it is yours to "
            "add); left out, the least that diameter is in the design as entered, exactly as if "
            "set to it; range: up to 10 m, larger than any coil system",
            None,
            0.0,
            10.0,
        ),
    }
)

#: Design keys the optimiser can choose (``--free KEY=MIN:MAX``, ``[optimize.free]``).
FREEABLE_KEYS = (
    *(
        f"coils.{ax}.{q}"
        for ax in "xyz"
        for q in ("turns", "wire_diameter_mm", "radius_m", "pack_aspect", "side_m", "sides_m")
    ),
    "capsule.magnet.diameter_mm",
    "capsule.magnet.length_mm",
    "capsule.spiral.wire_diameter_mm",
)


#: A freed key whose range is checked as another key's value: a rectangle is sized at its
#: aspect b/a, its range bounds the first side a (a side, as a square's).
_FREE_RANGE_AS = {f"coils.{ax}.sides_m": f"coils.{ax}.side_m" for ax in "xyz"}


def _free_range(key: str) -> Key:
    spec = KEYS[_FREE_RANGE_AS.get(key, key)]

    def ok(v: Any) -> bool:
        if not (isinstance(v, list) and len(v) == 2 and all(_num(x) for x in v)):
            return False
        lo, hi = v
        if spec.kind is int:  # a count: whole-number bounds, never rounded behind the user
            if not all(math.isfinite(x) and float(x).is_integer() for x in v):
                return False
            lo, hi = int(lo), int(hi)
        return lo < hi and spec.check(lo) and spec.check(hi)

    whole = "whole numbers" if spec.kind is int else "numbers"
    return Key(
        list,
        None,
        f"a pair [min, max] of {whole} with min < max, each {spec.allowed}",
        ok,
        f"let the optimiser choose {key} between min and max",
    )


KEYS.update({f"optimize.free.{k}": _free_range(k) for k in FREEABLE_KEYS})

# --- coils as they really run (issue 10) ---
KEYS.update(
    {
        "coils.winding_conductivity_W_mK": _between(
            "effective transverse thermal conductivity of the winding pack (impregnated round "
            "wire 0.3-1.0; Simpson, Wrobel & Mellor, IEEE Trans. Ind. Appl. 49(6), 2013); "
            "range: still-air voids (0.01) to solid copper (400)",
            0.5,
            0.01,
            400.0,
            open_=False,
        ),
        "coils.surface_emissivity": _between(
            "grey-body emissivity of the winding surface (varnish or enamel ~0.9; "
            "Incropera & DeWitt Table A.11; 0 switches radiation off)",
            0.9,
            0.0,
            1.0,
            open_=False,
        ),
        "operation.session_min": _between(
            "length of one continuous run from ambient: the temperature limit then applies at "
            "its end (absent: steady state); range: up to 1e5 min (~70 days), steady long before",
            None,
            0.0,
            1.0e5,
            open_=True,
        ),
    }
)


# --- tissue uncertainty (issue 11) ---
#: The names ``spiralcap fit`` fits (``tissue.fit.fitted``, ``tissue.fit.not_pinned_down``).
_FIT_NAMES = ("scale", "E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s")


def _is_matrix5(v: Any) -> bool:
    return (
        isinstance(v, list)
        and len(v) == 5
        and all(isinstance(r, list) and len(r) == 5 and all(_num(x) for x in r) for r in v)
    )


KEYS.update(
    {
        "tissue.uncertainty.scale_sigma_log": _between(
            "standard deviation of ln(k), k a log-normal factor common to all five moduli and "
            "viscosities of every tissue set (the calibration's uncertainty; 0: none); range: up "
            "to 2 (a factor e^2 ~ 7 per standard deviation)",
            0.0,
            0.0,
            2.0,
            open_=False,
        ),
        **{
            f"tissue.uncertainty.{p}_sigma_log": _between(
                f"standard deviation of ln({p}) on its own (independent of the others; 0: none); "
                "range: up to 2 (a factor e^2 ~ 7 per standard deviation)",
                0.0,
                0.0,
                2.0,
                open_=False,
            )
            for p in ("E1", "E2", "E3", "eta1", "eta2")
        },
        "tissue.uncertainty.friction_sigma_log": _between(
            "standard deviation of ln(friction coefficient) (0: none); range: up to 2 (a factor "
            "e^2 ~ 7 per standard deviation)",
            0.0,
            0.0,
            2.0,
            open_=False,
        ),
        "tissue.uncertainty.lumen_diameter_sigma_mm": _between(
            "standard deviation of the lumen diameter (normal, truncated at 10 % of nominal); "
            "range: up to 20 mm, the size of the lumen itself",
            0.0,
            0.0,
            20.0,
            open_=False,
        ),
        "tissue.uncertainty.wall_thickness_sigma_mm": _between(
            "standard deviation of the wall thickness (normal, truncated at 10 % of nominal); "
            "range: up to 5 mm, thicker than the intestinal wall",
            0.0,
            0.0,
            5.0,
            open_=False,
        ),
        "tissue.uncertainty.covariance_from": Key(
            str,
            None,
            "a path to a TOML file written by `spiralcap fit -o` (relative to the design file)",
            lambda v: isinstance(v, str) and v.strip() != "",
            "correlated uncertainty of ln(E1, E2, E3, eta1, eta2): the fit's covariance",
        ),
        "tissue.fit.covariance_log": Key(
            list,
            None,
            "a 5 x 5 list of finite numbers",
            _is_matrix5,
            "covariance of ln(E1, E2, E3, eta1, eta2) from `spiralcap fit -o` (read through "
            "tissue.uncertainty.covariance_from; not used on its own)",
        ),
        **{
            f"tissue.fit.bench_{leaf}": _between(
                f"{what}: record of the bench the constants were fitted on; not used by the model "
                f"(the design's own tissue.{leaf} is); range as tissue.{leaf}",
                None,
                lo,
                hi,
                open_=False,
            )
            for leaf, what, lo, hi in (
                ("lumen_diameter_mm", "lumen diameter of the bench sample", 1.0, 100.0),
                ("wall_thickness_mm", "wall thickness of the bench sample", 0.05, 20.0),
                ("friction_coefficient", "capsule-mucosa friction of the bench", 1e-3, 5.0),
            )
        },
        "tissue.fit.bench_capsule_diameter_mm": _between(
            "capsule diameter on the bench: record of the bench the constants were fitted on; not "
            "used by the model; range as capsule.diameter_mm",
            None,
            3.0,
            40.0,
            open_=False,
        ),
        "tissue.fit.bench_wire_diameter_mm": _between(
            "spiral wire diameter on the bench: record of the bench the constants were fitted "
            "on; not used by the model; range as capsule.spiral.wire_diameter_mm",
            None,
            0.05,
            10.0,
            open_=False,
        ),
        "tissue.fit.not_pinned_down": Key(
            list,
            None,
            "a list of tissue keys (scale, E1_kPa, E2_kPa, E3_kPa, eta1_kPa_s, eta2_kPa_s)",
            lambda v: isinstance(v, list) and all(x in _FIT_NAMES for x in v),
            "the fitted constants the bench data did not pin down (written by `spiralcap fit "
            "-o`; empty: every fitted constant pinned down): a record, the report never calls "
            "such constants calibrated",
        ),
        "tissue.fit.fitted": Key(
            list,
            None,
            "a list of tissue keys (scale, E1_kPa, E2_kPa, E3_kPa, eta1_kPa_s, eta2_kPa_s)",
            lambda v: isinstance(v, list) and 0 < len(v) and all(x in _FIT_NAMES for x in v),
            "the constants `spiralcap fit -o` fitted (the others were held): a record",
        ),
        "tissue.fit.bench_helical_angles_deg": Key(
            list,
            None,
            "a list of 1-64 numbers in (0, 90)",
            lambda v: (
                isinstance(v, list) and 0 < len(v) <= 64 and all(_num(x) and 0 < x < 90 for x in v)
            ),
            "helical angles of the bench capsules (at most 64, spread over the range with both "
            "ends, when the bench had more): record of the bench the constants were fitted "
            "on; not used by the model",
        ),
        "tissue.fit.bench_frequency_range_hz": Key(
            list,
            None,
            "[lowest, highest], numbers in [0.001, 100] with lowest <= highest",
            lambda v: (
                isinstance(v, list)
                and len(v) == 2
                and all(_num(x) and 1e-3 <= x <= 100.0 for x in v)
                and v[0] <= v[1]
            ),
            "rotation frequencies the bench covered: record of the bench the constants were "
            "fitted on; not used by the model (the fitted constants are calibrated only there)",
        ),
        "requirements.max_failure_probability": _between(
            "largest allowed probability that the capsule fails over the tissue uncertainty: "
            "steps out, or its spiral stretches some wall by less than "
            "requirements.min_wall_strain (a CVaR constraint on optimize.scenarios scenarios; "
            "unset: none)",
            None,
            0.0,
            0.5,
            open_=True,
        ),
        "optimize.scenarios": _count(
            "tissue scenarios (Sobol' points; a power of 2 keeps them balanced) for objective "
            "margin_p05 and requirements.max_failure_probability (at most 8192: each adds a "
            "variable and a row to the NLP)",
            1024,
            20,
            8192,
        ),
        "optimize.scenario_seed": _count(
            "seed of the optimiser's tissue scenarios (numpy's seed range)", 0, 0, 2**32 - 1
        ),
    }
)


# --- tolerances (issue 36): the design must hold over value ± tolerance of each key ---
KEYS.update(
    {
        "tolerances.helical_angle_deg": _between(
            "± on the spiral's helical angle the design must hold over (winding): every "
            "requirement is met at its own worst angle in the band (0: off). Default 0.5 deg, an "
            "engineering estimate (no standard covers a capsule's spiral): the lead pi D_h "
            "tan(alpha) then errs by 0.34 mm per turn at 10 deg on a 12 mm helix, a third of the "
            "1 mm wire, what a wire wound by hand on a jig or laid in a printed groove holds; "
            "without it the built-in optimum failed a spiral angle rounded to two decimals "
            "(issue 36); range: 0-5 deg (a spiral wound more than 5 deg off is another spiral)",
            0.5,
            0.0,
            5.0,
            open_=False,
        ),
        "tolerances.spiral_wire_diameter_mm": _between(
            "± on the spiral wire's diameter as it stands on the body (wire and bonding): the "
            "strain is held at the thinnest wire, the torque at the thickest (0: off). Default "
            "0.02 mm: the round-wire standards (IEC 60317-0-1, NEMA MW 1000) allow about ±0.01 "
            "mm on a 1 mm bare copper conductor, and a cyanoacrylate or epoxy bond line under "
            "the wire adds 0.01 mm or more; range: 0-0.5 mm (beyond that the wire is another wire)",
            0.02,
            0.0,
            0.5,
            open_=False,
        ),
        "tolerances.lumen_diameter_mm": _between(
            "± on every tissue set's lumen about the design's (tissue.lumen_diameter_mm or each "
            "set's own): the strain is held at the widest lumen, the torque at the narrowest (0: "
            "off; the spread of lumens over patients is tissue.uncertainty's). Default 0.05 mm: "
            "the paper gives its samples' lumens to 0.1 mm (Zhou 2013, Tables I-II: 10.9 and "
            "11.1 mm), so each is known to half that digit; 0.1 mm would leave the built-in "
            "10 deg design 1.56 % strain in sample 3, below requirements.min_wall_strain; "
            "range: 0-5 mm (wider spreads are a distribution, "
            "tissue.uncertainty.lumen_diameter_sigma_mm)",
            0.05,
            0.0,
            5.0,
            open_=False,
        ),
    }
)


# --- report front matter (issue 12) ---
def _text(help_: str) -> Key:
    """An optional line of text (shown on the report's title page), at most 200 characters."""
    return Key(
        str,
        None,
        "a line of text, at most 200 characters",
        lambda v: isinstance(v, str) and len(v) <= 200 and "\n" not in v,
        help_,
    )


KEYS.update(
    {
        "report.title": _text("title of the report (default: spiralcap engineering report)"),
        "report.project": _text("project the design belongs to, shown on the title page"),
        "report.author": _text("author of the report, shown on the title page"),
        "report.revision": _text("revision of the design or report, e.g. 'B' or '2026-03'"),
    }
)


# --- the lab's coils as measured (issue 37) ---
#: Largest Frobenius distance of a calibration map from the identity (coils.calibration).
CALIBRATION_MAP_DOMAIN = 0.5


def _is_calibration_map(v: Any) -> bool:
    if not (
        isinstance(v, list)
        and len(v) == 3
        and all(
            isinstance(r, list) and len(r) == 3 and all(_num(x) and abs(x) <= 10.0 for x in r)
            for r in v
        )
    ):
        return False  # (an entry beyond 10 is far outside the domain; no overflow below)
    off = sum((v[i][j] - (1.0 if i == j else 0.0)) ** 2 for i in range(3) for j in range(3))
    return math.sqrt(off) <= CALIBRATION_MAP_DOMAIN


KEYS.update(
    {
        **{
            f"calibration.map_{ax}": Key(
                list,
                None,
                "a 3 x 3 list of rows of finite numbers within "
                f"{CALIBRATION_MAP_DOMAIN:g} of the identity (Frobenius distance)",
                _is_calibration_map,
                f"the {ax} pair's calibration map M (dimensionless, `spiralcap calibrate -o`): "
                f"its field per ampere is M times the modelled one everywhere; absent: the "
                "identity; beyond the domain the survey's pair is not the modelled one (wired "
                "backwards, another channel)",
            )
            for ax in "xyz"
        },
        "calibration.background_field_uT": Key(
            list,
            None,
            "three finite numbers [Bx, By, Bz], each within +/-10000 uT",
            lambda v: (
                isinstance(v, list) and len(v) == 3 and all(_num(c) and abs(c) <= 1e4 for c in v)
            ),
            "constant background field the survey saw (the Earth's ~50 uT, the building's); "
            "the waveforms cancel it with a steady current offset; range: +/-10 mT, beyond "
            "any room's ambient field",
        ),
        "calibration.survey_csv": Key(
            str,
            None,
            "a path to the survey CSV (relative to the file that sets it)",
            lambda v: isinstance(v, str) and v.strip() != "",
            "the gaussmeter survey the calibration was fitted to (the report re-reads it for "
            "its residuals); a record, not used by the field model",
        ),
        "calibration.residual_rms_uT": _between(
            "RMS residual of the calibration fit over every survey row and component: a record "
            "of the fit, not used by the model; range: 0-1e6 uT",
            None,
            0.0,
            1e6,
            open_=False,
        ),
        "calibration.holdout_rms_uT": _between(
            "RMS residual on the survey rows held out of the check fit: a record, not used by "
            "the model; range: 0-1e6 uT",
            None,
            0.0,
            1e6,
            open_=False,
        ),
        "calibration.rows": _count(
            "survey rows the calibration was fitted to: a record, not used by the model",
            None,
            1,
            10**7,
        ),
    }
)


def _with_units(name: str, spec: Key) -> Key:
    from spiralcap.core.constants import design_unit

    unit, si_unit, factor = design_unit(name)
    return replace(spec, name=name, unit=unit, si_unit=si_unit, si_factor=factor)


def finish_keys() -> None:
    """Give every key its name and its unit conversion (called once every block is in).

    Idempotent; call it again after adding keys outside this module.
    """
    for _name, _spec in list(KEYS.items()):
        KEYS[_name] = _with_units(_name, _spec)


finish_keys()


def to_si(key: str, value: Any) -> Any:
    """``value`` of design key ``key`` in SI (``requirements.axial_load_mN`` 50 -> 0.05 N).

    From the key's name alone (the unit table), so it holds for keys added anywhere.
    """
    from spiralcap.core.constants import design_unit

    return value * design_unit(key)[2]


def si_name(key: str) -> str:
    """The leaf of ``key`` with its unit in SI: ``requirements.axial_load_mN`` -> ``axial_load_N``."""
    from spiralcap.core.constants import design_unit

    unit, si_unit, _ = design_unit(key)
    leaf = key.rpartition(".")[2]
    return leaf[: len(leaf) - len(unit)] + si_unit if unit else leaf


def si_values(design: Any, prefix: str) -> dict[str, float]:
    """Every set numeric key under ``prefix`` in SI, by SI leaf name.

    ``si_values(design, "tissue.")`` -> ``{"E1_Pa": ..., "lumen_diameter_m": ...}`` for the
    keys the design sets (optional keys left unset are absent).
    """
    out: dict[str, float] = {}
    for name, spec in KEYS.items():
        if name.startswith(prefix) and spec.kind in (float, int) and design.get(name) is not None:
            out[si_name(name)] = to_si(name, design[name])
    return out


#: Keys that are no longer read, and what replaces them (refused with that one line).
RETIRED_KEYS = {
    "requirements.max_stepout_probability": "no longer read: use "
    "requirements.max_failure_probability (a failure is a step-out or a spiral that stretches "
    "some wall by less than requirements.min_wall_strain)",
}


def validate_value(key: str, value: Any) -> Any:
    """Check one value against its key; return it coerced (int -> float where a float is due).

    Raises
    ------
    InputError
        Unknown key (with the closest known key suggested) or a value outside what is allowed.
    """
    spec = KEYS.get(key)
    if key in RETIRED_KEYS:
        raise InputError(key, value, RETIRED_KEYS[key])
    if spec is None:
        import difflib

        near = difflib.get_close_matches(key, KEYS, n=1, cutoff=0.6)
        hint = (
            f"unknown key; did you mean {near[0]}?"
            if near
            else "unknown key; see `spiralcap init` for every key"
        )
        raise InputError(key, value, hint)
    if spec.kind is float and isinstance(value, int) and not isinstance(value, bool):
        try:
            value = float(value)
        except OverflowError:
            raise InputError(key, value, spec.allowed) from None
    if isinstance(value, str) and _control_character(value):
        raise InputError(
            key, value, f"text without control characters ({_control_character(value)})"
        )
    if not spec.check(value):
        raise InputError(key, value, spec.allowed)
    return value


#: Characters that are not text: line and paragraph separators, and the bidirectional
#: embeddings, overrides and isolates that make text read other than it is stored.
_NOT_TEXT = "\u2028\u2029\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069"


def _control_character(text: str) -> str | None:
    """The first control character of ``text`` (NUL, escape, a line break, a bidirectional
    override) by its code point, ``"U+0000"``; None if there is none."""
    import unicodedata

    for ch in text:
        if ch in _NOT_TEXT or unicodedata.category(ch) == "Cc":
            return f"U+{ord(ch):04X}"
    return None


def defaults() -> dict[str, Any]:
    """The default of every key that has one (optional keys are absent)."""
    return {k: s.default for k, s in KEYS.items() if s.default is not None}


def winding_temperature_C(design: Any) -> float | None:
    """Fixed copper temperature for the resistance, or None (solved with the heating)."""
    value = design.get("coils.winding_temperature_C")
    return None if value is None else float(value)
