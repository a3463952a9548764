"""Count the NLP solves of one command and their CPU seconds (for per-solve overheads).

Run: python benchmarks/bench_solve_count.py optimize --json [ARGS ...]
Runs ``spiralcap ARGS`` in this process with ``optimize.nlp.CompiledNLP.solve`` counted and
timed (``time.process_time``); prints, on stderr, the solves, their CPU seconds and the
process CPU total. With the per-solve overhead of ``benchmarks/bench_nlp_opti.py`` this says
what an interface adding that overhead to every solve would cost the command. Asserts nothing.
"""

from __future__ import annotations

import atexit
import sys
import time
from typing import Any

from optimize import nlp
from spiralcap.cli import console

_COUNT = [0, 0.0]
_REAL = nlp.CompiledNLP.solve


def _spy(*args: Any, **kwargs: Any) -> Any:
    t0 = time.process_time()
    out = _REAL(*args, **kwargs)
    _COUNT[0] += 1
    _COUNT[1] += time.process_time() - t0
    return out


def _report() -> None:
    print(
        f"SOLVES {_COUNT[0]} in {_COUNT[1]:.2f} s CPU; total CPU {time.process_time():.2f} s",
        file=sys.stderr,
    )


if __name__ == "__main__":
    nlp.CompiledNLP.solve = _spy  # type: ignore[method-assign]
    atexit.register(_report)
    sys.argv = ["spiralcap", *sys.argv[1:]]
    console()
