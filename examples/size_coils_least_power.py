"""Size the windings of all three coil pairs for the least copper power at a safety factor of 2,
and print the bill of materials.

Run: python examples/size_coils_least_power.py
"""

from __future__ import annotations

from optimize import evaluate, optimize_design, prepare
from optimize.physics import winding_resistance_ohm
from spiralcap.assemble import build_model
from spiralcap.assemble.system import optimum_values
from spiralcap.design import load_design

free = {
    f"optimize.free.coils.{ax}.{key}": bounds
    for ax in "xyz"
    for key, bounds in (("turns", [100, 800]), ("wire_diameter_mm", [0.8, 3.0]))
}
design = load_design().with_values(
    {**free, "optimize.objective": "power", "requirements.min_safety_factor": 2.0}
)
result = optimize_design(build_model(design))
if not result.feasible:
    raise SystemExit(result.message)

# the answer is a design: build it and read the hardware off it
best = design.with_values(optimum_values(design, result))
model = build_model(best)
ev = evaluate(model)
h = result.hardware
print(f"least copper power at safety factor {ev.safety_factor:.3f}: {result.objective_value:.1f} W")
print(
    f"(continuous bound {h.relaxed_objective:.1f} W; whole turns and R40 wire cost "
    f"{h.rounding_cost:.2f} W)"
)
print(
    f"helical angle {ev.helical_angle_deg:.2f} deg, {ev.frequency_hz:.3f} Hz, "
    f"field {ev.field_amplitude_T * 1e3:.3f} mT"
)
print()
print("axis  turns  wire mm  wire m  copper kg  R ohm   L mH   I A    V V")
model = prepare(model)
for k, (ax, pair, current) in enumerate(zip("xyz", model.coils.pairs, ev.current_amplitudes_A)):
    # at the pair's own mean winding temperature carrying this current (coils.thermal)
    r = float(winding_resistance_ohm(current, k, model.constants, model.ambient_temperature_C))
    mass = 8890.0 * pair.wire_length_m * pair.wire_area_m2
    volts = next(c.value for c in ev.checks if c.name == f"voltage_{ax}")
    print(
        f"{ax:<5} {pair.turns:>5}  {pair.wire_diameter_m * 1e3:7.2f}  {pair.wire_length_m:6.0f}  "
        f"{mass:9.1f}  {r:6.2f}  {pair.series_inductance_H * 1e3:5.0f}  {current:5.2f}  "
        f"{volts:5.1f}"
    )
