"""Section 8: the models behind the numbers, their assumptions and their sources."""

from __future__ import annotations

from spiralcap.report.document import (
    Bullets,
    Equation,
    Inline,
    Link,
    Paragraph,
    Section,
    Strong,
)
from spiralcap.report.sections._util import Context
from spiralcap.report.sections.conclusion import REFERENCES as CONCLUSION_REFERENCES

#: The references the report cites (no URLs: the report must open offline and fetch nothing).
REFERENCES: tuple[str, ...] = (
    '[1] H. Zhou, G. Alici, T. D. Than, W. Li, "Modeling and experimental investigation of '
    'rotational resistance of a spiral-type robotic capsule inside a real intestine", '
    "IEEE/ASME Transactions on Mechatronics 18(5), 2013.",
    '[2] ICNIRP, "Guidelines for limiting exposure to time-varying electric and magnetic fields '
    '(1 Hz to 100 kHz)", Health Physics 99(6):818-836, 2010.',
    "[3] W. R. Smythe, Static and Dynamic Electricity, 3rd ed., McGraw-Hill, 1968, §7.10.",
    '[4] J. C. Simpson, J. E. Lane, C. D. Immer, R. C. Youngquist, "Simple analytic expressions '
    'for the magnetic field of a circular current loop", NASA/TM-2001-210040, 2001.',
    "[5] J. C. Maxwell, A Treatise on Electricity and Magnetism, 1873, §701 (mutual inductance "
    "of coaxial circles).",
    '[6] E. B. Rosa, F. W. Grover, "Formulas and tables for the calculation of mutual and '
    "self-inductance\", Bulletin of the Bureau of Standards 8, 1912 (Stefan's formula); "
    "F. W. Grover, Inductance Calculations, 1946, ch. 16.",
    "[7] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed., "
    "McGraw-Hill, 2011, §8-2 (power screws).",
    "[8] J. D. Jackson, Classical Electrodynamics, 3rd ed., Wiley, 1999, eq. (5.1) (torque on "
    "a dipole).",
    "[9] IEC 60028, International standard of resistance for copper (resistivity and its "
    "temperature coefficient).",
    '[10] J. A. E. Andersson, J. Gillis, G. Horn, J. B. Rawlings, M. Diehl, "CasADi: a software '
    'framework for nonlinear optimization and optimal control", Mathematical Programming '
    "Computation 11:1-36, 2019.",
    '[11] A. Wächter, L. T. Biegler, "On the implementation of an interior-point filter '
    'line-search algorithm for large-scale nonlinear programming", Mathematical Programming '
    "106:25-57, 2006.",
    '[12] M. Ortner, L. G. Coliado Bandeira, "Magpylib: a free Python package for magnetic '
    'field computation", SoftwareX 11:100466, 2020 (independent reference in the tests).',
)


#: The model in five lines: the margin, the field cap, the moment, the screw, the heating.
EQUATIONS: tuple[Equation, ...] = (
    Equation(
        "M(alpha, f) = min_(bold(p), bold(h)) m B_0(f) kappa(bold(p), bold(h))"
        ' - max_"tissue" [tau_r (alpha, f) + F D_h / 2 tan(alpha + arctan mu)]',
        "M(α, f) = min over points p, headings h of m·B0(f)·κ(p, h) − max over tissue sets of "
        "[τ_r(α, f) + F·(D_h/2)·tan(α + atan μ)]",
        "margin: synchronous torque minus required torque",
    ),
    Equation(
        "B_0(f) = min(G I_max, G V_max / abs(R + j 2 pi f L), G sqrt(P_max / R), "
        'G I_(Delta T), B_"ICNIRP"(f))',
        "B0(f) = min(G·I_max, G·V_max/|R + j2πfL|, G·√(P_max/R), G·I_ΔT, B_ICNIRP(f))",
        "field cap per pair [2, 5, 6, 9]",
    ),
    Equation("m = B_r V / mu_0", "m = B_r·V/μ0", "magnet moment [8]"),
    Equation(
        "v = eta f pi D_h tan alpha, quad N = L_w / (pi D_h tan alpha)",
        "v = η·f·π·D_h·tan α,   N = L_w/(π·D_h·tan α)",
        "speed and spiral turns [7]",
    ),
    Equation(
        "Delta T = P / (h A)",
        "ΔT = P/(h·A)",
        "steady coil heating",
    ),
)


