"""Run the CLI in-process and judge the outcome as issue 14 asks: exit 0 with finite numbers,
exit 2 with exactly one line on stderr, or exit 3 -- no traceback, no null/"inf"/NaN number."""

from __future__ import annotations

import contextlib
import io
import json
import math
from typing import Any

from spiralcap.cli import main


def run(argv: list[str]) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of ``spiralcap argv`` (argparse exits caught)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(argv)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 2
    return rc, out.getvalue(), err.getvalue()


def run_json(argv: list[str]) -> dict:
    """``spiralcap argv --json`` parsed; exit 0 asserted (stderr in the message)."""
    rc, out, err = run([*argv, "--json"])
    assert rc == 0, err
    return json.loads(out)


#: The ``_undefined`` flags a point with no contact has by design (docs/json/README.md: the
#: spiral does not touch some wall, so the model has no margin there): allowed where the same
#: object says ``grip: "none"`` (and the margin check's value inside its ``checks``).
NO_CONTACT_UNDEFINED = frozenset(
    {
        "margin_Nm_undefined",
        "safety_factor_undefined",
        "step_out_frequency_hz_undefined",
        "max_frequency_hz_undefined",
    }
)


def bad_numbers(value: Any, path: str = "$", no_contact: bool = False) -> list[str]:
    """Where a JSON document holds null, a non-finite number, a number-like string or an
    ``_undefined`` flag (a NaN that was hidden) other than a no-contact point's own
    (:data:`NO_CONTACT_UNDEFINED`)."""
    found: list[str] = []
    if value is None:
        found.append(f"{path}: null")
    elif isinstance(value, float) and not math.isfinite(value):
        found.append(f"{path}: {value}")
    elif isinstance(value, str) and value.strip().lower() in {"inf", "-inf", "nan", "infinity"}:
        found.append(f"{path}: {value!r}")
    elif isinstance(value, dict):
        here = value.get("grip") == "none"
        margin_check = no_contact and value.get("name") == "margin"
        # compare: a row whose ``defined`` names a design without a value (no contact: no
        # margin), and the margin block of such designs
        row = isinstance(value.get("defined"), list) and not all(value["defined"])
        for k, v in value.items():
            allowed = (
                (here and k in NO_CONTACT_UNDEFINED)
                or (margin_check and k in ("value_undefined", "value_in_key_unit_undefined"))
                or (row and k == "values_undefined")
                or (
                    path.endswith(".margin_Nm")
                    and k in ("evaluate_undefined", "optimize_undefined")
                )
            )
            if k.endswith("_undefined") and not allowed:
                found.append(f"{path}.{k}")
            found += bad_numbers(v, f"{path}.{k}", here and k == "checks")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            found += bad_numbers(v, f"{path}[{i}]", no_contact)
    return found


def sound(argv: list[str], allowed: tuple[int, ...] = (0, 2, 3)) -> tuple[int, str, str]:
    """Run and assert the outcome is sound; return (status, stdout, stderr)."""
    rc, out, err = run(argv)
    assert rc in allowed, f"{argv}: exit {rc} not in {allowed}; stderr: {err[-400:]}"
    assert "Traceback" not in err, f"{argv}: traceback on stderr:\n{err}"
    if rc == 2:
        lines = err.splitlines()
        assert len(lines) == 1, f"{argv}: exit 2 needs exactly one stderr line, got {lines}"
        assert lines[0].startswith("spiralcap"), f"{argv}: message not prefixed: {lines[0]}"
    if rc in (0, 3) and "--json" in argv and out.strip():
        doc = json.loads(out, parse_constant=lambda c: float(c))
        bad = bad_numbers(doc)
        assert not bad, f"{argv}: non-finite numbers in JSON: {bad[:5]}"
    if rc == 0 and "--json" not in argv:
        assert err.strip() == "", f"{argv}: exit 0 with warnings on stderr: {err[-400:]}"
    if rc in (0, 3):
        assert "Warning" not in err, f"{argv}: a warning on stderr: {err[-400:]}"
    return rc, out, err


#: Options that make the required torque zero (no axial load, a lumen wider than the capsule,
#: one tissue set): the infinite safety factor case.
#: A lumen wider than the capsule and no axial load: the spiral does not touch the wall, so the
#: tissue model resists nothing and only the friction of the capsule's weight remains (the
#: design fails the grip requirement). No design file reaches a required torque of exactly 0
#: any more (``capsule.mass_g`` >= 0.1 g): :func:`weightless` builds that edge case in Python.
ZERO_TORQUE = [
    "--set",
    "requirements.axial_load_mN=0",
    "--set",
    "tissue.lumen_diameter_mm=30",
    "--set",
    "tissue.worst_case_presets=[]",
]


def weightless(sets: list[str]) -> Any:
    """The prepared model of the built-in design with ``sets`` and a capsule of no mass: with
    :data:`ZERO_TORQUE` nothing at all resists it (the required torque is exactly 0)."""
    from dataclasses import replace

    from optimize import prepare
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = build_model(load_design(None, [s for s in sets if s != "--set"]))
    return prepare(replace(model, capsule=replace(model.capsule, set_mass_kg=0.0)))


#: ``--free`` arguments of the six-key sizing the tests share: every pair's turns (100 to 800)
#: and wire (0.8 to 3 mm).
SIX_KEYS = [
    arg
    for ax in "xyz"
    for arg in (
        "--free",
        f"coils.{ax}.turns=100:800",
        "--free",
        f"coils.{ax}.wire_diameter_mm=0.8:3.0",
    )
]
#: ``--set`` arguments that switch the tolerance box off (issue 36): the nominal rows, for tests
#: whose subject is not the box (tests/test_tolerances.py holds the box's own).
NO_TOLERANCES = [
    *("--set", "tolerances.helical_angle_deg=0"),
    *("--set", "tolerances.spiral_wire_diameter_mm=0"),
    *("--set", "tolerances.lumen_diameter_mm=0"),
]
#: The same as design keys (``load_design(None, [...])``).
NO_TOLERANCE_SETS = NO_TOLERANCES[1::2]
#: ``--set`` arguments of a least-power sizing at safety factor 2 (its numbers pinned before the
#: tolerance box: nominal rows).
LEAST_POWER = [
    "--set",
    "optimize.objective=power",
    "--set",
    "requirements.min_safety_factor=2",
    *NO_TOLERANCES,
]
