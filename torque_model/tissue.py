"""Tissue parameter sets in SI: the five-element viscoelastic constants and the lumen geometry.

The five-element model (Zhou et al. 2013, eq. 2 and Fig. 7) is two Maxwell arms (E1, eta1),
(E2, eta2) in parallel with a spring E3. The lumen (D_before in eq. 6), the wall thickness (d in
eqs. 3 and 6) and the capsule-mucosa Coulomb friction coefficient (mu in eq. 7) complete a set.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Protocol

from spiralcap.core.constants import design_unit, from_si
from spiralcap.core.errors import InputError, check_positive

__all__ = ["VISCOELASTIC_FIELDS", "TissueParameters", "ViscoelasticConstants"]

#: The viscoelastic fields (moduli and viscosities), in the order the identification uses.
VISCOELASTIC_FIELDS = ("E1_Pa", "E2_Pa", "E3_Pa", "eta1_Pa_s", "eta2_Pa_s")


class ViscoelasticConstants(Protocol):
    """What the relaxation integral reads: the five constants, floats or CasADi values, SI.

    :class:`TissueParameters` is one; the identification passes CasADi symbols through the same
    model function to differentiate it.
    """

    @property
    def E1_Pa(self) -> Any:
        """Spring modulus of the first Maxwell arm, Pa."""

    @property
    def E2_Pa(self) -> Any:
        """Spring modulus of the second Maxwell arm, Pa."""

    @property
    def E3_Pa(self) -> Any:
        """Modulus of the parallel spring, Pa."""

    @property
    def eta1_Pa_s(self) -> Any:
        """Dashpot viscosity of the first Maxwell arm, Pa·s."""

    @property
    def eta2_Pa_s(self) -> Any:
        """Dashpot viscosity of the second Maxwell arm, Pa·s."""


@dataclass(frozen=True)
class TissueParameters:
    """One intestinal tissue: five-element viscoelastic constants, lumen geometry, friction.

    Parameters
    ----------
    E1_Pa, E2_Pa, E3_Pa : float
        Spring moduli of the five-element model (Zhou 2013 eq. 2), Pa, >= 0.
    eta1_Pa_s, eta2_Pa_s : float
        Dashpot viscosities of the two Maxwell arms, Pa·s, > 0.
    lumen_diameter_m : float
        Inner diameter of the undeformed intestine, D_before in eq. 6, m.
    wall_thickness_m : float
        Intestinal wall thickness, d in eqs. 3 and 6, m.
    friction_coefficient : float
        Capsule-mucosa Coulomb friction coefficient, mu in eq. 7 (dimensionless).
    name : str
        Where the set came from (a preset name, ``"fit"``, ``"custom"``).
    """

    E1_Pa: float
    E2_Pa: float
    E3_Pa: float
    eta1_Pa_s: float
    eta2_Pa_s: float
    lumen_diameter_m: float
    wall_thickness_m: float
    friction_coefficient: float
    name: str = "custom"

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            if f.name == "name":
                continue
            value = getattr(self, f.name)
            if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
                value = value.item()
            allow_zero = f.name in ("E1_Pa", "E2_Pa", "E3_Pa")
            object.__setattr__(self, f.name, check_positive(f.name, value, allow_zero=allow_zero))
        if not isinstance(self.name, str):
            raise InputError("name", self.name, "a string")

    def replace(self, **changes: Any) -> TissueParameters:
        """A copy with some fields changed (validated again).

        Parameters
        ----------
        **changes : float or str
            New field values by field name, SI as the names say (``E1_Pa=...``, Pa).

        Returns
        -------
        TissueParameters
            The changed copy.
        """
        return dataclasses.replace(self, **changes)

    def scaled(self, factor: float, name: str | None = None) -> TissueParameters:
        """A copy with every modulus and viscosity multiplied by ``factor`` (geometry unchanged).

        The torque of :func:`torque_model.resistive_torque_Nm` is linear in this factor and the
        shape of torque against frequency is unchanged (the exponents hold E/eta ratios only).

        Parameters
        ----------
        factor : float
            Multiplier on E1, E2, E3, eta1, eta2, dimensionless, > 0.
        name : str, optional
            Name of the copy (default: this set's name).

        Returns
        -------
        TissueParameters
            The scaled copy.
        """
        factor = check_positive("factor", factor)
        return self.replace(
            name=name or self.name, **{k: getattr(self, k) * factor for k in VISCOELASTIC_FIELDS}
        )

    def as_design_table(self) -> dict[str, float]:
        """The set as ``tissue.*`` design-key values (kPa, kPa·s, mm): the keys without prefix.

        Returns
        -------
        dict of str to float
            Design value by key, the unit in each key name (``E1_kPa``, ``lumen_diameter_mm``).
        """
        out = {}
        for key in _DESIGN_KEYS:
            si_name, factor = _si(key)
            out[key] = from_si(getattr(self, si_name), factor)
        return out

    @classmethod
    def from_design_table(cls, table: dict[str, float], name: str = "custom") -> TissueParameters:
        """Build from ``tissue.*`` design units (the inverse of :meth:`as_design_table`).

        Parameters
        ----------
        table : dict of str to float
            Exactly the eight ``tissue.*`` keys without prefix, the unit in each key name (kPa,
            kPa·s, mm; friction dimensionless).
        name : str
            Name of the set.

        Returns
        -------
        TissueParameters
            The set in SI.
        """
        missing = [k for k in _DESIGN_KEYS if k not in table]
        unknown = [k for k in table if k not in _DESIGN_KEYS]
        if missing or unknown:
            raise InputError(
                "tissue", sorted(missing + unknown), "exactly the keys " + ", ".join(_DESIGN_KEYS)
            )
        si = {}
        for key in _DESIGN_KEYS:
            si_name, factor = _si(key)
            si[si_name] = table[key] * factor
        return cls(name=name, **si)


_DESIGN_KEYS = (
    "E1_kPa",
    "E2_kPa",
    "E3_kPa",
    "eta1_kPa_s",
    "eta2_kPa_s",
    "lumen_diameter_mm",
    "wall_thickness_mm",
    "friction_coefficient",
)


def _si(key: str) -> tuple[str, float]:
    """A tissue design key's SI field name and factor, from the one unit table."""
    unit, si_unit, factor = design_unit(key)
    return (key[: len(key) - len(unit)] + si_unit if unit else key), factor
