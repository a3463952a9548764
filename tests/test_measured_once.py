"""A lab's measured constants are written once, on the pair (issue 37 follow-up).

``coils.{x,y,z}.measured.*`` become the pair's own ``measured`` field
(:class:`coils.winding.MeasuredConstants`, built by the assembler); the pair's
``resistance_ohm(T)`` and ``series_inductance_H`` answer them and every consumer asks the pair.
The grep below keeps it so: outside ``coils/``, the schema and the assembler, no module reads a
measured design key or carries a measured override of its own. The behaviour checks are hand
formulas written here: IEC 60028's copper (ρ ∝ 1 + α20 (T - 20), α20 = 0.00393 /K).
"""

from __future__ import annotations

import dataclasses
import inspect
import re
from pathlib import Path

import pytest

from spiralcap.core.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("spiralcap", "optimize", "capsule", "torque_model", "coils")
#: Where the measured constants may be named: the pair, the design keys, the assembler.
ALLOWED = ("coils/winding.py", "spiralcap/schema.py", "spiralcap/assemble/")
ALPHA20 = 0.00393  # IEC 60028 annealed copper, per K at 20 °C
PATTERNS = {
    "a measured design key read": re.compile(
        r"""(?:\.get\(|\[)\s*f?["']coils\.[^"']*measured\.(?:resistance|inductance|temper)"""
    ),
    "a measured key prefix": re.compile(r"""f["']coils\.\{[^}]*\}\.measured\.["']"""),
    "a measured override of its own": re.compile(
        r"\bmeasured_(?:resistance|inductance|constants|temperature)\w*"
    ),
    "a measured value passed over the pair": re.compile(
        r"\b(?:resistance_20C_ohm|inductance_H)\s*=\s*c\.(?:resistance_20C_ohm|inductance_H)\b"
    ),
}


def _sites() -> list[str]:
    out = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            if rel.startswith(ALLOWED):
                continue
            for n, line in enumerate(path.read_text().splitlines(), 1):
                for what, pattern in PATTERNS.items():
                    if pattern.search(line):
                        out.append(f"{rel}:{n}: {what}: {line.strip()}")
    return out


def test_no_measured_override_outside_the_pair_and_the_assembler() -> None:
    sites = _sites()
    assert not sites, (
        "outside the pair (coils/winding.py), the schema and the assembler, ask the pair "
        "(resistance_ohm(T), series_inductance_H) instead of reading or passing measured "
        "constants:\n" + "\n".join(sites)
    )


@pytest.mark.parametrize(
    ("line", "what"),
    [
        ('    r = design.get(f"coils.{ax}.measured.resistance_ohm")', "a measured design key read"),
        ('    t = d["coils.x.measured.temperature_C"]', "a measured design key read"),
        ('        key = f"coils.{pair.axis}.measured."', "a measured key prefix"),
        ("    measured_inductance_H: Any = None", "a measured override of its own"),
        ("    r20, ind = measured_constants(d)", "a measured override of its own"),
        (
            "        resistance_20C_ohm=c.resistance_20C_ohm,",
            "a measured value passed over the pair",
        ),
    ],
)
def test_the_patterns_catch_what_they_name(line: str, what: str) -> None:
    assert PATTERNS[what].search(line), f"the pattern for {what} finds {line!r}"


def test_no_consumer_takes_a_resistance_or_inductance_override() -> None:
    from coils import size_system
    from optimize.system import DesignModel

    params = [p for p in inspect.signature(size_system).parameters if "ance" in p]
    assert not params, f"size_system asks each pair for R and L, takes none: {params}"
    fields = [f.name for f in dataclasses.fields(DesignModel) if "measured" in f.name]
    assert not fields, f"DesignModel carries no measured constants (the pairs do): {fields}"


@pytest.fixture(scope="module")
def pairs():
    from coils import HelmholtzPair, MeasuredConstants, SquarePair

    plain = HelmholtzPair(radius_m=0.3, turns=200, axis="x", wire_diameter_m=1.5e-3)
    square = SquarePair(side_m=0.6, turns=150, axis="y", wire_diameter_m=1.5e-3)
    m = MeasuredConstants(resistance_ohm=7.0, temperature_C=60.0, inductance_H=0.8)
    return plain, dataclasses.replace(plain, measured=m), square


