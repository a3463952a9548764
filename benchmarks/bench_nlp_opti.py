"""Benchmark: the own NLP builder (optimize.nlp) against ``casadi.Opti`` on the built-in optimize.

Run: python benchmarks/bench_nlp_opti.py [--repeat N]
``spiralcap optimize``'s NLP (the built-in design) is built by ``compile_problem`` as the
command builds it, and the solves the command makes are recorded (start, parameters,
bounds). The same problem is then posed through ``casadi.Opti``: one vector variable and one
vector parameter, the builder's objective and rows through a CasADi ``Function`` of them, the
variable bounds as ``opti.bounded`` (``detect_simple_bounds``: IPOPT sees them as bounds, as
with the builder), the same IPOPT options. Each recorded solve is repeated ``N`` times with
both, alternating, and timed in CPU seconds (``time.process_time``); IPOPT's own time
the difference is Opti's per-solve overhead when both take the same iterations. Also
prints the one-off cost of posing the problem with Opti. Asserts nothing.
"""

from __future__ import annotations

import statistics
import sys
import time
from typing import Any

import casadi as ca
import numpy as np


def _recorded() -> tuple[Any, list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]]:
    """The built-in optimize's NLP and its solves: (scaled start, p, lbx, ubx) each."""
    import optimize
    from optimize import nlp as nlp_module
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    calls: list[tuple[Any, ...]] = []
    real = nlp_module.CompiledNLP.solve

    def spy(self: Any, x0: Any, p: np.ndarray, bounds: Any = None, lam_g0: Any = None) -> Any:
        x0s = self.scaled_start(x0, p) if isinstance(x0, dict) else np.asarray(x0, float)
        b = bounds or {}
        lo = np.array([b.get(v.name, (v.lo, v.hi))[0] / v.ref for v in self.variables])
        hi = np.array([b.get(v.name, (v.lo, v.hi))[1] / v.ref for v in self.variables])
        calls.append((self, x0s, np.asarray(p, float), lo, hi))
        return real(self, x0, p, bounds, lam_g0)

    nlp_module.CompiledNLP.solve = spy  # type: ignore[method-assign]
    try:
        optimize.optimize_design(optimize.prepare(build_model(load_design(None, []))))
    finally:
        nlp_module.CompiledNLP.solve = real  # type: ignore[method-assign]
    nlp = calls[0][0]
    return nlp, [c[1:] for c in calls if c[0] is nlp]


def _opti(nlp: Any, lo: np.ndarray, hi: np.ndarray) -> tuple[Any, Any, Any, float]:
    """The builder's problem posed through casadi.Opti; (opti, X, P, CPU s to pose it)."""
    from optimize.compiled import IPOPT_OPTIONS

    t0 = time.process_time()
    prob = nlp._problem
    fg = ca.Function("fg", [prob["x"], prob["p"]], [prob["f"], prob["g"]])
    opti = ca.Opti()
    X = opti.variable(prob["x"].shape[0])
    P = opti.parameter(prob["p"].shape[0])
    f, g = fg(X, P)
    opti.minimize(f)
    opti.subject_to(g <= 0)
    finite_lo, finite_hi = np.where(np.isfinite(lo), lo, -1e20), np.where(np.isfinite(hi), hi, 1e20)
    opti.subject_to(opti.bounded(finite_lo, X, finite_hi))
    plugin = {k: v for k, v in IPOPT_OPTIONS.items() if not k.startswith("ipopt.")}
    solver = {k[6:]: v for k, v in IPOPT_OPTIONS.items() if k.startswith("ipopt.")}
    opti.solver("ipopt", {**plugin, "detect_simple_bounds": True}, solver)
    return opti, X, P, time.process_time() - t0


def main() -> None:
    argv = sys.argv[1:]
    repeat = int(argv[argv.index("--repeat") + 1]) if "--repeat" in argv else 7
    nlp, solves = _recorded()
    x0, p, lo, hi = solves[0]
    opti, X, P, pose_s = _opti(nlp, lo, hi)
    print(
        f"built-in optimize: {len(solves)} solves of its NLP ({X.shape[0]} variables, "
        f"{len(nlp.rows)} rows); posing it with Opti: {pose_s * 1e3:.1f} ms CPU"
    )
    named = np.array([not v.name.startswith("positive_part[") for v in nlp.variables])
    for k, (x0, p, lo, hi) in enumerate(solves):
        own, theirs, its = [], [], set()
        x_own = x_opti = np.zeros(0)
        f_own = f_opti = np.nan
        for _ in range(repeat):
            t0 = time.process_time()
            sol = nlp.solver(x0=x0, p=p, lbx=lo, ubx=hi, lbg=-np.inf, ubg=0.0)
            x_own, _ = np.asarray(sol["x"]).ravel(), np.asarray(sol["lam_g"]).ravel()
            f_own = float(sol["f"])
            own.append(time.process_time() - t0)
            its.add(("builder", nlp.solver.stats()["iter_count"]))

            t0 = time.process_time()
            opti.set_value(P, p)
            opti.set_initial(X, x0)
            s = opti.solve_limited()
            x_opti, _ = np.ravel(s.value(X)), s.value(opti.lam_g)
            f_opti = float(s.value(opti.f))
            theirs.append(time.process_time() - t0)
            its.add(("Opti", s.stats()["iter_count"]))
        mo, mt = statistics.median(own), statistics.median(theirs)
        print(
            f"solve {k}: builder {mo * 1e3:.2f} ms, Opti {mt * 1e3:.2f} ms CPU (median of "
            f"{repeat}): Opti's overhead {(mt - mo) * 1e3:.2f} ms a solve; iterations "
            f"{sorted(its)}; objective {abs(f_own - f_opti):.0e} apart; the variables "
            f"{np.max(np.abs(x_own - x_opti)[named]):.0e} apart (scaled; the epigraph slacks, "
            "free inside their bounds at the optimum, left out)",
            flush=True,
        )


if __name__ == "__main__":
    main()
