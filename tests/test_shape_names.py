"""A coil's shape is an object every layer asks (issue 38): outside ``coils/``, only the schema
and the assembler (``spiralcap/assemble/``) name a shape or test one.

Every other module asks the pair (its ``terms``, ``pack_solids``, ``view_pack``,
``thermal_ring``, ``tube_radius_m``, ``RING``, ...). The patterns below are what the review of
issue 38 counted (about 60 sites in 16 files): a shape compared with a name, a ``square=`` flag,
``isinstance`` on a pair class, a shape's name as a string, a pair class named in code.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("spiralcap", "optimize", "capsule", "torque_model")
#: Where shapes may be named: the design keys and the assembler that builds the pair.
ALLOWED = ("spiralcap/schema.py", "spiralcap/assemble/")
#: ``spiralcap.core.backend.square`` is numpy's x², not a coil.
NOT_A_SHAPE = {("spiralcap/core/backend.py", '"square"')}
PAIRS = r"(?:HelmholtzPair|SquarePair|RectanglePair|WoundPair)"
PATTERNS = {
    "a shape compared with a name": re.compile(r"""\bshape\s*[!=]=\s*["']"""),
    "a square= flag": re.compile(r"[(,]\s*square\s*="),
    "isinstance on a pair class": re.compile(rf"isinstance\([^)]*\b{PAIRS}\b"),
    "a shape's name as a string": re.compile(r"""["'](?:circle|square|rectangle)["']"""),
    "a pair class named in code": re.compile(rf"(?:import[^\n#]*\b{PAIRS}\b|\b{PAIRS}\()"),
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
                    m = pattern.search(line)
                    if m and (rel, m.group(0).strip("(,= ")) not in NOT_A_SHAPE:
                        out.append(f"{rel}:{n}: {what}: {line.strip()}")
    return out


def test_no_shape_named_outside_coils_schema_and_assembler() -> None:
    sites = _sites()
    assert not sites, (
        "outside coils/, the schema and the assembler, ask the pair instead of naming its "
        "shape:\n" + "\n".join(sites)
    )


@pytest.mark.parametrize(
    ("line", "what"),
    [
        ('    if p.shape == "square":', "a shape compared with a name"),
        ("    q = coil_quantities(r, n, d, s, square=True)", "a square= flag"),
        ("    if isinstance(pair, HelmholtzPair):", "isinstance on a pair class"),
        ('    kinds = {"circle": 1}', "a shape's name as a string"),
        ("    from coils import SquarePair", "a pair class named in code"),
    ],
)
def test_the_patterns_catch_what_they_name(line: str, what: str) -> None:
    assert PATTERNS[what].search(line), f"the pattern for {what} finds {line!r}"
