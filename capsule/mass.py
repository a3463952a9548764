"""The capsule's mass from its parts, for the friction of its weight on the wall.

A magnetically actuated capsule is its shell with electronics, battery and camera, plus a
permanent magnet. Without a measured mass (``capsule.mass_g``) the tool estimates it from the
volumes: the magnet at the density of sintered NdFeB, the rest of the capsule's outer volume at
the mean density of a commercial capsule endoscope without a magnet.
"""

from __future__ import annotations

import math

from spiralcap.core.backend import Scalar
from spiralcap.core.checks import guard, nonnegative, positive

__all__ = [
    "CONTENTS_DENSITY_kg_m3",
    "NDFEB_DENSITY_kg_m3",
    "body_volume_m3",
    "mass_from_parts_kg",
]

#: Sintered NdFeB, kg/m³ (manufacturers' data sheets give 7.4-7.6 g/cm³).
NDFEB_DENSITY_kg_m3 = 7500.0
#: Mean density of a capsule endoscope's shell, electronics and battery, kg/m³: the PillCam SB3
#: (Medtronic data sheet: 3.0 g, 11.4 mm x 26.2 mm, an outer volume of 2.29 cm³) averages
#: 1310 kg/m³.
CONTENTS_DENSITY_kg_m3 = 1300.0


@guard(diameter_m=positive(), length_m=positive())
def body_volume_m3(diameter_m: Scalar, length_m: Scalar) -> Scalar:
    """Outer volume of a capsule: a cylinder closed by two hemispheres, m³.

    Parameters
    ----------
    diameter_m : float or CasADi
        Outer diameter D, m.
    length_m : float or CasADi
        Overall length L including both ends, m (> D).

    Returns
    -------
    float or CasADi
        pi D² (L - D) / 4 + pi D³ / 6, m³.

    Examples
    --------
    A 12 × 25 mm capsule, a cylinder of 13 mm with two hemispherical ends:

    >>> import math
    >>> from capsule import body_volume_m3
    >>> by_hand = math.pi * 0.006**2 * 0.013 + 4 / 3 * math.pi * 0.006**3
    >>> print(f"{body_volume_m3(0.012, 0.025) * 1e6:.4f} cm3; by hand {by_hand * 1e6:.4f}")
    2.3750 cm3; by hand 2.3750
    """
    return 0.25 * math.pi * diameter_m**2 * (length_m - diameter_m) + math.pi * diameter_m**3 / 6.0


@guard(diameter_m=positive(), length_m=positive(), magnet_volume_m3=nonnegative())
def mass_from_parts_kg(diameter_m: Scalar, length_m: Scalar, magnet_volume_m3: Scalar) -> Scalar:
    """Capsule mass estimated from its parts, kg.

    Parameters
    ----------
    diameter_m : float or CasADi
        Outer diameter, m.
    length_m : float or CasADi
        Overall length, m.
    magnet_volume_m3 : float or CasADi
        Volume of the magnet, m³ (inside the outer volume).

    Returns
    -------
    float or CasADi
        NdFeB density x magnet volume + contents density x the rest of the outer volume, kg.
    """
    rest = body_volume_m3(diameter_m, length_m) - magnet_volume_m3
    return NDFEB_DENSITY_kg_m3 * magnet_volume_m3 + CONTENTS_DENSITY_kg_m3 * rest
