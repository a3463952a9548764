"""Issue 39, item 4, "JSON keeps its word": every command's --json validates against its schema
in docs/json under every key combination the schema's fields depend on -- per-channel amplifier
limits (limits.{x,y,z}.current_A / voltage_V / power_W, which rename a pair's rows), circular
and square pairs (examples/square_coils.toml), every objective (margin, power, copper mass,
margin_p05), a sizing with free hardware -- and the JSON stays in SI (README: "--json stays in
SI with the unit in every key"), the evaluation's checks included.

Each case is one in-process CLI run (no IPOPT beyond the optimise cases: ~25 s in all)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from _te_memo import solved_once  # noqa: F401 (the fixture)
from cli_outcome import LEAST_POWER, sound

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs" / "json"
SQUARE = str(ROOT / "examples" / "square_coils.toml")
CSV = str(ROOT / "examples" / "bench_synthetic_sample2.csv")

#: Per-channel limit sets: each kind of channel row on one pair, then every row on every pair.
#: The values are above what the built-in pairs draw (so the design stays feasible) except the
#: y voltage, which binds (so the own-channel row is the one that limits the field).
CHANNELS = {
    "none": [],
    "x-current": ["--set", "limits.x.current_A=14"],
    "y-voltage": ["--set", "limits.y.voltage_V=90"],
    "z-power": ["--set", "limits.z.power_W=900"],
    "all": [
        arg
        for ax, (amps, volts, watts) in zip(
            "xyz", ((20, 160, 1500), (13, 90, 1200), (18, 140, 900))
        )
        for arg in (
            "--set",
            f"limits.{ax}.current_A={amps}",
            "--set",
            f"limits.{ax}.voltage_V={volts}",
            "--set",
            f"limits.{ax}.power_W={watts}",
        )
    ],
}
SHAPES = {"circle": [], "square": [SQUARE]}
#: what the checks' and binding rows' ``unit`` may be: SI (temperatures in °C, counts, ratios)
SI_UNITS = {"N·m", "m/s", "rad", "m", "T", "A", "V", "W", "kg", "K", "°C", "1", "turns", "Hz"}


def _cases() -> list:
    out: list = []
    for shape in SHAPES.values():
        for label, channel in CHANNELS.items():
            out.append(("evaluate", ["evaluate", *shape, *channel]))
            if label == "all" or (label == "none" and not shape):  # single kinds: the test below
                out.append(("coils", ["coils", *shape, *channel]))
    every = CHANNELS["all"]
    for shape in SHAPES.values():
        for objective in ("margin", "power", "copper_mass") if not shape else ("power",):
            sf = ["--set", "requirements.min_safety_factor=1.5"] if objective != "margin" else []
            argv = ["optimize", *shape, *every, "--set", f"optimize.objective={objective}", *sf]
            out.append(("optimize", argv))
        out.append(
            ("waveforms", ["waveforms", *shape, *every, "--heading", "1,0,0", "--dwell-s", "2"])
        )
        out.append(("sweep", ["sweep", *shape, *every, "--over", "operation.frequency_hz=1:3:3"]))
    out += [
        pytest.param(
            "optimize",
            [
                "optimize",
                *CHANNELS["y-voltage"],
                "--set",
                "optimize.objective=margin_p05",
                "--set",
                "tissue.uncertainty.scale_sigma_log=0.3",
                "--set",
                "optimize.scenarios=32",
            ],
            marks=pytest.mark.slow,
        ),
        (
            "optimize",
            [
                "optimize",
                *every,
                *LEAST_POWER,
                "--free",
                "coils.y.turns=200:500",
                "--free",
                "coils.y.wire_diameter_mm=1.5:3.0",
            ],
        ),
        (
            "sweep",
            [
                "sweep",
                *CHANNELS["y-voltage"],
                "--optimize",
                "--over",
                "limits.y.voltage_V=60:120:2",
            ],
        ),
        ("compare", ["compare", "builtin", SQUARE, *every]),
        (
            "uncertainty",
            [
                "uncertainty",
                SQUARE,
                *every,
                "--samples",
                "128",
                "--sobol-samples",
                "0",
                "--set",
                "tissue.uncertainty.scale_sigma_log=0.3",
            ],
        ),
        ("capsule", ["capsule", *every]),
        ("torque", ["torque", "--frequency", "0.5", "2"]),
        ("fit", ["fit", CSV, "--only", "scale,E1"]),
    ]
    return out


CASES = _cases()


def _validator(name: str):
    schema = json.loads((DOCS / f"{name}.schema.json").read_text())
    return jsonschema.Draft202012Validator(schema)


def _units(doc: object, path: str = "$") -> list[tuple[str, str]]:
    """Every ``unit`` of a check or a binding row in the document, with its path."""
    found: list[tuple[str, str]] = []
    if isinstance(doc, dict):
        if "unit" in doc and "value" in doc and "allowed" in doc:
            found.append((path, str(doc["unit"])))
        for k, v in doc.items():
            found += _units(v, f"{path}.{k}")
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            found += _units(v, f"{path}[{i}]")
    return found


def _id(case) -> str:
    name, argv = case.values if hasattr(case, "values") else case
    shape = "square" if SQUARE in argv else "circle"
    sets = [a.split("=")[0] for a in argv if "=" in a and not a.startswith("--")]
    return f"{name}-{shape}-" + ",".join(s.removeprefix("limits.") for s in sets)[:60]


#: each model evaluated and optimised once in this process (tests/_te_memo.py): ``compare``
#: re-solves what the evaluate and optimize cases did, ``evaluate --json`` runs twice
@pytest.mark.usefixtures("solved_once")
@pytest.mark.parametrize(("name", "argv"), CASES, ids=[_id(c) for c in CASES])
def test_every_command_json_matches_its_schema(name, argv):
    _, out, _ = sound([*argv, "--json"], allowed=(0, 3))
    doc = json.loads(out)
    errors = [
        f"{'/'.join(map(str, e.path))}: {e.message[:160]}"
        for e in _validator(name).iter_errors(doc)
    ]
    assert not errors, f"{argv}: docs/json/{name}.schema.json: " + "; ".join(errors[:5])
    not_si = [(p, u) for p, u in _units(doc) if u not in SI_UNITS]
    assert not not_si, f"{argv}: JSON is SI (README); these are not: {not_si[:5]}"


@pytest.mark.usefixtures("solved_once")
def test_checks_are_si_and_carry_their_key_unit():
    """The speed check: 6.6 mm/s is 0.0066 m/s in ``value``, 6.6 in ``value_in_key_unit``."""
    _, out, _ = sound(["evaluate", "--json"], allowed=(0,))
    doc = json.loads(out)
    speed = next(c for c in doc["checks"] if c["name"] == "speed")
    assert speed["unit"] == "m/s" and speed["value"] == pytest.approx(doc["speed_m_s"], rel=1e-12)
    assert speed["key_unit"] == "mm/s"
    assert speed["value_in_key_unit"] == pytest.approx(1e3 * doc["speed_m_s"], rel=1e-12), (
        "mm/s = 1e3 m/s (definition), 1e-12"
    )
    margin = next(c for c in doc["checks"] if c["name"] == "margin")
    assert (margin["unit"], margin["value"]) == ("N·m", pytest.approx(doc["margin_Nm"], rel=1e-12))
    lock = next(c for c in doc["checks"] if c["name"] == "self_lock")
    assert lock["unit"] == "rad" and math.isclose(lock["allowed"], math.pi / 2, rel_tol=1e-12)


@pytest.mark.parametrize("kind", ["current", "voltage", "power"])
def test_coils_per_limit_keys_stay_the_same_whichever_channel(kind):
    """limits.y.<kind> renames the y pair's row inside the model (axis_<kind>_y); the JSON keeps
    one name per limit and says which design key sets it."""
    value = {"current": 13, "voltage": 90, "power": 400}[kind]
    unit = {"current": "A", "voltage": "V", "power": "W"}[kind]
    _, out, _ = sound(["coils", "--set", f"limits.y.{kind}_{unit}={value}", "--json"], (0,))
    w = json.loads(out)["rotating_field_within_limits"]
    caps, keys = w["per_limit_max_field_T"], w["per_limit_key"]
    assert set(caps) == set(keys), "one design key per limit"
    assert not any(k.startswith("axis_") for k in caps), f"internal row names leak: {sorted(caps)}"
    assert keys[f"{kind}_y"] == f"limits.y.{kind}_{unit}", keys
    if kind != "power":
        assert keys[f"{kind}_x"] == f"limits.{kind}_{unit}", "the other pairs keep the global key"
    assert w["limited_by"] in caps and keys[w["limited_by"]] == w["limit_key"]
