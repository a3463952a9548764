"""``spiralcap optimize``: helical angle, frequency, field (and freed hardware) for the objective.

``-o FILE`` writes the optimum as a complete, commented design file that ``spiralcap evaluate``
reproduces.
"""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING, Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    print_json,
)
from spiralcap.core.constants import from_unit

if TYPE_CHECKING:
    from optimize.result import OptimizationResult

#: how to show a sensitivity per SI unit in engineering units: unit -> (label, factor)
_ENGINEERING = {
    "N·m": ("mN·m", from_unit(1.0, "mNm")),
    "A": ("A", 1.0),
    "V": ("V", 1.0),
    "W": ("W", 1.0),
    "K": ("K", 1.0),
    "T": ("mT", from_unit(1.0, "mT")),
    "m/s": ("mm/s", from_unit(1.0, "mm_s")),
    "turns": ("turn", 1.0),
    "rad": ("deg", from_unit(1.0, "deg")),
    "Hz": ("Hz", 1.0),
    "m": ("mm", from_unit(1.0, "mm")),
    "1": ("", 1.0),
}
EXIT_INFEASIBLE = 3


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help="write the optimum as a complete design file (TOML) to FILE",
    )
    parser.add_argument(
        "--free",
        action="append",
        default=[],
        metavar="KEY=MIN:MAX",
        help="let the optimiser choose a hardware key in [MIN, MAX] (repeatable), e.g. "
        "coils.x.turns=100:800; same as an [optimize.free] entry",
    )


def parse_free(expr: str) -> str:
    """``KEY=MIN:MAX`` -> the ``--set`` override ``optimize.free.KEY=[MIN, MAX]``."""
    from spiralcap.core.errors import InputError
    from spiralcap.schema import FREEABLE_KEYS

    key, sep, rng = expr.partition("=")
    key = key.strip()
    parts = rng.split(":")
    if not sep or len(parts) != 2:
        raise InputError("--free", expr, "the form KEY=MIN:MAX, e.g. coils.x.turns=100:800")
    if key not in FREEABLE_KEYS:
        raise InputError("--free", expr, "a key that can be freed: " + ", ".join(FREEABLE_KEYS))
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise InputError(
            "--free", expr, "numbers MIN and MAX, e.g. coils.x.turns=100:800"
        ) from None
    from spiralcap.schema import KEYS

    if KEYS[key].kind is int and not (lo.is_integer() and hi.is_integer()):
        raise InputError("--free", expr, f"whole numbers MIN and MAX: {key} is a count")
    return f"optimize.free.{key}=[{lo!r}, {hi!r}]"


def free_overrides(exprs: list[str]) -> list[str]:
    """Every ``--free KEY=MIN:MAX`` as its override (:func:`parse_free`); a key freed twice is
    refused (InputError: which range would count is not the user's to guess)."""
    from spiralcap.core.errors import InputError

    seen: dict[str, str] = {}
    out = []
    for expr in exprs:
        override = parse_free(expr)
        key = expr.partition("=")[0].strip()
        if key in seen:
            raise InputError(
                "--free",
                expr,
                f"each key freed once: {key} is already freed by --free {seen[key]}",
            )
        seen[key] = expr
        out.append(override)
    return out


def _starts(n: int) -> str:
    return f"{n} start" if n == 1 else f"{n} starts"


def objective_line(res) -> str:
    """``objective  copper mass of the three coil pairs, minimised: 140.06 kg``."""
    from spiralcap.presentation import objective_words

    what, unit, factor, sense = objective_words(res.objective)
    value = res.objective_value * factor
    return f"objective           {what}, {sense}: {value:.5g}{' ' + unit if unit else ''}"


def binding_line(res, b) -> str:
    """One binding limit: its name, key, value against allowed (key units) and its gain."""
    from spiralcap.assemble.system import constraint_key
    from spiralcap.presentation import (
        gain_per_key_unit,
        gain_step,
        in_key_units,
        readable,
        with_unit,
    )

    key = constraint_key(b.name)
    unit, factor = in_key_units(b.unit, key)
    gain, label = gain_per_key_unit(res.objective, b.unit, key, b.gain_per_unit_relaxed)
    obj_unit = label.split(" per ", 1)[0]
    step, per = gain_step(key, unit)
    verb = "raising" if b.relax_sign > 0 else "lowering"
    better = "less" if res.objective in ("power", "copper_mass") else "more"
    at = (
        f"  {readable(b.name)} ({key or b.name}): {with_unit(f'{b.value * factor:.5g}', unit)} of "
        f"{with_unit(f'{b.allowed * factor:.5g}', unit)}"
    )
    if gain == 0 and res.objective == "copper_mass":  # fixed hardware: the copper cannot move
        return f"{at}; the copper is fixed (free hardware keys to size it)"
    return f"{at}; {verb} it by {per} gains {gain * step:.4g} {obj_unit} {better}".rstrip()


