"""The capsule shell: a cylinder closed by two hemispherical ends.

Geometry only; no physics. The spiral is wound on the cylindrical part and the magnet sits
inside the shell (see :mod:`capsule.magnet` for the fit test).
"""

from __future__ import annotations

from dataclasses import dataclass

from spiralcap.core.errors import InputError, check_positive

#: Relative tolerance on geometric comparisons, so that 26 mm - 11 mm = 15 mm in binary floating
#: point does not fail a "wound length <= cylinder length" test by one unit in the last place.
GEOMETRY_RTOL = 1e-9


@dataclass(frozen=True)
class Body:
    """Capsule shell: cylinder of diameter ``diameter_m`` with hemispherical ends.

    No defaults: the design file (``spiralcap.schema``) holds the product's default capsule
    (the PillCam SB2 of Zhou et al. 2013, section II.A: 11 mm x 26 mm; the shell thickness is
    an assumption, the paper gives none).

    Parameters
    ----------
    diameter_m : float
        Outer diameter of the shell, m (> 0).
    length_m : float
        Overall length including both hemispherical ends, m (> ``diameter_m``).
    shell_thickness_m : float
        Wall thickness of the shell, the same on the cylinder and the ends, m
        (> 0 and < ``diameter_m / 2``).

    Raises
    ------
    spiralcap.core.errors.InputError
        Naming ``diameter_m``, ``length_m`` or ``shell_thickness_m``.
    """

    diameter_m: float
    length_m: float
    shell_thickness_m: float

    def __post_init__(self) -> None:
        for name in ("diameter_m", "length_m", "shell_thickness_m"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        if self.length_m <= self.diameter_m:
            raise InputError(
                "length_m",
                self.length_m,
                f"more than the diameter {self.diameter_m:g} m "
                "(two hemispherical ends need at least a full diameter)",
            )
        if self.shell_thickness_m >= self.radius_m:
            raise InputError(
                "shell_thickness_m",
                self.shell_thickness_m,
                f"less than the outer radius {self.radius_m:g} m",
            )

    @property
    def radius_m(self) -> float:
        """Outer radius of the cylindrical part, m."""
        return 0.5 * self.diameter_m

    @property
    def end_radius_m(self) -> float:
        """Outer radius of each hemispherical end, m (equal to the body radius)."""
        return 0.5 * self.diameter_m

    @property
    def cylinder_length_m(self) -> float:
        """Length of the cylindrical part between the two hemispheres, m (length - diameter)."""
        return self.length_m - self.diameter_m

    @property
    def inner_radius_m(self) -> float:
        """Radius of the shell's inner surface (cylinder and hemispheres alike), m."""
        return self.radius_m - self.shell_thickness_m
