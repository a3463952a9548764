"""Size the windings of all three coil pairs for the least copper power at a safety factor of 2,
and print the bill of materials.

Run: python examples/size_coils_least_power.py
"""

from __future__ import annotations

from optimize import evaluate, optimize_design
from spiralcap.analysis.bom import bill_of_materials, bom_table
from spiralcap.analysis.coils import analyse_coils
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
# the bill of materials from the one function behind `spiralcap coils` and the report
print(bom_table(bill_of_materials(model, analyse_coils(best, model))))
