"""Sound answers for the last hostile inputs: deep dotted keys, streams that cannot encode the
units, fractional bounds of whole-number keys, long keys in error lines, duplicated CSV
columns, control characters in text keys, long sweeps off a terminal -- and a bounded fuzz of
random ``--set`` values, corrupted design files and bench CSVs (no traceback, no non-finite
number with exit 0).
"""

from __future__ import annotations

import io
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run, sound
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from proc_util import SPIRALCAP

from spiralcap.cli import ascii_fallback
from spiralcap.design import example_toml
from spiralcap.progress import PlainProgress, progress_bar
from spiralcap.schema import KEYS

ROOT = Path(__file__).resolve().parents[1]
CSV_TEXT = (ROOT / "examples" / "bench_synthetic_sample2.csv").read_text()
#: Examples per fuzz class: a few seconds in the suite; ``SPIRALCAP_FUZZ_EXAMPLES=1000`` for a
#: long run (not derandomized then: each long run draws new cases).
FUZZ_EXAMPLES = int(os.environ.get("SPIRALCAP_FUZZ_EXAMPLES", "8"))
FUZZ = settings(
    max_examples=FUZZ_EXAMPLES,
    deadline=None,
    derandomize="SPIRALCAP_FUZZ_EXAMPLES" not in os.environ,
    suppress_health_check=[HealthCheck.too_slow],
)


def _one_line_exit_2(argv: list[str], *needles: str) -> str:
    rc, _, err = run(argv)
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and "Traceback" not in err, (rc, err[-600:])
    for n in needles:
        assert n in lines[0], f"the message names {n!r}: {lines[0]}"
    return lines[0]


def _file(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# --- nesting ------------------------------------------------------------------------------


@pytest.mark.parametrize("parts", [40, 300, 1000, 100_000])
def test_a_deep_dotted_key_is_one_line(tmp_path, parts):
    path = _file(tmp_path, "deep.toml", ".".join(["a"] * parts) + " = 1\n")
    _one_line_exit_2(["evaluate", path], path)


def test_a_deep_key_inside_an_inline_table_is_one_line(tmp_path):
    path = _file(tmp_path, "deep.toml", "x = {" + ".".join(["a"] * 40) + " = 1}\n")
    _one_line_exit_2(["evaluate", path], "nested more than 32 levels")


def test_floats_in_arrays_are_not_key_dots(tmp_path):
    row = "[" + ", ".join(["0.01"] * 5) + "]"
    matrix = "[" + ", ".join([row] * 5) + "]"
    path = _file(tmp_path, "cov.toml", f"[tissue.fit]\ncovariance_log = {matrix}\n")
    rc, _, err = run(["capsule", path])
    assert rc == 0, err


# --- streams that cannot encode the units ------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "spelled", "process"),
    [
        (["torque"], "mN m", True),  # a process that loads no optimiser: 0.2 s, not 0.8
        (["evaluate"], "mN m", False),
        (["coils"], "deg C", False),
        (
            ["uncertainty", "--samples", "512", "--set", "tissue.uncertainty.scale_sigma_log=0.3"],
            "",
            False,
        ),
    ],
)
def test_an_ascii_stream_gets_ascii_spellings(argv, spelled, process, monkeypatch):
    """One command as a process started with PYTHONIOENCODING=ascii (what Python makes of
    that environment is the point); the others in-process on the stream that environment gives
    (ASCII, errors 'strict': ``main`` reconfigures it the same way), without a second and third
    interpreter start."""
    if process:
        env = {**os.environ, "PYTHONIOENCODING": "ascii", "LANG": "C", "LC_ALL": "C"}
        proc = subprocess.run(
            [*SPIRALCAP, *argv],
            capture_output=True,
            env=env,
            timeout=300,
            cwd=tempfile.gettempdir(),
        )
        rc, stdout, stderr = proc.returncode, proc.stdout, proc.stderr
    else:
        from spiralcap.cli import main

        out = io.TextIOWrapper(io.BytesIO(), encoding="ascii", errors="strict")
        err = io.TextIOWrapper(io.BytesIO(), encoding="ascii", errors="backslashreplace")
        monkeypatch.setattr("sys.stdout", out)
        monkeypatch.setattr("sys.stderr", err)
        rc = main(argv)
        out.flush()
        err.flush()
        stdout, stderr = out.buffer.getvalue(), err.buffer.getvalue()  # type: ignore[attr-defined]
    assert rc == 0 and b"Traceback" not in stderr, stderr[-600:]
    text = stdout.decode("ascii")  # raises if anything but ASCII was written
    assert spelled in text, f"{spelled!r} written for the unit"


