"""spiralcap: design tool for magnetically actuated spiral-type capsule endoscopes.

Kept light on purpose: importing the core (``spiralcap.backend``, ``spiralcap.constants``,
``spiralcap.errors``) must not pull in the application (design files, CLI, report).
"""

__version__ = "0.1.0"
