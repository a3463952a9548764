"""The sizing NLP against the fixed-hardware NLP at the same point (tests of optimize.hardware)."""

from __future__ import annotations

import math

from optimize import hardware as hw


def assert_sizing_rows_equal_fixed_rows(model, names: tuple[str, ...], what: str) -> None:
    """With the frozen factors taken at ``model``'s hardware, every row of the sizing NLP
    (``names`` as variables) equals the fixed-hardware NLP's row at the same operating point,
    to 1e-9 (``what`` names the case in the message)."""
    from optimize.physics import total_loss_W
    from optimize.solve import compile_problem, scales_for, structure_of

    hs = hw.HardwareStructure(
        names, hw.helmholtz_flags(model), len(model.headings), shapes=hw.shape_keys(model)
    )
    sized = compile_problem(structure_of(model, hardware=hs))
    fixed = compile_problem(structure_of(model))
    scales = scales_for(model)
    extra = hw.sizing_parameters(model, hw.frozen_factors(model), hw.bore_m(model))
    point = {"helical_angle_rad": 0.3, "frequency_hz": 1.2, "field_scaled": 0.8, "t": 0.1}
    here = hw.hardware_of(model)
    loss = total_loss_W(
        point["field_scaled"] * scales.field_T, model.constants, model.ambient_temperature_C
    )
    p_sized = sized.parameters(model, scales, extra)
    start = {**point, **{n: here[n] for n in names}, "power_W_scaled": float(loss) / scales.power_W}
    _, g_sized = sized.nlp.evaluate(sized.nlp.scaled_start(start, p_sized), p_sized)
    p_fixed = fixed.parameters(model, scales)
    _, g_fixed = fixed.nlp.evaluate(fixed.nlp.scaled_start(point, p_fixed), p_fixed)
    by_name = dict(zip(sized.nlp.row_names, g_sized))
    for name, g in zip(fixed.nlp.row_names, g_fixed):
        assert math.isclose(by_name[name], g, rel_tol=1e-9, abs_tol=1e-12), (
            f"{name}: sizing and fixed rows agree ({what}, 1e-9)"
        )
