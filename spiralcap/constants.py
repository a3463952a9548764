"""Physical constants and material data (SI). Imported by every package; imports none."""

from __future__ import annotations

#: Vacuum permeability, T·m/A (CODATA 2018: 1.25663706212e-6; the pre-2019 exact 4π·1e-7
#: differs by 5e-10 relative, below every tolerance in this project).
MU0_T_m_per_A = 1.25663706212e-6

#: Resistivity of annealed copper at 20 °C, Ω·m (IEC 60028 standard annealed copper, 1/58 Ω·mm²/m).
COPPER_RESISTIVITY_20C_ohm_m = 1.7241e-8

#: Temperature coefficient of copper resistivity at 20 °C, 1/K (IEC 60028).
COPPER_TEMPERATURE_COEFFICIENT_per_K = 0.00393

#: Standard gravity, m/s² (used to quote loads in gram-force where a paper does).
STANDARD_GRAVITY_m_s2 = 9.80665

#: Density of annealed copper, kg/m³ (IEC 60028: 8.89 g/cm³ at 20 °C).
COPPER_DENSITY_kg_m3 = 8890.0
