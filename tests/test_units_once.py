"""Units are converted once, through one helper, and the helical angle has one name (issue 38
item 3).

Every degree <-> radian conversion in the five packages goes through
:func:`spiralcap.core.constants.to_unit` / :func:`~spiralcap.core.constants.from_unit`, which
read the same unit table as the design keys. The scan below reads the code (not docstrings:
the ``Examples`` sections may show ``math.radians`` to a reader) and fails on a hand
conversion, so a new one cannot slip in. The helical angle in rad is ``helical_angle_rad`` in
every public function's parameters and every public class's fields (a model's maths-local short
names inside a function body stay, where they read like the paper's formula).
"""

from __future__ import annotations

import ast
import doctest
import math
from pathlib import Path

import numpy as np
import pytest

from spiralcap.core import constants
from spiralcap.core.constants import UNIT_FACTORS, from_unit, to_unit

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("spiralcap", "optimize", "capsule", "torque_model", "coils")
#: The helper itself holds the table's factor.
HELPER = Path("spiralcap/core/constants.py")
_CONVERTERS = {"radians", "degrees", "deg2rad", "rad2deg"}
#: pi/180 and 180/pi written out as numbers.
_FACTORS = {math.pi / 180.0, 180.0 / math.pi}
USE = (
    'use spiralcap.core.constants.to_unit(value_si, "deg") (SI -> deg) or '
    'from_unit(value_deg, "deg") (deg -> SI), the one unit table'
)


def _mentions_pi(node: ast.AST) -> bool:
    return any(
        (isinstance(n, ast.Name) and n.id == "pi")
        or (isinstance(n, ast.Attribute) and n.attr == "pi")
        for n in ast.walk(node)
    )


def _mentions_180(node: ast.AST) -> bool:
    return any(isinstance(n, ast.Constant) and n.value in (180, 180.0) for n in ast.walk(node))


def hand_conversions(source: str) -> list[tuple[int, str]]:
    """(line, what) of every hand degree <-> radian conversion in ``source``'s code.

    Docstrings and comments are not code, so ``>>> math.radians(30.0)`` in an ``Examples``
    section passes; ``math.radians(x)``, ``np.degrees(a)``, ``x * math.pi / 180``,
    ``180.0 / np.pi`` and the two factors written as numbers do not.
    """
    found: set[tuple[int, str]] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in _CONVERTERS:
                found.add((node.lineno, f"{name}(...)"))
        elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div)):
            if _mentions_pi(node) and _mentions_180(node):
                found.add((node.lineno, "pi and 180 by hand"))
        elif isinstance(node, ast.Constant) and isinstance(node.value, float):
            if any(math.isclose(node.value, c, rel_tol=1e-12) for c in _FACTORS):
                found.add((node.lineno, f"the factor {node.value!r} written out"))
    return sorted(found)


def test_the_scan_finds_each_kind_of_hand_conversion() -> None:
    src = '''
def f(x, a):
    """Examples
    --------
    >>> math.radians(30.0)
    0.5235987755982988
    """
    y = math.radians(x)  # 8
    z = np.degrees(a)  # 9
    w = x * math.pi / 180  # 10
    v = 180.0 / np.pi * a  # 11
    u = x * 0.017453292519943295  # 12
    t = np.deg2rad(x) + numpy.rad2deg(a)  # 13
    return x * 180  # not an angle: no pi
'''
    lines = [line for line, _ in hand_conversions(src)]
    assert sorted(set(lines)) == [8, 9, 10, 11, 12, 13], (
        f"the scan must flag lines 8-13 of the sample and not its docstring example: {lines}"
    )


def test_no_hand_degree_conversions_in_the_packages() -> None:
    bad = []
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            rel = path.relative_to(ROOT)
            if rel == HELPER:
                continue
            for line, what in hand_conversions(path.read_text(encoding="utf-8")):
                bad.append(f"{rel}:{line}: {what}")
    assert not bad, "hand degree/radian conversions; " + USE + ":\n" + "\n".join(bad)


