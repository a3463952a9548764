"""Which headings share a coil current, and CasADi tables built once per distinct current.

The rotating field about heading n needs current amplitude B0 sqrt(1 - n_k²)/g_k on axis k
(coils.rotating); headings with equal sqrt(1 - n_k²) share one node (and one thermal solve) in
the compiled problem (optimize.compiled) and in the sizing problem (optimize.hardware).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np


def heading_pattern(headings: Any) -> tuple:
    """Which headings share a current per tesla on each axis (a property of the headings alone).

    Per axis k: ``(entries, worst)`` with ``entries[h]`` the first heading whose
    sqrt(1 - n_k²) equals heading h's (-1 where it is 0: no current) and ``worst`` the heading
    with the largest. The NLP builds one node per distinct entry, so a thermal solve is shared
    by the headings that carry the same current (optimize.physics.heading_losses_W).

    Parameters
    ----------
    headings : array_like, shape (h, 3)
        Unit headings, dimensionless.

    Returns
    -------
    tuple of (tuple of int, int)
        Per axis: the index of each heading's first equal heading (-1: no current) and that of
        the worst heading.
    """
    s = np.sqrt(np.clip(1.0 - np.asarray(headings, dtype=float) ** 2, 0.0, 1.0))
    out = []
    for k in range(3):
        col = s[:, k]
        entries = []
        for h, v in enumerate(col):
            if v <= 0:
                entries.append(-1)
                continue
            entries.append(next(j for j in range(h + 1) if abs(col[j] - v) <= 1e-12 * v))
        worst = int(np.argmax(col))
        out.append((tuple(entries), entries[worst]))
    return tuple(out)


def shared_heading_table(entry: Any, pattern: tuple, headings: int) -> tuple[Any, Any]:
    """(table (headings, 3), per-axis worst column (3,)) with one node per distinct entry.

    ``entry(h, k)`` builds the value of heading h on axis k; ``pattern`` is
    :func:`heading_pattern`'s. Zero entries are the constant 0.

    Parameters
    ----------
    entry : callable
        ``entry(h, k)``, the value of heading h on axis k (a CasADi expression, in the caller's
        unit).
    pattern : tuple
        :func:`heading_pattern` of the headings.
    headings : int
        Number of headings.

    Returns
    -------
    table : casadi.SX, shape (headings, 3)
        The values, in the unit of ``entry``'s quantity (its name carries it).
    worst : casadi.SX, shape (3,)
        Each axis' worst heading's value, in the unit of ``entry``'s quantity (its name
    carries it).
    """
    nodes: dict[tuple[int, int], Any] = {}
    cols, worst = [], []
    for k, (entries, top) in enumerate(pattern):
        col = []
        for h in range(headings):
            first = entries[h]
            if first < 0:
                col.append(ca.SX(0.0))
                continue
            if (first, k) not in nodes:
                nodes[(first, k)] = entry(first, k)
            col.append(nodes[(first, k)])
        cols.append(ca.vertcat(*col))
        worst.append(nodes[(top, k)] if top >= 0 else ca.SX(0.0))
    return ca.horzcat(*cols), ca.vertcat(*worst)
