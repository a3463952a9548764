"""Run the ``spiralcap`` command as a separate process (what stderr and exit codes promise is
seen only there: C code such as CasADi writes to file descriptor 2 directly)."""

from __future__ import annotations

import sys

#: ``[*SPIRALCAP, "coils", "--json"]`` runs ``spiralcap coils --json`` with this interpreter.
SPIRALCAP = [
    sys.executable,
    "-c",
    "import sys; sys.argv[0] = 'spiralcap'\nfrom spiralcap.cli import console; console()",
]
