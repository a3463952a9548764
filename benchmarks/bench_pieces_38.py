"""Benchmark: issue 38's speed pieces, each switched off alone, in CPU seconds of whole commands.

Run: python benchmarks/bench_pieces_38.py [--repeat N] [PIECE ...]
Every run is a fresh ``spiralcap`` process (imports included, BLAS single-threaded); "on" and
"off" alternate, so a busy machine slows both alike. The figure is the child's CPU time
(user + sys, ``resource.getrusage(RUSAGE_CHILDREN)``), which another engineer's load moves
far less than the wall time. Prints, per piece and command, the median CPU seconds on and off,
the saving ``1 - on / off`` (docs/architecture.md: a piece stays only if it saves at least
20 % of a command a user waits on for more than a second), the median wall time on, and the
load average. Asserts nothing.

Most of these pieces were retired by issue 38: measure them on a checkout of the tree before
it, with ``PYTHONPATH`` pointing there (``git archive 925e794``); the kept ones (the
``thermal_states`` and ``compile_problem`` memos) switch off on the current tree too.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SIX = [
    f"--free=coils.{ax}.{key}"
    for ax in "xyz"
    for key in ("turns=100:800", "wire_diameter_mm=0.8:3.0")
]
ROBUST = [
    "--set",
    "tissue.uncertainty.scale_sigma_log=0.3",
    "--set",
    "optimize.objective=margin_p05",
]
OUT = str(Path(tempfile.gettempdir()) / "spiralcap-bench-pieces-38.html")

COMMANDS: dict[str, list[str]] = {
    "coils": ["coils", "--json"],
    "evaluate": ["evaluate", "--json"],
    "optimize": ["optimize", "--json"],
    "sizing": ["optimize", "--json", *SIX],
    "robust": ["optimize", "--json", *ROBUST],
    "report": ["report", "-o", OUT, "--workers", "1"],
    "sweep40": ["sweep", "--optimize", "--over", "limits.power_W=300:3000:40"],
    "square-sizing": [
        "optimize",
        "--json",
        "examples/square_coils.toml",
        *SIX,
        *("--free", "coils.x.side_m=0.7:1.2"),
        *("--set", "optimize.objective=power", "--set", "requirements.min_safety_factor=2"),
    ],
}

#: The filament scratch buffers and the ``out=`` twin off: the numpy field through the same
#: formulas as the CasADi path (coils.loop.loop_terms on (n, L) arrays).
FILAMENTS_OFF = """
import numpy as np, coils.filaments as f
from coils.loop import loop_terms
def _terms(self, points):
    mats = self._matrices(False)
    zeta = points @ mats["sel_w"]
    rho_sq = (points * points) @ mats["across"]
    s, b_z = loop_terms(mats["sizes"], zeta - mats["centres"], np.sqrt(rho_sq), rho_sq)
    return s @ mats["weights"], (b_z - s * zeta) @ mats["weights"]
def terms(self, points):
    import spiralcap.core.backend as bk
    if bk.is_casadi(points):
        return orig(self, points)
    return _terms(self, np.asarray(points, dtype=float))
orig = f.FilamentSet.terms
f.FilamentSet.terms = terms
f.FilamentSet._field_chunk = lambda self, p, c: self._field_rows(p, c, self._matrices(False))
def _matrix_chunk(self, p):
    S, T = _terms(self, p)
    d = self._matrices(False)["direction"]
    return p[:, :, None] * S[:, None, :] + d.T[None, :, :] * T[:, None, :]
f.FilamentSet._matrix_chunk = _matrix_chunk
"""

#: heading_losses_W without its memo (each heading's resistance traced on its own).
HEADING_MEMO_OFF = """
import inspect, textwrap, optimize.physics as ph
src = textwrap.dedent(inspect.getsource(ph.heading_losses_W))
src = src.replace("if key is None or key not in memo:", "if True:").replace(
    "if key is None:", "if True:")
