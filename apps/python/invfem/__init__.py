"""invfem: invertible finite elements for cloth, shells and solids (see README.md, "Python").

The extension module is invfem._invfem; its names are re-exported here under `invfem`, which is
where the type stubs (__init__.pyi) describe them.
"""

from ._invfem import Simulation, __version__, check

__all__ = ["Simulation", "check", "__version__"]

# Reprs, help() and type checkers name the package, not the extension module behind it.
Simulation.__module__ = __name__
check.__module__ = __name__
