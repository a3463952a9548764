"""Benchmark: each speed piece switched off alone, against the same command with it on.

Run: python benchmarks/bench_pieces.py [--repeat N] [--base] [PIECE ...]
Every run is a fresh ``spiralcap`` process (imports included, BLAS single-threaded, as the
installed command runs); "on" and "off" alternate so a busy machine slows both alike. Prints,
per piece, the median wall times and the saving ``1 - on / off`` (the rule of
docs/architecture.md: a piece stays only if it saves at least 20 % of a command that takes
more than a second). ``--base`` measures the pieces retired in issue 27 on a checkout of the
tree before it (``PYTHONPATH`` pointing there, e.g. ``git archive af2be38``). Asserts nothing.
"""

from __future__ import annotations

import os
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
COPPER = ["--set", "optimize.objective=copper_mass", "--set", "requirements.min_safety_factor=2.5"]
#: A two-limit re-optimising sweep of 200 points (about 9 s)
SWEEP_200 = [
    "sweep",
    "--optimize",
    "--over",
    "limits.power_W=300:3000:10",
    "--over",
    "limits.current_A=5:30:20",
]
OUT = str(Path(tempfile.gettempdir()) / "spiralcap-bench-pieces.html")

POOLED = (
    "import optimize, spiralcap.parallel as p\n"
    "real = optimize.optimize_design\n"
    "def pooled(model, **kw):\n"
    "    with p.process_pool(2) as pool:\n"
    "        return real(model, executor=pool, **kw)\n"
    "optimize.optimize_design = pooled"
)

#: The thermal states by the Python model, operation by operation (optimize.thermal_states off).
THERMAL_OFF = (
    "import optimize.thermal_states as t\n"
    "from coils.thermal_system import pair_temperatures as pt\n"
    "t.states = lambda f, a, per, r, packs, vf, s=None, only=None: pt(\n"
    "    packs, r, [f * per[k] for k in range(3)], a, vf, s, only)"
)

#: name -> (command on, code run before it; command off, code run before it)
PIECES: dict[str, tuple[list[str], str, list[str], str]] = {
    "sizing's neighbours on two forked workers (retired)": (
        ["optimize", "--json", *SIX],
        POOLED,
        ["optimize", "--json", *SIX],
        "",
    ),
    "screen (least copper, safety factor 2.5)": (
        ["optimize", "--json", *SIX, *COPPER],
        "",
        ["optimize", "--json", *SIX, *COPPER],
        "import optimize.discrete as d\n"
        "d.size_design.__kwdefaults__['options'] = d.SizingOptions(screen=False)",
    ),
    "report analyses and figures in forked processes": (
        ["report", "-o", OUT],
        "",
        ["report", "-o", OUT, "--workers", "1"],
        "",
    ),
    "thermal states through one compiled CasADi Function (optimize)": (
        ["optimize", "--json"],
        "",
        ["optimize", "--json"],
        THERMAL_OFF,
    ),
    "thermal states through one compiled CasADi Function (report)": (
        ["report", "-o", OUT],
        "",
        ["report", "-o", OUT],
        THERMAL_OFF,
    ),
    "thermal states through one compiled CasADi Function (six-key sizing)": (
        ["optimize", "--json", *SIX],
        "",
        ["optimize", "--json", *SIX],
        THERMAL_OFF,
    ),
    "thermal states through one compiled CasADi Function (40-point re-optimising sweep)": (
        ["sweep", "--optimize", "--over", "limits.power_W=300:3000:40"],
        "",
        ["sweep", "--optimize", "--over", "limits.power_W=300:3000:40"],
        THERMAL_OFF,
    ),
    "thermal states through one compiled CasADi Function (10 x 20 re-optimising sweep)": (
        SWEEP_200,
        "",
        SWEEP_200,
        THERMAL_OFF,
    ),
    "thermal states through one compiled CasADi Function (robust optimum)": (
        ["optimize", "--json", *ROBUST],
        "",
        ["optimize", "--json", *ROBUST],
        THERMAL_OFF,
    ),
    "pair states kept in Constants.memo (optimize)": (
        ["optimize", "--json"],
        "",
        ["optimize", "--json"],
        "import optimize.system as s; s.PhysicsMemo.states = property(lambda m: {}, lambda m, v: None)",
    ),
}

#: The pieces retired in issue 27, measured on the tree before it (``--base``).
BASE_PIECES: dict[str, tuple[list[str], str, list[str], str]] = {
    "standby helper (sizing)": (
        ["optimize", "--json", *SIX],
        "",
        ["optimize", "--json", *SIX],
        "import spiralcap.assemble, optimize.discrete as d\n"
        "from spiralcap.parallel import map_free_cores\n"
        "d.set_neighbour_map(map_free_cores, None)",
    ),
    "screen (least copper, safety factor 2.5)": (
        ["optimize", "--json", *SIX, *COPPER],
        "",
        ["optimize", "--json", *SIX, *COPPER],
        "import optimize.discrete as d; d.SCREEN = False",
    ),
    "robust run's forked deterministic optimum": (
        ["optimize", "--json", *ROBUST],
        "",
        ["optimize", "--json", *ROBUST],
        "import spiralcap.robust as r; r._fork = lambda fn: None",
    ),
    "field thread pool (coils)": (
        ["coils", "--json"],
        "",
        ["coils", "--json"],
        "import coils.filaments as f; f.THREADS = 1",
    ),
    "GC pause and gc.freeze (report)": (
        ["report", "-o", OUT],
        "",
        ["report", "-o", OUT],
        "import contextlib, gc, spiralcap.runtime as r\n"
        "r.cyclic_gc_paused = contextlib.nullcontext; gc.freeze = lambda: None",
    ),
}


def _wall_s(args: list[str], setup: str) -> float:
    code = f"{setup}\nimport sys\nfrom spiralcap.cli import console\nsys.argv = ['spiralcap', *{args!r}]\nconsole()"
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], env=env, stdout=subprocess.DEVNULL, check=False)
    return time.perf_counter() - t0


def main() -> None:
    argv = sys.argv[1:]
    repeat = 5
    if "--repeat" in argv:
        i = argv.index("--repeat")
        repeat = int(argv[i + 1])
        del argv[i : i + 2]
    pieces = BASE_PIECES if "--base" in argv else PIECES
    chosen = [a for a in argv if not a.startswith("--")]
    for name, (on, on_setup, off, off_setup) in pieces.items():
        if chosen and not any(c in name for c in chosen):
            continue
        t_on, t_off = [], []
        for _ in range(repeat):
            t_on.append(_wall_s(on, on_setup))
            t_off.append(_wall_s(off, off_setup))
        m_on, m_off = statistics.median(t_on), statistics.median(t_off)
        print(
            f"{name}: on {m_on:.2f} s, off {m_off:.2f} s, saving {100 * (1 - m_on / m_off):.0f} % "
            f"(median of {repeat}; load average {os.getloadavg()[0]:.1f})",
            flush=True,
        )


if __name__ == "__main__":
    main()