@pytest.mark.parametrize(
    ("text", "ascii_text"),
    [
        ("3.2 mN·m", "3.2 mN m"),
        ("75.8 °C <= 90 °C", "75.8 deg C <= 90 deg C"),
        ("α + atan μ = 37°, below 90°", "alpha + atan mu = 37 deg, below 90 deg"),
        ("±1 %: ×0.99, 5 μm, W/(m²·K)", "+/-1 %: x0.99, 5 um, W/(m^2 K)"),
    ],
)
def test_ascii_spellings(text, ascii_text):
    stream = io.TextIOWrapper(io.BytesIO(), encoding="ascii")
    ascii_fallback(stream)
    stream.write(text)
    stream.flush()
    assert stream.buffer.getvalue().decode("ascii") == ascii_text  # type: ignore[attr-defined]


@given(st.text(max_size=80), st.sampled_from(["ascii", "latin-1", "cp1252"]))
@settings(max_examples=60, deadline=None, derandomize=True)
def test_any_text_goes_through_a_narrow_stream(text, encoding):
    stream = io.TextIOWrapper(io.BytesIO(), encoding=encoding)
    ascii_fallback(stream)
    stream.write(text)  # never a UnicodeEncodeError
    stream.flush()
    written = stream.buffer.getvalue().decode(encoding)  # type: ignore[attr-defined]
    assert all(ch in written for ch in set(text) if ord(ch) < 128 and ch.isalnum())


def test_stderr_with_pythons_default_handler_gets_the_spellings_too():
    stream = io.TextIOWrapper(io.BytesIO(), encoding="ascii", errors="backslashreplace")
    ascii_fallback(stream, ("strict", "backslashreplace"))
    stream.write("90 °C")
    stream.flush()
    assert stream.buffer.getvalue() == b"90 deg C"  # type: ignore[attr-defined]
    chosen = io.TextIOWrapper(io.BytesIO(), encoding="ascii", errors="replace")
    ascii_fallback(chosen, ("strict", "backslashreplace"))
    assert chosen.errors == "replace", "a handler the user chose is kept"


def test_a_stream_that_encodes_the_units_is_left_alone():
    stream = io.TextIOWrapper(io.BytesIO(), encoding="utf-8")
    ascii_fallback(stream)
    assert stream.errors == "strict"


# --- whole-number keys, long keys, text keys, CSV columns ---------------------------------


def test_fractional_bounds_of_a_whole_number_key_are_refused(tmp_path):
    _one_line_exit_2(["optimize", "--free", "coils.x.turns=1.5:10.5"], "coils.x.turns")
    path = _file(tmp_path, "d.toml", "[optimize.free]\n'coils.x.turns' = [100.5, 800]\n")
    _one_line_exit_2(["evaluate", path], "optimize.free.coils.x.turns", "whole numbers")
    _one_line_exit_2(["sweep", "--over", "coils.x.turns=100.5:200:3"], "coils.x.turns")
    rc, _, err = run(["evaluate", "--set", "optimize.free.coils.x.turns=[100, 800.0]"])
    assert rc == 0, f"whole bounds written as floats stay accepted: {err}"


def test_a_long_key_is_shortened_in_the_error_line():
    key = "coils." + "k" * 1600 + ".turns"
    line = _one_line_exit_2(["evaluate", "--set", f"{key}=3"], "coils.kkk", "kkk.turns")
    assert len(line) < 400, f"the 1600-character key is cut: {len(line)} characters"


