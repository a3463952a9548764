"""The named tissue sets a design can ask for (``tissue.preset``): calibrated Zhou 2013 samples.

Kept apart from :mod:`torque_model.tissue` so that the parameter modules may import
:class:`~torque_model.tissue.TissueParameters` without a cycle (tissue <- parameters <- presets).
"""

from __future__ import annotations

from spiralcap.core.errors import InputError
from torque_model.parameters import zhou2013
from torque_model.tissue import TissueParameters

__all__ = ["PRESET_NAMES", "preset"]

_SETS = {"zhou2013-sample2": zhou2013.SAMPLE2, "zhou2013-sample3": zhou2013.SAMPLE3}

PRESET_NAMES = tuple(_SETS)


def preset(name: str) -> TissueParameters:
    """The calibrated tissue set the tool uses for ``name`` (see ``docs/torque-model.md``).

    Parameters
    ----------
    name : str
        ``"zhou2013-sample2"`` or ``"zhou2013-sample3"``.

    Returns
    -------
    TissueParameters
        The published set times :data:`torque_model.parameters.zhou2013.CALIBRATION_FACTOR`,
        SI.

    Raises
    ------
    InputError
        An unknown name.

    Examples
    --------
    >>> from torque_model import preset
    >>> t = preset("zhou2013-sample2")
    >>> print(f"{t.name}: E1 {t.E1_Pa / 1e3:.1f} kPa, lumen {t.lumen_diameter_m * 1e3:.1f} mm, mu {t.friction_coefficient}")
    zhou2013-sample2: E1 42.8 kPa, lumen 10.9 mm, mu 0.28
    """
    if name not in _SETS:
        raise InputError("tissue.preset", name, "one of " + ", ".join(repr(n) for n in _SETS))
    return zhou2013.calibrated_tissue(_SETS[name], name)