def _shared_key_lines(res) -> list[str]:
    """A key several binding rows share (the three pairs' current limit): the gain of relaxing
    the key, which relaxes them all (their multipliers may split in any proportion)."""
    from spiralcap.serialize import binding_keys, optimization_to_dict

    shared = [
        k for k in binding_keys(optimization_to_dict(res)["binding_limits"]) if len(k["rows"]) > 1
    ]
    out = []
    for k in shared:
        obj_unit = k["gain_per_key_unit_label"].split(" per ", 1)[0]
        verb = "raising" if k["relaxing_means"] == "raising" else "lowering"
        better = "less" if res.objective in ("power", "copper_mass") else "more"
        out.append(
            f"  {k['key']} binds {len(k['rows'])} rows; {verb} it by {k['gain_step']} gains "
            f"{k['gain_per_step']:.4g} {obj_unit} {better} in all"
        )
    return out


def format_result(res) -> str:
    """Readable summary of an :class:`optimize.OptimizationResult`."""
    from spiralcap.assemble.system import constraint_key, message_in_key_units
    from spiralcap.commands.evaluate import safety_factor_text, tissue_line
    from spiralcap.presentation import edge_text, model_domain_text, readable, step_out_words
    from spiralcap.serialize import _step_out

    ev = res.evaluation
    lines = [
        f"status              {res.status} ({res.solver_status}, {res.iterations} IPOPT "
        f"iterations, {_starts(res.starts)}, {res.solve_time_s:.3f} s)"
    ]
    if res.status == "optimal":
        lines += [
            objective_line(res),
            f"helical angle       {res.helical_angle_deg:.4g} deg",
            f"frequency           {res.frequency_hz:.4g} Hz",
            f"rotating field      {res.field_amplitude_T * 1e3:.4g} mT",
            "current amplitudes  "
            + ", ".join(f"{a} {i:.4g} A" for a, i in zip("xyz", res.current_amplitudes_A)),
            f"margin              {res.margin_Nm * 1e3:.4g} mN·m "
            f"(safety factor {safety_factor_text(res.safety_factor)})",
            f"forward speed       {res.speed_m_s * 1e3:.4g} mm/s",
            "step-out frequency  "
            + step_out_words(
                *_step_out(res.step_out_frequency_hz),
                ev.max_frequency_hz,
                ev.max_frequency_beyond_search,
                ev.max_frequency_limited_by,
                res.field_is_set,
            ),
            f"copper              {res.evaluation.copper_mass_kg:.4g} kg ("
            + ", ".join(f"{ax} {m:.4g}" for ax, m in zip("xyz", res.evaluation.copper_masses_kg))
            + ")",
            tissue_line(ev),
            model_domain_text(ev.extrapolations)
            + (" (the optimum rests on this extrapolation)" if ev.extrapolations else "")
            + edge_text(ev.calibration_edges),
            "binding limits"
            + (
                " (of the continuous relaxation: the gains are those of the continuous bound):"
                if res.hardware is not None
                else ":"
            ),
        ]
        from spiralcap.presentation import binding

        for b in binding(res.binding_limits):
            lines.append(binding_line(res, b))
        if not binding(res.binding_limits):
            lines.append("  none")
        lines += _shared_key_lines(res)
        if res.hardware is not None:
            lines += _hardware_lines(res)
    else:
        lines.append(message_in_key_units(res.message))
        from spiralcap.explain import advice_lines, explained_at_line

        if res.evaluation is not None:
            lines.append(explained_at_line(res))
        lines += _grip_binds(res)
        for s in res.shortfalls:
            label, factor = _ENGINEERING.get(s.unit, (s.unit, 1.0))
            if s.name == "margin":
                lines.append(
                    f"  the magnet's torque falls short of the required torque by "
                    f"{s.short_by / factor:.4g} {label} at the best design inside the "
                    f"limits{_field_cap_words(res)}"
                )
            elif s.name == "solver":
                lines.append(
                    f"  IPOPT did not converge from any start ({res.solver_status}); at the "
                    f"closest point found the safety factor is {s.best:.4g} (needs "
                    f"{s.needed:.4g}): try more starts (optimize.starts) or a narrower box"
                )
            else:
                u = f" {label}" if label else ""
                key = constraint_key(s.name) or s.name
                if key == "limits.envelope_mm" or ("[" in s.name and key != s.name):
                    key = f"{key} ({readable(s.name)})"  # one key, several rows: name the row
                if key.startswith("limits."):  # a limit the closest design still breaks
                    lines.append(
                        f"  {key}: allows {s.needed / factor:.4g}{u}, the closest design "
                        f"reaches {s.best / factor:.4g}{u} (over by {s.short_by / factor:.4g}{u})"
                    )
                    continue
                lines.append(
                    f"  {key}: needs {s.needed / factor:.4g}{u}, best reachable "
                    f"{s.best / factor:.4g}{u} (short by {s.short_by / factor:.4g}{u})"
                )
        if res.evaluation is not None:
            lines += advice_lines(res)
    return "\n".join(lines)


