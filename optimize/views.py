"""Notebook views of results: an HTML table (``_repr_html_``) and ``.plot(ax=None)``.

The domain draws nothing and formats no HTML: a result class mixes in :class:`Viewable`, and
the application registers, per kind of result, *where* its view lives as an import path
``"package.module:name"`` (:func:`register_view`; :mod:`spiralcap.assemble` registers
:mod:`spiralcap.notebook`'s). The path is resolved when a notebook first shows or plots a
result, so the domain never imports the application (the registry is an entry-point table,
as Python packaging resolves plugins), and importing a domain package loads no plotting code.

A view is an object with ``html(result) -> str`` and ``plot(result, ax) -> Plot``.
"""

from __future__ import annotations

import importlib
from typing import Any, ClassVar

#: Result kind -> "module:attribute" of its view (filled by the application).
_VIEWS: dict[str, str] = {}


def register_view(kind: str, target: str) -> None:
    """Register where the view of one kind of result lives.

    Parameters
    ----------
    kind : str
        The result kind (``"evaluation"``, ``"optimization"``, ...), a class's ``_view_kind``.
    target : str
        Import path ``"package.module:attribute"`` of an object with ``html`` and ``plot``.
    """
    _VIEWS[kind] = target


def view_of(kind: str) -> Any | None:
    """The registered view of ``kind``, imported now.

    Parameters
    ----------
    kind : str
        The result kind.

    Returns
    -------
    object or None
        The view (``html`` and ``plot``); None when the application registered none (the
        domain used on its own).
    """
    target = _VIEWS.get(kind)
    if target is None:
        return None
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


class Viewable:
    """``_repr_html_`` and ``plot`` of a result, through the view its application registered."""

    _view_kind: ClassVar[str] = ""

    def _repr_html_(self) -> str | None:
        """An HTML table of the result (Jupyter); None without a registered view (Jupyter
        then shows the plain repr)."""
        view = view_of(self._view_kind)
        return None if view is None else str(view.html(self))

    def plot(self, ax: Any = None) -> Any:
        """Draw the result's main figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; a new figure when None.

        Returns
        -------
        spiralcap.figures.api.Plot
            The figure, its main axes and what was drawn.

        Raises
        ------
        RuntimeError
            No view is registered (import :mod:`spiralcap.assemble`, which registers them).
        """
        view = view_of(self._view_kind)
        if view is None:
            raise RuntimeError(
                f"no view registered for {self._view_kind!r} results: import spiralcap.assemble "
                "(it registers spiralcap.notebook's views)"
            )
        return view.plot(self, ax)