def test_the_pair_answers_its_measured_constants(pairs) -> None:
    plain, meas, _ = pairs
    for t in (20.0, 60.0, 95.0):
        want = 7.0 * (1 + ALPHA20 * (t - 20.0)) / (1 + ALPHA20 * 40.0)
        assert meas.resistance_ohm(t) == pytest.approx(want, rel=1e-12), (
            f"IEC 60028 copper scaling from 60 °C to {t} °C, rel 1e-12"
        )
    assert meas.resistance_ohm(60.0) == pytest.approx(7.0, rel=1e-15), "as measured at 60 °C"
    assert meas.series_inductance_H == 0.8, "exactly the measured inductance"
    assert meas.computed_resistance_ohm(35.0) == plain.resistance_ohm(35.0), "the geometry's R"
    assert meas.computed_series_inductance_H == plain.series_inductance_H, "the geometry's L"
    assert plain.computed_series_inductance_H == pytest.approx(
        2 * plain.self_inductance_H + 2 * plain.mutual_inductance_H, rel=1e-15
    ), "2 L + 2 M of the two coils in series aiding"


def test_only_the_measured_constant_replaces_the_computed_one(pairs) -> None:
    from coils import MeasuredConstants

    _, _, square = pairs
    only_l = dataclasses.replace(square, measured=MeasuredConstants(inductance_H=0.05))
    assert only_l.series_inductance_H == 0.05, "the measured inductance"
    assert only_l.resistance_ohm(40.0) == square.resistance_ohm(40.0), "R not measured: computed"
    assert only_l.centre_field_per_amp_T_per_A == square.centre_field_per_amp_T_per_A, "field"


def test_a_pair_of_other_sizes_is_not_the_measured_pair(pairs) -> None:
    plain, meas, _ = pairs
    bigger = meas.with_sizes((0.35,))
    assert bigger.measured is None, "with_sizes drops the measured constants"
    assert bigger.resistance_ohm(20.0) == plain.with_sizes((0.35,)).resistance_ohm(20.0)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({}, "resistance_ohm"),
        ({"resistance_ohm": -1.0}, "resistance_ohm"),
        ({"inductance_H": 0.0}, "inductance_H"),
        ({"resistance_ohm": 1.0, "temperature_C": 400.0}, "temperature_C"),
    ],
)
def test_measured_constants_refuse_bad_values_by_name(kwargs, key) -> None:
    from coils import MeasuredConstants

    with pytest.raises(InputError) as err:
        MeasuredConstants(**kwargs)
    assert err.value.key == key, f"the error names {key}: {err.value}"


def test_the_assembler_puts_the_design_keys_on_the_pairs() -> None:
    from spiralcap.assemble import build_coils
    from spiralcap.design import load_design

    design = load_design(
        None,
        overrides=[
            "coils.z.measured.resistance_ohm=7",
            "coils.z.measured.temperature_C=60",
            "coils.x.measured.inductance_H=0.8",
        ],
    )
    x, y, z = build_coils(design).pairs
    assert (x.measured.resistance_ohm, x.measured.inductance_H) == (None, 0.8), "x: L only"
    assert y.measured is None, "y untouched"
    assert (z.measured.resistance_ohm, z.measured.temperature_C) == (7.0, 60.0), "z: R at 60 °C"
    assert z.resistance_ohm(20.0) == pytest.approx(7.0 / (1 + ALPHA20 * 40.0), rel=1e-12), (
        "IEC 60028 copper scaling to 20 °C, rel 1e-12"
    )


def test_a_rectangle_of_other_sides_is_not_the_measured_pair() -> None:
    """The rectangle's own ``with_sizes`` drops the measured constants too (every shape)."""
    from coils import MeasuredConstants
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    design = load_design(
        str(Path(__file__).resolve().parents[1] / "examples" / "rectangle_coils.toml")
    )
    rect = next(p for p in build_model(design).coils.pairs if len(p.sizes_m) == 2)
    meas = dataclasses.replace(rect, measured=MeasuredConstants(resistance_ohm=3.0))
    assert meas.resistance_ohm(20.0) == 3.0, "the measured resistance at its 20 °C"
    other = meas.with_sizes((0.7, 0.9))
    assert other.measured is None, "other sides: computed constants"
    assert other.resistance_ohm(20.0) == rect.with_sizes((0.7, 0.9)).resistance_ohm(20.0)
