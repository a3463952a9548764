"""spiralcap: design tool for magnetically actuated spiral-type capsule endoscopes.

Kept light on purpose: importing the core (``spiralcap.core.backend``, ``spiralcap.core.constants``,
``spiralcap.core.errors``) must not pull in the application (design files, CLI, report).

The four domain packages (``coils``, ``capsule``, ``torque_model``, ``optimize``) are top-level
packages beside this one. A file of the same name found first on the import path (an
``optimize.py`` beside a user's script) would be imported in their place and fail deep inside;
importing spiralcap refuses it at once, with one line naming the file
(:class:`ShadowedPackageError`). The check only looks the names up; it imports nothing.
"""

__version__ = "0.1.0"

#: The top-level packages that ship with spiralcap, beside it.
DOMAIN_PACKAGES = ("coils", "capsule", "torque_model", "optimize")


class ShadowedPackageError(ImportError):
    """A module on the import path hides one of spiralcap's own top-level packages."""


def _shadowing() -> tuple[str, str] | None:
    """(package name, the file or folder Python would import instead) for the first of
    :data:`DOMAIN_PACKAGES` that would not come from beside spiralcap; None if all do (or one is
    missing altogether: that is said where it is imported)."""
    import os
    import sys
    from importlib.util import find_spec

    home = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for name in DOMAIN_PACKAGES:
        module = sys.modules.get(name)
        try:
            spec = module.__spec__ if module is not None else find_spec(name)
        except (ImportError, ValueError):
            continue
        if spec is None:
            continue
        where = spec.origin or next(iter(spec.submodule_search_locations or ()), None)
        if where is None or where in ("built-in", "frozen"):
            where = f"a {where or 'namespace'} module"
        expected = os.path.join(home, name, "__init__.py")
        if not (os.path.exists(where) and os.path.samefile(where, expected)):
            return name, where
    return None


_found = _shadowing()
if _found is not None:  # raised here, not in a function: a traceback of two lines at most
    raise ShadowedPackageError(
        f"spiralcap cannot import its {_found[0]!r} package: {_found[1]} comes first on the "
        "import path and hides it; rename that file (or folder), or run from another folder"
    )
