"""Design file -> domain objects. One module per domain, each converting units at the edge.

Every builder takes a validated :class:`spiralcap.design.Design` and returns SI domain objects;
cross-key checks (a magnet that does not fit, a separation that makes no sense) raise
:class:`spiralcap.errors.InputError` naming the design key.
"""

from spiralcap.assemble.capsule import build_capsule
from spiralcap.assemble.coils import build_coils
from spiralcap.assemble.system import build_model
from spiralcap.assemble.tissue import build_tissues

__all__ = ["build_capsule", "build_coils", "build_model", "build_tissues"]