@pytest.mark.parametrize("bad", ["\\u0000", "\\u001b[31m", "\\u202e", "\\u2028", "\\t"])
def test_control_characters_in_text_keys_are_refused(tmp_path, bad):
    _one_line_exit_2(["evaluate", "--set", f'report.project="a{bad}b"'], "report.project")
    path = _file(tmp_path, "d.toml", f'[report]\nproject = "a{bad}b"\n')
    _one_line_exit_2(["evaluate", path], "report.project", "line 2")


def test_ordinary_unicode_text_is_accepted():
    rc, _, err = run(["capsule", "--set", 'report.project="Zürich – 東京, 10 °C"'])
    assert rc == 0, err


def test_a_duplicated_csv_column_is_refused(tmp_path):
    rows = [line for line in CSV_TEXT.splitlines() if line and not line.startswith("#")]
    text = rows[0] + ",torque_mNm\n" + "\n".join(f"{r},0" for r in rows[1:]) + "\n"
    path = _file(tmp_path, "dup.csv", text)
    _one_line_exit_2(["fit", path], "torque_mNm", "more than once")


def test_a_header_of_long_column_names_is_shortened_in_the_error_line(tmp_path):
    names = ",".join(["frequency_hz", "x" * 5000, *(f"c{i}" for i in range(3000))])
    path = _file(tmp_path, "wide.csv", names + "\n1,2,3\n")
    line = _one_line_exit_2(["fit", path], "missing column 'torque_mNm'")
    assert len(line) < 600, f"the header is not echoed whole: {len(line)} characters"


# --- long sweeps off a terminal --------------------------------------------------------------


class _Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_plain_progress_is_silent_for_a_short_job_and_modest_for_a_long_one():
    clock, out = _Clock(), io.StringIO()
    quick = PlainProgress("evaluating", stream=out, clock=clock)
    for done in range(0, 1001, 10):
        clock.now = done * 0.005  # 5 s in all
        quick(done, 1000)
    assert out.getvalue() == "", "a job under 10 s says nothing"
    clock.now = 0.0
    slow = PlainProgress("evaluating", stream=out, clock=clock)
    for done in range(0, 100_001, 100):  # 1000 updates over 200 s
        clock.now = done * 0.002
        slow(done, 100_000)
    lines = out.getvalue().splitlines()
    assert 10 <= len(lines) <= 30, f"every 10 % or 10 s, not every update: {len(lines)} lines"
    assert lines[-1].startswith("evaluating: 100000 of 100000 points (100 %)"), lines[-1]


def test_progress_off_a_terminal_is_plain_lines_on_an_os_stream(monkeypatch, tmp_path):
    with open(tmp_path / "log", "w") as log:
        monkeypatch.setattr("sys.stderr", log)
        with progress_bar("evaluating") as progress:
            assert isinstance(progress, PlainProgress), "a log file gets plain lines"
        with progress_bar("evaluating", enabled=False) as progress:
            assert progress is None
    monkeypatch.setattr("sys.stderr", io.StringIO())
    with progress_bar("evaluating") as progress:
        assert progress is None, "an in-process capture gets nothing"


def test_a_vectorised_sweep_in_chunks_gives_the_same_numbers(monkeypatch):
    import spiralcap.sweep as sw
    from spiralcap.design import load_design

    design = load_design()
    axes = [
        sw.parse_over("capsule.spiral.helical_angle_deg=3:40:3"),
        sw.parse_over("operation.frequency_hz=0.5:5:5"),
    ]
    inputs = sw._grid(axes)
    whole = sw._evaluate_vectorised(design, inputs)
    monkeypatch.setattr(sw, "VECTOR_CHUNK", 2)
    seen: list[tuple[int, int]] = []
    parts = sw._evaluate_vectorised(design, inputs, lambda d, n: seen.append((d, n)))
    for key in whole:
        assert np.array_equal(whole[key], parts[key]), f"{key}: chunked equals one call"
    assert len(seen) == 8 and seen[-1] == (15, 15), f"eight calls of 2 points at most: {seen}"
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


# --- bounded fuzz -------------------------------------------------------------------------

