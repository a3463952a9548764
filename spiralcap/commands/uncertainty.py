"""``spiralcap uncertainty``: step-out probability and margin distribution over uncertain tissue.

The design's ``[tissue.uncertainty]`` table says what is uncertain; the command samples it
(:mod:`optimize.uncertainty`), evaluates the worst-case margin of every sample at the operating
point, and reports the step-out probability, percentiles and Sobol indices (SALib). The samples
run in chunks here, in ``--workers`` processes or on a Dask cluster (``--dask``): same seed, same
numbers bit for bit.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    print_json,
    whole_number,
)
from spiralcap.uncertainty import (
    DEFAULT_SAMPLES,
    DEFAULT_SOBOL_BASE,
    Study,
    study,
    study_to_dict,
)


def add_execution_arguments(parser: argparse.ArgumentParser) -> None:
    """``--workers N | --dask ADDRESS`` (shared with ``sweep``)."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--workers",
        type=whole_number,
        default=1,
        metavar="N",
        help="local worker processes (default 1)",
    )
    group.add_argument(
        "--dask",
        metavar="ADDRESS",
        help="run the chunks on a running Dask scheduler, e.g. tcp://HOST:8786 "
        '(optional extra: pip install ".[dask]")',
    )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)
    parser.add_argument(
        "--samples",
        type=whole_number,
        default=DEFAULT_SAMPLES,
        metavar="N",
        help=f"tissue samples (default {DEFAULT_SAMPLES})",
    )
    parser.add_argument("--seed", type=whole_number, default=0, metavar="S", help="sampling seed")
    parser.add_argument(
        "--method",
        choices=("sobol", "halton", "random"),
        default="sobol",
        help="scrambled quasi-random sequence or pseudo-random draws (default sobol)",
    )
    parser.add_argument(
        "--sobol-samples",
        type=whole_number,
        default=DEFAULT_SOBOL_BASE,
        metavar="N",
        help=f"base samples of the Sobol-index estimate, a power of 2; 0 skips it "
        f"(default {DEFAULT_SOBOL_BASE})",
    )
    parser.add_argument("--plot", metavar="FILE.png", help="margin distribution and Sobol bars")
    add_execution_arguments(parser)


def format_study(st: Study, design_source: str = "") -> str:
    """Readable summary of a :class:`Study`."""
    from spiralcap.commands._common import format_table

    r = st.result
    mp, sp = r.margin_percentiles_Nm, r.speed_percentiles_m_s

    def share(p: Any) -> str:
        lo, hi = p.ci95
        return f"{100 * p.value:.4g} % (95 % interval {100 * lo:.3g}-{100 * hi:.3g} %)"

    closed = r.closed_form
    below_exact = (
        f"; exact {100 * closed['below_min_strain']:.4g} %" if "below_min_strain" in closed else ""
    )
    lines = [
        f"design {design_source}: {r.samples} tissue samples ({r.method}, seed {r.seed}) on "
        f"{st.where}, {st.elapsed_s:.3g} s",
        "uncertain inputs    " + ", ".join(dict.fromkeys(g for _, g in st.uncertainty.factors())),
        f"P(failure)          {share(r.failure)}: steps out, or stretches a wall by less than "
        f"{100 * r.min_wall_strain:.3g} % (requirements.min_wall_strain)",
        f"  step-out          {share(r.stepout)}",
        f"  below min strain  {share(r.below_min_strain)}{below_exact}",
        f"  no contact        {share(r.no_grip)}; exact {100 * closed['no_grip']:.4g} % "
        "(a sampled lumen as wide as the spiral: no grip, no screw)",
        f"nominal margin      {_nominal_words(r.nominal_margin_Nm)} "
        f"(magnetic torque {r.available_torque_Nm * 1e3:.4g} mN·m)",
        "margin, mN·m        " + "  ".join(f"{k} {v * 1e3:.4g}" for k, v in mp.items()),
        "                    (a sample below the minimum strain counts as min(margin, 0))",
        "speed, mm/s         "
        + "  ".join(f"{k} {v * 1e3:.4g}" for k, v in sp.items())
        + "  (0 in every failed sample)",
    ]
    if r.sobol is not None:
        s = r.sobol
        lines += [
            "",
            f"Sobol indices of the counted margin (SALib, {s.base_samples} base samples; ± 95 %):",
            format_table(
                ["input", "first_order", "±", "total", "± "],
                [
                    [n, s.first_order[i], s.first_order_conf[i], s.total[i], s.total_conf[i]]
                    for i, n in enumerate(s.inputs)
                ],
            ),
        ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from optimize.uncertainty import check_samples, check_seed
    from spiralcap.commands.torque import check_plot_path
    from spiralcap.parallel import check_workers
    from spiralcap.uncertainty import check_sobol_base

    check_samples(args.samples)
    check_seed(args.seed)
    check_workers(args.workers)
    check_sobol_base(args.sobol_samples)
    if args.plot:
        check_plot_path(args.plot)
    check_outputs({"--plot": args.plot}, design_paths(args))
    design = design_from_args(args)
    from spiralcap.progress import progress_bar
    from spiralcap.stopping import checked

    with progress_bar(
        "sampling tissues", unit="chunk", enabled=False if args.json else None
    ) as bar:
        st = study(
            design,
            samples=args.samples,
            seed=args.seed,
            method=args.method,
            sobol_base=args.sobol_samples,
            workers=args.workers,
            dask=args.dask,
            progress=checked(bar),
        )
    if args.plot:
        from spiralcap.figures.uncertainty import save_uncertainty_figure

        save_uncertainty_figure(args.plot, st.result)
    if args.json:
        print_json(study_to_dict(st, design.source))
    else:
        print(format_study(st, design.source))
        if args.plot:
            print(f"wrote {args.plot}")
    return 0


def _nominal_words(margin_Nm: float) -> str:
    """The nominal margin in mN·m, or that there is none (no contact at the nominal tissue)."""
    if math.isnan(margin_Nm):
        return "none (no contact at the nominal lumen)"
    return f"{margin_Nm * 1e3:.4g} mN·m"