def _field_cap_words(res: OptimizationResult) -> str:
    """``; there limits.x.power_W (...) caps the field at 1.139 mT``: the limit that sets the
    field at the best design found, as a design key ("" when the evaluation names none)."""
    from spiralcap.assemble.system import constraint_key
    from spiralcap.presentation import readable

    name, field_T = res.evaluation.field_limited_by, float(res.evaluation.field_amplitude_T)
    key = constraint_key(name) if name else ""
    if not key.startswith("limits.") or not math.isfinite(field_T):  # e.g. "fixed": the solver's
        return ""
    return f"; there {key} ({readable(name)}) caps the field at {field_T * 1e3:.4g} mT"


def _grip_binds(res) -> list[str]:
    """A line naming the engagement requirement where it binds at the closest design: the
    spiral must stretch the wall (a small helical angle), which is what keeps the rest out of
    reach (e.g. the speed, which needs a larger angle)."""
    ev = res.evaluation
    if ev is None:
        return []
    tight = [
        c
        for c in ev.checks
        if c.name.startswith("wall_strain[") and abs(c.value / c.allowed - 1.0) <= 1e-3
    ]
    if not tight:
        return []
    need = tight[0].allowed
    return [
        f"  requirements.min_wall_strain binds there: for the spiral to stretch every wall by "
        f"{100 * need:.3g} % (grip) the helical angle can be at most "
        f"{ev.helical_angle_deg:.3g} deg, which holds the rest out of reach"
    ]


def _hardware_lines(res) -> list[str]:
    from spiralcap.assemble.system import hardware_design_values
    from spiralcap.presentation import objective_words

    h = res.hardware
    _, unit, factor, _ = objective_words(res.objective)
    label = unit or "(safety factor)"
    relaxed = hardware_design_values(
        {k: v for k, v in h.relaxed.items() if not k.endswith(".turns")}
    )
    relaxed.update({k: v for k, v in _turns(h.relaxed).items()})
    chosen = hardware_design_values(h.discrete)
    rel = h.rounding_cost / abs(h.relaxed_objective) if h.relaxed_objective else 0.0
    lines = [
        f"hardware            {len(chosen)} keys sized; {h.feasible} of {h.candidates} "
        f"buildable neighbours feasible, {h.outer_iterations} outer iterations"
        + (
            ""
            if h.settled
            else " (the frozen factors had not settled: the relaxed values are "
            "the last round's; the neighbours were checked exactly)"
        ),
        f"  continuous bound  {h.relaxed_objective * factor:.5g} {label}; "
        f"discrete {h.discrete_objective * factor:.5g} {label} "
        f"(whole turns and standard wire"
        + (" and the declined copper" if getattr(h, "copper_declined", None) else "")
        + f" cost {h.rounding_cost * factor:.3g} {label}, {100 * rel:.2g} %)",
    ]
    for key, value in chosen.items():
        lines.append(f"  {key:<34} {_value(value):<10} (relaxed {_value(relaxed[key], 5)})")
    declined = getattr(h, "copper_declined", None)
    if declined:  # optimize.discrete.leaner: copper that bought too little power
        lines.append(
            f"  copper declined   the least power, {declined['objective'] * factor:.5g} "
            f"{label}, took {declined['copper_kg']:.4g} kg of copper; this design takes "
            f"{res.evaluation.copper_mass_kg:.4g} kg for {h.discrete_objective * factor:.5g} "
            f"{label} (a sizing spends at most 10 % more copper for 1 % of its objective)"
        )
    return lines


def _value(value: Any, digits: int | None = None) -> str:
    """A sized key's value: a number, or a list of numbers (a rectangle's sides) as [a, b]."""
    if isinstance(value, list):
        return "[" + ", ".join(_value(v, digits) for v in value) + "]"
    return str(value) if digits is None else f"{value:.{digits}g}"


def _turns(values: dict[str, float]) -> dict[str, float]:
    return {f"coils.{k.split('.')[0]}.turns": v for k, v in values.items() if k.endswith(".turns")}


