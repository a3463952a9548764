"""Benchmark: the issue 27 speed targets, as ratios to one ``spiralcap optimize`` of the same run.

Run: python benchmarks/bench_ratios.py [--repeat N] [TREE ...]
Each command is a fresh ``spiralcap`` process (imports included, BLAS single-threaded, as the
installed command runs). The commands take turns, round after round, so a busy machine slows
them alike; with several TREEs (checkouts, e.g. one from ``git archive af2be38``) the trees take
turns too, and each tree's ratios are against its own ``optimize``. Targets: six-key sizing
<= 2.5x, robust optimum <= 3x, report <= 3x, a 40-point re-optimising sweep <= 3x. Asserts
nothing; prints the medians and ratios.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SIX = [
    f"--free=coils.{ax}.{key}"
    for ax in "xyz"
    for key in ("turns=100:800", "wire_diameter_mm=0.8:3.0")
]
OUT = str(Path(tempfile.gettempdir()) / "spiralcap-bench-ratios.html")
COMMANDS = {
    "one optimize (reference)": ["optimize", "--json"],
    "six-key sizing": ["optimize", "--json", *SIX],
    "robust optimum (margin_p05, scale sigma 0.3)": [
        "optimize",
        "--json",
        "--set",
        "tissue.uncertainty.scale_sigma_log=0.3",
        "--set",
        "optimize.objective=margin_p05",
    ],
    "report (HTML)": ["report", "-o", OUT],
    "40-point re-optimising sweep": [
        "sweep",
        "--optimize",
        "--json",
        "--over",
        "limits.power_W=300:3000:40",
    ],
}
TARGETS = {
    "six-key sizing": 2.5,
    "robust optimum (margin_p05, scale sigma 0.3)": 3.0,
    "report (HTML)": 3.0,
    "40-point re-optimising sweep": 3.0,
}


def _wall_s(tree: Path, args: list[str]) -> float:
    code = "import sys\nfrom spiralcap.cli import console\nsys.argv[0] = 'spiralcap'\nconsole()"
    env = {**os.environ, "PYTHONPATH": str(tree)}
    t0 = time.perf_counter()
    subprocess.run(
        [sys.executable, "-c", code, *args], env=env, cwd=tree, stdout=subprocess.DEVNULL
    )
    return time.perf_counter() - t0


def main() -> None:
    argv = sys.argv[1:]
    repeat = 5
    if "--repeat" in argv:
        i = argv.index("--repeat")
        repeat = int(argv[i + 1])
        del argv[i : i + 2]
    trees = [Path(a).resolve() for a in argv] or [ROOT]
    times: dict[tuple[Path, str], list[float]] = {}
    for _ in range(repeat):
        for name, args in COMMANDS.items():
            for tree in trees:
                times.setdefault((tree, name), []).append(_wall_s(tree, args))
    for tree in trees:
        ref = statistics.median(times[tree, "one optimize (reference)"])
        print(
            f"{tree}: one optimize {ref:.2f} s (median of {repeat}; load {os.getloadavg()[0]:.1f})"
        )
        for name, target in TARGETS.items():
            t = statistics.median(times[tree, name])
            print(f"  {name}: {t:.2f} s = {t / ref:.2f}x (target <= {target:g}x)")


if __name__ == "__main__":
    main()
