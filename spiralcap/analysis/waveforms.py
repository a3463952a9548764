"""Amplifier waveforms of a design for a heading sequence (what ``spiralcap waveforms`` runs).

>>> from spiralcap.design import load_design                       # doctest: +SKIP
>>> from spiralcap.analysis.waveforms import waveforms_for_design  # doctest: +SKIP
>>> w, check, _ = waveforms_for_design(load_design(), [(1, 0, 0), (0, 1, 0)], 5.0, 1.0)  # doctest: +SKIP
"""

from __future__ import annotations

from typing import Any

from spiralcap.core.errors import InputError

#: Most samples one sequence may have (200 per rotation period and per ramp).
MAX_SAMPLES = 2_000_000


def waveforms_for_design(design: Any, headings: Any, dwell_s: float, ramp_s: float) -> tuple:
    """(Waveforms, WaveformCheck, model) at the design's operating field and frequency.

    The resistance of each pair is taken at its mean winding temperature at the operating point
    (worst-heading current; steady, or at the end of the session), as ``spiralcap coils``.
    Calibrated coils (a design with ``[calibration]``): the currents invert the calibrated
    centre matrix and cancel the survey's background field.
    """
    import numpy as np

    from coils.waveforms import check_waveforms, heading_waveforms
    from optimize import physics, prepare
    from optimize.evaluate import operating_field_T
    from spiralcap.assemble import build_model
    from spiralcap.core.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K as alpha

    model = prepare(build_model(design, optimiser=False))
    c, f = model.constants, model.frequency_hz
    field = float(operating_field_T(model, f))
    temps = [
        float(
            physics.winding_temperatures_C(
                field * float(c.current_per_tesla_A_per_T[k]), k, c, model.ambient_temperature_C
            )[1]
        )
        for k in range(3)
    ]
    r = np.asarray(c.resistance_20C_ohm) * (1.0 + alpha * (np.asarray(temps) - 20.0))
    samples = len(headings) * dwell_s / min(1.0 / (200.0 * f), ramp_s / 200.0)
    if samples > MAX_SAMPLES:
        raise InputError(
            "--dwell-s",
            dwell_s,
            f"a sequence of at most {MAX_SAMPLES} samples (200 per rotation period and per "
            f"ramp; this one needs {samples:.3g})",
        )
    w = heading_waveforms(
        model.coils.field_matrix(np.zeros((1, 3)))[0],
        r,
        c.inductance_H,
        np.asarray(headings, dtype=float),
        amplitude_T=field,
        frequency_hz=f,
        dwell_s=dwell_s,
        ramp_s=ramp_s,
        background_T=getattr(model.coils, "background_T", None),
    )
    # each pair against its own amplifier channel where limits.{x,y,z}.* is set
    lim = model.limits
    amps = [float(lim.channel("current", k)[1]) for k in range(3)]
    volts = [float(lim.channel("voltage", k)[1]) for k in range(3)]
    return w, check_waveforms(w, amps, volts), model