#: What a scenario objective maximises, in the robust lines (the key's name says p05).
_ROBUST_OBJECTIVE_WORDS = {
    "margin_p05": " (maximises CVaR05, the mean of the worst 5 % of the scenario margins, a lower "
    "bound on their p05; a failed scenario's margin is negative)"
}


def format_robust(rc) -> str:
    """Text lines for the scenarios of a robust optimum (:class:`spiralcap.robust.RobustCheck`)."""
    from spiralcap.robust import format_scenario_solve, robust_to_dict

    ins, oos, d_oos = rc.in_sample, rc.out_of_sample, rc.deterministic_out_of_sample
    rel = robust_to_dict(rc)["out_of_sample"].get("p05_relative_to_claim")
    p = rc.max_failure_probability
    cons = f", P(failure) <= {p:g} (CVaR)" if p is not None else ""
    lo, hi = oos.failure.ci95
    return "\n".join(
        [
            f"tissue scenarios    {ins.scenarios} (Sobol', seed {ins.seed}); objective "
            f"{rc.objective}{_ROBUST_OBJECTIVE_WORDS.get(rc.objective, '')}{cons}; a scenario "
            "fails when it steps out or stretches a wall by less than "
            "requirements.min_wall_strain",
            f"in-sample           P(failure) {100 * ins.failure_probability:.3g} % (step-out "
            f"{100 * ins.stepout_probability:.3g} %, below min strain "
            f"{100 * ins.below_min_strain_probability:.3g} %), margin p05 "
            f"{ins.margin_p05_Nm * 1e3:.4g} mN·m, CVaR05 {ins.cvar_Nm * 1e3:.4g} mN·m",
            f"out-of-sample       P(failure) {100 * oos.failure.value:.3g} % (95 % interval "
            f"{100 * lo:.3g}-{100 * hi:.3g} %; step-out {100 * oos.stepout_probability:.3g} %, "
            f"below min strain {100 * oos.below_min_strain.value:.3g} %, no contact "
            f"{100 * oos.no_grip.value:.3g} %), margin p05 "
            f"{oos.margin_percentiles_Nm['p05'] * 1e3:.4g} mN·m"
            + (f" ({100 * rel:+.2g} % vs claim)" if rel is not None else "")
            + f" ({oos.samples} fresh samples, seed {rc.fresh_seed})",
            f"deterministic opt.  {rc.deterministic.helical_angle_deg:.4g} deg, "
            f"{rc.deterministic.frequency_hz:.4g} Hz: out-of-sample P(failure) "
            f"{100 * d_oos.failure.value:.3g} % (step-out {100 * d_oos.stepout_probability:.3g} "
            f"%, below min strain {100 * d_oos.below_min_strain.value:.3g} %), margin p05 "
            f"{d_oos.margin_percentiles_Nm['p05'] * 1e3:.4g} mN·m",
            format_scenario_solve(rc.result.scenario_solve, p),
        ]
    )


def run(args: argparse.Namespace) -> int:
    from optimize import optimize_design
    from spiralcap.robust import optimization_model, robust_optimum, robust_to_dict, wants_robust
    from spiralcap.serialize import optimization_to_dict

    check_outputs({"-o": args.output}, design_paths(args))
    args.overrides = [*args.overrides, *free_overrides(args.free)]
    from spiralcap.progress import working
    from spiralcap.stopping import checked

    design = design_from_args(args)
    rc = None
    if wants_robust(design):  # margin_p05 / max_failure_probability: over tissue scenarios
        with working("optimize (robust)") as say:
            if say is not None:
                say("the optimum over the tissue scenarios, then checked on fresh tissues")
            rc = robust_optimum(design)
        res = rc.result
    else:
        with working("optimize") as say:
            res = optimize_design(optimization_model(design), progress=checked(say))
    from spiralcap import tolerances

    intervals = tolerances.optimum_rows(design, res)  # before the write: all work done first
    written = None
    if args.output and res.status == "optimal":
        from spiralcap.assemble.system import optimum_design_toml
        from spiralcap.design import write_text_atomic

        written = write_text_atomic(args.output, optimum_design_toml(design, res))
    if args.json:
        payload = {"design": design.source, **optimization_to_dict(res)}
        if intervals:
            payload["tolerance_intervals"] = tolerances.to_dict(intervals)
        if rc is not None:
            payload["robust"] = robust_to_dict(rc)
        if written is not None:
            payload["written"] = str(written)
        print_json(payload)
    else:
        print("\n".join([format_result(res), *tolerances.text_lines(intervals)]))
        if rc is not None:
            print(format_robust(rc))
        if written is not None:
            print(f"wrote the optimised design to {written}")
        elif args.output:
            print(f"nothing written to {args.output}: no feasible design")
    return 0 if res.status == "optimal" else EXIT_INFEASIBLE
