"""Property-based tests (hypothesis): every schema key over its allowed range, values just outside
it, and malformed design files -- each run ends in exit 0 with finite numbers, exit 2 with one
line, or exit 3 (``cli_outcome.sound``), and no self-locking design is called feasible.

Profiles: ``ci`` (default, a few seconds) and ``nightly`` (many more examples); choose with
``HYPOTHESIS_PROFILE=nightly python -m pytest tests/test_properties.py -o filterwarnings=``
(the override keeps hypothesis's failure report from tripping on a libcst deprecation warning;
warnings from spiralcap itself still fail the runs through ``cli_outcome.sound``).
"""

from __future__ import annotations

import json
import math
import os

import pytest
from cli_outcome import sound
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from spiralcap.core.errors import SpiralcapError
from spiralcap.design import example_toml, load_design
from spiralcap.schema import KEYS

settings.register_profile(
    "ci",
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "nightly", max_examples=2000, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

NUMERIC = sorted(k for k, s in KEYS.items() if s.kind in (float, int))


def _literal(value: float | int) -> str:
    return str(value) if isinstance(value, int) else repr(float(value))


@st.composite
def allowed_value(draw, key: str):
    spec = KEYS[key]
    if spec.kind is int:
        lo = int(spec.lo if spec.lo is not None else 1)
        hi = int(spec.hi) if spec.hi is not None else lo + 10**6
        return draw(st.one_of(st.integers(lo, hi), st.sampled_from([lo, hi])))
    lo = spec.lo if spec.lo is not None else 0.0
    hi = spec.hi if spec.hi is not None else 1e300
    values = st.floats(lo, hi, exclude_min=spec.open_, exclude_max=spec.open_, allow_nan=False)
    if lo > 0:  # decades matter more than digits: draw the exponent too
        values = st.one_of(values, st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e))
    if isinstance(spec.default, float) and spec.default > 0:  # and near the built-in design,
        near = st.floats(-1.0, 1.0).map(lambda e: spec.default * 3.0**e).filter(spec.check)
        values = st.one_of(values, near)  # where the other keys' cross-checks still hold
    v = draw(values)
    assume(spec.check(v))
    return v


@st.composite
def design_overrides(draw, n_max: int = 3):
    keys = draw(st.lists(st.sampled_from(NUMERIC), min_size=1, max_size=n_max, unique=True))
    return [f"{k}={_literal(draw(allowed_value(k)))}" for k in keys]


def _judge_evaluation(out: str) -> None:
    ev = json.loads(out)
    lock = next(c for c in ev["checks"] if c["name"] == "self_lock")
    if lock["value"] <= 0:
        assert ev["feasible"] is False, "a self-locking spiral is never feasible"
    assert ev["feasible"] == all(c["ok"] for c in ev["checks"]), "feasible <=> every check"


@given(design_overrides())
def test_allowed_values_give_a_sound_answer(overrides):
    args = [a for o in overrides for a in ("--set", o)]
    rc, out, err = sound(["evaluate", "--json", *args])
    event(f"evaluate exit {rc}" + (f": {err.split(': ')[2][:40]}" if rc == 2 else ""))
    if rc == 0:
        _judge_evaluation(out)
    sound(["capsule", "--json", *args])
    sound(["torque", "--json", *args])


