"""Figures: matplotlib lives here and in ``spiralcap.report`` only.

Every plotting function takes ``ax=`` (a matplotlib Axes), draws on it, labels the axes with
units, and returns what it drew, so the CLI and the report compose them freely. Importing this
package does not import matplotlib; the modules do, and the caller chooses the backend (the CLI
uses Agg).

The functions of :mod:`spiralcap.figures.api` -- one per report figure, taking the model and
result objects and an optional ``ax=`` -- are available here (imported on first use):
``spiralcap.figures.margin_vs_frequency(model, evaluation, result)`` and so on.
"""

from typing import Any

from spiralcap.figures.api import __all__ as _names  # the api module imports numpy only

_API = tuple(_names)
__all__ = list(_API)


def __getattr__(name: str) -> Any:
    if name in _API:
        from spiralcap.figures import api

        return getattr(api, name)
    raise AttributeError(f"module 'spiralcap.figures' has no attribute {name!r}")