def test_deg_is_bit_for_bit_the_standard_library() -> None:
    """to_unit/from_unit for degrees are math.degrees/math.radians to the last bit, so routing a
    conversion through the helper moves no pinned output."""
    rng = np.random.default_rng(38)
    x = np.concatenate([rng.uniform(-400.0, 400.0, 2000), rng.uniform(-7.0, 7.0, 2000)])
    for v in x.tolist():
        assert from_unit(v, "deg") == math.radians(v), f"from_unit({v!r}, 'deg') vs math.radians"
        assert to_unit(v, "deg") == math.degrees(v), f"to_unit({v!r}, 'deg') vs math.degrees"
    assert np.array_equal(to_unit(x, "deg"), np.degrees(x)), "arrays vs np.degrees, bit for bit"
    assert np.array_equal(from_unit(x, "deg"), np.radians(x)), "arrays vs np.radians, bit for bit"


def test_round_trips_over_the_whole_table() -> None:
    values = np.array([1e-9, 0.0109, 1.0, 12.5, 3.3e4])
    for unit in UNIT_FACTORS:
        back = to_unit(from_unit(values, unit), unit)
        np.testing.assert_allclose(
            back, values, rtol=4e-16, err_msg=f"{unit}: to_unit(from_unit(x)) == x to 2 ulp"
        )
    assert to_unit(0.0109, "mm") == 10.9, "decimal prefixes come back exactly (0.0109 m = 10.9 mm)"
    assert from_unit(90.0, "deg") == math.pi / 2, "90 deg = pi/2 rad (math.pi), exact"
    assert UNIT_FACTORS["deg"] == math.pi / 180, "the deg factor is math.pi/180 (exact double)"
    assert UNIT_FACTORS["kPa_s"] == 1e3 and UNIT_FACTORS["mNm"] == 1e-3, "SI prefixes (BIPM)"


def test_helper_is_backend_generic_and_names_a_wrong_unit() -> None:
    import casadi as ca

    a = ca.SX.sym("a")
    fn = ca.Function("deg", [a], [to_unit(a, "deg"), from_unit(a, "deg")])
    deg, rad = (float(v) for v in fn(0.3))
    assert deg == math.degrees(0.3) and rad == math.radians(0.3), "CasADi path = numpy path, exact"
    with pytest.raises(KeyError, match=r"'degree'.*not in the unit table"):
        to_unit(1.0, "degree")


def test_helper_examples_run() -> None:
    for test in doctest.DocTestFinder().find(constants):
        result = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS).run(test)
        assert result.failed == 0, f"{test.name}: its Examples section"


#: Other names the helical angle went by (issue 38: 23 files, 4 names).
OLD_ANGLE_NAMES = {
    "alpha",
    "alpha_rad",
    "angle_rad",
    "helical_angle",
    "helix_angle",
    "spiral_angle",
}


def other_angle_names(source: str) -> list[tuple[int, str]]:
    """(line, where) of a public function's parameter or a public class's field named by
    :data:`OLD_ANGLE_NAMES` (module level and class bodies; private names and nested helpers
    are a function's own business)."""
    out = []

    def params(node: ast.FunctionDef | ast.AsyncFunctionDef, owner: str) -> None:
        if node.name.startswith("_") and node.name != "__init__":
            return
        a = node.args
        for arg in a.posonlyargs + a.args + a.kwonlyargs:
            if arg.arg in OLD_ANGLE_NAMES:
                out.append((node.lineno, f"{owner}{node.name}({arg.arg})"))

    for node in ast.parse(source).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            params(node, "")
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            for item in node.body:
                target = getattr(item, "target", None)
                if isinstance(item, ast.AnnAssign) and isinstance(target, ast.Name):
                    if target.id in OLD_ANGLE_NAMES:
                        out.append((item.lineno, f"{node.name}.{target.id}"))
                elif isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    params(item, f"{node.name}.")
    return out


def test_the_name_scan_finds_public_parameters_and_fields() -> None:
    src = """
def worst(model, alpha, f):  # 2
    def inner(alpha):  # nested: its own business
        return alpha
    return inner(alpha)
def _private(alpha_rad):
    return alpha_rad
class Context:
    helical_angle: float  # 9
    helical_angle_rad: float
    def at(self, angle_rad):  # 11
        return angle_rad
"""
    found = [line for line, _ in other_angle_names(src)]
    assert found == [2, 9, 11], f"the scan must flag lines 2, 9 and 11 of the sample: {found}"


def test_the_helical_angle_has_one_name() -> None:
    bad = []
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            for line, where in other_angle_names(path.read_text(encoding="utf-8")):
                bad.append(f"{path.relative_to(ROOT)}:{line}: {where}")
    assert not bad, (
        "the helical angle in rad is helical_angle_rad in public parameters and fields "
        "(design keys and JSON keys keep their schema names):\n" + "\n".join(bad)
    )