@settings(max_examples=max(8, settings().max_examples // 6))
@given(design_overrides(n_max=2))
def test_allowed_values_optimise_soundly(overrides):
    args = [a for o in overrides for a in ("--set", o)]
    rc, out, _ = sound(["optimize", "--json", *args])
    event(f"optimize exit {rc}")
    if rc == 0:
        res = json.loads(out)
        _judge_evaluation(json.dumps(res["evaluation"]))


@st.composite
def outside_value(draw):
    key = draw(st.sampled_from([k for k in NUMERIC if KEYS[k].hi is not None]))
    spec = KEYS[key]
    side = draw(st.sampled_from(["above", "below", "special"]))
    if side == "special":
        return key, draw(st.sampled_from(["inf", "-inf", "nan", "true", '"3"', "[1]", "{a=1}"]))
    if side == "above":
        hi = float(spec.hi)
        v = draw(st.floats(hi, 1e308, exclude_min=True, allow_nan=False))
        v = float(int(v) + 1) if spec.kind is int and v < 1e18 else v
        return key, _literal(int(v) if spec.kind is int and v < 1e18 else v)
    lo = float(spec.lo)
    v = draw(st.floats(-1e308, lo, exclude_max=True, allow_nan=False))
    return key, _literal(math.floor(v) if spec.kind is int and v > -1e18 else v)


@given(outside_value())
def test_values_outside_the_range_are_refused_in_one_line(kv):
    key, literal = kv
    _, _, err = sound(["evaluate", "--json", "--set", f"{key}={literal}"], allowed=(2,))
    assert key in err, f"the message names {key}: {err}"


_EXAMPLE = example_toml()


@st.composite
def malformed_design(draw):
    kind = draw(st.sampled_from(["bytes", "text", "mutated", "truncated", "encoded"]))
    if kind == "bytes":
        return draw(st.binary(max_size=400))
    if kind == "text":
        return draw(st.text(max_size=300)).encode("utf-8", "surrogatepass")
    if kind == "truncated":
        return _EXAMPLE.encode()[: draw(st.integers(0, len(_EXAMPLE)))]
    if kind == "encoded":
        enc = draw(st.sampled_from(["latin-1", "utf-16-le", "utf-16-be", "utf-32", "cp1252"]))
        return ("# é\n" + _EXAMPLE).encode(enc, "replace")
    text = bytearray(_EXAMPLE.encode())
    for _ in range(draw(st.integers(1, 5))):
        pos = draw(st.integers(0, len(text)))
        junk = draw(st.sampled_from([b"[", b"]", b"=", b"\x00", b"\xff", b'"', b"\n", b"9" * 40]))
        text[pos:pos] = junk
    return bytes(text)


@given(malformed_design())
def test_malformed_design_files_never_crash(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("fuzz") / "design.toml"
    path.write_bytes(data)
    try:
        load_design(path)
        event("read")
    except SpiralcapError as exc:
        event(type(exc).__name__)
        message = str(exc)
        assert "\n" not in message, f"one line: {message!r}"
        assert str(path) in message or "=" in message, f"names the file or key: {message}"
    except Exception as exc:  # pragma: no cover - the property under test
        pytest.fail(f"{type(exc).__name__} escaped load_design: {exc}")


_CSV = "frequency_hz,torque_mNm,helical_angle_deg\n0.5,0.6,10\n1,0.8,10\n2,1.1,10\n3,1.3,10\n"


@st.composite
def malformed_csv(draw):
    kind = draw(st.sampled_from(["bytes", "text", "mutated"]))
    if kind == "bytes":
        return draw(st.binary(max_size=300))
    if kind == "text":
        return draw(st.text(max_size=200)).encode("utf-8", "surrogatepass")
    text = bytearray(_CSV.encode())
    for _ in range(draw(st.integers(1, 4))):
        pos = draw(st.integers(0, len(text)))
        junk = draw(
            st.sampled_from(
                [b",", b"\n", b'"', b"\x00", b"\xe9", b"-", b"e999", b"nan", b"9" * 400]
            )
        )
        text[pos:pos] = junk
    return bytes(text)


@given(malformed_csv())
def test_malformed_bench_csv_never_crashes(tmp_path_factory, data):
    from spiralcap.commands.fit import read_bench_csv

    path = tmp_path_factory.mktemp("csv") / "bench.csv"
    path.write_bytes(data)
    try:
        read_bench_csv(path)
        event("read")
    except SpiralcapError as exc:
        event(type(exc).__name__)
        assert "\n" not in str(exc) and str(path) in str(exc), f"one line naming the file: {exc}"
    except Exception as exc:  # pragma: no cover - the property under test
        pytest.fail(f"{type(exc).__name__} escaped read_bench_csv: {exc}")


@given(
    st.one_of(st.sampled_from(sorted(KEYS)), st.text(max_size=30)),
    st.text(max_size=40),
)
def test_arbitrary_set_expressions_are_sound(key, raw):
    assume("\x00" not in key + raw)
    sound(["capsule", "--json", "--set", f"{key}={raw}"])
