"""Benchmark: the robust optimum at about the cost of a deterministic one (issue 21).

Run: python benchmarks/bench_robust.py [--quick]
Prints, all in this run (fresh ``spiralcap`` processes, end to end, median of 3; ratios against
one deterministic ``spiralcap optimize`` of the built-in design timed the same way):
- the three cases of issue 21 (target <= 3x): ``margin_p05`` with scale σ 0.3; the same with
  lumen σ 0.3 mm, friction σ 0.2 and ``min_spiral_turns = 0``; ``max_failure_probability =
  0.01`` with scale σ 0.3 — with how the scenarios were solved (working set, rounds, or the
  constraint found unable to bind), the angle and frequency against the whole formulation
  (every scenario in one NLP, solved here in-process; target 1e-4 relative) and the
  out-of-sample p05 against the in-sample claim (target 1 %);
- robust sizing, all six turns and wires free, ``margin_p05`` (target < 10 s);
- ``examples/size_copper_vs_safety.py`` (target < 10 s);
- ``sweep --optimize`` over 8 axial loads with ``margin_p05`` (1024 scenarios) against the same
  sweep with the deterministic ``margin``.
``--quick`` skips the whole-formulation solves (about a minute). Asserts nothing.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCALE = ["tissue.uncertainty.scale_sigma_log=0.3"]
CASES = {
    "margin_p05, scale σ 0.3": [*SCALE, "optimize.objective=margin_p05"],
    "margin_p05, scale 0.3, lumen 0.3 mm, friction 0.2, min turns 0": [
        *SCALE,
        "tissue.uncertainty.lumen_diameter_sigma_mm=0.3",
        "tissue.uncertainty.friction_sigma_log=0.2",
        "requirements.min_spiral_turns=0",
        "optimize.objective=margin_p05",
    ],
    "max_failure_probability 0.01, scale σ 0.3": [
        *SCALE,
        "requirements.max_failure_probability=0.01",
    ],
}
FREE = [
    f"coils.{ax}.{key}={bounds}"
    for ax in "xyz"
    for key, bounds in (("turns", "50:800"), ("wire_diameter_mm", "0.8:3.0"))
]


def _sets(sets: list[str]) -> list[str]:
    return [a for s in sets for a in ("--set", s)]


def timed(argv: list[str], repeat: int = 3) -> tuple[float, str]:
    """Median wall time of ``argv`` in fresh processes (s), and the last output."""
    times, out = [], ""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    for _ in range(repeat):
        t0 = time.perf_counter()
        done = subprocess.run(argv, env=env, cwd=ROOT, capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        out = done.stdout
    return statistics.median(times), out


def spiralcap(*args: str, repeat: int = 3) -> tuple[float, str]:
    """``spiralcap ARGS`` (the command's entry point: BLAS single-threaded, as installed)."""
    exe = Path(sys.executable).with_name("spiralcap")
    if exe.exists():
        return timed([str(exe), *args], repeat)
    code = "import sys; from spiralcap.cli import console; sys.exit(console())"
    return timed([sys.executable, "-c", code, *args], repeat)


def whole_formulation(sets: list[str]):
    """Every scenario in one NLP (the formulation before issue 21), in this process."""
    from optimize import optimize_design
    from spiralcap.design import load_design
    from spiralcap.robust import robust_model

    model = robust_model(load_design(None, sets))
    n = model.scenarios.count
    t0 = time.perf_counter()
    res = optimize_design(replace(model, scenarios=model.scenarios.working(np.arange(n))))
    return res, time.perf_counter() - t0


def main() -> None:
    quick = "--quick" in sys.argv
    t_det, _ = spiralcap("optimize")
    print(f"deterministic `spiralcap optimize` (built-in design): {t_det:.2f} s")
    for name, sets in CASES.items():
        t, out = spiralcap("optimize", *_sets(sets), "--json")
        r = json.loads(out)
        rob, solve = r["robust"], r["robust"]["solve"]
        how = (
            "constraint cannot bind (checked over all scenarios), returned at once"
            if solve["failure_constraint_cannot_bind"]
            else f"working set {solve['working_set']} of {solve['scenarios']}, "
            f"{solve['rounds']} round(s)"
        )
        rel = rob["out_of_sample"]["p05_relative_to_claim"]
        print(
            f"{name}: {t:.2f} s = {t / t_det:.2f}x deterministic (target <= 3x); {how}; "
            f"out-of-sample p05 {100 * rel:+.2f} % vs the in-sample claim (target 1 %)"
        )
        if not quick:
            whole, t_whole = whole_formulation(sets)
            da = r["helical_angle_deg"] / whole.helical_angle_deg - 1
            df = r["frequency_hz"] / whole.frequency_hz - 1
            print(
                f"  vs every scenario in one NLP ({t_whole:.1f} s in-process): angle "
                f"{da:+.1e}, frequency {df:+.1e} relative (target 1e-4)"
            )
    t_size, out = spiralcap(
        "optimize", *_sets([*SCALE, "optimize.objective=margin_p05"]),
        *[a for f in FREE for a in ("--free", f)], "--json", repeat=1,
    )  # fmt: skip
    r = json.loads(out)
    print(
        f"robust sizing, six turns and wires free, margin_p05: {t_size:.2f} s (target < 10 s; "
        f"{t_size / t_det:.1f}x deterministic optimize), {r['status']}, "
        f"p05 claim {r['robust']['in_sample']['margin_p05_Nm'] * 1e3:.4g} mN·m"
    )
    t_ex, _ = timed(
        [sys.executable, "examples/size_copper_vs_safety.py", os.devnull + ".png"], repeat=1
    )
    print(f"examples/size_copper_vs_safety.py: {t_ex:.2f} s (target < 10 s)")
    over = ["--over", "requirements.axial_load_mN=20:90:8", "--optimize", "--json"]
    robust_sets = _sets([*SCALE, "optimize.objective=margin_p05"])
    t_sweep, _ = spiralcap("sweep", *robust_sets, *over, repeat=1)
    t_dsweep, _ = spiralcap("sweep", *over, repeat=1)
    print(
        f"sweep --optimize, 8 loads: margin_p05 (1024 scenarios) {t_sweep:.2f} s, "
        f"deterministic {t_dsweep:.2f} s ({t_sweep / t_dsweep:.1f}x)"
    )


if __name__ == "__main__":
    main()
