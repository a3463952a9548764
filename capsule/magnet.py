"""The permanent magnet inside the capsule: a diametrically magnetised cylinder or ring.

The magnet's axis is the capsule's axis and its magnetisation is perpendicular to it, so that a
field rotating about the capsule axis drags the capsule round (Zhou et al. 2013, introduction).
It is treated as uniformly magnetised at its remanence: moment ``m = B_r V / mu0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from capsule.body import GEOMETRY_RTOL, Body
from spiralcap.core.checks import guard, instance
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError, check_positive

#: Nominal remanence B_r (T) of sintered NdFeB grades at 20 °C: the middle of the range each
#: grade allows. Ranges (T) as tabulated by Shanghai Magnet (NdFeB performance parameter table,
#: https://en.shanghaimagnet.com/about/Production-Process), which follow the usual Chinese
#: grade bands (also quoted by HGT Advanced Magnets and others): N35 1.17-1.22, N42 1.28-1.32,
#: N45 1.32-1.37, N48 1.37-1.42, N52 1.42-1.46. A specific supplier's datasheet may differ by a
#: few per cent; set ``capsule.magnet.remanence_T`` to use it.
GRADE_REMANENCE_RANGE_T: dict[str, tuple[float, float]] = {
    "N35": (1.17, 1.22),
    "N42": (1.28, 1.32),
    "N45": (1.32, 1.37),
    "N48": (1.37, 1.42),
    "N52": (1.42, 1.46),
}

#: Nominal (mid-range) remanence of each grade, T. See :data:`GRADE_REMANENCE_RANGE_T`.
GRADE_REMANENCE_T: dict[str, float] = {
    g: round(0.5 * (lo + hi), 4) for g, (lo, hi) in GRADE_REMANENCE_RANGE_T.items()
}


def remanence_for_grade(grade: str) -> float:
    """Nominal remanence of a sintered NdFeB grade.

    Parameters
    ----------
    grade : str
        One of ``N35``, ``N42``, ``N45``, ``N48``, ``N52`` (case-insensitive).

    Returns
    -------
    float
        Remanence B_r, T (mid-range; see :data:`GRADE_REMANENCE_RANGE_T` for the source).

    Raises
    ------
    spiralcap.core.errors.InputError
        Naming ``grade`` for an unknown grade.

    Examples
    --------
    >>> from capsule import remanence_for_grade
    >>> print(f"N52: {remanence_for_grade('N52')} T")
    N52: 1.44 T
    """
    key = grade.upper() if isinstance(grade, str) else grade
    if key not in GRADE_REMANENCE_T:
        raise InputError("grade", grade, "one of " + ", ".join(GRADE_REMANENCE_T))
    return GRADE_REMANENCE_T[key]


@dataclass(frozen=True)
class Magnet:
    """Diametrically magnetised cylinder (``inner_diameter_m == 0``) or ring magnet.

    Parameters
    ----------
    diameter_m : float
        Outer diameter, m (> 0).
    length_m : float
        Axial length, m (> 0).
    remanence_T : float
        Remanence B_r, T (> 0); see :func:`remanence_for_grade`.
    inner_diameter_m : float
        Bore of a ring magnet, m (>= 0 and < ``diameter_m``); 0 for a solid cylinder.

    Raises
    ------
    spiralcap.core.errors.InputError
        Naming the parameter at fault.

    Examples
    --------
    An 8 × 10 mm N52 cylinder: its moment is B_r V / μ0:

    >>> import math
    >>> from capsule import Magnet
    >>> m = Magnet(0.008, 0.010, 1.44)
    >>> volume = math.pi * 0.004**2 * 0.010
    >>> print(f"{m.moment_Am2:.5f} A m2; Br V / mu0 = {1.44 * volume / (4e-7 * math.pi):.5f}")
    0.57600 A m2; Br V / mu0 = 0.57600
    """

    diameter_m: float
    length_m: float
    remanence_T: float
    inner_diameter_m: float = 0.0

    def __post_init__(self) -> None:
        for name in ("diameter_m", "length_m", "remanence_T"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        bore = check_positive("inner_diameter_m", self.inner_diameter_m, allow_zero=True)
        if bore >= self.diameter_m:
            raise InputError(
                "inner_diameter_m", bore, f"less than the outer diameter {self.diameter_m:g} m"
            )
        object.__setattr__(self, "inner_diameter_m", bore)

    @property
    def shape(self) -> str:
        """``"ring"`` if the magnet has a bore, else ``"cylinder"``."""
        return "ring" if self.inner_diameter_m > 0 else "cylinder"

    @property
    def volume_m3(self) -> float:
        """Magnet volume ``pi (d^2 - d_i^2) l / 4``, m^3."""
        return 0.25 * math.pi * (self.diameter_m**2 - self.inner_diameter_m**2) * self.length_m

    @property
    def magnetization_A_per_m(self) -> float:
        """Magnetisation ``M = B_r / mu0`` (uniform, at remanence), A/m."""
        return self.remanence_T / MU0_T_m_per_A

    @property
    def moment_Am2(self) -> float:
        """Magnetic dipole moment ``m = B_r V / mu0``, A·m^2.

        Assumes uniform magnetisation at remanence, i.e. recoil permeability 1 and no
        demagnetisation loss (sintered NdFeB: recoil permeability about 1.05, so the true moment
        in the magnet's own field is typically a few per cent lower).
        """
        return self.remanence_T * self.volume_m3 / MU0_T_m_per_A


@guard(body=instance(Body, "a capsule.Body"), magnet=instance(Magnet, "a capsule.Magnet"))
def magnet_fit_check(body: Body, magnet: Magnet) -> tuple[str, str] | None:
    """Like :func:`magnet_fit_problem`, also saying which size is at fault.

    Parameters
    ----------
    body : Body
        Capsule shell.
    magnet : Magnet
        Magnet, coaxial with and centred in the shell.

    Returns
    -------
    (str, str) or None
        None if it fits, else ``("diameter_m" | "length_m", reason)``.
    """
    r_in = body.inner_radius_m
    half_d = 0.5 * magnet.diameter_m
    if half_d > r_in * (1.0 + GEOMETRY_RTOL):
        return (
            "diameter_m",
            f"magnet diameter {magnet.diameter_m * 1e3:g} mm exceeds the "
            f"shell's inner diameter {2e3 * r_in:g} mm",
        )
    half_l_max = 0.5 * body.cylinder_length_m + math.sqrt(max(r_in**2 - half_d**2, 0.0))
    if 0.5 * magnet.length_m > half_l_max * (1.0 + GEOMETRY_RTOL):
        return (
            "length_m",
            f"magnet length {magnet.length_m * 1e3:g} mm exceeds the "
            f"{2e3 * half_l_max:.4g} mm that fits between the shell's hemispherical ends "
            f"at that width",
        )
    return None


@guard(body=instance(Body, "a capsule.Body"), magnet=instance(Magnet, "a capsule.Magnet"))
def magnet_fit_problem(body: Body, magnet: Magnet) -> str | None:
    """Whether a magnet centred on the capsule axis fits inside the shell; why not if it does not.

    The cavity is the shell's inner surface: a cylinder of radius ``r_in`` over the cylindrical
    part (length ``L_cyl``) closed by hemispheres of radius ``r_in``. A cylinder of diameter ``d``
    and length ``l`` fits when ``d/2 <= r_in`` and its rim circle stays inside the hemispheres:
    ``l/2 <= L_cyl/2 + sqrt(r_in^2 - (d/2)^2)``.

    Parameters
    ----------
    body : Body
        Capsule shell.
    magnet : Magnet
        Magnet, coaxial with and centred in the shell.

    Returns
    -------
    str or None
        None if it fits, else a short reason (sizes in mm) that names ``diameter`` when the
        magnet is too wide and ``length`` (and not ``diameter``) when it is too long.
    """
    check = magnet_fit_check(body, magnet)
    return None if check is None else check[1]
