"""spiralcap: design tool for magnetically actuated spiral-type capsule endoscopes.

Kept light on purpose: importing the core (``spiralcap.core.backend``, ``spiralcap.core.constants``,
``spiralcap.core.errors``) must not pull in the application (design files, CLI, report).
"""

__version__ = "0.1.0"
