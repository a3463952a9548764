"""Design file -> domain objects. One module per domain, each converting units at the edge.

Every builder takes a validated :class:`spiralcap.design.Design` and returns SI domain objects;
cross-key checks (a magnet that does not fit, a separation that makes no sense) raise
:class:`spiralcap.core.errors.InputError` naming the design key.
"""

from spiralcap.assemble.capsule import build_capsule
from spiralcap.assemble.coils import build_coils
from spiralcap.assemble.system import build_model
from spiralcap.assemble.tissue import build_tissues

#: The notebook views of the results (optimize.views): kind -> where the view lives. By import
#: path, resolved on first use: the views draw through spiralcap.figures, which imports this
#: package, so neither side imports the other here.
NOTEBOOK_VIEWS = {
    "evaluation": "spiralcap.notebook:EVALUATION",
    "optimization": "spiralcap.notebook:OPTIMIZATION",
    "coil_analysis": "spiralcap.notebook:COIL_ANALYSIS",
    "uncertainty_study": "spiralcap.notebook:UNCERTAINTY_STUDY",
}


def _notebook_views() -> None:
    """Results show as tables and plot in notebooks (spiralcap.notebook's views)."""
    from optimize.views import register_view

    for kind, target in NOTEBOOK_VIEWS.items():
        register_view(kind, target)


_notebook_views()

__all__ = ["build_capsule", "build_coils", "build_model", "build_tissues"]
