"""Import paths of release 0.1 that moved in 0.2, kept working (with a DeprecationWarning) for one release.

Release 0.2 grouped the DG methods under :mod:`ngdgfric.dg` and the contact solvers under
:mod:`ngdgfric.solvers`, and split ``ngdgfric.linalg`` into :mod:`ngdgfric.sparse` and
:mod:`ngdgfric.threads`.  ``import ngdgfric.newton`` (or ``from ngdgfric.newton import ...``)
still works and returns the module at its new place; the finder below is the one place that knows
the old names.  It goes in 0.3.
"""

import importlib
import importlib.abc
import importlib.util
import sys
import types

from .errors import warn

MOVED_MODULES = {
    **{name: f"ngdgfric.dg.{name}" for name in ("methods", "forms", "liftings", "material", "discretization")},
    **{name: f"ngdgfric.solvers.{name}" for name in (
        "newton", "fixed_point", "uzawa", "semismooth", "reduced", "condensation", "complementary_energy",
        "nonlinear", "pardiso", "options")},
    "traces": "ngdgfric.contact.traces",
}
"""Old module name (below ``ngdgfric``) -> its module in 0.2."""

MOVED_NAMES = {"refine": "ngdgfric.meshes", "minimum_angle": "ngdgfric.adaptivity", "HPState": "ngdgfric.hp"}
"""Names that left the top level in 0.2 -> the module that has them."""


def _warn(old, new):
    warn(f"{old} moved to {new} in ngdgfric 0.2; the old path goes in 0.3", DeprecationWarning)


class _LinalgModule(types.ModuleType):
    """``ngdgfric.linalg`` of 0.1: the names of :mod:`ngdgfric.sparse` and :mod:`ngdgfric.threads`."""

    def __getattr__(self, name):
        for module in ("ngdgfric.sparse", "ngdgfric.threads"):
            module = importlib.import_module(module)
            if hasattr(module, name):
                return getattr(module, name)
        raise AttributeError(f"module 'ngdgfric.linalg' has no attribute {name!r}")


class _Alias(importlib.abc.Loader):
    def __init__(self, new):
        self.new = new

    def create_module(self, spec):
        _warn(spec.name, self.new or "ngdgfric.sparse and ngdgfric.threads")
        if self.new is None:
            return _LinalgModule(spec.name)
        return importlib.import_module(self.new)

    def exec_module(self, module):
        """Nothing to run: the module was imported at its new place."""


class MovedFinder(importlib.abc.MetaPathFinder):
    """Finds ``ngdgfric.<old name>`` of :data:`MOVED_MODULES` (and ``ngdgfric.linalg``) at its new place."""

    def find_spec(self, fullname, path=None, target=None):
        package, _, name = fullname.rpartition(".")
        if package != "ngdgfric" or (name not in MOVED_MODULES and name != "linalg"):
            return None
        return importlib.util.spec_from_loader(fullname, _Alias(MOVED_MODULES.get(name)))


def install():
    """Put :class:`MovedFinder` on ``sys.meta_path`` (once)."""
    if not any(isinstance(finder, MovedFinder) for finder in sys.meta_path):
        sys.meta_path.append(MovedFinder())


def moved_name(name):
    """The top-level name ``name`` of 0.1 that moved (module ``__getattr__`` of ``ngdgfric``): a function or
    class of :data:`MOVED_NAMES`, or a module of :data:`MOVED_MODULES` (``ngdgfric.uzawa.uzawa``)."""
    if name in MOVED_MODULES or name == "linalg":
        return importlib.import_module(f"ngdgfric.{name}")  # the finder warns
    if name not in MOVED_NAMES:
        raise AttributeError(f"module 'ngdgfric' has no attribute {name!r}")
    _warn(f"ngdgfric.{name}", f"{MOVED_NAMES[name]}.{name}")
    return getattr(importlib.import_module(MOVED_NAMES[name]), name)
