r"""ngdgfric: DG methods for frictional contact with normal compliance on NGSolve.

Porwal & Tanvi, "Unified analysis of DG methods for frictional contact problem with normal
compliance": model (1.1)-(1.10), DG forms of Section 3, estimator of Section 4, Section 6's
adaptive loop.  Everything a script needs is here (``ngdgfric.__all__``); the modules below are the
data path problem (:mod:`ngdgfric.problem`) -> :mod:`ngdgfric.dg` (methods, forms, liftings, discretisation)
beside :mod:`ngdgfric.contact` (the laws and :math:`\Gamma_C`) -> :mod:`ngdgfric.solvers` (the contact solvers)
-> estimator (:mod:`ngdgfric.estimator`) -> marking (:mod:`ngdgfric.marking`) -> refinement
(:mod:`ngdgfric.adaptivity`).

The entry points (:func:`~ngdgfric.solve`, :func:`~ngdgfric.finish`, :func:`~ngdgfric.estimate`,
:func:`~ngdgfric.adapt`) limit OpenBLAS to one thread while they run (``blas_threads`` of
:mod:`ngdgfric.threads`); importing changes nothing.  Import paths of 0.1 that
moved in 0.2 still work for one release, with a DeprecationWarning: each is a stub module of the old name
(``ngdgfric.newton``, ...) that warns and hands over the module at its new place.
"""

from importlib import import_module as _import_module
from importlib.metadata import PackageNotFoundError, version

from .adaptivity import Adaptation, AdaptOptions, adapt, dorfler_mark
from .checks import DataError
from .contact import Contact, contact_state, kkt_residuals, pair_state
from .dg.discretization import Discretization
from .dg.material import MaterialWarning
from .dg.methods import DG_METHODS, METHODS, LockingWarning, Method, PenaltyWarning
from .domain import Domain, Loop
from .equilibration import Equilibration, equilibrate
from .errors import SolverError, SolverWarning, TimeLimitError
from .errors import warn as _warn
from .estimator import Estimate, estimate
from .examples import example, example_6_1, example_6_2
from .forces import ForceBalance, force_balance
from .hp import hp_refine
from .meshes import check_mesh, netgen_mesh, refined, uniform_mesh
from .problem import ContactPair, ContactProblem, Polygon
from .problem_file import example_file, load_problem
from .reference import Reference, energy_error, energy_norm, load_reference, save_reference
from .solution import Solution, finish, solve
from .solvers.fixed_point import FixedPointOptions
from .solvers.newton import NewtonOptions
from .solvers.options import SolverOptions
from .solvers.pardiso import PardisoError
from .solvers.uzawa import UzawaOptions
from .storage import load_solution, save_solution
from .transfer import WarmStart

try:
    __version__ = version("ngdgfric")
    """The installed release (setup.py is the one place that states it)."""
except PackageNotFoundError:  # pragma: no cover - run from a source tree that was never installed
    __version__ = "unknown"

__all__ = [
    "__version__",
    # scenes
    "ContactProblem", "ContactPair", "Polygon", "Domain", "Loop", "example", "example_6_1", "example_6_2",
    "load_problem", "example_file", "DataError",
    # meshes
    "uniform_mesh", "netgen_mesh", "check_mesh", "refined",
    # methods and discretisation
    "Method", "METHODS", "DG_METHODS", "Discretization", "Contact", "MaterialWarning", "PenaltyWarning",
    "LockingWarning",
    # solving
    "solve", "finish", "Solution", "WarmStart", "save_solution", "load_solution", "SolverOptions", "NewtonOptions",
    "UzawaOptions", "FixedPointOptions", "SolverError", "TimeLimitError", "PardisoError", "SolverWarning",
    # outputs
    "contact_state", "pair_state", "kkt_residuals", "force_balance", "ForceBalance",
    # estimators and adaptivity
    "estimate", "Estimate", "equilibrate", "Equilibration", "dorfler_mark", "adapt", "AdaptOptions", "Adaptation",
    "hp_refine",
    # true errors
    "energy_norm", "Reference", "energy_error", "load_reference", "save_reference",
]

_OLD_MODULES = frozenset({
    "methods", "forms", "liftings", "material", "discretization",  # now in ngdgfric.dg
    "newton", "fixed_point", "uzawa", "semismooth", "reduced", "condensation", "complementary_energy", "nonlinear",
    "traces", "pardiso", "options",  # now in ngdgfric.solvers
    "linalg",  # now ngdgfric.sparse and ngdgfric.threads
})
"""The module paths of 0.1 kept as stub modules of the same name for one release (they go in 0.3)."""

_MOVED_NAMES = {"refine": "ngdgfric.meshes", "minimum_angle": "ngdgfric.adaptivity", "HPState": "ngdgfric.hp"}
"""Names that left the top level in 0.2 -> the module that has them."""


def __getattr__(name):
    """Names of 0.1 that moved in 0.2, each with a DeprecationWarning: an old module as an attribute
    (``ngdgfric.uzawa``: its stub module warns) and ``refine``, ``minimum_angle``, ``HPState``."""
    if name in _OLD_MODULES:
        return _import_module(f"{__name__}.{name}")
    if name not in _MOVED_NAMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    _warn(f"ngdgfric.{name} moved to {_MOVED_NAMES[name]}.{name} in ngdgfric 0.2; the old path goes in 0.3",
          DeprecationWarning)
    return getattr(_import_module(_MOVED_NAMES[name]), name)