exec(compile(src, ph.__file__, "exec"), ph.__dict__)
"""

#: scipy.optimize.brentq in place of optimize._roots.brentq.
ROOTS_OFF = """
import scipy.optimize as so, optimize._roots as r, optimize.evaluate as ev
r.brentq = so.brentq
ev.brentq = so.brentq
"""

SYMBOLIC_ONCE_OFF = """
import spiralcap.core.backend as bk
bk.symbolic_once = lambda fn, n_args: fn
"""

SCALAR_FAST_OFF = """
import spiralcap.core.backend as bk
bk.scalar_fast = lambda math_fn, bk_fn: bk_fn
"""


def _uncached(module: str, name: str, users: tuple[str, ...] = ()) -> str:
    lines = [f"import importlib\nm = importlib.import_module({module!r})"]
    lines.append(f"plain = m.{name}.__wrapped__\nm.{name} = plain")
    for user in users:
        lines.append(f"importlib.import_module({user!r}).{name} = plain")
    return "\n".join(lines)


#: name -> (setup that switches the piece off, commands it is measured on)
PIECES: dict[str, tuple[str, tuple[str, ...]]] = {
    "filament scratch buffers and out= twin": (FILAMENTS_OFF, ("coils", "evaluate", "report")),
    "heading-loss memo": (HEADING_MEMO_OFF, ("optimize", "sizing", "robust")),
    "own brentq (optimize._roots)": (ROOTS_OFF, ("evaluate", "optimize", "report")),
    "symbolic_once (pack convection)": (SYMBOLIC_ONCE_OFF, ("optimize", "sizing", "report")),
    "scalar_fast (pack conduction)": (SCALAR_FAST_OFF, ("evaluate", "sizing", "report")),
    "lru_cache clearance._closest": (
        _uncached("coils.clearance", "_closest"),
        ("sizing", "square-sizing", "report"),
    ),
    "lru_cache viewfactors.halton_points": (
        _uncached("coils.viewfactors", "halton_points"),
        ("evaluate", "sizing", "report"),
    ),
    "lru_cache viewfactors._traced": (
        _uncached("coils.viewfactors", "_traced"),
        ("evaluate", "sizing", "report"),
    ),
    "lru_cache thermal_states._traced": (
        _uncached("optimize.thermal_states", "_traced"),
        ("optimize", "sizing", "report"),
    ),
    "lru_cache thermal_states._numeric": (
        _uncached("optimize.thermal_states", "_numeric"),
        ("optimize",),  # off: 6 s instead of 0.6 s for evaluate; longer commands far more
    ),
    "lru_cache compiled.compile_problem": (
        _uncached(
            "optimize.compiled",
            "compile_problem",
            ("optimize.solve", "optimize.discrete"),
        ),
        ("optimize", "sizing", "sweep40"),
    ),
    "lru_cache hardware._gap": (_uncached("optimize.hardware", "_gap"), ("sizing",)),
    "lru_cache hardware._shape_gap": (
        _uncached("optimize.hardware", "_shape_gap"),
        ("square-sizing",),
    ),
}


def run(args: list[str], setup: str) -> tuple[float, float]:
    """(wall s, CPU s) of one fresh ``spiralcap ARGS`` process with ``setup`` run first."""
    code = (
        f"{setup}\nimport sys\nfrom spiralcap.cli import console\n"
        f"sys.argv = ['spiralcap', *{args!r}]\nconsole()"
    )
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, stdout=subprocess.DEVNULL, check=False
    )
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 3):
        raise SystemExit(f"{args} with {setup!r} exited {done.returncode}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> None:
    argv = sys.argv[1:]
    repeat = 5
    if "--repeat" in argv:
        i = argv.index("--repeat")
        repeat = int(argv[i + 1])
        del argv[i : i + 2]
    for name, (off_setup, commands) in PIECES.items():
        if argv and not any(c in name for c in argv):
            continue
        for command in commands:
            on, off, loads = [], [], []
            for _ in range(repeat):
                on.append(run(COMMANDS[command], ""))
                off.append(run(COMMANDS[command], off_setup))
                loads.append(os.getloadavg()[0])
            c_on = statistics.median(c for _, c in on)
            c_off = statistics.median(c for _, c in off)
            w_on = statistics.median(w for w, _ in on)
            print(
                f"{name} | {command}: CPU on {c_on:.2f} s, off {c_off:.2f} s, "
                f"saving {100 * (1 - c_on / c_off):.0f} % (wall on {w_on:.2f} s; median of "
                f"{repeat} pairs; load {min(loads):.1f}-{max(loads):.1f})",
                flush=True,
            )


if __name__ == "__main__":
    main()