def build(ctx: Context) -> Section:
    """The assumptions-and-sources section."""
    d = ctx.data.design
    exposure = d["limits.field_exposure"]
    items: list[list[Inline]] = [
        [
            Strong("Tissue resistive torque"),
            " — Zhou et al. 2013 [1], section III, eqs. 2–8: "
            "the deformed wall over the wound section as a circle of the same perimeter (D′, the "
            "convex envelope of capsule and wire bump), strain (6), five-element viscoelastic "
            "stress (2)/(4) with t = θ/ω over one revolution, thin-walled pressure (3), Coulomb "
            "friction (7) and moment arm D_after/2 (8), read as a force per unit axial length "
            "(the only dimensionally consistent reading). Parameters: Tables I–II with the "
            "lumen, wall and friction of section II.",
        ],
        [
            Strong("Calibration factor"),
            " — read literally in SI the published sets give a torque "
            "about 350 times below the measured 0.6–1.8 mN·m while the frequency shape matches; "
            "all five moduli and viscosities are multiplied by k = ",
            ctx.num("tissue.calibration_factor"),
            ", a least-squares fit (relative error) to the "
            "two sample-2, capsule-No.-2 points only, which leaves every E/η ratio, and so the "
            "frequency shape, as published. The reading, the arithmetic and the validation against "
            "capsule No. 1 (errors up to +24 % at 3 Hz) are in docs/torque-model.md. k is a "
            "calibration to the paper's measurements, not a tissue property.",
        ],
        [
            Strong("Field exposure"),
            f" — limits.field_exposure = '{exposure}': ICNIRP 2010 [2], "
            "Tables 3–4, reference levels of magnetic flux density (rms): occupational 0.2/f² T "
            "for 1–8 Hz, 2.5·10⁻²/f T for 8–25 Hz, 1 mT above; general public 4·10⁻²/f² T, "
            "5·10⁻³/f T, 0.2 mT. Below 1 Hz the 1 Hz level is held. A circularly rotating field's "
            "rms equals its amplitude, so the level bounds B0 directly. Occupational levels "
            "protect the operator and staff, public levels everyone else; neither covers the "
            "patient (a medical exposure, see ",
            Link("section Conclusion", "conclusion"),
            ").",
        ],
        [
            Strong("Coil field"),
            " — exact off-axis field of each circular filament from the "
            "complete elliptic integrals K(m), E(m) (Smythe [3], in the notation of Simpson et al. "
            "[4]), with a series form of the radial term near the axis; each coil is one "
            "filament at the mean radius of its winding pack (the pack's own centre field, its "
            "current spread over a Gauss–Legendre grid, is in coils --json as "
            "pack_field_per_amp_T_per_A for comparison); the field is linear in the three "
            "currents, B(p) = G(p)·I. magpylib [12] is the independent reference in the tests.",
        ],
        [
            Strong("Inductance and resistance"),
            " — mutual inductance of coaxial circles by "
            "Maxwell's elliptic-integral formula [5] averaged over both winding packs; self "
            "inductance by Stefan's formula for a square section [6]; series pair 2L + 2M. DC "
            "copper resistance at each pack's mean winding temperature, solved with the heating "
            "(or at coils.winding_temperature_C if set; IEC 60028 resistivity and temperature "
            "coefficient [9]); at these frequencies "
            "the skin depth exceeds the wire radius. Voltage amplitude |R + j2πfL|·I.",
        ],
        [
            Strong("Heating"),
            " — each rectangular winding pack conducts its uniform copper loss to its faces "
            "with coils.winding_conductivity_W_mK (Robin problem of the section, Carslaw & "
            "Jaeger) and sheds it by natural convection from correlations by face orientation "
            "(Churchill & Chu; z axis vertical) or coils.heat_transfer_coefficient_W_m2K if "
            "set, and by radiation (coils.surface_emissivity) to the room and to the other "
            "packs (ray-traced view factors); the temperature limit applies to the hot spot, "
            "steady or at the end of operation.session_min (transient conduction from "
            "ambient). No conduction to the frame (docs/coils-thermal.md).",
        ],
        [
            Strong("Magnet and magnetic torque"),
            " — uniformly magnetised at its remanence, "
            "moment m = B_r·V/μ0; point dipole in the local field, τ = m × B [8]. In a rotating "
            "field the capsule lags by δ with τ = m·B0·sin δ, so m·B0 is the most it delivers; a "
            "larger load steps it out of synchrony.",
        ],
        [
            Strong("Propulsion"),
            " — the spiral as a square-thread power screw in a compliant nut: "
            "thrust torque F·(D_h/2)·tan(α + atan μ) (Budynas & Nisbett [7], §8-2), axial load "
            "requirements.axial_load_mN (20–100 mN is cited for capsules in porcine small "
            "intestine [1]); forward speed η·f·lead with lead = π·D_h·tan α and one slip "
            "efficiency η (requirements.slip_efficiency). A documented default, not a validated "
            "model.",
        ],
        [
            Strong("Workspace and headings"),
            " — the margin uses the weakest rotating field the "
            "magnet sees over the workspace points (centre, ±radius on each axis, the eight cube "
            "corners on the sphere) and over the design's headings (13 cube symmetry directions "
            "for 'all'); each axis is driven with the worst heading's current.",
        ],
        [
            Strong("Optimisation"),
            " — epigraph NLP over helical angle, frequency and field "
            "amplitude, built with CasADi [10] (exact first and second derivatives) and solved by "
            "IPOPT [11] from several starts; the multipliers of the active constraints give the "
            "gain of relaxing each binding limit by one step of its key (docs/optimisation.md).",
        ],
    ]
    return Section(
        "assumptions",
        "Assumptions and sources",
        [
            Paragraph(
                [
                    "Every number in this report comes from the models below; where a model is "
                    f"a simplification it says so. In short: the optimiser {_goal(ctx)} over "
                    "the helical angle α and the frequency f, the field amplitude B0 "
                    "capped by every limit of every pair (G: centre field per ampere, κ: the "
                    "field at a workspace point and heading over the centre field)."
                ]
            ),
            *EQUATIONS,
            Bullets(items),
            Paragraph([Strong("References")]),
            Bullets([[r] for r in (*REFERENCES, *CONCLUSION_REFERENCES)]),
        ],
    )


def _goal(ctx: Context) -> str:
    """``maximises the worst-case torque margin M`` / ``minimises the worst-heading copper
    power, subject to the safety factor on M``, from the optimisation's JSON."""
    try:
        o = ctx.value("optimize")
    except (KeyError, TypeError, AttributeError):
        return "maximises the margin M"
    what, sense = o.get("objective_description"), o.get("objective_direction")
    if not what or o.get("objective") == "margin":
        return "maximises the margin M"
    verb = {"maximised": "maximises", "minimised": "minimises"}.get(str(sense), "optimises")
    tail = " (the margin M held at the required safety factor)" if sense == "minimised" else ""
    return f"{verb} the {what}{tail}"
