"""Start-up time of ``spiralcap evaluate --json`` and ``spiralcap coils --json`` in subprocesses.

Each is timed against the bare ``python -c "import numpy, scipy.special, casadi"`` (the
libraries every command needs), run in turn in the same loop so that a load change on the
machine hits them alike; the medians over ``--repeat`` rounds and their ratios are printed
(target <= 2.5x). Asserts nothing; run ``python benchmarks/bench_startup.py``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

BARE = [sys.executable, "-c", "import numpy, scipy.special, casadi"]
COMMANDS = {
    "evaluate --json": [sys.executable, "-m", "spiralcap.cli", "evaluate", "--json"],
    "coils --json": [sys.executable, "-m", "spiralcap.cli", "coils", "--json"],
}
TARGET = 2.5


def _wall_s(argv: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, env=env, cwd=ROOT)
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="rounds (median reported)")
    args = parser.parse_args()
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    runs: dict[str, list[float]] = {"bare imports": [], **{k: [] for k in COMMANDS}}
    for argv in [BARE, *COMMANDS.values()]:  # warm the file cache and __pycache__
        _wall_s(argv, env)
    for _ in range(args.repeat):
        runs["bare imports"].append(_wall_s(BARE, env))
        for name, argv in COMMANDS.items():
            runs[name].append(_wall_s(argv, env))
    base = statistics.median(runs["bare imports"])
    print(f"bare 'import numpy, scipy.special, casadi': {base:.3f} s (median of {args.repeat})")
    for name in COMMANDS:
        t = statistics.median(runs[name])
        print(f"spiralcap {name}: {t:.3f} s, ratio {t / base:.2f}x (target <= {TARGET}x)")


if __name__ == "__main__":
    main()
