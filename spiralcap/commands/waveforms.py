"""``spiralcap waveforms [DESIGN] --heading X,Y,Z ... --dwell-s T``: amplifier waveforms.

Samples the three coil currents, drive voltages (R i + L di/dt) and the centre field for a
sequence of capsule headings, each held ``--dwell-s`` at the operating field and frequency with
a smooth change of rotation plane over ``--ramp-s`` (coils.waveforms), checks every sample
against the current and voltage limits, and writes CSV / a plot. Exits 3 after writing the files
when a sample exceeds a limit, naming the time and axis.
"""

from __future__ import annotations

import argparse
import io
import math
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    allow_negative_numbers,
    check_outputs,
    design_from_args,
    design_paths,
    print_json,
)
from spiralcap.core.errors import InputError

EXIT_LIMIT = 3
CSV_COLUMNS = (
    "t_s",
    "heading_index",
    "current_x_A",
    "current_y_A",
    "current_z_A",
    "voltage_x_V",
    "voltage_y_V",
    "voltage_z_V",
    "field_x_T",
    "field_y_T",
    "field_z_T",
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN, --set, --json, --heading (repeatable), --dwell-s, --ramp-s, --csv, --plot."""
    add_design_arguments(parser)
    allow_negative_numbers(parser)
    parser.add_argument(
        "--heading",
        action="append",
        default=[],
        metavar="X,Y,Z",
        help="capsule heading (rotation axis), repeat for a sequence, e.g. --heading 1,0,0 "
        "--heading -1,0,0 (a reversed axis)",
    )
    parser.add_argument(
        "--dwell-s", metavar="T", help="time each heading is held, s (required)", default=None
    )
    parser.add_argument(
        "--ramp-s",
        metavar="R",
        default=None,
        help="duration of each change of rotation plane, 0 < R <= T (default: one rotation "
        "period, at most T)",
    )
    parser.add_argument("--csv", metavar="F", help="write every sample to this CSV file")
    parser.add_argument("--plot", metavar="F.png", help="draw currents, voltages and field")


def parse_heading(text: str) -> tuple[float, float, float]:
    """``"X,Y,Z"`` -> three finite numbers, not all zero (InputError naming --heading)."""
    allowed = "three comma-separated finite numbers X,Y,Z, not all zero"
    parts = str(text).split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        raise InputError("--heading", text, allowed) from None
    if len(values) != 3 or not all(math.isfinite(v) for v in values) or not any(values):
        raise InputError("--heading", text, allowed)
    # a direction: scaled so its largest component is 1 (as workspace.headings), so its length
    # never overflows or underflows (1e200,1e200,0 is the direction 1,1,0)
    top = max(abs(v) for v in values)
    return values[0] / top, values[1] / top, values[2] / top


#: Shortest dwell and plane change, s: the sequence is sampled 200 times per ramp, and a plane
#: change faster than a microsecond needs volts no coil amplifier gives (L/R is milliseconds).
MIN_TIME_S = 1e-6


def _positive(option: str, text: Any, allowed: str) -> float:
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise InputError(option, text, allowed) from None
    if not (math.isfinite(value) and value >= MIN_TIME_S):
        raise InputError(option, text, allowed)
    return value


def parse_timing(dwell: Any, ramp: Any, frequency_hz: float) -> tuple[float, float]:
    """Validated (dwell_s, ramp_s)."""
    if dwell is None:
        raise InputError("--dwell-s", None, "a time in seconds > 0 (required)")
    least = f"at least {MIN_TIME_S:g} s (sampled 200 times per plane change)"
    dwell_s = _positive("--dwell-s", dwell, f"a time in seconds, {least}")
    if ramp is None:
        return dwell_s, min(dwell_s, 1.0 / frequency_hz)
    allowed = f"a time in seconds, {least} and <= --dwell-s = {dwell_s:g}"
    ramp_s = _positive("--ramp-s", ramp, allowed)
    if ramp_s > dwell_s:
        raise InputError("--ramp-s", ramp, allowed)
    return dwell_s, ramp_s


def _csv(w: Any) -> str:
    import numpy as np

    data = np.column_stack([w.time_s, w.heading_index, w.current_A, w.voltage_V, w.field_T])
    buf = io.StringIO()
    buf.write(",".join(CSV_COLUMNS) + "\n")
    fmt = ["%.9g", "%d"] + ["%.9g"] * 9
    np.savetxt(buf, data, delimiter=",", fmt=fmt)
    return buf.getvalue()


def _plot(path: str, w: Any, model: Any) -> bytes:
    """The waveform figure as the bytes of ``path``'s format."""
    import matplotlib
    from matplotlib.figure import Figure

    from spiralcap.figures.style import REPORT_RC
    from spiralcap.figures.thermal import change_windows, draw_waveform_sequence

    rc: Any = REPORT_RC
    with matplotlib.rc_context(rc):
        columns = len(change_windows(w))
        fig = Figure(figsize=(max(8.0, 3.0 * columns + 1.0), 9.0), layout="constrained")
        draw_waveform_sequence(
            fig,
            w,
            # each pair's own amplifier channel where limits.{x,y,z}.* is set
            current_limit_A=[float(model.limits.channel("current", k)[1]) for k in range(3)],
            voltage_limit_V=[float(model.limits.channel("voltage", k)[1]) for k in range(3)],
        )
        fig.suptitle(
            f"{w.amplitude_T * 1e3:.4g} mT at {w.frequency_hz:g} Hz, plane change over "
            f"{w.ramp_s:g} s"
        )
        buf = io.BytesIO()
        suffix = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else "png"
        fig.savefig(buf, format=suffix, dpi=130)
    return buf.getvalue()


def _sample_dict(s: Any) -> dict[str, Any]:
    return {
        "quantity": s.quantity,
        "axis": s.axis,
        "time_s": s.time_s,
        "heading_index": s.heading_index,
        "value": s.value,
        "allowed": s.allowed,
        "utilisation": s.utilisation,
    }


def _words(s: Any) -> str:
    unit = "A" if s.quantity == "current" else "V"
    return (
        f"{s.quantity} of the {s.axis} pair {abs(s.value):.4g} {unit} vs {s.allowed:.4g} {unit} "
        f"at t = {s.time_s:.4g} s (heading {s.heading_index})"
    )


def run(args: argparse.Namespace) -> int:
    """Sample, check, write; exit 3 if a limit is exceeded."""
    from spiralcap.commands._plot import check_figure_path

    check_outputs({"--csv": args.csv, "--plot": args.plot}, design_paths(args))
    if args.plot:
        check_figure_path("--plot", args.plot)
    if not args.heading:
        raise InputError("--heading", None, "at least one heading X,Y,Z")
    headings = [parse_heading(h) for h in args.heading]
    design = design_from_args(args)
    dwell_s, ramp_s = parse_timing(args.dwell_s, args.ramp_s, design["operation.frequency_hz"])
    from spiralcap.analysis.waveforms import waveforms_for_design

    w, check, model = waveforms_for_design(design, headings, dwell_s, ramp_s)
    outputs: dict[str, str | bytes] = {}
    if args.csv:
        outputs[args.csv] = _csv(w)
    if args.plot:
        outputs[args.plot] = _plot(args.plot, w, model)
    if outputs:
        from spiralcap.design import write_files_atomic

        write_files_atomic(outputs)  # both or neither
    import numpy as np

    peaks = {
        "current_A": dict(zip("xyz", np.max(np.abs(w.current_A), axis=0).tolist())),
        "voltage_V": dict(zip("xyz", np.max(np.abs(w.voltage_V), axis=0).tolist())),
    }
    if args.json:
        print_json(
            {
                "design": getattr(design, "source", "design"),
                "field_amplitude_T": w.amplitude_T,
                "frequency_hz": w.frequency_hz,
                "dwell_s": w.dwell_s,
                "ramp_s": w.ramp_s,
                "samples": len(w.time_s),
                "headings": w.headings.tolist(),
                "resistance_ohm": dict(zip("xyz", w.resistance_ohm.tolist())),
                "inductance_H": dict(zip("xyz", w.inductance_H.tolist())),
                "peaks": peaks,
                "binding": [_sample_dict(s) for s in check.binding],
                "exceeded": [_sample_dict(s) for s in check.exceeded],
                "ok": check.ok,
            }
        )
    else:
        print(
            f"{len(w.headings)} headings x {w.dwell_s:g} s at {w.amplitude_T * 1e3:.4g} mT, "
            f"{w.frequency_hz:g} Hz; plane change over {w.ramp_s:g} s; {len(w.time_s)} samples"
        )
        for ax in "xyz":
            print(
                f"  {ax} pair: peak {peaks['current_A'][ax]:.4g} A, {peaks['voltage_V'][ax]:.4g} V"
            )
        for s in check.binding:
            print(f"  heading {s.heading_index}: closest to a limit: {_words(s)}")
    if not check.ok:
        import sys

        first = check.exceeded[0]
        print(f"spiralcap waveforms: limit exceeded: {_words(first)}", file=sys.stderr)
        return EXIT_LIMIT
    return 0