_RAW = st.one_of(
    st.sampled_from(
        [
            "1.5",
            "-1",
            "0",
            "1e308",
            "-1e-320",
            "nan",
            "inf",
            "-inf",
            "1" * 40,
            "[1, 2]",
            "[[1]]",
            "[1.5, 10.5]",
            "{a = 1}",
            '"\\u0000"',
            '"x\\u001by"',
            "true",
            '"' + "y" * 300 + '"',
            "[" * 40 + "]" * 40,
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**20), 10**20).map(str),
    st.text(max_size=20),
)


class TestFuzz:
    """Random ``--set`` values on random keys, corrupted design files, corrupted bench CSVs:
    exit 0 with finite JSON, exit 2 with one line, or exit 3 (``cli_outcome.sound``)."""

    @FUZZ
    @given(key=st.sampled_from(sorted(KEYS)), raw=_RAW)
    def test_random_set_values(self, key, raw):
        sound(["evaluate", "--json", "--set", f"{key}={raw}"])

    @FUZZ
    @given(
        cuts=st.lists(
            st.tuples(
                st.integers(0, 10**6),
                st.sampled_from(
                    [
                        "\x00",
                        "[",
                        "]]",
                        "=",
                        '"',
                        "9" * 40,
                        ".a" * 200,
                        "\nx.y.z = 1\n",
                        "\n[optimize.free]\n'coils.x.turns' = [1.5, 9.5]\n",
                        "\n[report]\nproject = '\x1b'\n",
                        "é",
                    ]
                ),
            ),
            min_size=1,
            max_size=3,
        )
    )
    def test_corrupted_design_files(self, cuts):
        text = example_toml()
        for pos, junk in cuts:
            pos %= len(text) + 1
            text = text[:pos] + junk + text[pos:]
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "d.toml"
            path.write_text(text, encoding="utf-8", errors="surrogatepass")
            sound(["evaluate", str(path), "--json"])

    @FUZZ
    @given(
        extra=st.sampled_from(["", ",torque_mNm", ",frequency_hz", ",x"]),
        cuts=st.lists(
            st.tuples(
                st.integers(0, 10**6),
                st.sampled_from([",", "\n", "nan", "-", "1e999", '"', "\x00"]),
            ),
            max_size=3,
        ),
    )
    def test_corrupted_bench_csvs(self, extra, cuts):
        rows = [line for line in CSV_TEXT.splitlines() if line and not line.startswith("#")]
        text = "\n".join([rows[0] + extra, *rows[1:]]) + "\n"
        for pos, junk in cuts:
            pos %= len(text) + 1
            text = text[:pos] + junk + text[pos:]
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "bench.csv"
            path.write_text(text)
            sound(["fit", str(path), "--json"])


def test_a_subnormal_grid_step_is_one_line_not_a_traceback(tmp_path: Path) -> None:
    """2h/step overflows to inf for a step of 1e-320 mm: exit 2 naming the key."""
    rc, out, err = run(
        ["coils", "--field-grid", str(tmp_path / "g.csv"), "--grid-step-mm", "1e-320"]
    )
    assert rc == 2 and "--grid-step-mm" in err and err.count("\n") <= 1 and not out, err
    assert not (tmp_path / "g.csv").exists()


def test_pdf_code_columns_never_repeat_a_line() -> None:
    """The design-file columns of the PDF: every line once, in order, whatever the layout (a
    review found ten ``a=N`` lines, a table and a key printed with two lines twice)."""
    import random

    from spiralcap.report.pdf import _balanced_columns

    cases = [[f"a={i}" for i in range(10)] + ["[b]", "c=1"]]
    rng = random.Random(0)
    for _ in range(500):
        pool = ["a=1", "[t]", "", "c=2", "key = 'x'"]
        cases.append([rng.choice(pool) for _ in range(rng.randint(1, 40))])
    for lines in cases:
        text = "\n".join(lines)
        for n in (2, 3):
            cols = _balanced_columns(text, n)
            assert "\n".join(cols).split("\n") == text.rstrip("\n").split("\n"), (lines, n)
