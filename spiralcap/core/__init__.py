"""The core every package may import: numpy/CasADi dispatch (:mod:`spiralcap.core.backend`),
physical constants and the design-unit table (:mod:`spiralcap.core.constants`) and the one-line
errors (:mod:`spiralcap.core.errors`). It imports no domain package and nothing of the
application (tests/test_import_graph.py)."""
