"""Every design-file key: its type, default, the values it allows, and a one-line meaning.

Keys carry their unit in the name (``radius_m``, ``helical_angle_deg``). A key with default
``None`` is optional: absent means "take it from elsewhere" (the tissue preset, the coil radius).
This table is the single source for validation, for ``spiralcap init`` comments and for the
report's input table.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from spiralcap.errors import InputError


@dataclass(frozen=True)
class Key:
    """One design key: type, default, allowed values (a predicate and its words), and meaning."""

    kind: type
    default: Any
    allowed: str
    check: Callable[[Any], bool]
    help: str


def _num(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _pos(help_: str, default: Any) -> Key:
    return Key(float, default, "a finite number > 0", lambda v: _num(v) and v > 0, help_)


def _nonneg(help_: str, default: Any) -> Key:
    return Key(float, default, "a finite number >= 0", lambda v: _num(v) and v >= 0, help_)


def _between(help_: str, default: Any, lo: float, hi: float, *, open_: bool = True) -> Key:
    if open_:
        return Key(
            float,
            default,
            f"a number in ({lo:g}, {hi:g})",
            lambda v: _num(v) and lo < v < hi,
            help_,
        )
    return Key(
        float, default, f"a number in [{lo:g}, {hi:g}]", lambda v: _num(v) and lo <= v <= hi, help_
    )


def _count(help_: str, default: Any, lo: int = 1) -> Key:
    return Key(
        int,
        default,
        f"a whole number >= {lo}",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= lo,
        help_,
    )


def _choice(help_: str, default: str, options: tuple[str, ...]) -> Key:
    return Key(
        str, default, "one of " + ", ".join(repr(o) for o in options), lambda v: v in options, help_
    )


def _is_heading_list(v: Any) -> bool:
    if v == "all":
        return True
    return (
        isinstance(v, list)
        and len(v) > 0
        and all(
            isinstance(h, list)
            and len(h) == 3
            and all(_num(c) for c in h)
            and sum(c * c for c in h) > 0
            for h in v
        )
    )


def _is_str_list(v: Any) -> bool:
    return isinstance(v, list) and all(isinstance(s, str) for s in v)


TISSUE_PRESETS = ("zhou2013-sample2", "zhou2013-sample3")
MAGNET_GRADES = ("N35", "N42", "N45", "N48", "N52")

KEYS: dict[str, Key] = {
    # --- coils ---------------------------------------------------------------------------------
    "coils.winding_temperature_C": Key(
        float,
        None,
        "a number in [-50, 250]",
        lambda v: _num(v) and -50 <= v <= 250,
        "fixed copper temperature for the resistance in the voltage and power limits (default: "
        "the mean winding temperature solved with the heating, coils.thermal)",
    ),
    "coils.ambient_temperature_C": Key(
        float,
        25.0,
        "a number in [-50, 100]",
        lambda v: _num(v) and -50 <= v <= 100,
        "air temperature around the coils",
    ),
    "coils.heat_transfer_coefficient_W_m2K": _pos(
        "convective heat-transfer coefficient from the winding surface (natural air ~5-15)", 10.0
    ),
    "coils.packing_factor": _between(
        "copper cross-section / winding-pack cross-section (round wire, layer wound ~0.6-0.8)",
        0.7,
        0.0,
        0.9069,
        open_=True,
    ),
}
for _ax, _r, _n in (("x", 0.40, 400), ("y", 0.35, 350), ("z", 0.30, 300)):
    KEYS[f"coils.{_ax}.radius_m"] = _pos(f"mean radius of each coil of the {_ax} pair", _r)
    KEYS[f"coils.{_ax}.turns"] = _count(f"turns of each coil of the {_ax} pair", _n)
    KEYS[f"coils.{_ax}.wire_diameter_mm"] = _pos(f"bare copper diameter of the {_ax} winding", 2.5)
    KEYS[f"coils.{_ax}.separation_m"] = _pos(
        f"distance between the two {_ax} coils (default: the radius, Helmholtz spacing)", None
    )

KEYS.update(
    {
        # --- capsule ---
        "capsule.diameter_mm": _pos("outer diameter of the capsule shell (PillCam SB2: 11)", 11.0),
        "capsule.length_mm": _pos(
            "overall length including the hemispherical ends (PillCam SB2: 26)", 26.0
        ),
        "capsule.shell_thickness_mm": _pos("wall thickness of the capsule shell", 0.5),
        "capsule.spiral.helical_angle_deg": _between(
            "angle between the spiral wire and the capsule's cross-section plane (paper: 5-20)",
            10.0,
            0.0,
            90.0,
        ),
        "capsule.spiral.wire_diameter_mm": _pos("diameter of the spiral wire (paper: 1)", 1.0),
        "capsule.spiral.wound_length_mm": _pos("axial length over which the spiral is wound", 15.0),
        "capsule.spiral.starts": _count("number of independent spiral wires (starts)", 1),
        "capsule.magnet.shape": _choice(
            "magnet shape, diametrically magnetised", "cylinder", ("cylinder", "ring")
        ),
        "capsule.magnet.diameter_mm": _pos("outer diameter of the magnet", 6.0),
        "capsule.magnet.length_mm": _pos("axial length of the magnet", 10.0),
        "capsule.magnet.inner_diameter_mm": _nonneg(
            "bore of a ring magnet (0 for a cylinder)", 0.0
        ),
        "capsule.magnet.grade": _choice(
            "sintered NdFeB grade (sets remanence_T if that is absent)", "N45", MAGNET_GRADES
        ),
        "capsule.magnet.remanence_T": _between(
            "remanence B_r (overrides the grade)", None, 0.0, 2.0
        ),
        # --- tissue ---
        "tissue.preset": _choice(
            "calibrated tissue parameter set (see docs/torque-model.md)",
            "zhou2013-sample2",
            TISSUE_PRESETS,
        ),
        "tissue.E1_kPa": _nonneg(
            "spring modulus E1 of the five-element model (overrides preset)", None
        ),
        "tissue.E2_kPa": _nonneg("spring modulus E2 (overrides preset)", None),
        "tissue.E3_kPa": _nonneg("spring modulus E3 (overrides preset)", None),
        "tissue.eta1_kPa_s": _pos("dashpot viscosity eta1 (overrides preset)", None),
        "tissue.eta2_kPa_s": _pos("dashpot viscosity eta2 (overrides preset)", None),
        "tissue.lumen_diameter_mm": _pos(
            "inner diameter of the undeformed intestine (overrides)", None
        ),
        "tissue.wall_thickness_mm": _pos("intestinal wall thickness (overrides preset)", None),
        "tissue.friction_coefficient": _pos(
            "capsule-mucosa Coulomb friction (overrides preset)", None
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
        "operation.frequency_hz": _pos(
            "rotation frequency of the field at the operating point", 2.0
        ),
        "workspace.radius_m": _nonneg(
            "radius of the region around the coil centre the capsule must work in (0: centre only)",
            0.05,
        ),
        "workspace.headings": Key(
            list,
            "all",
            '"all" or a list of [x, y, z] direction vectors',
            _is_heading_list,
            "capsule headings (rotation axes) to design for",
        ),
        # --- requirements ---
        "requirements.axial_load_mN": _nonneg(
            "axial resistance the spiral must push against (20-100 in porcine small bowel)", 50.0
        ),
        "requirements.slip_efficiency": _between(
            "forward speed / (frequency x spiral lead); 1 is a nut on a screw",
            0.5,
            0.0,
            1.0,
            open_=False,
        ),
        "requirements.min_speed_mm_s": _nonneg(
            "least forward speed the capsule must reach (5 mm/s: about 17 min per metre)", 5.0
        ),
        "requirements.min_spiral_turns": _nonneg(
            "fewest spiral turns over the wound length that can be made (0 switches the rule off)",
            1.0,
        ),
        # --- limits ---
        "limits.current_A": _pos("largest current amplitude of any coil pair", 15.0),
        "limits.voltage_V": _pos("largest drive-voltage amplitude across any coil pair", 150.0),
        "limits.power_W": _pos("largest total copper loss of the three pairs", 2000.0),
        "limits.coil_temperature_C": _pos(
            "hottest winding temperature allowed (the hot spot at the pack centre)", 90.0
        ),
        "limits.field_exposure": _choice(
            "ICNIRP 2010 reference level applied to the rotating field",
            "occupational",
            ("occupational", "public", "off"),
        ),
        # --- optimisation ---
        "optimize.helical_angle_min_deg": _between("lower bound on the helical angle", 2.0, 0, 90),
        "optimize.helical_angle_max_deg": _between("upper bound on the helical angle", 45.0, 0, 90),
        "optimize.frequency_min_hz": _pos("lower bound on the rotation frequency", 0.5),
        "optimize.frequency_max_hz": _pos("upper bound on the rotation frequency", 5.0),
        "optimize.objective": _choice(
            "maximise the torque margin or the safety factor", "margin", ("margin", "ratio")
        ),
        "optimize.starts": _count("initial helical angles IPOPT is started from", 4),
    }
)


# Keys added by later work are declared in one block per capability below, so each stays in one
# place (numeric keys with physical bounds: _between(..., lo, hi, open_=False)).

# --- hardware sizing (issue 9) ---
KEYS.update({})

# --- coils as they really run (issue 10) ---
KEYS.update(
    {
        "coils.winding_conductivity_W_mK": _between(
            "effective transverse thermal conductivity of the winding pack (impregnated round "
            "wire 0.3-1.0; Simpson, Wrobel & Mellor, IEEE Trans. Ind. Appl. 49(6), 2013)",
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
            "its end (absent: steady state)",
            None,
            0.0,
            1.0e5,
            open_=True,
        ),
        "operation.field_amplitude_mT": _between(
            "fixed rotating-field amplitude at the centre (absent: the largest the limits allow)",
            None,
            0.0,
            1000.0,
            open_=True,
        ),
    }
)

# --- tissue uncertainty (issue 11) ---
KEYS.update({})

# --- report front matter (issue 12) ---
KEYS.update({})


def validate_value(key: str, value: Any) -> Any:
    """Check one value against its key; return it coerced (int -> float where a float is due).

    Raises
    ------
    InputError
        Unknown key (with the closest known key suggested) or a value outside what is allowed.
    """
    spec = KEYS.get(key)
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
        value = float(value)
    if not spec.check(value):
        raise InputError(key, value, spec.allowed)
    return value


def defaults() -> dict[str, Any]:
    """The default of every key that has one (optional keys are absent)."""
    return {k: s.default for k, s in KEYS.items() if s.default is not None}


def winding_temperature_C(design: Any) -> float | None:
    """Fixed copper temperature for the resistance, or None (solved with the heating)."""
    value = design.get("coils.winding_temperature_C")
    return None if value is None else float(value)
